"""Tecomat values at their edges, with the limits written out from TECOAPI.md.

A plain variable (no T_ApiObject attributes) is only known by its JSON: an integer may
be any DINT to any UDINT (-2147483648 to 4294967295), a string at most 255 ASCII
characters. Negative zero, a zero duration, a date that is a date and time: each test
pins an edge an off-by-one or a flipped test would move (scripts/mutate found them).
"""

from datetime import UTC, date, datetime, time, timedelta, timezone
import math

import pytest

from custom_components.tecoapi.pyplc import InvalidValueError
from custom_components.tecoapi.pyplc.core.codec import check_value
from custom_components.tecoapi.pyplc.core.models import ValueKind
from custom_components.tecoapi.pyplc.tecomat.points import TECOMAT_TYPES
from custom_components.tecoapi.pyplc.tecomat.tecoapi.values import (
    format_time,
    parse_timestamp,
    parse_value,
    real,
)


@pytest.mark.parametrize("value", [-2147483648, 0, 2147483647, 4294967295])
def test_a_plain_integer_is_any_dint_or_udint(value: int) -> None:
    assert check_value(TECOMAT_TYPES[ValueKind.INTEGER], "x", value) == value


@pytest.mark.parametrize("value", [-2147483649, 4294967296])
def test_a_plain_integer_beyond_both_is_refused(value: int) -> None:
    with pytest.raises(InvalidValueError):
        check_value(TECOMAT_TYPES[ValueKind.INTEGER], "x", value)


def test_a_plain_string_is_at_most_255_characters() -> None:
    text = TECOMAT_TYPES[ValueKind.STRING]
    assert check_value(text, "x", "a" * 255) == "a" * 255
    with pytest.raises(InvalidValueError, match="longer than 255 characters"):
        check_value(text, "x", "a" * 256)


def test_a_date_is_a_date_and_a_date_and_time_is_no_date() -> None:
    day = date(2026, 11, 26)
    assert parse_value(ValueKind.DATE, day) == day
    assert parse_value(ValueKind.DATE, datetime(2026, 11, 26, tzinfo=UTC)) is None


def test_a_date_and_time_keeps_its_zone_and_a_naive_one_is_utc() -> None:
    prague = datetime(2026, 11, 26, 9, 30, tzinfo=timezone(timedelta(hours=1)))
    kept = parse_value(ValueKind.DATETIME, prague)
    assert kept == prague
    assert kept.utcoffset() == timedelta(hours=1)
    naive = datetime(2026, 11, 26, 9, 30)  # noqa: DTZ001 - a naive one on purpose
    assert parse_value(ValueKind.DATETIME, naive) == naive.replace(tzinfo=UTC)


@pytest.mark.parametrize("raw", [-0.0, -0])
def test_negative_zero_is_a_real_zero(raw: float) -> None:
    for value in (real(raw), parse_value(ValueKind.REAL, raw)):
        assert value == 0.0
        assert math.copysign(1.0, value) == 1.0


@pytest.mark.parametrize("raw", [5, None, "", ["2018-01-18T16:39:38.000Z"]])
def test_a_timestamp_that_is_no_text_is_none(raw: object) -> None:
    assert parse_timestamp(raw) is None


def test_a_duration_is_formatted_from_zero_and_a_negative_one_is_refused() -> None:
    assert format_time(timedelta(0)) == "00:00:00.000"
    assert format_time(timedelta(milliseconds=1)) == "00:00:00.001"
    for negative in (timedelta(milliseconds=-1), timedelta(milliseconds=-2)):
        with pytest.raises(ValueError, match="negative duration"):
            format_time(negative)


def test_a_time_of_day_is_formatted_to_the_millisecond() -> None:
    assert format_time(time(1, 2, 3, 456_789)) == "01:02:03.456"
    assert format_time(time(23, 59, 59, 999_999)) == "23:59:59.999"
