"""IEC 61131-3 data types of a Tecomat PLC program and the values they accept.

Values are held JSON-shaped: BOOL as `bool`, the integer types as `int`, REAL/LREAL as
`float` (so they print with six decimals), STRING and the date/time types as `str` in
the manual's chapter 4 formats, arrays as lists (a multi-dimensional array nests) and
structs as dicts keyed by the PLC's spelling of the member names.
"""

from dataclasses import dataclass, field
import datetime as dt
import math
import re
from typing import Any, Final

INTEGER_RANGES: Final[dict[str, tuple[int, int]]] = {
    "BYTE": (0, 0xFF),
    "WORD": (0, 0xFFFF),
    "DWORD": (0, 0xFFFF_FFFF),
    "SINT": (-128, 127),
    "INT": (-32768, 32767),
    "DINT": (-2147483648, 2147483647),
    "USINT": (0, 0xFF),
    "UINT": (0, 0xFFFF),
    "UDINT": (0, 0xFFFF_FFFF),
}
REAL_LIMITS: Final[dict[str, float]] = {
    "REAL": 3.4028234663852886e38,
    "LREAL": 1.7976931348623157e308,
}
TIME_TYPES: Final = frozenset({"TIME", "TOD", "DATE", "DT"})
ELEMENTARY_NAMES: Final = frozenset(
    {"BOOL", "STRING", *INTEGER_RANGES, *REAL_LIMITS, *TIME_TYPES}
)
# Mosaic's length of a STRING declared without one.
DEFAULT_STRING_LENGTH: Final = 80
MAX_STRING_LENGTH: Final = 255
# TIME holds milliseconds in a DINT: at most 24d 20:31:23.647.
MAX_TIME_MS: Final = 2147483647
EPOCH: Final = dt.date(1970, 1, 1)

_INTEGER_TEXT: Final = re.compile(r"[+-]?[0-9]+")
_REAL_TEXT: Final = re.compile(r"[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)")
_CLOCK_TEXT: Final = re.compile(
    r"([0-9]{2,3}):([0-5][0-9]):([0-5][0-9])(?:\.([0-9]{1,3}))?"
)
_DATE_TEXT: Final = re.compile(r"([0-9]{4})-([0-9]{2})-([0-9]{2})")
_DT_TEXT: Final = re.compile(
    r"([0-9]{4}-[0-9]{2}-[0-9]{2})T([0-9]{2}:[0-9]{2}:[0-9]{2}(?:\.[0-9]{1,3})?)Z?"
)


# Declared ahead of the classes it names: `type` aliases are evaluated lazily.
type IecType = Elementary | ArrayOf | Struct


class RejectedValueError(ValueError):
    """A value does not fit a variable's type or range (the PLC answers 400.015)."""


@dataclass(frozen=True, slots=True)
class Elementary:
    """BOOL, the integers, REAL/LREAL, TIME, TOD, DATE, DT or STRING[length]."""

    name: str
    length: int | None = None

    @property
    def type_name(self) -> str:
        """The declaration as a PLC error message names it (`USINT`, `STRING[10]`)."""
        if self.name == "STRING" and self.length != DEFAULT_STRING_LENGTH:
            return f"STRING[{self.length}]"
        return self.name


@dataclass(frozen=True, slots=True)
class ArrayOf:
    """A zero-based array; a multi-dimensional one is an array of arrays."""

    size: int
    element: IecType
    type_name: str


@dataclass(frozen=True, slots=True)
class Struct:
    """A STRUCT type, or the variables of a program instance."""

    type_name: str
    members: dict[str, IecType]
    _by_lower: dict[str, str] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        """Index the members case-insensitively."""
        object.__setattr__(self, "_by_lower", {m.lower(): m for m in self.members})

    def member(self, name: str) -> str | None:
        """The PLC's spelling of a member, looked up case-insensitively."""
        return self._by_lower.get(name.lower())


def default_value(iec_type: IecType) -> Any:
    """The value a variable holds when its declaration gives none."""
    if isinstance(iec_type, Struct):
        return {name: default_value(t) for name, t in iec_type.members.items()}
    if isinstance(iec_type, ArrayOf):
        return [default_value(iec_type.element) for _ in range(iec_type.size)]
    return {
        "BOOL": False,
        "STRING": "",
        "REAL": 0.0,
        "LREAL": 0.0,
        "TIME": "00:00:00.000",
        "TOD": "00:00:00.000",
        "DATE": EPOCH.isoformat(),
        "DT": "1970-01-01T00:00:00.000Z",
    }.get(iec_type.name, 0)


def leaf_count(iec_type: IecType) -> int:
    """How many items a value of this type counts toward the response limit."""
    if isinstance(iec_type, Struct):
        return sum(leaf_count(t) for t in iec_type.members.values())
    if isinstance(iec_type, ArrayOf):
        return iec_type.size * leaf_count(iec_type.element)
    return 1


def _format_clock(milliseconds: int) -> str:
    """`hh:mm:ss.zzz` (hours may exceed 24 for TIME)."""
    seconds, ms = divmod(milliseconds, 1000)
    minutes, seconds = divmod(seconds, 60)
    hours, minutes = divmod(minutes, 60)
    return f"{hours:02d}:{minutes:02d}:{seconds:02d}.{ms:03d}"


def _parse_clock(text: str, limit_ms: int) -> str:
    """A TIME or TOD text normalised to `hh:mm:ss.zzz`, within `limit_ms`."""
    match = _CLOCK_TEXT.fullmatch(text)
    if match is None:
        raise RejectedValueError(text)
    hours, minutes, seconds, fraction = match.groups()
    milliseconds = (int(hours) * 3600 + int(minutes) * 60 + int(seconds)) * 1000 + int(
        (fraction or "0").ljust(3, "0")
    )
    if milliseconds > limit_ms:
        raise RejectedValueError(text)
    return _format_clock(milliseconds)


def _parse_date(text: str) -> dt.date:
    """A `YYYY-MM-DD` date from 1970 on."""
    if _DATE_TEXT.fullmatch(text) is None:
        raise RejectedValueError(text)
    try:
        date = dt.date.fromisoformat(text)
    except ValueError as err:
        raise RejectedValueError(text) from err
    if date < EPOCH:
        raise RejectedValueError(text)
    return date


def _time_value(name: str, text: str) -> str:
    """A TIME/TOD/DATE/DT text checked and normalised to the manual's format."""
    if name == "TIME":
        return _parse_clock(text, MAX_TIME_MS)
    if name == "TOD":
        return _parse_clock(text, 24 * 3600 * 1000 - 1)
    if name == "DATE":
        return _parse_date(text).isoformat()
    match = _DT_TEXT.fullmatch(text)
    if match is None:
        raise RejectedValueError(text)
    date = _parse_date(match.group(1))
    clock = _parse_clock(match.group(2), 24 * 3600 * 1000 - 1)
    return f"{date.isoformat()}T{clock}Z"


def _string_value(iec_type: Elementary, text: str) -> str:
    """A STRING value: ASCII and no longer than declared."""
    if not text.isascii() or len(text) > (iec_type.length or 0):
        raise RejectedValueError(text)
    return text


def _integer_value(name: str, number: int) -> int:
    """An integer within its type's range."""
    low, high = INTEGER_RANGES[name]
    if not low <= number <= high:
        raise RejectedValueError(str(number))
    return number


def _real_value(name: str, number: float) -> float:
    """A finite REAL/LREAL within its type's range."""
    if not math.isfinite(number) or abs(number) > REAL_LIMITS[name]:
        raise RejectedValueError(str(number))
    return float(number)


def from_query_text(iec_type: Elementary, text: str) -> Any:
    """The value SetObject writes for `name=text` (text already percent-decoded).

    BOOL takes `true`/`false` (any case) and `1`/`0`; integers and reals take plain
    decimal notation; a STRING may be given bare (`five`) or in double quotes
    (`"testing is funny"`) as the manual shows.
    """
    name = iec_type.name
    if name == "BOOL":
        lowered = text.lower()
        if lowered in {"true", "1"}:
            return True
        if lowered in {"false", "0"}:
            return False
        raise RejectedValueError(text)
    if name in INTEGER_RANGES:
        if _INTEGER_TEXT.fullmatch(text) is None:
            raise RejectedValueError(text)
        return _integer_value(name, int(text))
    if name in REAL_LIMITS:
        if _REAL_TEXT.fullmatch(text) is None:
            raise RejectedValueError(text)
        return _real_value(name, float(text))
    if name == "STRING":
        if len(text) >= 2 and text[0] == text[-1] == '"':
            text = text[1:-1]
        return _string_value(iec_type, text)
    return _time_value(name, text)


def from_json(iec_type: Elementary, value: object) -> Any:
    """The value PutObject writes for a JSON scalar (numbers as parsed, never strings)."""
    name = iec_type.name
    if name == "BOOL":
        if isinstance(value, bool):
            return value
        if type(value) is int and value in {0, 1}:
            return bool(value)
        raise RejectedValueError(str(value))
    if name in INTEGER_RANGES:
        if type(value) is not int:
            raise RejectedValueError(str(value))
        return _integer_value(name, value)
    if name in REAL_LIMITS:
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise RejectedValueError(str(value))
        return _real_value(name, float(value))
    if not isinstance(value, str):
        raise RejectedValueError(str(value))
    if name == "STRING":
        return _string_value(iec_type, value)
    return _time_value(name, value)


def from_program(iec_type: Elementary, value: object) -> Any:
    """An initial value from a program file; also takes `16#FF`-style integers."""
    if iec_type.name in INTEGER_RANGES and isinstance(value, str):
        radix_text = re.fullmatch(r"(2|8|16)#([0-9A-Fa-f_]+)", value)
        if radix_text is None:
            raise RejectedValueError(value)
        value = int(radix_text.group(2).replace("_", ""), int(radix_text.group(1)))
    if iec_type.name in TIME_TYPES and isinstance(value, dt.datetime):
        # YAML reads an unquoted timestamp as a datetime.
        value = (
            value.strftime("%Y-%m-%dT%H:%M:%S.") + f"{value.microsecond // 1000:03d}Z"
        )
    elif iec_type.name in TIME_TYPES and isinstance(value, dt.date):
        value = value.isoformat()
    if iec_type.name == "STRING" and not isinstance(value, str):
        raise RejectedValueError(str(value))
    return from_json(iec_type, value)
