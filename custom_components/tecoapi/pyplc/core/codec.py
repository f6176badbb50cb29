"""Values between what a device holds and what is shown: write checks, scale, offset.

Every source checks a write the same way before anything is sent, by the point's
:class:`~.models.DataType` and its latest :class:`~.models.PointAttributes`:

- a point the source says is read-only is refused (:class:`ReadOnlyError`),
  and so is one the user made read only (a point's override: its writability
  and range are the user's where given, :mod:`.overrides`);
- a value must fit the kind: a flag for BOOL, an integer (an integral float is
  taken) within the type's bounds for INTEGER, a finite number for REAL, text
  for STRING that the type's encoding can carry (:class:`NotAsciiError` for an
  ASCII-only type, :class:`NotEncodableError` for another) and no longer than
  its length, a date, a date and time, a time or a duration for those kinds
  (:class:`InvalidValueError` otherwise), within what the type holds: no date
  before its earliest (:class:`DateTooEarlyError`), no duration negative or
  longer than its longest (:class:`DurationOutOfRangeError`);
- a number must lie in the attributes' range, when they give one
  (:class:`OutOfRangeError`).

What is shown is ``raw * scale + offset``; :func:`to_raw` turns a shown value
back into the raw one (rounded for an integer register, whose bounds are then
checked again) and :func:`to_shown` the raw one into what is shown.
"""

from datetime import UTC, datetime, time, timedelta
import math
from typing import Any, Final

from .exceptions import (
    DateTooEarlyError,
    DurationOutOfRangeError,
    InvalidValueError,
    NotAsciiError,
    NotEncodableError,
    OutOfRangeError,
    ReadOnlyError,
)
from .models import NUMERIC_KINDS, DataType, Point, PointAttributes, ValueKind
from .scalars import (
    as_date,
    as_datetime,
    as_duration,
    format_date,
    format_datetime,
    format_duration,
    is_finite_number,
    is_time_text,
)
from .texts import Template

# Why a value does not fit a point (a write's reasons).
EXPECTED_FLAG: Final = Template("write_flag", "expected true or false")
EXPECTED_NUMBER: Final = Template("write_number", "expected a finite number")
EXPECTED_DATE: Final = Template("write_date", "expected a date (YYYY-MM-DD)")
EXPECTED_DATETIME: Final = Template(
    "write_datetime", "expected a date and time (YYYY-MM-DDThh:mm:ss.zzzZ)"
)
EXPECTED_TIME: Final = Template("write_time", "expected a time (hh:mm:ss.zzz)")
A_RECORD: Final = Template("write_record", "a record is read, never written")
EXPECTED_INTEGER: Final = Template("write_integer", "expected an integer")
OUTSIDE_INTEGERS: Final = Template(
    "write_integers", "outside the type's integers {low}..{high}"
)
EXPECTED_TEXT: Final = Template("write_text", "expected a string")
TOO_LONG: Final = Template("write_too_long", "longer than {length} characters")
OUTSIDE_REGISTER: Final = Template("write_register", "outside the register")
NOT_A_VALUE: Final = Template("write_not_a_value", "not a value a variable holds")
NOT_OF_KIND: Final = Template("write_not_of_kind", "not a {kind} value")
NOT_A_SCALAR: Final = Template("write_not_a_scalar", "not a bool, number or text")
NOT_A_PATH: Final = Template("write_not_a_path", "not a variable path")
NOT_A_NAME: Final = Template("write_member_name", "member names are text")
OUTSIDE_REAL: Final = Template("write_real", "outside the range of a 32-bit real")
TOO_MANY_BYTES: Final = Template(
    "write_too_many_bytes", "longer than the variable's {length} bytes"
)
TOO_MANY_TICKS: Final = Template(
    "write_ticks", "more than the variable's {length} bytes of ticks hold"
)


def check_write(
    point: Point,
    value: Any,
    attributes: PointAttributes | None = None,
    name: str | None = None,
) -> Any:
    """Check a value written to ``point`` as shown; return it as its kind takes it.

    ``attributes`` are the point's latest (default: the catalogue's); ``name``
    is what a refusal names (default: the point's path). An integral float
    written to an integer becomes an int; text for a date or a time in the
    forms :mod:`.scalars` reads is kept as text.
    """
    path = point.path if name is None else name
    if not point.takes_writes(attributes):
        raise ReadOnlyError(path, value)
    checked = check_value(_shown_type(point), path, value)
    low, high = point.range_of(attributes)
    if (
        point.kind in NUMERIC_KINDS
        and low is not None
        and high is not None
        and not low <= float(checked) <= high
    ):
        raise OutOfRangeError(path, value, low, high)
    return checked


def check_value(data_type: DataType, path: str, value: Any) -> Any:
    """Check a value against a data type alone; return it as the kind takes it."""
    match data_type.kind:
        case ValueKind.BOOL:
            if not isinstance(value, bool):
                raise InvalidValueError(path, value, EXPECTED_FLAG())
            return value
        case ValueKind.INTEGER:
            return _integer(data_type, path, value)
        case ValueKind.REAL:
            if not is_finite_number(value):
                raise InvalidValueError(path, value, EXPECTED_NUMBER())
            return float(value)
        case ValueKind.STRING:
            return _text(data_type, path, value)
        case ValueKind.DATE:
            if (day := as_date(value)) is None:
                raise InvalidValueError(path, value, EXPECTED_DATE())
            earliest = data_type.earliest
            if earliest is not None and day < _utc(earliest).date():
                raise DateTooEarlyError(path, value, format_date(earliest))
            return day
        case ValueKind.DATETIME:
            if (moment := as_datetime(value)) is None:
                raise InvalidValueError(path, value, EXPECTED_DATETIME())
            earliest = data_type.earliest
            # What is sent is whole milliseconds, so is what is compared.
            if earliest is not None and _to_millisecond(moment) < _utc(earliest):
                raise DateTooEarlyError(path, value, format_datetime(earliest))
            return moment
        case ValueKind.TIME | ValueKind.DURATION:
            return _duration(data_type, path, value)
        case ValueKind.RECORD:
            raise InvalidValueError(path, value, A_RECORD())


def _duration(data_type: DataType, path: str, value: Any) -> timedelta:
    """Check a time or a duration: its form, then the type's range, to the millisecond.

    A time of day is taken for a TIME only. A negative duration (a timedelta, or
    the text with a minus, ``-00:00:01.000``) is refused: as out of the type's
    range where it names its longest, as no time otherwise.
    """
    longest = data_type.longest
    minus = isinstance(value, str) and value.startswith("-")
    given = value[1:] if minus else value
    duration = (
        as_duration(given)
        if isinstance(given, timedelta)
        or (isinstance(given, time) and data_type.kind is ValueKind.TIME)
        or (isinstance(given, str) and is_time_text(given))
        else None
    )
    if duration is None or (longest is None and (minus or duration < timedelta(0))):
        raise InvalidValueError(path, value, EXPECTED_TIME())
    if minus:
        duration = -duration
    if longest is not None and not (
        0 <= _milliseconds(duration) <= _milliseconds(longest)
    ):
        raise DurationOutOfRangeError(path, value, format_duration(longest))
    return duration


def _milliseconds(duration: timedelta) -> int:
    """Return the whole milliseconds a duration is written as."""
    return round(duration / timedelta(milliseconds=1))


def _utc(moment: datetime) -> datetime:
    """Return a moment in UTC (a naive one is UTC already)."""
    if moment.tzinfo is None:
        return moment.replace(tzinfo=UTC)
    return moment.astimezone(UTC)


def _to_millisecond(moment: datetime) -> datetime:
    """Return a moment without what is below its millisecond (as it is written)."""
    return moment.replace(microsecond=moment.microsecond // 1000 * 1000)


def _integer(data_type: DataType, path: str, value: Any) -> int:
    """Check an integer (an integral float is taken) within the type's bounds."""
    if isinstance(value, float) and value.is_integer():
        value = int(value)
    if isinstance(value, bool) or not isinstance(value, int):
        raise InvalidValueError(path, value, EXPECTED_INTEGER())
    bounds = data_type.integer_bounds()
    if bounds is not None and not bounds[0] <= value <= bounds[1]:
        raise InvalidValueError(
            path, value, OUTSIDE_INTEGERS(low=bounds[0], high=bounds[1])
        )
    return value


def _text(data_type: DataType, path: str, value: Any) -> str:
    """Check text: the type's encoding can carry it, and it is not too long."""
    if not isinstance(value, str):
        raise InvalidValueError(path, value, EXPECTED_TEXT())
    encoding = data_type.encoding
    if encoding is not None:
        try:
            value.encode(encoding)
        except UnicodeEncodeError:
            if encoding.lower() in ("ascii", "us-ascii"):
                raise NotAsciiError(path, value) from None
            raise NotEncodableError(path, value, encoding) from None
    if data_type.length is not None and len(value) > data_type.length:
        raise InvalidValueError(path, value, TOO_LONG(length=data_type.length))
    return value


def _shown_type(point: Point) -> DataType:
    """Return the type of what is shown: the raw one, a scaled register's unbounded.

    (The raw value's bounds are checked when it is made, :func:`to_raw`.)
    """
    if not point.scaled or point.type.kind is not ValueKind.INTEGER:
        return point.type
    return DataType(kind=point.kind)


def _integral(point: Point) -> bool:
    """Whether a scaled integer stays integral: its scale and offset are whole."""
    return float(point.scale).is_integer() and float(point.offset).is_integer()


SHOWN_DIGITS: Final = 15
"""Significant digits of a scaled value: what a float holds exactly (no ``…0004``)."""


def to_shown(point: Point, raw: Any) -> Any:
    """Return what is shown of a raw value: ``raw * scale + offset`` for numbers.

    A float's rounding error is left out: 498 tenths show 49.8, not
    49.800000000000004.
    """
    if not point.scaled or not is_finite_number(raw):
        return raw
    shown = raw * point.scale + point.offset
    if point.type.kind is ValueKind.INTEGER and _integral(point):
        return int(shown)
    return float(f"{shown:.{SHOWN_DIGITS}g}") + 0.0


def shown_bounds(point: Point) -> tuple[float, float] | None:
    """Return the lowest and highest value shown of the point's type (None: unbounded).

    An integer's bounds through its scale and offset: an INT in tenths shows
    -3276.8..3276.7 (a negative scale swaps the ends).
    """
    bounds = point.type.integer_bounds()
    if bounds is None:
        return None
    low, high = (to_shown(point, bound) for bound in bounds)
    return (low, high) if low <= high else (high, low)


def to_raw(point: Point, shown: Any) -> Any:
    """Return the raw value of a shown one (checked again against the raw type)."""
    if not point.scaled or not is_finite_number(shown):
        return shown
    raw = (shown - point.offset) / point.scale
    if point.type.kind is ValueKind.INTEGER:
        if not math.isfinite(raw):
            raise InvalidValueError(point.path, shown, OUTSIDE_REGISTER())
        return _integer(point.type, point.path, round(raw))
    return float(raw)
