"""FP addresses at the ends of their areas, with the numbers written out.

The other address tests read the ends from MAX_WORD; these name them (the largest of
any FP series CPU, as the module says), so a limit moved by one fails here.
"""

import pytest

from custom_components.tecoapi.pyplc.panasonic.address import (
    AddressError,
    WireType,
    parse_address,
    type_problem,
)

LAST_WORDS = {"DT": 999_999, "FL": 32_767, "LD": 16_383, "WR": 9_999, "WX": 9_999, "WY": 9_999, "WL": 9_999}  # fmt: skip
BIT_WORDS = {"R": "WR", "X": "WX", "Y": "WY", "L": "WL"}


@pytest.mark.parametrize(("area", "last"), LAST_WORDS.items())
def test_a_register_area_ends_at_its_last_word(area: str, last: int) -> None:
    assert parse_address(f"{area}{last}").word == last
    with pytest.raises(AddressError):
        parse_address(f"{area}{last + 1}")


@pytest.mark.parametrize(("area", "words"), BIT_WORDS.items())
def test_a_bit_area_ends_with_the_last_bit_of_its_words(area: str, words: str) -> None:
    last = LAST_WORDS[words]
    address = parse_address(f"{area}{last}F")
    assert (address.word, address.bit) == (last, 15)
    with pytest.raises(AddressError, match="no word above"):
        parse_address(f"{area}{last + 1}0")
    assert type_problem(address, WireType.BOOL) is None


def test_registers_a_value_of_each_type_takes() -> None:
    """One for INT and UINT, two for DINT, UDINT and REAL, a STRING's first, a bit none."""
    assert {wire: wire.registers for wire in WireType} == {
        WireType.INT: 1,
        WireType.UINT: 1,
        WireType.DINT: 2,
        WireType.UDINT: 2,
        WireType.REAL: 2,
        WireType.STRING: 1,
        WireType.BOOL: 0,
    }


@pytest.mark.parametrize(("area", "last"), LAST_WORDS.items())
@pytest.mark.parametrize("wire", list(WireType))
def test_a_value_at_the_end_of_its_area(area: str, last: int, wire: WireType) -> None:
    if wire is WireType.BOOL:
        return  # a bit has its own area (above)
    at_last = type_problem(parse_address(f"{area}{last}"), wire)
    if wire in (WireType.DINT, WireType.UDINT, WireType.REAL):
        assert str(at_last) == (
            f"a {wire} at {area}{last} takes {area}{last} and {area}{last + 1}, "
            "past the area's end"
        )
        assert type_problem(parse_address(f"{area}{last - 1}"), wire) is None
    else:
        assert at_last is None
