"""Panasonic addresses: registers by word, bits by word and hex digit, types that fit."""

from hypothesis import given, strategies as st
import pytest

from custom_components.tecoapi.pyplc.core.models import DataType, ValueKind
from custom_components.tecoapi.pyplc.core.pointmap import TYPE_NAMES
from custom_components.tecoapi.pyplc.panasonic.address import (
    BIT_AREAS,
    MAX_WORD,
    Address,
    AddressError,
    Area,
    WireType,
    bit_start,
    parse_address,
    type_problem,
    wire_type,
)

REGISTER_AREAS = [area for area in Area if not area.bits]


@pytest.mark.parametrize(
    ("text", "area", "word", "bit"),
    [
        ("DT100", Area.DT, 100, None),
        ("LD5", Area.LD, 5, None),
        ("WR3", Area.WR, 3, None),
        ("FL0", Area.FL, 0, None),
        ("wx12", Area.WX, 12, None),
        (" WY7 ", Area.WY, 7, None),
        ("WL1", Area.WL, 1, None),
        ("R1A", Area.R, 1, 10),
        ("Y18", Area.Y, 1, 8),
        ("X0", Area.X, 0, 0),
        ("RF", Area.R, 0, 15),
        ("r10", Area.R, 1, 0),
        ("L100F", Area.L, 100, 15),
        ("R9010", Area.R, 901, 0),
    ],
)
def test_addresses_as_panasonic_writes_them(
    text: str, area: Area, word: int, bit: int | None
) -> None:
    address = parse_address(text)
    assert (address.area, address.word, address.bit) == (area, word, bit)


def test_a_bit_is_its_word_area_seen_bit_by_bit() -> None:
    assert parse_address("R1A").index == 26
    assert parse_address("Y18").index == 24
    assert parse_address("DT100").index == 100
    assert {area.words for area in BIT_AREAS} == {Area.WR, Area.WX, Area.WY, Area.WL}
    assert Area.DT.words is Area.DT
    # A request's start: a number for a register, text for a bit.
    assert parse_address("DT100").start == 100
    assert parse_address("R1A").start == "1A"
    assert parse_address("YF").start == "F"
    assert bit_start(24) == "18"


@pytest.mark.parametrize(
    "text",
    [
        "",
        "DT",
        "DT-1",
        "DX5",
        "D100",
        "R1G",
        "DT1000000",
        "FL32768",
        "WR10000",
        "X99999F",
        "R 1A",
        "DT1.5",
        "LD16384",
    ],
)
def test_what_is_no_address_says_why(text: str) -> None:
    with pytest.raises(AddressError):
        parse_address(text)


def test_the_highest_words_are_the_areas_ends() -> None:
    assert parse_address("DT999999").word == MAX_WORD[Area.DT]
    assert parse_address("R9999F").word == MAX_WORD[Area.WR]
    with pytest.raises(AddressError, match="no word above"):
        parse_address("WR10000")
    with pytest.raises(AddressError, match="no word above"):
        parse_address("R10000F")


@st.composite
def addresses(draw: st.DrawFn) -> Address:
    """Any address of any area: a register, or a bit of a bit area."""
    area = draw(st.sampled_from(list(Area)))
    word = draw(st.integers(0, MAX_WORD[area.words]))
    bit = draw(st.integers(0, 15)) if area.bits else None
    return Address(area, word, bit)


@given(addresses(), st.sampled_from([str.upper, str.lower, str.title]))
def test_every_address_round_trips_through_its_text(
    address: Address, case: object
) -> None:
    assert callable(case)
    text = str(address)
    assert parse_address(case(text)) == address
    # Written the way a request starts it, too.
    assert f"{address.area}{address.start}" == text


@given(st.sampled_from(list(BIT_AREAS)), st.integers(0, 9999), st.integers(0, 15))
def test_every_bit_index_is_word_times_sixteen_plus_bit(
    area: Area, word: int, bit: int
) -> None:
    address = parse_address(f"{area}{word}{bit:X}")
    assert address.index == word * 16 + bit
    assert parse_address(f"{area}{bit_start(address.index)}") == address


def test_the_gateway_types_of_the_maps_types() -> None:
    found = {name: wire_type(data_type) for name, data_type in TYPE_NAMES.items()}
    assert found["int"] is WireType.INT
    assert found["uint"] is found["word"] is WireType.UINT
    assert found["dint"] is WireType.DINT
    assert found["udint"] is found["dword"] is WireType.UDINT
    assert found["real"] is WireType.REAL
    assert found["string"] is WireType.STRING
    assert found["bool"] is WireType.BOOL
    assert {name for name, wire in found.items() if wire is None} == {
        "byte", "usint", "sint", "lword", "ulint", "lint", "lreal", "date", "time",
        "tod", "time_of_day", "dt", "date_and_time",
    }  # fmt: skip
    assert wire_type(DataType(kind=ValueKind.STRING, length=10)) is WireType.STRING


def test_a_type_fits_its_area() -> None:
    assert type_problem(parse_address("DT0"), WireType.INT) is None
    assert type_problem(parse_address("Y18"), WireType.BOOL) is None
    assert "BOOL" in str(type_problem(parse_address("R1A"), WireType.INT))
    assert "R100" in str(type_problem(parse_address("WR10"), WireType.BOOL))
    assert "reads INT" in str(type_problem(parse_address("DT0"), None))


@pytest.mark.parametrize("area", REGISTER_AREAS)
def test_a_double_word_takes_two_registers_within_the_area(area: Area) -> None:
    last = MAX_WORD[area]
    for wire in (WireType.DINT, WireType.UDINT, WireType.REAL):
        assert wire.registers == 2
        assert type_problem(Address(area, last - 1), wire) is None
        problem = type_problem(Address(area, last), wire)
        assert problem is not None
        assert f"{area}{last + 1}" in str(problem)
    assert type_problem(Address(area, last), WireType.INT) is None
    assert type_problem(Address(area, last), WireType.STRING) is None
