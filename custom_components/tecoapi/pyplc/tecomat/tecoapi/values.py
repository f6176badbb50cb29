"""TecoApi's JSON wire form: kinds, typed values and wire text of Tecomat values.

The manual's PLC prints REAL/LREAL with six decimals (``1000.000000``), real
devices also the short way (``29.0``), and integers without a point, so Python's
``json`` already tells them apart (float vs int) either way. Negative zero
(``-0.0``, ``-0.000000``, a REAL the PLC computed from a negative value) is read
as zero: it would show as ``-0.0`` in a state and in ranges.
TIME/TOD, DATE and DT travel as strings in the manual's formats; a string is
given the date/time kinds only when it matches those formats exactly (the same
forms :mod:`...core.scalars` reads for every system).
"""

from collections.abc import Callable, Mapping
from datetime import UTC, datetime, time, timedelta
from typing import Any, Final

from ...core.models import Record, ValueKind
from ...core.scalars import (
    as_date,
    as_datetime,
    as_duration,
    format_duration,
    is_time_text,
)

STRING_MAX_LENGTH: Final = 255
INTEGER_MIN: Final = -2147483648  # DINT
INTEGER_MAX: Final = 4294967295  # UDINT / DWORD
# The manual's table of types (chapter 4): DATE and DT from 1.1.1970 00:00:00.0,
# TIME and TOD <0, 24d 20:31:23.647>: 2**31 - 1 ms, never negative (neither the
# manual's "hh:mm:ss.zzz" nor PLCComS's unsigned milliseconds can say a sign).
EARLIEST: Final = datetime(1970, 1, 1, tzinfo=UTC)
TIME_LONGEST: Final = timedelta(milliseconds=2**31 - 1)


def infer_kind(raw: Any) -> ValueKind | None:
    """Return the kind of a JSON scalar, or None if it is not a PLC scalar."""
    if isinstance(raw, bool):
        return ValueKind.BOOL
    if isinstance(raw, int):
        return ValueKind.INTEGER
    if isinstance(raw, float):
        return ValueKind.REAL
    if isinstance(raw, str):
        if as_date(raw) is not None:
            return ValueKind.DATE
        if as_datetime(raw) is not None:
            return ValueKind.DATETIME
        if is_time_text(raw):
            return ValueKind.TIME
        return ValueKind.STRING
    return None


def parse_value(kind: ValueKind, raw: Any) -> Any:
    """Return the typed value of a JSON scalar for a point of ``kind``.

    bool, int, float, str, ``date``, UTC ``datetime``, and a ``timedelta`` for a
    TIME or a DURATION (from its ``"hh:mm:ss.zzz"`` text, or a ``timedelta`` or
    ``time`` already). None when the JSON does not fit the kind.
    """
    return value_parser(kind)(raw)


def value_parser(kind: ValueKind) -> Callable[[Any], Any]:
    """Return what reads a JSON scalar of ``kind`` (:func:`parse_value`, chosen once)."""
    return _PARSERS.get(kind, _nothing)


TEXT_KINDS: Final = frozenset(
    {ValueKind.DATE, ValueKind.DATETIME, ValueKind.TIME, ValueKind.DURATION}
)
"""Kinds read from a text by its format (costlier to parse than a number)."""


class RememberedParser:
    """Reads one point's values of a text kind, parsing a text again only if it changed.

    A poll reads the same text again and again (a date, a duration); its
    typed value is kept with it.
    """

    __slots__ = ("_parse", "_raw", "_value")

    def __init__(self, kind: ValueKind) -> None:
        """Read values of ``kind``; nothing read yet."""
        self._parse = value_parser(kind)
        self._raw: Any = _NOT_READ
        self._value: Any = None

    def __call__(self, raw: Any) -> Any:
        """Return the typed value of ``raw`` (:func:`parse_value`)."""
        if raw == self._raw and type(raw) is type(self._raw):
            return self._value
        self._value = value = self._parse(raw)
        self._raw = raw
        return value


_NOT_READ: Final = object()


def _bool(raw: Any) -> Any:
    return raw if isinstance(raw, bool) else None


def _integer(raw: Any) -> Any:
    if type(raw) is int:  # the common case, at once
        return raw
    return raw if isinstance(raw, int) and not isinstance(raw, bool) else None


def _real(raw: Any) -> Any:
    if type(raw) is float:  # the common case, at once
        return raw + 0.0
    if isinstance(raw, bool) or not isinstance(raw, int | float):
        return None
    return real(raw)


def _string(raw: Any) -> Any:
    return raw if isinstance(raw, str) else None


def _record(raw: Any) -> Any:
    return raw if isinstance(raw, Record) else None


def _nothing(raw: Any) -> None:
    return None


_PARSERS: Final[Mapping[ValueKind, Callable[[Any], Any]]] = {
    ValueKind.BOOL: _bool,
    ValueKind.INTEGER: _integer,
    ValueKind.REAL: _real,
    ValueKind.STRING: _string,
    ValueKind.DATE: as_date,
    ValueKind.DATETIME: as_datetime,
    ValueKind.TIME: as_duration,
    ValueKind.DURATION: as_duration,
    ValueKind.RECORD: _record,
}


def real(raw: float) -> float:
    """Return a JSON number as a REAL, negative zero as zero."""
    return float(raw) + 0.0


def parse_timestamp(raw: Any) -> datetime | None:
    """Parse an ISO 8601 timestamp of GetInfo (``2018-01-18T16:39:38.000Z``)."""
    if not isinstance(raw, str) or not raw:
        return None
    try:
        parsed = datetime.fromisoformat(raw)
    except ValueError:
        return None
    return parsed if parsed.tzinfo is not None else parsed.replace(tzinfo=UTC)


def format_time(value: time | timedelta) -> str:
    """Format a TIME/TOD the manual's way: ``hh:mm:ss.zzz`` (hours may pass 24)."""
    if isinstance(value, timedelta):
        return format_duration(value)
    return format_duration(
        timedelta(
            hours=value.hour,
            minutes=value.minute,
            seconds=value.second,
            milliseconds=value.microsecond // 1000,
        )
    )
