"""Values of the web panel API: big-endian bytes to Python values and back.

Reads carry each variable's bytes as hex (the seed's *Encoding of values,
version 1*): integers and unsigned integers of 1, 2, 4 or 8 bytes, float32 and
double, a bool's byte (0 false, anything else true), enums as 32-bit integers,
``dt`` as 100-ns ticks since 0001-01-01 00:00 UTC (a ``date`` as the same ticks
at midnight, our reading), ``time`` as a count of 100-ns ticks (a ``tod`` the
same, from midnight). Text is our reading too: UTF-8 (else Windows-1250) up to
the first NUL byte.

A float32 is shown as the shortest decimal that is the same float32 (0.1, not
0.10000000149011612): exact, since it encodes back to the same bits. Ticks are
shown to the microsecond (Python's resolution; the last tenth is dropped).

Writes send a value as :func:`plain_value` (a JSON number or text, as the
seed's ``set: 5``) or as :func:`hex_value` (the bytes, as reads carry them);
both check what the core's codec does not: a float32's range, a duration's
ticks, text's bytes.
"""

from datetime import UTC, date, datetime, timedelta
import math
import struct
from typing import Any, Final

from ..core.codec import NOT_OF_KIND, OUTSIDE_REAL, TOO_MANY_BYTES, TOO_MANY_TICKS
from ..core.exceptions import InvalidValueError
from ..core.models import DataType, ValueKind

EPOCH: Final = datetime(1, 1, 1, tzinfo=UTC)
"""Where ``dt`` ticks count from."""
TICKS_PER_MICROSECOND: Final = 10
FLOAT32_MAX: Final = struct.unpack(">f", bytes.fromhex("7F7FFFFF"))[0]
_MAX_TICKS: Final = (datetime.max.replace(tzinfo=UTC) - EPOCH) // timedelta(
    microseconds=1
) * TICKS_PER_MICROSECOND + 9


class UndecodableError(ValueError):
    """Bytes that are no value of the type (wrong width, a date out of range)."""


def decode(data_type: DataType, raw: bytes) -> Any:
    """Return the value of a variable's bytes (see the module's docstring)."""
    match data_type.kind:
        case ValueKind.BOOL:
            _width(raw, 1)
            return raw != b"\x00"
        case ValueKind.INTEGER:
            if data_type.bits is not None:
                _width(raw, data_type.bits // 8)
            return int.from_bytes(raw, "big", signed=data_type.signed)
        case ValueKind.REAL:
            return _real(raw)
        case ValueKind.STRING:
            return _text(raw)
        case ValueKind.DATETIME:
            return _datetime(raw)
        case ValueKind.DATE:
            return _datetime(raw).date()
        case ValueKind.TIME | ValueKind.DURATION:
            return _duration(_ticks(raw, (4, 8)))


def _width(raw: bytes, *widths: int) -> None:
    if len(raw) not in widths:
        raise UndecodableError(f"{len(raw)} bytes, not {widths}")


def _real(raw: bytes) -> float:
    if len(raw) == 8:
        value: float = struct.unpack(">d", raw)[0]
    else:
        _width(raw, 4)
        value = struct.unpack(">f", raw)[0]
        if math.isfinite(value):
            value = _shortest_float32(value, raw)
    if not math.isfinite(value):
        raise UndecodableError(f"{raw.hex()} is not a finite number")
    return value + 0.0


def _shortest_float32(value: float, raw: bytes) -> float:
    """Return the shortest decimal that is the same float32."""
    for digits in range(6, 10):
        candidate = float(f"{value:.{digits}g}")
        if struct.pack(">f", candidate) == raw:
            return candidate
    return value  # pragma: no cover (9 significant digits always round-trip)


def _text(raw: bytes) -> str:
    raw = raw.split(b"\x00", 1)[0]
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError:
        return raw.decode("cp1250", errors="replace")


def _ticks(raw: bytes, widths: tuple[int, ...] = (8,)) -> int:
    _width(raw, *widths)
    return int.from_bytes(raw, "big", signed=True)


def _datetime(raw: bytes) -> datetime:
    ticks = _ticks(raw)
    if not 0 <= ticks <= _MAX_TICKS:
        raise UndecodableError(f"{ticks} ticks are no date")
    return EPOCH + timedelta(microseconds=ticks // TICKS_PER_MICROSECOND)


def _duration(ticks: int) -> timedelta:
    micros = abs(ticks) // TICKS_PER_MICROSECOND
    return timedelta(microseconds=micros if ticks >= 0 else -micros)


# --- writes ------------------------------------------------------------------------


def plain_value(data_type: DataType, length: int, path: str, value: Any) -> Any:
    """Return a checked value as JSON: a number (bool 1 or 0, ticks) or text."""
    match data_type.kind:
        case ValueKind.BOOL:
            return 1 if value else 0
        case ValueKind.INTEGER:
            return int(value)
        case ValueKind.REAL:
            return _checked_real(data_type, length, path, value)
        case ValueKind.STRING:
            _text_bytes(length, path, value)
            return str(value)
        case _:
            return _checked_ticks(data_type, length, path, value)


def hex_value(data_type: DataType, length: int, path: str, value: Any) -> str:
    """Return a checked value as the hex of its big-endian bytes."""
    raw: bytes
    match data_type.kind:
        case ValueKind.BOOL:
            raw = b"\x01" if value else b"\x00"
        case ValueKind.INTEGER:
            raw = int(value).to_bytes(length, "big", signed=data_type.signed)
        case ValueKind.REAL:
            number = _checked_real(data_type, length, path, value)
            raw = struct.pack(">d" if length == 8 else ">f", number)
        case ValueKind.STRING:
            raw = _text_bytes(length, path, value).ljust(length, b"\x00")
        case _:
            ticks = _checked_ticks(data_type, length, path, value)
            raw = ticks.to_bytes(length, "big", signed=True)
    return raw.hex().upper()


def _checked_real(data_type: DataType, length: int, path: str, value: Any) -> float:
    number = float(value)
    if length == 4 and abs(number) > FLOAT32_MAX:
        raise InvalidValueError(path, value, OUTSIDE_REAL())
    return number + 0.0


def _text_bytes(length: int, path: str, value: Any) -> bytes:
    encoded = str(value).encode("utf-8")
    if len(encoded) > length:
        raise InvalidValueError(path, value, TOO_MANY_BYTES(length=length))
    return encoded


def _checked_ticks(data_type: DataType, length: int, path: str, value: Any) -> int:
    """Return the ticks of a date, a date and time or a duration, checked to fit."""
    if isinstance(value, datetime):
        ticks = (value.astimezone(UTC) - EPOCH) // timedelta(microseconds=1)
    elif isinstance(value, date):
        ticks = (datetime.combine(value, datetime.min.time(), UTC) - EPOCH) // (
            timedelta(microseconds=1)
        )
    elif isinstance(value, timedelta):
        ticks = value // timedelta(microseconds=1)
    else:
        raise InvalidValueError(path, value, NOT_OF_KIND(kind=data_type.kind.value))
    ticks *= TICKS_PER_MICROSECOND
    half = 1 << (8 * length - 1)
    if not -half <= ticks < half:
        raise InvalidValueError(path, value, TOO_MANY_TICKS(length=length))
    return ticks
