"""Paths, request targets and their encoding: no name or value can add a parameter."""

from urllib.parse import unquote

import pytest

from custom_components.tecoapi.pyplc.tecomat.tecoapi.paths import (
    MISSING,
    encode_name,
    encode_value,
    get_object_target,
    join_path,
    lookup,
    lookup_path,
    member,
    merge_into,
    path_steps,
    readable_name,
    split_path,
    walk,
)

HOSTILE = [
    "a&b=c",
    "x#frag",
    'quote"d',
    "space d",
    "°C",
    "plus+sign",
    "per%cent",
    "a?b",
]


@pytest.mark.parametrize(
    ("path", "segments"),
    [
        ("plcName", ["plcName"]),
        ("Main.myObject3", ["Main", "myObject3"]),
        ("arr2[1][3]", ["arr2", 1, 3]),
        ("myObject.interests[2]", ["myObject", "interests", 2]),
        ("house.floor[1].room[0].temp", ["house", "floor", 1, "room", 0, "temp"]),
        ("odd name&x", ["odd name&x"]),
    ],
)
def test_paths_split_and_join(path: str, segments: list[str | int]) -> None:
    assert split_path(path) == segments
    assert join_path(segments) == path


@pytest.mark.parametrize(
    "path", ["", ".a", "a.", "a..b", "a[", "a[x]", "[1]", "a[1]b", "a]b", "a[-1]"]
)
def test_malformed_paths_are_rejected(path: str) -> None:
    with pytest.raises(ValueError, match="Not a variable path"):
        split_path(path)


def test_array_elements_are_read_through_their_array() -> None:
    assert readable_name("arr1[5]") == "arr1"
    assert readable_name("plcData.varStringArray[2]") == "plcData.varStringArray"
    assert readable_name("rooms[2].value") == "rooms"
    assert readable_name("Main.myObject3") == "Main.myObject3"


def test_names_keep_dots_brackets_and_underscores_readable() -> None:
    assert encode_name("plc_Data.arr[2]") == "plc_Data.arr[2]"
    assert encode_name("a b") == "a%20b"
    assert encode_value("testing is funny") == "testing%20is%20funny"
    assert "+" not in encode_value("a b+c")


@pytest.mark.parametrize("text", HOSTILE)
def test_nothing_can_inject_a_parameter(text: str) -> None:
    target = get_object_target(["ok", text])
    query = target.partition("?")[2]
    pieces = query.split("&")
    assert len(pieces) == 2
    assert unquote(pieces[1]) == text
    for forbidden in '=#" ?+':
        assert forbidden not in pieces[1]
    assert pieces[1].isascii()
    value = encode_value(text)
    assert unquote(value) == text
    for forbidden in '&=#" ?+[]':
        assert forbidden not in value


def test_lookup_ignores_case_and_finds_indexed_members_both_ways() -> None:
    tree = {
        "MAIN": {"MyObject3": {"Value": 23.0}},
        "arr2": [[0.0, 0.1], [1.0, 1.1]],
        "myObject": {"INTERESTS[1]": "Mountain Biking"},
    }
    assert lookup(tree, ["Main", "myObject3", "value"]) == 23.0
    assert lookup(tree, ["arr2", 1, 0]) == 1.0
    assert lookup(tree, ["myObject", "interests", 1]) == "Mountain Biking"
    assert lookup(tree, ["arr2", 5]) is MISSING
    assert lookup(tree, ["arr2", 0, 0, 0]) is MISSING
    assert lookup(tree, ["main", "nothing"]) is MISSING
    assert lookup(tree, [1]) is MISSING


@pytest.mark.parametrize(
    "path",
    [
        "Main.myObject3.value",
        "arr2[1][0]",
        "myObject.interests[1]",
        "arr2[5]",
        "arr2[0][0][0]",
        "main.nothing",
        "MAIN",
    ],
)
def test_lookup_of_a_path_text_matches_the_lookup_of_its_segments(path: str) -> None:
    tree = {
        "MAIN": {"MyObject3": {"Value": 23.0}},
        "arr2": [[0.0, 0.1], [1.0, 1.1]],
        "myObject": {"INTERESTS[1]": "Mountain Biking"},
    }
    assert lookup_path(tree, path) == lookup(tree, split_path(path))
    # Cached steps do not tie a path to the tree it was first looked up in.
    assert lookup_path({"main": {"myobject3": {"value": 1.5}}}, path) == lookup(
        {"main": {"myobject3": {"value": 1.5}}}, split_path(path)
    )


def test_a_walk_that_remembers_objects_without_brackets_finds_the_same() -> None:
    """Remembering which objects have no key with ``[`` (so no literal indexed
    key) changes nothing found, in one answer walked by many paths."""
    tree = {
        "MAIN": {"MyObject3": {"Value": 23.0}},
        "arr2": [[0.0, 0.1], [1.0, 1.1]],
        "myObject": {"INTERESTS[1]": "Mountain Biking", "interests": ["a", "b", "c"]},
    }
    paths = [
        "Main.myObject3.value",
        "arr2[1][0]",
        "myObject.interests[1]",
        "myObject.interests[2]",
        "arr2[5]",
        "MAIN",
    ]
    bracketed: dict[int, bool] = {}
    for path in paths * 2:
        assert walk(tree, path_steps(path), bracketed) == lookup_path(tree, path)
    assert walk(tree, path_steps("myObject.interests[1]"), bracketed) == (
        "Mountain Biking"
    )
    assert bracketed == {id(tree): False, id(tree["myObject"]): True}


def test_lookup_of_text_that_is_not_a_path_raises() -> None:
    with pytest.raises(ValueError, match="Not a variable path"):
        lookup_path({}, "a..b")


def test_exact_spelling_first_then_the_first_case_insensitive_match() -> None:
    tree = {"A": 1, "a": 2, "B": 3}
    assert member(tree, "a") == 2
    assert member(tree, "b") == 3
    assert member(tree, "c") is MISSING
    assert member([1], "a") is MISSING


def test_responses_merge_by_root_ignoring_case() -> None:
    tree: dict[str, object] = {"myObject": {"first": "John"}}
    merge_into(tree, {"MYOBJECT": {"favorites": {"sport": "Soccer"}}, "x": 1})
    merge_into(tree, {"x": 2})
    assert tree == {
        "myObject": {"first": "John", "favorites": {"sport": "Soccer"}},
        "x": 2,
    }
