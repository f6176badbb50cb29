"""Scalars every system shares: plain reals, dates, times, durations, finite numbers.

Each test pins an edge an off-by-one or a flipped test would move (scripts/mutate
found them when these lived with the TecoApi values).
"""

from datetime import UTC, date, datetime, time, timedelta, timezone
import math

import pytest

from custom_components.tecoapi.pyplc.core.scalars import (
    as_date,
    as_datetime,
    as_duration,
    format_date,
    format_datetime,
    format_duration,
    format_real,
    is_finite_number,
    is_time_text,
    time_of_day,
    time_seconds,
)


@pytest.mark.parametrize(
    ("value", "text"),
    [
        (21.5, "21.5"),
        (1000.0, "1000.0"),
        (0.1, "0.1"),
        (-0.0, "0.0"),
        (-3.25, "-3.25"),
        (1e-7, "0.0"),
        (1.5e3, "1500.0"),
        (12345678.123456, "12345678.123456"),
    ],
)
def test_reals_are_never_scientific(value: float, text: str) -> None:
    formatted = format_real(value)
    assert formatted == text
    assert "e" not in formatted.lower()


@pytest.mark.parametrize("value", [3.4e38, -1.7e308, 1.5e-3, 123456.5, 2.0**60])
def test_huge_and_tiny_reals_round_trip_without_an_exponent(value: float) -> None:
    formatted = format_real(value)
    assert "e" not in formatted.lower()
    assert float(formatted) == pytest.approx(value, rel=1e-12, abs=1e-6)


def test_a_date_is_a_date_and_a_date_and_time_is_no_date() -> None:
    day = date(2026, 11, 26)
    assert as_date(day) == day
    assert as_date(datetime(2026, 11, 26, tzinfo=UTC)) is None


def test_a_date_and_time_keeps_its_zone_and_a_naive_one_is_utc() -> None:
    prague = datetime(2026, 11, 26, 9, 30, tzinfo=timezone(timedelta(hours=1)))
    kept = as_datetime(prague)
    assert kept == prague
    assert kept.utcoffset() == timedelta(hours=1)
    naive = datetime(2026, 11, 26, 9, 30)  # noqa: DTZ001 - a naive one on purpose
    assert as_datetime(naive) == naive.replace(tzinfo=UTC)


def test_the_seconds_a_time_text_spans() -> None:
    assert time_seconds("01:02:03.456") == pytest.approx(3723.456)
    assert time_seconds("00:00:00.001") == pytest.approx(0.001)
    assert time_seconds("1:02:03.456") is None


def test_a_time_of_day_is_from_midnight_up_to_the_last_microsecond() -> None:
    assert time_of_day(timedelta(0)) == time(0)
    last = timedelta(hours=23, minutes=59, seconds=59, microseconds=999_999)
    assert time_of_day(last) == time(23, 59, 59, 999_999)
    assert time_of_day(timedelta(hours=1, minutes=2, seconds=3)) == time(1, 2, 3)
    assert time_of_day(timedelta(days=1)) is None
    assert time_of_day(timedelta(microseconds=-1)) is None


@pytest.mark.parametrize(
    ("value", "finite"),
    [
        (0, True),
        (-1.5, True),
        (True, False),
        (math.inf, False),
        (math.nan, False),
        ("1", False),
    ],
)
def test_a_finite_number_is_an_int_or_a_finite_float(
    value: object, finite: bool
) -> None:
    assert is_finite_number(value) is finite


def test_time_text_is_the_hh_mm_ss_zzz_form_only() -> None:
    assert is_time_text("01:02:03.456")
    assert is_time_text("100:00:00.000")  # hours may pass 24
    assert not is_time_text("1:02:03.456")
    assert not is_time_text("01:02:03")


def test_dates_and_times_are_read_from_their_text_forms_only() -> None:
    assert as_date("2015-06-17") == date(2015, 6, 17)
    assert as_date("2015-13-45") is None
    assert as_date("2015-06-17 ") is None
    assert as_datetime("2018-05-11T11:22:33.456Z") == datetime(
        2018, 5, 11, 11, 22, 33, 456000, tzinfo=UTC
    )
    assert as_datetime("2018-05-11") is None
    assert as_datetime("2018-13-11T11:22:33.456Z") is None
    assert as_duration("120:02:03.450") == timedelta(
        hours=120, minutes=2, seconds=3, milliseconds=450
    )
    assert as_duration("1 hour") is None


def test_dates_are_written_the_library_s_way() -> None:
    """The manual's forms (seed 000, §4): ``YYYY-MM-DD``, and DT in UTC to the ms."""
    naive = datetime(2018, 5, 11, 11, 22, 33, 456789)  # noqa: DTZ001 - on purpose
    aware = datetime(
        2018, 5, 11, 13, 22, 33, 456000, tzinfo=timezone(timedelta(hours=2))
    )
    assert format_date(date(2015, 6, 17)) == "2015-06-17"
    assert format_date(date(987, 6, 5)) == "0987-06-05"
    assert format_datetime(naive) == "2018-05-11T11:22:33.456Z"
    assert format_datetime(aware) == "2018-05-11T11:22:33.456Z"


def test_durations_are_written_hh_mm_ss_zzz_hours_past_24() -> None:
    assert format_duration(timedelta(0)) == "00:00:00.000"
    assert format_duration(timedelta(milliseconds=2**31 - 1)) == "596:31:23.647"
    assert format_duration(timedelta(microseconds=1500)) == "00:00:00.002"
    assert format_duration(timedelta(hours=1, minutes=2, seconds=3.45)) == (
        "01:02:03.450"
    )
    with pytest.raises(ValueError, match="negative"):
        format_duration(timedelta(milliseconds=-1))
