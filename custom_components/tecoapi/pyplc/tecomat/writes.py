"""Write validation and the wire forms of written values, for TecoApi and PLCComS.

A value is checked against its point before anything is sent, by the core's
checks (:func:`~..core.codec.check_write`: read-only, range, the Tecomat data
type: ASCII text of at most 255 characters, integers within DINT..UDINT), then
given two spellings: the text of a SetObject query (``21.5``, ``true``,
``"five"``) and the JSON literal of a PutObject body. Reals never use
scientific notation (the PLC's parser rejects ``1.5E3``); SetObject strings
travel in double quotes, the manual's ``plcDesc="testing is funny"`` form, so
text that itself starts and ends with a quote survives; dates and times travel
bare, as the PLC parses them. PLCComS, which spells values its own way, takes
the checked value typed as the PLC then holds it (:func:`written_value`).
"""

from collections.abc import Mapping
from dataclasses import dataclass
from datetime import UTC, timedelta
import json
from typing import Any

from ..core.codec import A_RECORD, NOT_A_NAME, NOT_A_VALUE, check_value, check_write
from ..core.exceptions import InvalidValueError
from ..core.models import Point, PointAttributes, ValueKind
from ..core.scalars import format_date, format_datetime, format_real
from .points import TECOMAT_TYPES, value_path
from .tecoapi.values import format_time, infer_kind


@dataclass(frozen=True, slots=True)
class WireValue:
    """A validated value as a SetObject query text and as a PutObject JSON literal.

    ``query`` is None for structured values, which only PutObject can carry.
    """

    query: str | None
    json: str


def validate_write(
    point: Point, value: Any, attributes: PointAttributes | None = None
) -> WireValue:
    """Check ``value`` against ``point`` and return its wire forms.

    ``attributes`` are the point's latest (default: the catalogue's). Refusals:
    :class:`ReadOnlyError` for read-only T_ApiObjects, :class:`OutOfRangeError`
    outside ``[minValue, maxValue]`` when the point has a range,
    :class:`InvalidValueError` (:class:`NotAsciiError`) for a value that does not
    fit the point's kind; each names the value's path (``path.value`` for a
    T_ApiObject).
    """
    return _spelled(
        point.kind, check_write(point, value, attributes, value_path(point))
    )


def written_value(point: Point, value: Any) -> Any:
    """Check a value as :func:`validate_write` does; return it typed as the PLC holds it.

    What TecoApi's forms carry, without spelling them: a REAL to the six
    decimals it is written with, a DT in UTC and a TIME to the millisecond;
    every other kind as checked.
    """
    checked = check_write(point, value, None, value_path(point))
    match point.kind:
        case ValueKind.REAL:
            return float(format_real(checked))
        case ValueKind.DATETIME:
            moment = checked.astimezone(UTC)
            return moment.replace(microsecond=moment.microsecond // 1000 * 1000)
        case ValueKind.TIME | ValueKind.DURATION:
            return timedelta(milliseconds=round(checked.total_seconds() * 1000))
        case _:
            return checked


def encode_json_value(path: str, value: Any) -> WireValue:
    """Wire forms of a JSON-shaped value written without a known point.

    Scalars are typed by what they are (bool, int, float, str); objects and
    lists become PutObject bodies only.
    """
    if isinstance(value, Mapping | list | tuple):
        return WireValue(None, _json_literal(path, value))
    kind = infer_kind(value)
    if kind is None:
        raise InvalidValueError(path, value, NOT_A_VALUE())
    return _spelled(kind, check_value(TECOMAT_TYPES[kind], path, value))


def _spelled(kind: ValueKind, value: Any) -> WireValue:
    """Spell one checked scalar of ``kind``."""
    match kind:
        case ValueKind.BOOL:
            text = "true" if value else "false"
            return WireValue(text, text)
        case ValueKind.INTEGER:
            return WireValue(str(value), str(value))
        case ValueKind.REAL:
            text = format_real(float(value))
            return WireValue(text, text)
        case ValueKind.STRING:
            return _quoted(value)
        case ValueKind.DATE:
            return _bare(value if isinstance(value, str) else format_date(value))
        case ValueKind.DATETIME:
            return _bare(value if isinstance(value, str) else format_datetime(value))
        case ValueKind.TIME | ValueKind.DURATION:
            return _bare(value if isinstance(value, str) else format_time(value))
        case ValueKind.RECORD:  # pragma: no cover (refused by the checks above)
            raise InvalidValueError("", value, A_RECORD())


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
                raise InvalidValueError(path, value, NOT_A_NAME())
            members.append(
                f"{json.dumps(check_value(TECOMAT_TYPES[ValueKind.STRING], path, key))}: "
                f"{_json_literal(f'{path}.{key}', member)}"
            )
        return "{" + ", ".join(members) + "}"
    if isinstance(value, list | tuple):
        items = (
            _json_literal(f"{path}[{index}]", item) for index, item in enumerate(value)
        )
        return "[" + ", ".join(items) + "]"
    return encode_json_value(path, value).json
