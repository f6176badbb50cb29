"""The web panel codec at its edges: the last tick, the last byte, the largest float32.

Each test pins a limit an off-by-one would move (scripts/mutate found them unpinned):
what is just inside is read or written, what is just outside is refused.
"""

from datetime import UTC, datetime, timedelta
import math
import struct

from hypothesis import example, given, strategies as st
import pytest

from custom_components.tecoapi.pyplc import InvalidValueError
from custom_components.tecoapi.pyplc.core.models import DataType, ValueKind
from custom_components.tecoapi.pyplc.mervis.codec import (
    EPOCH,
    FLOAT32_MAX,
    UndecodableError,
    decode,
    hex_value,
    plain_value,
)
from tests.pyplc.mervis.test_codec import typed

LAST_TICK = (datetime.max.replace(tzinfo=UTC) - EPOCH) // timedelta(
    microseconds=1
) * 10 + 9
"""The tick count of 9999-12-31 23:59:59.9999999, the last a ``dt`` can hold."""


def test_the_last_tick_of_9999_is_a_date_and_the_next_is_not() -> None:
    last = decode(typed("dt"), LAST_TICK.to_bytes(8, "big"))
    assert last == datetime.max.replace(tzinfo=UTC)
    for beyond in (LAST_TICK + 1, LAST_TICK + 10):
        with pytest.raises(UndecodableError, match="no date"):
            decode(typed("dt"), beyond.to_bytes(8, "big"))


@pytest.mark.parametrize("type_name", ["real", "lreal"])
def test_negative_zero_is_read_and_written_as_zero(type_name: str) -> None:
    length = 4 if type_name == "real" else 8
    read = decode(typed(type_name), b"\x80" + bytes(length - 1))
    assert math.copysign(1.0, read) == 1.0
    written = plain_value(typed(type_name), length, "x", -0.0)
    assert math.copysign(1.0, written) == 1.0
    assert hex_value(typed(type_name), length, "x", -0.0) == "00" * length


def test_the_largest_float32_is_written_and_the_next_double_is_not() -> None:
    assert plain_value(typed("real"), 4, "x", FLOAT32_MAX) == FLOAT32_MAX
    assert hex_value(typed("real"), 4, "x", -FLOAT32_MAX) == "FF7FFFFF"
    with pytest.raises(InvalidValueError, match="32-bit real"):
        plain_value(typed("real"), 4, "x", math.nextafter(FLOAT32_MAX, math.inf))
    # an 8-byte real holds it all
    assert plain_value(typed("lreal"), 8, "x", 1e39) == 1e39


def _same_float32(candidate: float, raw: bytes) -> bool:
    try:
        return struct.pack(">f", candidate) == raw
    except OverflowError:  # rounded beyond the largest float32
        return False


def _shortest(raw: bytes) -> float:
    """The decimal with the fewest significant digits that is the same float32."""
    value = struct.unpack(">f", raw)[0]
    return next(
        candidate
        for digits in range(1, 10)
        if _same_float32(candidate := float(f"{value:.{digits}g}"), raw)
    )


@given(st.integers(0x00800000, 0x7F7FFFFF), st.booleans())
@example(0x5D68BCF0, False)  # 1.04815894e+18 needs all nine digits
@example(0x3DCCCCCD, True)  # -0.1
def test_a_float32_reads_as_its_shortest_decimal(bits: int, sign: bool) -> None:
    raw = (bits | (0x80000000 if sign else 0)).to_bytes(4, "big")
    shown = decode(typed("real"), raw)
    assert shown == _shortest(raw)
    assert struct.pack(">f", shown) == raw


def test_a_subnormal_float32_shows_six_significant_digits() -> None:
    """Below 1.2e-38 a float32 has fewer bits: six digits show it, trailing zeros dropped.

    Fewer digits would name the same bits (1e-45 is 00000001 too); six is where the
    search for the shortest starts, a normal float32's decimal precision.
    """
    assert decode(typed("real"), bytes.fromhex("00000001")) == 1.4013e-45
    assert decode(typed("real"), bytes.fromhex("00000008")) == 1.12104e-44


def test_text_of_exactly_its_bytes_is_written_and_one_more_is_not() -> None:
    text = DataType(kind=ValueKind.STRING, length=4)
    assert plain_value(text, 4, "x", "abcd") == "abcd"
    assert hex_value(text, 4, "x", "žž") == "C5BEC5BE"  # two letters, four bytes
    with pytest.raises(InvalidValueError, match="4 bytes"):
        hex_value(text, 4, "x", "abcde")


def _duration_fits(length: int, micros: int) -> None:
    """Signed ticks of `length` bytes: -2**(8*length-1) up to 2**(8*length-1) - 1.

    A tick is 100 ns and a duration counts microseconds, so the ticks are a multiple
    of ten: the last microsecond that fits is the one whose ticks are below the half.
    """
    half = 1 << (8 * length - 1)
    value = timedelta(microseconds=micros)
    if -half <= micros * 10 < half:
        hexed = hex_value(typed("time"), length, "x", value)
        assert int.from_bytes(bytes.fromhex(hexed), "big", signed=True) == micros * 10
        assert decode(typed("time"), bytes.fromhex(hexed)) == value
        assert plain_value(typed("time"), length, "x", value) == micros * 10
    else:
        with pytest.raises(InvalidValueError, match=f"{length} bytes of ticks"):
            hex_value(typed("time"), length, "x", value)


LAST_4 = (2**31 - 1) // 10
LAST_8 = (2**63 - 1) // 10


@pytest.mark.parametrize(
    ("length", "micros", "hexed"),
    [
        (4, LAST_4, "7FFFFFF8"),
        (4, LAST_4 + 1, None),
        (4, -LAST_4, "80000008"),
        (4, -LAST_4 - 1, None),
        (4, -1, "FFFFFFF6"),
        (8, LAST_8, "7FFFFFFFFFFFFFF8"),
        (8, LAST_8 + 1, None),
        (8, -LAST_8, "8000000000000008"),
        (8, -LAST_8 - 1, None),
    ],
)
def test_a_duration_is_written_while_its_ticks_fit_its_bytes(
    length: int, micros: int, hexed: str | None
) -> None:
    value = timedelta(microseconds=micros)
    if hexed is None:
        with pytest.raises(InvalidValueError, match=f"{length} bytes of ticks"):
            hex_value(typed("time"), length, "x", value)
        with pytest.raises(InvalidValueError, match=f"{length} bytes of ticks"):
            plain_value(typed("time"), length, "x", value)
    else:
        assert hex_value(typed("time"), length, "x", value) == hexed
    _duration_fits(length, micros)


@given(st.sampled_from([4, 8]), st.integers(-2 * LAST_8, 2 * LAST_8))
def test_every_duration_is_written_exactly_or_refused(length: int, micros: int) -> None:
    _duration_fits(length, micros)
