"""Values of the web panel: big-endian bytes decoded exactly, writes checked to fit."""

from datetime import UTC, date, datetime, timedelta
import struct
from typing import Any

from hypothesis import given, strategies as st
import pytest

from custom_components.tecoapi.pyplc import InvalidValueError
from custom_components.tecoapi.pyplc.core.models import DataType, ValueKind
from custom_components.tecoapi.pyplc.core.pointmap import data_type
from custom_components.tecoapi.pyplc.mervis.codec import (
    EPOCH,
    UndecodableError,
    decode,
    hex_value,
    plain_value,
)
from tests.simulator.mervis.project import Row, encode

INTEGER_TYPES = ["sint", "usint", "int", "uint", "dint", "udint", "lint", "ulint"]


def typed(name: str) -> DataType:
    found = data_type(name)
    assert found is not None
    return found


@pytest.mark.parametrize(
    ("type_name", "hex_text", "value"),
    [
        ("bool", "00", False),
        ("bool", "01", True),
        ("sint", "80", -128),
        ("usint", "FF", 255),
        ("byte", "7F", 127),
        ("int", "ACA1", -21343),
        ("uint", "ACA1", 44193),
        ("word", "FFFF", 65535),
        ("dint", "80000000", -(2**31)),
        ("udint", "FFFFFFFF", 2**32 - 1),
        ("lint", "8000000000000000", -(2**63)),
        ("ulint", "FFFFFFFFFFFFFFFF", 2**64 - 1),
        ("lword", "0000000000000001", 1),
        ("real", "41AC0000", 21.5),
        ("real", "3DCCCCCD", 0.1),  # the float32 0.1: shown as 0.1, not 0.100000001
        ("lreal", "3FB999999999999A", 0.1),
        ("real", "80000000", 0.0),  # negative zero is zero
    ],
)
def test_numbers_decode_big_endian(type_name: str, hex_text: str, value: Any) -> None:
    decoded = decode(typed(type_name), bytes.fromhex(hex_text))
    assert decoded == value
    assert type(decoded) is type(value)


def test_a_float32_shows_the_shortest_decimal_of_the_same_bits() -> None:
    raw = struct.pack(">f", 22.3)
    shown = decode(typed("real"), raw)
    assert shown == 22.3
    assert struct.pack(">f", shown) == raw


def test_ticks_are_dates_and_durations() -> None:
    moment = datetime(2026, 3, 14, 10, 0, 0, 123456, tzinfo=UTC)
    ticks = (moment - EPOCH) // timedelta(microseconds=1) * 10 + 7
    assert decode(typed("dt"), ticks.to_bytes(8, "big")) == moment
    assert decode(typed("dt"), bytes(8)) == EPOCH
    assert decode(typed("date"), ticks.to_bytes(8, "big")) == date(2026, 3, 14)
    ninety = (90 * 10_000_000).to_bytes(8, "big", signed=True)
    assert decode(typed("time"), ninety) == timedelta(seconds=90)
    assert decode(typed("tod"), ninety) == timedelta(seconds=90)
    negative = (-15).to_bytes(8, "big", signed=True)
    assert decode(typed("time"), negative) == timedelta(microseconds=-1)
    assert decode(typed("time"), (10).to_bytes(4, "big")) == timedelta(microseconds=1)


def test_an_enum_is_a_32_bit_integer() -> None:
    assert (
        decode(DataType(kind=ValueKind.INTEGER, bits=32), bytes.fromhex("00000003"))
        == 3
    )


def test_text_ends_at_its_first_nul_in_utf8_or_windows_1250() -> None:
    text = DataType(kind=ValueKind.STRING, length=8)
    assert decode(text, "Kuchyň".encode() + b"\x00\x00") == "Kuchyň"
    assert decode(text, "Kuchyň".encode("cp1250") + b"\x00x") == "Kuchyň"


@pytest.mark.parametrize(
    ("type_name", "hex_text"),
    [
        ("bool", "0001"),
        ("int", "01"),
        ("real", "000000"),
        ("real", "7F800000"),  # infinity
        ("lreal", "7FF8000000000000"),  # NaN
        ("dt", "FFFFFFFFFFFFFFFF"),  # before the epoch
        ("dt", "7FFFFFFFFFFFFFFF"),  # after 9999
        ("dt", "00"),
        ("time", "000000"),
    ],
)
def test_bytes_that_are_no_value_of_the_type(type_name: str, hex_text: str) -> None:
    with pytest.raises(UndecodableError):
        decode(typed(type_name), bytes.fromhex(hex_text))


@pytest.mark.parametrize(
    ("type_name", "length", "value", "plain", "hexed"),
    [
        ("bool", 1, True, 1, "01"),
        ("bool", 1, False, 0, "00"),
        ("int", 2, -2, -2, "FFFE"),
        ("udint", 4, 4000000000, 4000000000, "EE6B2800"),
        ("real", 4, 21.5, 21.5, "41AC0000"),
        ("lreal", 8, 0.1, 0.1, "3FB999999999999A"),
        ("time", 8, timedelta(seconds=1), 10_000_000, "0000000000989680"),
        ("dt", 8, EPOCH + timedelta(microseconds=1), 10, "000000000000000A"),
        ("date", 8, date(1, 1, 2), 864_000_000_000, "000000C92A69C000"),
    ],
)
def test_writes_in_either_form(
    type_name: str, length: int, value: Any, plain: Any, hexed: str
) -> None:
    assert plain_value(typed(type_name), length, "x", value) == plain
    assert hex_value(typed(type_name), length, "x", value) == hexed


def test_text_is_written_within_its_bytes() -> None:
    text = DataType(kind=ValueKind.STRING, length=4)
    assert plain_value(text, 4, "x", "ab") == "ab"
    assert hex_value(text, 4, "x", "ab") == "61620000"
    with pytest.raises(InvalidValueError, match="4 bytes") as caught:
        plain_value(text, 4, "x", "žžž")
    assert caught.value.text().key == "write_too_many_bytes"
    assert caught.value.text().params == {"length": "4"}


@pytest.mark.parametrize(
    ("type_name", "length", "value", "reason", "key"),
    [
        ("real", 4, 1e39, "32-bit real", "write_real"),
        ("time", 4, timedelta(days=3), "4 bytes of ticks", "write_ticks"),
        ("time", 8, "soon", "not a", "write_not_of_kind"),
    ],
)
def test_what_does_not_fit_is_refused_before_sending(
    type_name: str, length: int, value: Any, reason: str, key: str
) -> None:
    """Refused with the reason in English and as a text a user reads translated."""
    with pytest.raises(InvalidValueError, match=reason) as caught:
        hex_value(typed(type_name), length, "x", value)
    assert caught.value.text().key == key
    with pytest.raises(InvalidValueError, match=reason) as caught:
        plain_value(typed(type_name), length, "x", value)
    assert caught.value.text().key == key


@given(
    st.sampled_from(INTEGER_TYPES).flatmap(
        lambda name: st.tuples(
            st.just(name),
            st.integers(*(typed(name).integer_bounds() or (0, 0))),
        )
    )
)
def test_integers_round_trip_through_the_simulator_s_encoding(
    case: tuple[str, int],
) -> None:
    """The simulator encodes from the seed on its own; the library reads it back."""
    name, value = case
    bits = typed(name).bits
    assert bits is not None
    row = Row("x", name, 1, 0, bits // 8)
    raw = encode(row, value)
    assert decode(typed(name), raw) == value
    assert hex_value(typed(name), bits // 8, "x", value) == raw.hex().upper()


@given(st.floats(width=32, allow_nan=False, allow_infinity=False))
def test_every_float32_round_trips(value: float) -> None:
    raw = encode(Row("x", "real", 1, 0, 4), value)
    shown = decode(typed("real"), raw)
    assert struct.pack(">f", shown) == raw or (shown == 0.0 and value == 0.0)


@given(
    st.datetimes(
        min_value=datetime(1, 1, 1),  # noqa: DTZ001 (hypothesis adds UTC)
        max_value=datetime(9999, 12, 31),  # noqa: DTZ001
        timezones=st.just(UTC),
    )
)
def test_every_date_and_time_round_trips(value: datetime) -> None:
    raw = encode(Row("x", "dt", 1, 0, 8), value)
    assert decode(typed("dt"), raw) == value
    assert hex_value(typed("dt"), 8, "x", value) == raw.hex().upper()
