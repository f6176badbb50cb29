"""Values between the PLC's JSON and Python: kinds, typed values, wire text.

The manual's PLC prints REAL/LREAL with six decimals (``1000.000000``), real
devices also the short way (``29.0``), and integers without a point, so Python's
``json`` already tells them apart (float vs int) either way. Negative zero
(``-0.0``, ``-0.000000``, a REAL the PLC computed from a negative value) is read
as zero: it would show as ``-0.0`` in a state and in ranges.
TIME/TOD, DATE and DT travel as strings in the manual's formats; a string is
given the date/time kinds only when it matches those formats exactly.
"""

from datetime import UTC, date, datetime, time, timedelta
import math
import re
from typing import Any, Final

from .models import Record, ValueKind

_DATE: Final = re.compile(r"[0-9]{4}-[0-9]{2}-[0-9]{2}")
_TIME: Final = re.compile(r"([0-9]{2,}):([0-5][0-9]):([0-5][0-9])\.([0-9]{3})")
_DATETIME: Final = re.compile(
    r"[0-9]{4}-[0-9]{2}-[0-9]{2}T[0-9]{2}:[0-9]{2}:[0-9]{2}\.[0-9]{3}Z"
)

STRING_MAX_LENGTH: Final = 255
INTEGER_MIN: Final = -2147483648  # DINT
INTEGER_MAX: Final = 4294967295  # UDINT / DWORD


def infer_kind(raw: Any) -> ValueKind | None:
    """Return the kind of a JSON scalar, or None if it is not a PLC scalar."""
    if isinstance(raw, bool):
        return ValueKind.BOOL
    if isinstance(raw, int):
        return ValueKind.INTEGER
    if isinstance(raw, float):
        return ValueKind.REAL
    if isinstance(raw, str):
        if _parse_date(raw) is not None:
            return ValueKind.DATE
        if _parse_datetime(raw) is not None:
            return ValueKind.DATETIME
        if _TIME.fullmatch(raw):
            return ValueKind.TIME
        return ValueKind.STRING
    return None


def parse_value(kind: ValueKind, raw: Any) -> Any:
    """Return the typed value of a JSON scalar for a point of ``kind``.

    bool, int, float, str, ``date``, UTC ``datetime``, and a ``timedelta`` for a
    TIME or a DURATION (from its ``"hh:mm:ss.zzz"`` text, or a ``timedelta`` or
    ``time`` already). None when the JSON does not fit the kind.
    """
    match kind:
        case ValueKind.BOOL:
            return raw if isinstance(raw, bool) else None
        case ValueKind.INTEGER:
            return raw if isinstance(raw, int) and not isinstance(raw, bool) else None
        case ValueKind.REAL:
            if isinstance(raw, bool) or not isinstance(raw, int | float):
                return None
            return real(raw)
        case ValueKind.STRING:
            return raw if isinstance(raw, str) else None
        case ValueKind.DATE:
            if isinstance(raw, date) and not isinstance(raw, datetime):
                return raw
            return _parse_date(raw) if isinstance(raw, str) else None
        case ValueKind.DATETIME:
            if isinstance(raw, datetime):
                return raw if raw.tzinfo is not None else raw.replace(tzinfo=UTC)
            return _parse_datetime(raw) if isinstance(raw, str) else None
        case ValueKind.TIME | ValueKind.DURATION:
            return as_duration(raw)
        case ValueKind.RECORD:
            return raw if isinstance(raw, Record) else None


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


def real(raw: float) -> float:
    """Return a JSON number as a REAL, negative zero as zero."""
    return float(raw) + 0.0


def _parse_date(text: str) -> date | None:
    """Parse a DATE in the manual's ``YYYY-MM-DD`` form."""
    if not _DATE.fullmatch(text):
        return None
    try:
        return date.fromisoformat(text)
    except ValueError:
        return None


def _parse_datetime(text: str) -> datetime | None:
    """Parse a DT in the manual's ``YYYY-MM-DDThh:mm:ss.zzzZ`` form, as UTC."""
    if not _DATETIME.fullmatch(text):
        return None
    try:
        return datetime.fromisoformat(text[:-1]).replace(tzinfo=UTC)
    except ValueError:
        return None


def parse_timestamp(raw: Any) -> datetime | None:
    """Parse an ISO 8601 timestamp of GetInfo (``2018-01-18T16:39:38.000Z``)."""
    if not isinstance(raw, str) or not raw:
        return None
    try:
        parsed = datetime.fromisoformat(raw)
    except ValueError:
        return None
    return parsed if parsed.tzinfo is not None else parsed.replace(tzinfo=UTC)


def format_real(value: float) -> str:
    """Format a REAL as plain decimal text, never scientific: ``21.5``."""
    text = format(value, ".6f").rstrip("0")
    if text.endswith("."):
        text += "0"
    return "0.0" if text == "-0.0" else text


def format_date(value: date) -> str:
    """Format a DATE the manual's way: ``2015-06-17``."""
    return f"{value.year:04d}-{value.month:02d}-{value.day:02d}"


def format_datetime(value: datetime) -> str:
    """Format a DT the manual's way: ``2018-05-11T11:22:33.456Z`` (UTC if aware)."""
    if value.tzinfo is not None:
        value = value.astimezone(UTC)
    return (
        f"{format_date(value)}T{value.hour:02d}:{value.minute:02d}:"
        f"{value.second:02d}.{value.microsecond // 1000:03d}Z"
    )


def format_time(value: time | timedelta) -> str:
    """Format a TIME/TOD the manual's way: ``hh:mm:ss.zzz`` (hours may pass 24)."""
    if isinstance(value, timedelta):
        millis = round(value.total_seconds() * 1000)
        if millis < 0:
            raise ValueError("negative duration")
    else:
        millis = (
            (value.hour * 60 + value.minute) * 60 + value.second
        ) * 1000 + value.microsecond // 1000
    seconds, millis = divmod(millis, 1000)
    minutes, seconds = divmod(seconds, 60)
    hours, minutes = divmod(minutes, 60)
    return f"{hours:02d}:{minutes:02d}:{seconds:02d}.{millis:03d}"


def time_seconds(text: str) -> float | None:
    """Return the seconds a TIME in the manual's ``hh:mm:ss.zzz`` form spans."""
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
    """Whether text is a TIME/TOD in the manual's ``hh:mm:ss.zzz`` form."""
    return _TIME.fullmatch(text) is not None


def is_finite_number(value: Any) -> bool:
    """Whether value is an int or finite float (bool excluded)."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        return False
    return not isinstance(value, float) or math.isfinite(value)
