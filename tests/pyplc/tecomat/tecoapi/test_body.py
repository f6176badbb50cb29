"""Reading answers: the size cap's formula and the per-string text decoding."""

from custom_components.tecoapi.pyplc.tecomat.tecoapi.body import (
    MAX_BODY_BYTES,
    MAX_ITEMS,
    MAX_NAME_CHARS,
    MAX_NESTING,
    MAX_VALUE_CHARS,
    decode_text,
)


def test_the_cap_is_the_documented_worst_case() -> None:
    indent = 2 * MAX_NESTING
    item = indent + MAX_NAME_CHARS + 2 + 2 + 6 * MAX_VALUE_CHARS + 2 + 1 + 2
    container = 3 * indent + MAX_NAME_CHARS + 2 + 4 + 6
    assert (item, container) == (1667, 268)
    assert MAX_BODY_BYTES == MAX_ITEMS * (item + 31 * container) + 6 == 2_553_606


def test_each_string_is_decoded_on_its_own() -> None:
    """One Windows-1250 string in a UTF-8 answer costs nothing else."""
    body = (
        b'{"a": "Teplota ob\xfdv\xe1k", "b": "\xc2\xb0C", "c": "\\"\xb0\\"",'
        b' "d": "\x81", "e": "plain"}'
    )
    assert decode_text(body) == (
        '{"a": "Teplota obývák", "b": "°C", "c": "\\"°\\"", "d": "\ufffd", "e": "plain"}'
    )
    assert decode_text("Žluťoučký kůň".encode()) == "Žluťoučký kůň"
    # Outside strings nothing is guessed: the JSON stays broken.
    assert decode_text(b"{\xfd: 1}") == "{\ufffd: 1}"
