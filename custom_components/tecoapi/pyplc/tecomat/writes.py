"""Write validation and the wire forms of written values.

A value is checked against its point before anything is sent (each refusal its
own exception), then given two spellings: the text of a SetObject query
(``21.5``, ``true``, ``"five"``) and the JSON literal of a PutObject body. Reals
never use scientific notation (the PLC's parser rejects ``1.5E3``); strings are
ASCII and at most 255 characters; SetObject strings travel in double quotes, the
manual's ``plcDesc="testing is funny"`` form, so text that itself starts and ends
with a quote survives; dates and times travel bare, as the PLC parses them.
"""

from collections.abc import Mapping
from dataclasses import dataclass
from datetime import date, datetime, time, timedelta
import json
from typing import Any

from ..core.exceptions import (
    InvalidValueError,
    NotAsciiError,
    OutOfRangeError,
    ReadOnlyError,
)
from ..core.models import Point, ValueKind
from ..core.values import (
    INTEGER_MAX,
    INTEGER_MIN,
    STRING_MAX_LENGTH,
    format_date,
    format_datetime,
    format_real,
    format_time,
    infer_kind,
    is_finite_number,
    is_time_text,
    parse_value,
)


@dataclass(frozen=True, slots=True)
class WireValue:
    """A validated value as a SetObject query text and as a PutObject JSON literal.

    ``query`` is None for structured values, which only PutObject can carry.
    """

    query: str | None
    json: str


def validate_write(point: Point, value: Any) -> WireValue:
    """Check ``value`` against ``point`` and return its wire forms.

    Refusals: :class:`ReadOnlyError` for read-only T_ApiObjects,
    :class:`OutOfRangeError` outside ``[minValue, maxValue]`` when the
    point has a range, :class:`InvalidValueError` for a value that does
    not fit the point's kind.
    """
    path = point.value_path
    if point.meta is not None and point.meta.read_only:
        raise ReadOnlyError(path, value)
    wire = _scalar(point.kind, path, value)
    if (
        point.meta is not None
        and point.meta.has_range
        and point.kind in (ValueKind.INTEGER, ValueKind.REAL)
    ):
        low, high = point.meta.min_value, point.meta.max_value
        if not low <= float(value) <= high:
            raise OutOfRangeError(path, value, low, high)
    return wire


def encode_json_value(path: str, value: Any) -> WireValue:
    """Wire forms of a JSON-shaped value written without a known point.

    Scalars are typed by what they are (bool, int, float, str); objects and
    lists become PutObject bodies only.
    """
    if isinstance(value, Mapping | list | tuple):
        return WireValue(None, _json_literal(path, value))
    kind = infer_kind(value)
    if kind is None:
        raise InvalidValueError(path, value, "not a value a PLC variable holds")
    return _scalar(kind, path, value)


def _scalar(kind: ValueKind, path: str, value: Any) -> WireValue:
    """Validate and spell one scalar of ``kind``."""
    match kind:
        case ValueKind.BOOL:
            if not isinstance(value, bool):
                raise InvalidValueError(path, value, "expected true or false")
            text = "true" if value else "false"
            return WireValue(text, text)
        case ValueKind.INTEGER:
            number = _integer(path, value)
            return WireValue(str(number), str(number))
        case ValueKind.REAL:
            if not is_finite_number(value):
                raise InvalidValueError(path, value, "expected a finite number")
            text = format_real(float(value))
            return WireValue(text, text)
        case ValueKind.STRING:
            return _quoted(_string(path, value))
        case ValueKind.DATE:
            return _bare(_date(path, value))
        case ValueKind.DATETIME:
            return _bare(_datetime(path, value))
        case ValueKind.TIME:
            return _bare(_time(path, value))


def _integer(path: str, value: Any) -> int:
    """Check an integer (an integral float is accepted) in the widest IEC range.

    Plain points do not say their IEC type, so only DINT..UDINT bounds apply.
    """
    if isinstance(value, float) and value.is_integer():
        value = int(value)
    if isinstance(value, bool) or not isinstance(value, int):
        raise InvalidValueError(path, value, "expected an integer")
    if not INTEGER_MIN <= value <= INTEGER_MAX:
        raise InvalidValueError(
            path, value, f"outside the PLC's integers {INTEGER_MIN}..{INTEGER_MAX}"
        )
    return value


def _string(path: str, value: Any) -> str:
    """Check a string: ASCII, at most 255 characters."""
    if not isinstance(value, str):
        raise InvalidValueError(path, value, "expected a string")
    if not value.isascii():
        raise NotAsciiError(path, value)
    if len(value) > STRING_MAX_LENGTH:
        raise InvalidValueError(
            path, value, f"longer than {STRING_MAX_LENGTH} characters"
        )
    return value


def _date(path: str, value: Any) -> str:
    """Spell a DATE from a ``date`` or its ``YYYY-MM-DD`` text."""
    if isinstance(value, date) and not isinstance(value, datetime):
        return format_date(value)
    if isinstance(value, str) and parse_value(ValueKind.DATE, value) is not None:
        return value
    raise InvalidValueError(path, value, "expected a date (YYYY-MM-DD)")


def _datetime(path: str, value: Any) -> str:
    """Spell a DT from a ``datetime`` (aware ones in UTC) or its text."""
    if isinstance(value, datetime):
        return format_datetime(value)
    if isinstance(value, str) and parse_value(ValueKind.DATETIME, value) is not None:
        return value
    raise InvalidValueError(
        path, value, "expected a date and time (YYYY-MM-DDThh:mm:ss.zzzZ)"
    )


def _time(path: str, value: Any) -> str:
    """Spell a TIME/TOD from a ``time``, a non-negative ``timedelta`` or text."""
    if isinstance(value, time) or (
        isinstance(value, timedelta) and value >= timedelta(0)
    ):
        return format_time(value)
    if isinstance(value, str) and is_time_text(value):
        return value
    raise InvalidValueError(path, value, "expected a time (hh:mm:ss.zzz)")


def _bare(text: str) -> WireValue:
    """Spell a date or time: bare in queries, a JSON string in bodies."""
    return WireValue(text, json.dumps(text))


def _quoted(text: str) -> WireValue:
    """Spell a string: in double quotes in queries, a JSON string in bodies."""
    return WireValue(f'"{text}"', json.dumps(text))


def _json_literal(path: str, value: Any) -> str:
    """Spell a value as PutObject JSON, reals without scientific notation."""
    if isinstance(value, Mapping):
        members = []
        for key, member in value.items():
            if not isinstance(key, str):
                raise InvalidValueError(path, value, "member names are text")
            members.append(
                f"{json.dumps(_string(path, key))}: "
                f"{_json_literal(f'{path}.{key}', member)}"
            )
        return "{" + ", ".join(members) + "}"
    if isinstance(value, list | tuple):
        items = (
            _json_literal(f"{path}[{index}]", item) for index, item in enumerate(value)
        )
        return "[" + ", ".join(items) + "]"
    return encode_json_value(path, value).json
