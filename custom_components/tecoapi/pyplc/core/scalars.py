"""Typed scalar values every system shares: dates, times, durations, plain reals.

A value written to any point may be given as a Python value or as text in the
library's forms: a DATE as ``YYYY-MM-DD``, a DT as ``YYYY-MM-DDThh:mm:ss.zzzZ``
(UTC) and a TIME or a duration as ``hh:mm:ss.zzz`` (hours may pass 24). A
system's own wire form (Tecomat's TecoApi JSON, for one) reads and writes its
values with these and its own rules.
"""

from datetime import UTC, date, datetime, time, timedelta
import math
import re
from typing import Any, Final

_DATE: Final = re.compile(r"[0-9]{4}-[0-9]{2}-[0-9]{2}")
_TIME: Final = re.compile(r"([0-9]{2,}):([0-5][0-9]):([0-5][0-9])\.([0-9]{3})")
_DATETIME: Final = re.compile(
    r"[0-9]{4}-[0-9]{2}-[0-9]{2}T[0-9]{2}:[0-9]{2}:[0-9]{2}\.[0-9]{3}Z"
)


def as_date(raw: Any) -> date | None:
    """Return a DATE: a ``date`` (not a date and time) itself, or its text."""
    if isinstance(raw, date) and not isinstance(raw, datetime):
        return raw
    return _parse_date(raw) if isinstance(raw, str) else None


def as_datetime(raw: Any) -> datetime | None:
    """Return a DT: a ``datetime`` (a naive one as UTC), or its text as UTC."""
    if isinstance(raw, datetime):
        return raw if raw.tzinfo is not None else raw.replace(tzinfo=UTC)
    return _parse_datetime(raw) if isinstance(raw, str) else None


def as_duration(raw: Any) -> timedelta | None:
    """Return a TIME as a ``timedelta``: from its text, a ``time`` of day, or itself."""
    if isinstance(raw, timedelta):
        return raw
    if isinstance(raw, time):
        return timedelta(
            hours=raw.hour,
            minutes=raw.minute,
            seconds=raw.second,
            microseconds=raw.microsecond,
        )
    if isinstance(raw, str) and (match := _TIME.fullmatch(raw)):
        hours, minutes, seconds, millis = (int(part) for part in match.groups())
        return timedelta(
            hours=hours, minutes=minutes, seconds=seconds, milliseconds=millis
        )
    return None


def _parse_date(text: str) -> date | None:
    """Parse a DATE in the ``YYYY-MM-DD`` form."""
    if not _DATE.fullmatch(text):
        return None
    try:
        return date.fromisoformat(text)
    except ValueError:
        return None


def _parse_datetime(text: str) -> datetime | None:
    """Parse a DT in the ``YYYY-MM-DDThh:mm:ss.zzzZ`` form, as UTC."""
    if not _DATETIME.fullmatch(text):
        return None
    try:
        return datetime.fromisoformat(text[:-1]).replace(tzinfo=UTC)
    except ValueError:
        return None


def format_date(value: date) -> str:
    """Format a DATE the library's way: ``2015-06-17``."""
    return f"{value.year:04d}-{value.month:02d}-{value.day:02d}"


def format_datetime(value: datetime) -> str:
    """Format a DT the library's way: ``2018-05-11T11:22:33.456Z`` (UTC if aware)."""
    if value.tzinfo is not None:
        value = value.astimezone(UTC)
    return (
        f"{format_date(value)}T{value.hour:02d}:{value.minute:02d}:"
        f"{value.second:02d}.{value.microsecond // 1000:03d}Z"
    )


def format_duration(value: timedelta) -> str:
    """Format a TIME the library's way: ``hh:mm:ss.zzz``, hours past 24 if need be.

    To the millisecond; a negative duration raises ValueError.
    """
    millis = round(value.total_seconds() * 1000)
    if millis < 0:
        raise ValueError("negative duration")
    seconds, millis = divmod(millis, 1000)
    minutes, seconds = divmod(seconds, 60)
    hours, minutes = divmod(minutes, 60)
    return f"{hours:02d}:{minutes:02d}:{seconds:02d}.{millis:03d}"


def format_real(value: float) -> str:
    """Format a REAL as plain decimal text, never scientific: ``21.5``."""
    text = format(value, ".6f").rstrip("0")
    if text.endswith("."):
        text += "0"
    return "0.0" if text == "-0.0" else text


def time_seconds(text: str) -> float | None:
    """Return the seconds a TIME in the ``hh:mm:ss.zzz`` form spans."""
    match = _TIME.fullmatch(text)
    if match is None:
        return None
    hours, minutes, seconds, millis = (int(part) for part in match.groups())
    return ((hours * 60 + minutes) * 60 + seconds) + millis / 1000


def time_of_day(value: timedelta) -> time | None:
    """Return a TIME as a time of day (None for one past 24 h or negative)."""
    if not timedelta(0) <= value < timedelta(days=1):
        return None
    seconds, micros = divmod(round(value.total_seconds() * 1_000_000), 1_000_000)
    minutes, seconds = divmod(seconds, 60)
    hours, minutes = divmod(minutes, 60)
    return time(hours, minutes, seconds, micros)


def is_time_text(text: str) -> bool:
    """Whether text is a TIME/TOD in the ``hh:mm:ss.zzz`` form."""
    return _TIME.fullmatch(text) is not None


def is_finite_number(value: Any) -> bool:
    """Whether value is an int or finite float (bool excluded)."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        return False
    return not isinstance(value, float) or math.isfinite(value)
