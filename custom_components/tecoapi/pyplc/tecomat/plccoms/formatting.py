"""PLCComS on the wire, the other way: the text ``SET:`` sends for a value.

:func:`format_value` writes a value for a variable of a kind, in the form its
server reads (:class:`~.protocol.DateForm` for DATE and DT);
:func:`plain_number` a number in plain decimal. Nothing here does I/O; reading
values is :mod:`.protocol`'s.
"""

from datetime import UTC, date, datetime, time, timedelta
from decimal import Decimal
import math
import struct
from typing import Any, Final

from ...core.codec import NOT_A_SCALAR, NOT_OF_KIND
from ...core.exceptions import InvalidValueError, NotEncodableError
from ...core.models import ValueKind
from ...core.texts import Template
from .protocol import (
    CLOCK,
    ENCODING,
    EPOCH,
    MAX_TIME_MS,
    DateForm,
    parse_milliseconds,
)

QUOTE_OR_LINE_BREAK: Final = Template(
    "write_quote", "a quote or line break cannot be sent"
)
"""Why a text is refused: PLCComS's lines carry a string between quotes."""


def plain_number(value: float) -> str:
    """Format a number in plain decimal, never scientific: ``0.0000001``, ``21.5``."""
    if float(value).is_integer() and abs(value) < 2**63:
        return str(int(value))
    return format(Decimal(repr(float(value))), "f")


def format_value(
    kind: ValueKind | None,
    value: Any,
    *,
    name: str,
    dates: DateForm = DateForm.DOUBLE_BITS,
) -> str:
    """Return the ``SET:`` text of a value for a variable of ``kind``.

    BOOL ``1``/``0``; integers and reals in plain decimal with a decimal point;
    strings in double quotes (Windows-1250, no quote or line break inside);
    TIME/TOD milliseconds (32 bits); DATE and DT seconds since 1970 UTC (to the
    millisecond) in the form ``dates`` (the server's).
    Raises InvalidValueError for a value that does not fit the kind.
    """
    match kind:
        case ValueKind.BOOL:
            if isinstance(value, bool) or (type(value) is int and value in {0, 1}):
                return "1" if value else "0"
        case ValueKind.INTEGER:
            if isinstance(value, int) and not isinstance(value, bool):
                return str(value)
            if isinstance(value, float) and value.is_integer():
                return str(int(value))
        case ValueKind.REAL:
            if _is_finite_number(value):
                return plain_number(float(value))
        case ValueKind.STRING:
            if isinstance(value, str):
                return _quoted(name, value)
        case ValueKind.TIME:
            millis = _time_milliseconds(value)
            if millis is not None:
                return str(millis)
        case ValueKind.DATE | ValueKind.DATETIME:
            seconds = _seconds_of(kind, value)
            if seconds is not None:
                return _moment_text(seconds, dates)
        case None:
            return _format_untyped(name, value)
    raise InvalidValueError(name, value, NOT_OF_KIND(kind=kind))


def _moment_text(seconds: float, form: DateForm) -> str:
    """Seconds since 1970 as a DATE/DT value in a server's form."""
    match form:
        case DateForm.DOUBLE_BITS:
            return str(int.from_bytes(struct.pack("<d", seconds), "little"))
        case DateForm.DECIMAL:
            return plain_number(seconds)
        case DateForm.SECONDS:
            return str(math.floor(seconds))


def _format_untyped(name: str, value: Any) -> str:
    """Format a value for a variable of unknown type, by its Python type."""
    if isinstance(value, bool):
        return "1" if value else "0"
    if isinstance(value, int):
        return str(value)
    if _is_finite_number(value):
        return plain_number(float(value))
    if isinstance(value, str):
        return _quoted(name, value)
    raise InvalidValueError(name, value, NOT_A_SCALAR())


def _is_finite_number(value: Any) -> bool:
    if isinstance(value, bool) or not isinstance(value, int | float):
        return False
    return math.isfinite(value)


def _quoted(name: str, text: str) -> str:
    """Quote a string, if one line of Windows-1250 can carry it."""
    if any(char in text for char in '"\r\n'):
        raise InvalidValueError(name, text, QUOTE_OR_LINE_BREAK())
    try:
        text.encode(ENCODING)
    except UnicodeEncodeError as err:
        raise NotEncodableError(name, text, "Windows-1250") from err
    return f'"{text}"'


def _time_milliseconds(value: Any) -> int | None:
    """Milliseconds of a TIME/TOD given as timedelta, time, ``hh:mm:ss.zzz`` or int."""
    if isinstance(value, timedelta):
        millis = round(value.total_seconds() * 1000)
        return millis if 0 <= millis <= MAX_TIME_MS else None
    if isinstance(value, time):
        return (
            (value.hour * 60 + value.minute) * 60 + value.second
        ) * 1000 + value.microsecond // 1000
    if isinstance(value, int) and not isinstance(value, bool):
        return value if 0 <= value <= MAX_TIME_MS else None
    if isinstance(value, str) and (match := CLOCK.fullmatch(value)):
        return parse_milliseconds(match.group(0))
    return None


def _seconds_of(kind: ValueKind, value: Any) -> float | None:
    """Seconds since 1970 (whole milliseconds) of a DATE's date or a DT's datetime.

    None for a value of the other type, or before 1970.
    """
    is_moment = isinstance(value, datetime)
    if not isinstance(value, date) or is_moment != (kind is ValueKind.DATETIME):
        return None
    millis = round((_to_datetime(value) - EPOCH).total_seconds() * 1000)
    return millis / 1000 if millis >= 0 else None


def _to_datetime(value: date) -> datetime:
    """Return a date (midnight) or datetime as aware UTC; naive means UTC."""
    if not isinstance(value, datetime):
        return datetime(value.year, value.month, value.day, tzinfo=UTC)
    if value.tzinfo is None:
        return value.replace(tzinfo=UTC)
    return value.astimezone(UTC)
