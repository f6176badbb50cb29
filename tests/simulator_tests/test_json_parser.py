"""The PLC's JSON parser for PutObject: agrees with JSON where allowed, fails only its way."""

import json
from typing import Any

from hypothesis import given, strategies as st
import pytest

from tests.simulator.errors import TecoError
from tests.simulator.json_parser import parse_put_body

ascii_text = st.text(st.characters(min_codepoint=0, max_codepoint=127), max_size=40)
# Numbers as the PLC takes them: integers and decimals without an exponent.
numbers = st.integers(-(10**12), 10**12) | st.integers(-(10**9), 10**9).map(
    lambda n: n / 100
)
scalars = st.none() | st.booleans() | numbers | ascii_text
names = st.text(st.sampled_from("abcXYZ_019"), min_size=1, max_size=64)
documents = st.dictionaries(
    names,
    st.recursive(
        scalars,
        lambda inner: (
            st.lists(inner, max_size=4) | st.dictionaries(names, inner, max_size=4)
        ),
        max_leaves=12,
    ),
    max_size=6,
)


@given(documents)
def test_parses_what_json_writes(document: dict[str, Any]) -> None:
    assert parse_put_body(json.dumps(document).encode()) == document


@given(documents)
def test_parses_compact_and_indented_layouts(document: dict[str, Any]) -> None:
    compact = json.dumps(document, separators=(",", ":")).encode()
    indented = json.dumps(document, indent="\t").encode()

    assert parse_put_body(compact) == parse_put_body(indented) == document


@given(st.binary(max_size=200))
def test_any_bytes_either_parse_or_fail_as_the_plc_does(body: bytes) -> None:
    outcome: object
    try:
        outcome = parse_put_body(body)
    except TecoError as error:
        outcome = error.code
    assert isinstance(outcome, dict) or outcome in {"400.008", "400.009"}


@pytest.mark.parametrize(
    ("body", "value"),
    [
        (b'{"a": -0.5}', -0.5),
        (b'{"a": 0}', 0),
        (b'{"a": "\\"\\\\\\/\\b\\f\\n\\r\\t"}', '"\\/\b\f\n\r\t'),
        (b'{"a": []}', []),
        (b'{"a": {}}', {}),
        (b' \r\n\t{"a": null} \r\n', None),
    ],
)
def test_details(body: bytes, value: object) -> None:
    assert parse_put_body(body) == {"a": value}


def test_a_later_duplicate_name_wins() -> None:
    assert parse_put_body(b'{"a": 1, "a": 2}') == {"a": 2}
