"""JSON as the FP-I4C's manual prints it: every example of the seed reads.

The examples are in ``seed_examples.txt`` as the manual prints them (no-break
spaces, trailing commas, ``"start": f``, bare hex words); none is JSON.
"""

import json
from pathlib import Path
from typing import Any

from hypothesis import given, strategies as st
import pytest

from custom_components.tecoapi.pyplc.panasonic.lenient import (
    MAX_DEPTH,
    MAX_TEXT,
    LenientJsonError,
    loads,
    loads_lenient,
)

SEED = Path(__file__).with_name("seed_examples.txt")


def seed_examples() -> list[str]:
    """The manual's JSON examples, in its order."""
    body = SEED.read_text(encoding="utf-8").split("\n\n", 1)[1]
    return [block.strip() for block in body.split("\n=====\n")]


def test_every_example_of_the_manual_reads_and_none_is_json() -> None:
    examples = seed_examples()
    assert len(examples) == 9
    for text in examples:
        with pytest.raises(ValueError):
            json.loads(text)
        value, lenient = loads(text)
        assert lenient
        assert isinstance(value, dict)


def test_the_manuals_requests_and_answers_read_as_meant() -> None:
    request, _, _, answer, _, any_answer, _, _, write_answer = (
        loads(text)[0] for text in seed_examples()
    )
    assert request["req"][2] == {"area": "y", "type": "bool", "start": "f", "count": 10}
    assert request["req"][3]["value"] == list(range(1, 11))
    assert (request["interface"], request["station"]) == (0, 0)
    assert answer["data"][0]["int"] == [20, 0, 0, 0, 0, 0, 0, 0, 0, 0]
    assert answer["data"][0]["err"] is False
    string, registers, bits = any_answer["data"]
    assert string["string"] == "This is a string"
    assert registers["udint"][:2] == [131073, 262147]
    assert registers["hex"][-1] == "000A"
    assert registers["hex"][0] == "0001"
    assert registers["real"][0] == pytest.approx(5.969307950918661e-39)
    assert bits["state"] == [0] * 16
    assert [item["request"] for item in write_answer["data"]] == ["DT10", "Y0", "DT20"]


def test_strict_json_is_read_strictly() -> None:
    assert loads('{"a": [1, 2.5, "x", true, null]}') == (
        {"a": [1, 2.5, "x", True, None]},
        False,
    )


@pytest.mark.parametrize(
    ("text", "value"),
    [
        ("[1, 2,]", [1, 2]),
        ('{"a": 1,}', {"a": 1}),
        ("[]", []),
        ("{}", {}),
        ("[ ]", []),
        ("[0001, 000A, 10, -3, 1e3, 2.5]", ["0001", "000A", 10, -3, 1000.0, 2.5]),
        ('{"start": f, "x": F1, "y": +5}', {"start": "f", "x": "F1", "y": "+5"}),
        ("[true, false, null,]", [True, False, None]),
        ('"\\u00e9t\\u00e9"', "été"),
        ("\u00a0[1]\u00a0", [1]),
    ],
)
def test_the_lenient_forms(text: str, value: Any) -> None:
    assert loads_lenient(text) == value


@pytest.mark.parametrize(
    "text",
    [
        "",
        "[1 2]",
        "[,1]",
        '{"a" 1}',
        "{a: 1}",
        '{"a": 1',
        "[1]]",
        '"open',
        "[1] x",
        "[@]",
        '{"a": 1 "b": 2}',
    ],
)
def test_what_is_not_json_even_leniently_is_refused(text: str) -> None:
    with pytest.raises(LenientJsonError):
        loads(text)


def test_size_and_depth_are_bounded() -> None:
    with pytest.raises(LenientJsonError, match="longer than"):
        loads(" " * (MAX_TEXT + 1))
    with pytest.raises(LenientJsonError, match="longer than"):
        loads_lenient(" " * (MAX_TEXT + 1))
    assert loads_lenient("[" * MAX_DEPTH + "]" * MAX_DEPTH) is not None
    with pytest.raises(LenientJsonError, match="nested too deep"):
        loads_lenient("[" * (MAX_DEPTH + 1) + "1," + "]" * (MAX_DEPTH + 1))
    # Far deeper than Python's recursion: refused, not a crash.
    with pytest.raises(LenientJsonError):
        loads("[" * 100_000)


_SCALARS = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(-(10**12), 10**12),
    st.floats(allow_nan=False, allow_infinity=False),
    st.text(max_size=10),
)
_VALUES = st.recursive(
    _SCALARS,
    lambda inner: (
        st.lists(inner, max_size=4)
        | st.dictionaries(st.text(max_size=5), inner, max_size=4)
    ),
    max_leaves=20,
)


def _with_trailing_commas(value: Any) -> str:
    """JSON as the manual prints it: a comma after every member and element."""
    if isinstance(value, list):
        return "[" + "".join(f"{_with_trailing_commas(item)}," for item in value) + "]"
    if isinstance(value, dict):
        return (
            "{"
            + "".join(
                f"{json.dumps(key)}: {_with_trailing_commas(item)},"
                for key, item in value.items()
            )
            + "}"
        )
    return json.dumps(value)


@given(_VALUES)
def test_any_json_reads_the_same_strictly_and_leniently(value: Any) -> None:
    text = json.dumps(value)
    assert loads_lenient(text) == json.loads(text)
    assert loads_lenient(json.dumps(value, indent=2)) == json.loads(text)


@given(_VALUES)
def test_trailing_commas_change_nothing(value: Any) -> None:
    parsed, lenient = loads(_with_trailing_commas(value))
    assert parsed == json.loads(json.dumps(value))
    assert lenient is (isinstance(value, list | dict) and bool(value))
