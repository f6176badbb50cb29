"""PLCComS values and lines at their edges, with the limits written out from the manual.

Teco's manual (TXV 138 63): the server listens on 5010, its error codes are those of
chapter 5, a TIME is a 32-bit unsigned count of milliseconds, a DATE/DT a double of
seconds since 1970 sent as its 8 bytes. Each test pins an edge an off-by-one or a
flipped test would move (scripts/mutate found them unpinned): the 2**53 where a DATE
integer becomes a double's bytes, a zero duration, the epoch itself, a line of exactly
its cap, a one-character quoted text.
"""

from datetime import UTC, date, datetime, time, timedelta
from typing import Any

import pytest

from custom_components.tecoapi.pyplc.core.exceptions import InvalidValueError
from custom_components.tecoapi.pyplc.core.models import ValueKind
from custom_components.tecoapi.pyplc.tecomat.plccoms.formatting import (
    format_value,
    plain_number,
)
from custom_components.tecoapi.pyplc.tecomat.plccoms.protocol import (
    DEFAULT_PORT,
    DOUBLE_BITS_FROM,
    MAX_LINE_LENGTH,
    MAX_TIME_MS,
    DateForm,
    ErrorCode,
    LineFramer,
    date_form,
    parse_server_error,
    parse_value,
    parse_variable,
)

EPOCH = datetime(1970, 1, 1, tzinfo=UTC)


def test_the_manual_s_port_and_error_codes() -> None:
    assert DEFAULT_PORT == 5010
    assert {code.name: int(code) for code in ErrorCode} == {
        "PLC_UNREACHABLE": 10,
        "TOO_MANY_CONNECTIONS": 11,
        "PLC_READ_FAILED": 20,
        "PLC_WRITE_FAILED": 21,
        "BAD_REQUEST": 30,
        "INCOMPLETE_REQUEST": 31,
        "UNKNOWN_COMMAND": 32,
        "UNKNOWN_VARIABLE": 33,
        "DISABLED_VARIABLE": 34,
        "WRONG_PARAMETER": 35,
    }
    error = parse_server_error("ERROR", "34 Variable is disabled: 'GET:x'")
    assert error.number == ErrorCode.DISABLED_VARIABLE


# --- the framer ----------------------------------------------------------------------------


def test_a_line_of_exactly_the_default_cap_is_kept_and_one_byte_more_is_not() -> None:
    framer = LineFramer()
    exact = b"x" * MAX_LINE_LENGTH
    assert MAX_LINE_LENGTH == 4096
    assert framer.feed(exact + b"\r\n" + exact + b"y\n") == [exact]
    assert framer.discarded == 1


def test_a_cap_of_one_byte_is_a_cap() -> None:
    framer = LineFramer(max_length=1)
    assert framer.feed(b"a\r\nbc\n") == [b"a"]
    assert framer.discarded == 1


def test_an_unfinished_line_is_held_up_to_its_cap_and_its_cr() -> None:
    """Held: the line's cap and the CR of its CRLF; one byte more and it is dropped."""
    framer = LineFramer(max_length=4)
    assert framer.feed(b"1234\r") == []
    assert framer.buffered == 5
    assert framer.feed(b"\n") == [b"1234"]
    assert framer.feed(b"1234\r") == []
    assert framer.feed(b"5") == []
    assert framer.buffered == 0
    assert framer.feed(b"\nok\n") == [b"ok"]
    assert framer.discarded == 1


# --- DATE and DT ---------------------------------------------------------------------------


def test_a_date_integer_from_2_53_is_a_double_s_bytes_and_below_it_seconds() -> None:
    assert DOUBLE_BITS_FROM == 2**53
    assert date_form(str(2**53)) is DateForm.DOUBLE_BITS
    assert date_form(str(2**53 - 1)) is DateForm.SECONDS
    # As a double's bytes 2**53 is a subnormal double: 1970 to the millisecond.
    assert parse_variable("DT", str(2**53)) == EPOCH
    # As seconds 2**53 - 1 is far beyond the year 9999.
    assert parse_variable("DT", str(2**53 - 1)) is None


def test_negative_zero_s_bytes_are_the_epoch() -> None:
    """2**63 is the bytes of -0.0: the first moment, not a negative one."""
    assert parse_variable("DT", str(2**63)) == EPOCH
    assert parse_variable("DATE", str(2**63)) == date(1970, 1, 1)


@pytest.mark.parametrize("text", ["0", "0.0", "0,0"])
def test_the_epoch_is_a_date(text: str) -> None:
    assert parse_variable("DT", text) == EPOCH
    assert parse_variable("DATE", text) == date(1970, 1, 1)


@pytest.mark.parametrize("text", ["-0.5", "-0.0001", "-1"])
def test_a_moment_before_the_epoch_is_none(text: str) -> None:
    assert parse_variable("DT", text) is None
    assert parse_variable("DATE", text) is None


def test_a_text_with_a_point_that_is_no_number_proves_no_date_form() -> None:
    assert date_form("2018-05-11T11:22:33.456Z") is None
    assert date_form("true") is None


@pytest.mark.parametrize("form", list(DateForm))
def test_the_epoch_is_written_and_a_millisecond_before_it_is_refused(
    form: DateForm,
) -> None:
    assert format_value(ValueKind.DATETIME, EPOCH, name="v", dates=form) == "0"
    assert format_value(ValueKind.DATE, date(1970, 1, 1), name="v", dates=form) == "0"
    before = EPOCH - timedelta(milliseconds=1)
    with pytest.raises(InvalidValueError):
        format_value(ValueKind.DATETIME, before, name="v", dates=form)


# --- TIME and TOD --------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("text", "value"),
    [
        ("0", timedelta(0)),
        ("0.0", timedelta(0)),
        ("0,4", timedelta(0)),
        ("0.5", timedelta(0)),  # rounded half to even
        ("4294967295.0", timedelta(milliseconds=MAX_TIME_MS)),
        ("4294967295.4", None),  # beyond 32 bits before it is rounded
        ("-0.4", None),
        ("4294967296.0", None),
    ],
)
def test_a_time_from_zero_to_32_bits(text: str, value: timedelta | None) -> None:
    assert parse_value(ValueKind.TIME, text) == value


@pytest.mark.parametrize(
    ("value", "text"),
    [
        (timedelta(0), "0"),
        (timedelta(milliseconds=MAX_TIME_MS), str(MAX_TIME_MS)),
        (0, "0"),
        (MAX_TIME_MS, str(MAX_TIME_MS)),
        (time(0, 0), "0"),
        (time(23, 59, 59, 999999), "86399999"),
        (time(0, 1, 2, 3000), "62003"),
    ],
)
def test_a_time_is_written_from_zero_to_32_bits(value: Any, text: str) -> None:
    assert format_value(ValueKind.TIME, value, name="v") == text


@pytest.mark.parametrize(
    "value",
    [
        timedelta(milliseconds=-1),
        timedelta(milliseconds=MAX_TIME_MS + 1),
        -1,
        MAX_TIME_MS + 1,
        True,
    ],
)
def test_a_time_beyond_32_bits_or_a_bool_is_refused(value: Any) -> None:
    with pytest.raises(InvalidValueError):
        format_value(ValueKind.TIME, value, name="v")


# --- quoted texts, booleans, plain numbers -----------------------------------------------


@pytest.mark.parametrize(
    ("text", "value"),
    [('""', ""), ('"', '"'), ('"a', '"a'), ('a"', 'a"'), ('"a"', "a")],
)
def test_only_a_text_in_two_quotes_is_unquoted(text: str, value: str) -> None:
    assert parse_value(ValueKind.STRING, text) == value
    assert parse_value(None, text) == value


def test_a_bool_is_written_of_true_false_0_and_1_only() -> None:
    assert format_value(ValueKind.BOOL, 1, name="v") == "1"
    assert format_value(ValueKind.BOOL, False, name="v") == "0"
    for value in (-1, 2, 1.0):
        with pytest.raises(InvalidValueError):
            format_value(ValueKind.BOOL, value, name="v")


def test_a_whole_number_is_written_exactly_below_2_63() -> None:
    """Below 2**63 every digit of a whole double; from it, the double's own digits."""
    below = 2.0**63 - 1024  # the largest double below 2**63
    assert plain_number(below) == "9223372036854774784"
    assert plain_number(-below) == "-9223372036854774784"
    assert plain_number(2.0**63) == "9223372036854776000"
