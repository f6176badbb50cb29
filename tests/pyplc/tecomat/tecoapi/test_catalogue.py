"""The catalogue walker: GetList shapes, T_ApiObjects anywhere, plain leaves, arrays."""

from datetime import date
import json
from typing import Any

from hypothesis import HealthCheck, given, settings, strategies as st
import pytest

from custom_components.tecoapi.pyplc import (
    PlcError,
    PlcResponseError,
    ValueKind,
)
from custom_components.tecoapi.pyplc.tecomat.points import api_object_attributes
from custom_components.tecoapi.pyplc.tecomat.tecoapi.catalogue import (
    as_api_object,
    build_catalogue,
    parse_root_list,
)
from custom_components.tecoapi.pyplc.tecomat.tecoapi.paths import (
    MISSING,
    lookup,
    split_path,
)

ATTR = {
    "enable": True,
    "visibility": True,
    "readOnly": False,
    "title": "requested temperature",
    "minValue": 10.0,
    "maxValue": 30.0,
    "units": "°C",
}


def _api(value: Any, **attr: Any) -> dict[str, Any]:
    return {"value": value, "attr": ATTR | attr}


def test_get_list_struct_and_array_shapes() -> None:
    struct = json.loads('{"plcName": {}, "plcType": {}, "plcDesc": {}}')
    array = json.loads('[{"plcName": {}}, {"plcType": {}}, {"plcDesc": {}}]')
    assert parse_root_list(struct) == ("plcName", "plcType", "plcDesc")
    assert parse_root_list(array) == ("plcName", "plcType", "plcDesc")
    assert parse_root_list({}) == ()
    assert parse_root_list({"a": {}, "A": {}, "": {}}) == ("a",)


@pytest.mark.parametrize("body", [None, "plcName", 3, ["plcName"], [{"a": {}}, 1]])
def test_get_list_in_another_shape_is_a_response_error(body: Any) -> None:
    with pytest.raises(PlcResponseError):
        parse_root_list(body)


def test_api_objects_anywhere_and_plain_leaves() -> None:
    tree = {
        "Main": {
            "myObject3": _api(23.0),
            "counter": 5,
        },
        "boiler": _api(True, readOnly=False, title="boiler", units=""),
        "rooms": [_api(21.5, title="room 0"), _api(22.5, title="room 1")],
        "house": {"floor": {"hall": _api("hello", title="display", units="")}},
        "arr2": [[0.0, 0.1], [1.0, 1.1]],
        "varDate": "2015-06-17",
        "empty": {},
        "nothing": None,
    }
    catalogue = build_catalogue([*tree, "ghost"], tree)
    points = catalogue.points
    assert list(points) == [
        "main.myobject3",
        "main.counter",
        "boiler",
        "rooms[0]",
        "rooms[1]",
        "house.floor.hall",
        "arr2[0][0]",
        "arr2[0][1]",
        "arr2[1][0]",
        "arr2[1][1]",
        "vardate",
    ]
    assert points["main.myobject3"].path == "Main.myObject3"
    assert points["main.myobject3"].attributes == api_object_attributes(
        title="requested temperature",
        units="°C",
        read_only=False,
        min_value=10.0,
        max_value=30.0,
        enable=True,
        visibility=True,
    )
    assert points["main.counter"].attributes is None
    assert points["main.counter"].kind is ValueKind.INTEGER
    assert points["boiler"].kind is ValueKind.BOOL
    assert points["rooms[1]"].attributes is not None
    assert points["rooms[1]"].attributes.name == "room 1"
    assert points["house.floor.hall"].kind is ValueKind.STRING
    assert points["arr2[1][0]"].kind is ValueKind.REAL
    assert points["vardate"].kind is ValueKind.DATE
    assert catalogue.values["vardate"] == date(2015, 6, 17)
    assert catalogue.values["rooms[0]"] == 21.5
    assert catalogue.values["boiler"] is True
    assert catalogue.groups == (*tree, "ghost")
    assert catalogue.skipped_groups == ("ghost",)


def test_names_match_ignoring_case_and_keep_the_plc_spelling() -> None:
    tree = {"MAIN": {"MyObject3": _api(23.0)}}
    catalogue = build_catalogue(["main"], tree, skipped_roots=["lost"])
    assert list(catalogue.points) == ["main.myobject3"]
    assert catalogue.points["main.myobject3"].path == "MAIN.MyObject3"
    assert catalogue.groups == ("main",)
    assert catalogue.skipped_groups == ("lost",)


@pytest.mark.parametrize(
    "node",
    [
        {"value": 1.0},
        {"value": 1.0, "attr": {}},
        {"value": 1.0, "attr": ATTR, "extra": 1},
        {"value": [1.0], "attr": ATTR},
        {"value": None, "attr": ATTR},
        {"value": 1.0, "attr": ATTR | {"readOnly": "no"}},
        {"value": 1.0, "attr": ATTR | {"minValue": True}},
        {"value": 1.0, "attr": ATTR | {"title": 5}},
        {"value": 1.0, "attr": {k: v for k, v in ATTR.items() if k != "units"}},
    ],
)
def test_near_misses_are_not_api_objects(node: dict[str, Any]) -> None:
    assert as_api_object(node) is None


def test_api_object_keys_match_ignoring_case() -> None:
    found = as_api_object(
        {"VALUE": 3, "Attr": {key.upper(): value for key, value in ATTR.items()}}
    )
    assert found is not None
    assert found[0] == 3
    assert found[1].minimum == 10.0


def test_ambiguous_member_names_are_skipped() -> None:
    tree = {"root": {"a.b": 1, "c[0]": 2, "": 3, "X": 4, "x": 5, "odd name&=": 6}}
    catalogue = build_catalogue(["root"], tree)
    assert list(catalogue.points) == ["root.x", "root.odd name&="]
    assert catalogue.values["root.x"] == 4


def test_a_deep_tree_does_not_exhaust_the_stack() -> None:
    tree: dict[str, Any] = {"leaf": 1}
    for _ in range(5000):
        tree = {"n": tree}
    catalogue = build_catalogue(["n"], {"n": tree})
    (point,) = catalogue.points.values()
    assert point.path == "n." * 5001 + "leaf"


_scalars = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(min_value=-(2**40), max_value=2**40),
    st.floats(allow_nan=True, allow_infinity=True),
    st.text(max_size=12),
    st.sampled_from(["2015-06-17", "01:02:03.450", "2018-05-11T11:22:33.456Z"]),
)
_names = st.one_of(
    st.text(max_size=6),
    st.sampled_from(["value", "attr", "Value", "ATTR", "a.b", "x[1]", "", "&=#"]),
)
_attrs = st.fixed_dictionaries(
    {
        "enable": st.booleans(),
        "visibility": st.booleans(),
        "readOnly": st.booleans(),
        "title": st.text(max_size=8),
        "minValue": st.floats(allow_nan=False),
        "maxValue": st.floats(allow_nan=False),
        "units": st.text(max_size=3),
    }
)
_json = st.recursive(
    _scalars,
    lambda children: st.one_of(
        st.lists(children, max_size=4),
        st.dictionaries(_names, children, max_size=4),
        st.fixed_dictionaries({"value": _scalars, "attr": _attrs}),
    ),
    max_leaves=30,
)


# No deadline: one example is a millisecond, but a busy machine (CI's two cores, each
# running a pytest worker) stalls one now and then past Hypothesis' 200 ms default.
@settings(
    max_examples=300,
    deadline=None,
    database=None,
    suppress_health_check=[HealthCheck.too_slow],
)
@given(
    tree=st.dictionaries(_names, _json, max_size=5),
    extra_roots=st.lists(_names, max_size=3),
)
def test_random_trees_never_break_the_walker(
    tree: dict[str, Any], extra_roots: list[str]
) -> None:
    roots = list(tree) + extra_roots
    try:
        catalogue = build_catalogue(roots, tree)
    except PlcError:
        return
    for key, point in catalogue.points.items():
        assert key == point.path.lower()
        node = lookup(tree, split_path(point.path))
        assert node is not MISSING
        raw = lookup(node, ["value"]) if point.described else node
        assert not isinstance(raw, dict | list)
        assert raw is not None
    for root in catalogue.skipped_groups:
        assert root in roots
