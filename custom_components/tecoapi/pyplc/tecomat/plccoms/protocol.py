r"""PLCComS on the wire: lines, the types ``LIST:`` names, and the values read.

Nothing here does I/O; :mod:`.client` (the client) uses it, and so can tests.
The facts are Teco's manual (*Komunikační server PLCComS*, TXV 138 63) and the
server's changelog; where they leave a detail open, the reading here says so.

Lines are Windows-1250 text ended by ``\n`` or ``\r\n``; a line is
``COMMAND:rest`` with the command in any case. Values are read leniently, since
servers differ in their settings:

- BOOL: ``0``/``1``/``true``/``false`` (any case).
- Integers: decimal, with an optional sign (an integral real such as ``5.0`` too).
- REAL/LREAL: plain decimal, with a decimal point or a decimal comma, or in
  scientific notation (``2.15e+01``, ``2,15E1``, ``2.15 e+001``).
- STRING: in double quotes (a bare text is taken as it is).
- TIME/TOD: a 32-bit unsigned integer of milliseconds (the manual, section
  4.2.3; a TOD below a day), also ``hh:mm:ss[.zzz]`` and IEC literals
  (``T#1h2m3s450ms``, ``TOD#12:30:00``), each within those 32 bits; returned
  as a ``timedelta``.
- DATE and DT (the manual, section 4.2.3): an IEEE double of seconds since
  1970-01-01 UTC (its fraction the milliseconds), sent by default
  (``DATE_TIME_DECIMAL = No``) as the 64-bit unsigned integer its 8 bytes make,
  or (``Yes``) as that double in decimal. The two cannot be confused: the
  integer of any moment after 1970-01-01T00:00:00 is at least 2**53, a plain
  count of seconds far below (and ``0`` is that moment in every form). A plain count of seconds (what servers were assumed to send
  before) is read too, and ISO text (``2018-05-11``,
  ``2018-05-11T11:22:33.456Z``) and IEC literals (``D#2018-05-11``,
  ``DT#2018-05-11-11:22:33``); returned as ``date`` and UTC ``datetime``. A
  moment outside 1970-01-01 .. 9999-12-31 is no date: it reads as None.

A value that does not fit its variable's type reads as None; reading a value
never raises. :class:`DateForm`
names the three ways a DATE or DT is written, :func:`date_form` tells which one
a server's text proves (``0`` proves none), :func:`learn_date_form` what a
client knows of its server's form after a value. Writing a value is
:mod:`.formatting`'s.
"""

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from datetime import UTC, date, datetime, timedelta
from enum import IntEnum, StrEnum
import math
import re
import struct
from types import MappingProxyType
from typing import Any, Final

from ...core.models import ValueKind

ENCODING: Final = "cp1250"
DEFAULT_PORT: Final = 5010
PLC_RUN: Final = "__PLC_RUN"
# Longest line kept, in bytes without its line end: far above any name and value
# (names are at most a few hundred characters, strings 255).
MAX_LINE_LENGTH: Final = 4096
# Flags LIST: prints after a name or after its type: * disabled, ~ hidden.
NAME_FLAGS: Final = "*~"
DISABLED_FLAG: Final = "*"
HIDDEN_FLAG: Final = "~"
# TIME is a 32-bit unsigned count of milliseconds, TOD one below a day.
MAX_TIME_MS: Final = 2**32 - 1
MAX_TOD_MS: Final = 24 * 3600 * 1000 - 1
# A DT/DATE integer at least this big is a double's 8 bytes, never a count of
# seconds (the double of 1970-01-01 00:00:00.001 is already above it).
DOUBLE_BITS_FROM: Final = 2**53


class ErrorCode(IntEnum):
    """The codes of ``ERROR:`` lines (the manual, chapter 5) a client acts on."""

    PLC_UNREACHABLE = 10
    TOO_MANY_CONNECTIONS = 11
    PLC_READ_FAILED = 20
    PLC_WRITE_FAILED = 21
    BAD_REQUEST = 30
    INCOMPLETE_REQUEST = 31
    UNKNOWN_COMMAND = 32
    UNKNOWN_VARIABLE = 33
    DISABLED_VARIABLE = 34
    WRONG_PARAMETER = 35


PLC_COMMUNICATION_CODES: Final = frozenset(
    {ErrorCode.PLC_UNREACHABLE, ErrorCode.PLC_READ_FAILED, ErrorCode.PLC_WRITE_FAILED}
)
"""The codes saying that the server cannot talk to its PLC (it answers itself)."""


class DateForm(StrEnum):
    """How a server writes DATE and DT (its ``DATE_TIME_DECIMAL`` setting).

    ``DOUBLE_BITS``: the double's 8 bytes as an unsigned integer (``No``, the
    default); ``DECIMAL``: the double in decimal (``Yes``); ``SECONDS``: a plain
    integer count of seconds, what this project assumed before the manual.
    """

    DOUBLE_BITS = "double_bits"
    DECIMAL = "decimal"
    SECONDS = "seconds"


_INTEGER_TYPES: Final = frozenset(
    {
        "BYTE",
        "WORD",
        "DWORD",
        "LWORD",
        "SINT",
        "INT",
        "DINT",
        "LINT",
        "USINT",
        "UINT",
        "UDINT",
        "ULINT",
    }
)
_KINDS: Final[dict[str, ValueKind]] = {
    "BOOL": ValueKind.BOOL,
    "REAL": ValueKind.REAL,
    "LREAL": ValueKind.REAL,
    "TIME": ValueKind.TIME,
    "TOD": ValueKind.TIME,
    "TIME_OF_DAY": ValueKind.TIME,
    "DATE": ValueKind.DATE,
    "DT": ValueKind.DATETIME,
    "DATE_AND_TIME": ValueKind.DATETIME,
    **dict.fromkeys(_INTEGER_TYPES, ValueKind.INTEGER),
}
_STRING_TYPE: Final = re.compile(
    r"W?STRING\s*(?:[\[(]\s*[0-9]+\s*[\])])?", re.IGNORECASE
)
_INTEGER: Final = re.compile(r"[+-]?[0-9]+")
_UNSIGNED: Final = re.compile(r"[0-9]+")
_TOD_TYPES: Final = frozenset({"TOD", "TIME_OF_DAY"})
_NUMBER: Final = re.compile(
    r"([+-]?(?:[0-9]+(?:[.,][0-9]*)?|[.,][0-9]+))(?:\s*[eE]\s*([+-]?[0-9]+))?"
)
CLOCK: Final = re.compile(r"([0-9]+):([0-5]?[0-9]):([0-5]?[0-9])(?:[.,]([0-9]{1,3}))?")
_DURATION: Final = re.compile(r"(?:T|TIME)#(-?)(.+)", re.IGNORECASE)
_DURATION_PART: Final = re.compile(
    r"([0-9]+(?:\.[0-9]+)?)(ms|d|h|m|s)_?", re.IGNORECASE
)
_TOD_LITERAL: Final = re.compile(r"(?:TOD|TIME_OF_DAY)#(.+)", re.IGNORECASE)
_DATE_TEXT: Final = re.compile(
    r"(?:D#|DATE#)?([0-9]{4}-[0-9]{2}-[0-9]{2})", re.IGNORECASE
)
_DT_TEXT: Final = re.compile(
    r"(?:DT#|DATE_AND_TIME#)?([0-9]{4}-[0-9]{2}-[0-9]{2})[T -]"
    r"([0-9]{2}):([0-9]{2}):([0-9]{2})(?:[.,]([0-9]{1,6}))?Z?",
    re.IGNORECASE,
)
_TRUE: Final = frozenset({"1", "true"})
_FALSE: Final = frozenset({"0", "false"})
EPOCH: Final = datetime(1970, 1, 1, tzinfo=UTC)
# The last moment a datetime holds, in seconds since 1970.
_LAST_SECOND: Final = (datetime.max.replace(tzinfo=UTC) - EPOCH).total_seconds()
_LAST_MS: Final = (datetime.max.replace(tzinfo=UTC) - EPOCH) // timedelta(
    milliseconds=1
)
_MS_PER_UNIT: Final = {"d": 86_400_000, "h": 3_600_000, "m": 60_000, "s": 1000, "ms": 1}


def kind_of_type(type_name: str) -> ValueKind | None:
    """Return the library's kind of a PLCComS type (``REAL``, ``STRING[32]``...), or None."""
    text = type_name.strip()
    if _STRING_TYPE.fullmatch(text):
        return ValueKind.STRING
    return _KINDS.get(text.upper())


class LineFramer:
    """Cuts a byte stream into lines and never holds more than one line's cap.

    A line longer than ``max_length`` bytes (its line end not counted) is thrown
    away as it streams in -- its bytes are not kept -- and counted in
    ``discarded``; reading resumes after its line end.
    """

    def __init__(self, max_length: int = MAX_LINE_LENGTH) -> None:
        """Start with nothing buffered."""
        if max_length < 1:
            raise ValueError("max_length must be at least 1")
        self.max_length = max_length
        self.discarded = 0
        self._buffer = bytearray()
        self._discarding = False

    @property
    def buffered(self) -> int:
        """Bytes of an unfinished line held now (at most ``max_length`` + 1)."""
        return len(self._buffer)

    def feed(self, data: bytes) -> list[bytes]:
        """Return the complete lines ``data`` finishes, without their line ends."""
        lines: list[bytes] = []
        # One more than the cap: the CR of a CRLF line end arrives before its LF.
        cap = self.max_length + 1
        start = 0
        while (end := data.find(b"\n", start)) >= 0:
            piece = data[start:end]
            if self._discarding:
                self._discarding = False
            elif len(self._buffer) + len(piece) > cap:
                self.discarded += 1
            else:
                self._buffer += piece
                line = bytes(self._buffer)
                if line.endswith(b"\r"):
                    line = line[:-1]
                if len(line) > self.max_length:
                    self.discarded += 1
                else:
                    lines.append(line)
            self._buffer.clear()
            start = end + 1
        rest = data[start:]
        if not self._discarding and rest:
            if len(self._buffer) + len(rest) > cap:
                self.discarded += 1
                self._discarding = True
                self._buffer.clear()
            else:
                self._buffer += rest
        return lines


@dataclass(frozen=True, slots=True)
class ServerError:
    """An ``ERROR:`` or ``WARNING:`` line: ``ERROR:<code> <text>: '<request>'``.

    ``code`` is the number as text ("" without one), ``request`` the command the
    line quotes at its end ("" if it quotes none), ``message`` the rest.
    """

    severity: str
    code: str
    message: str
    request: str = ""

    @property
    def number(self) -> int | None:
        """The code as a number (None without one)."""
        return int(self.code) if self.code else None

    @property
    def variable(self) -> str:
        """The variable name the quoted request names ("" if none)."""
        _, colon, argument = self.request.partition(":")
        if not colon:
            return ""
        return argument.split(",", 1)[0].split(None, 1)[0] if argument.strip() else ""


def split_line(text: str) -> tuple[str, str] | None:
    """``(COMMAND, rest)`` of a line, the command upper-cased; None without a colon."""
    command, colon, rest = text.partition(":")
    if not colon or not command.strip():
        return None
    return command.strip().upper(), rest


def split_answer(rest: str) -> tuple[str, str] | None:
    """``(name, value text)`` of a ``GET:``/``DIFF:`` answer; None if malformed.

    The value is everything after the first comma: names hold no commas, values
    may (a decimal comma, a string).
    """
    name, comma, value = rest.partition(",")
    name = name.strip()
    if not comma or not name:
        return None
    return name, value.strip()


def split_list_entry(rest: str) -> tuple[str, str, str] | None:
    """``(name, flags, type)`` of a ``LIST:name,type`` line; None if malformed.

    The ``*`` (disabled) and ``~`` (hidden) flags may follow the type
    (``svetlo_kuchyn,BOOL*``, the changelog) or the name (``test_btn_up*~``,
    the manual's example, which prints no type): they are cut from both and
    returned together. An entry without a type has the type "".
    """
    raw_name, _, raw_type = rest.partition(",")
    name = raw_name.strip().rstrip(NAME_FLAGS).strip()
    type_name = raw_type.strip().rstrip(NAME_FLAGS).strip()
    if not name:
        return None
    flags = raw_name.strip()[len(name) :] + raw_type.strip()[len(type_name) :]
    return name, "".join(flag for flag in NAME_FLAGS if flag in flags), type_name


_QUOTED_REQUEST: Final = re.compile(r".*'([^']*)'\s*")


def parse_server_error(severity: str, rest: str) -> ServerError:
    """Read the rest of an ``ERROR:``/``WARNING:`` line: code, text, quoted request."""
    text = rest.strip()
    code, _, message = text.partition(" ")
    if not code.isdigit():
        code, message = "", text
    message = message.strip()
    if match := _QUOTED_REQUEST.fullmatch(message):
        return ServerError(severity, code, message, match.group(1))
    return ServerError(severity, code, message)


def parse_variable(type_name: str | None, text: str) -> Any:
    """Return the typed value of a variable of a ``LIST:`` type (None if unfit).

    As :func:`parse_value` for the type's kind, within the type's own range (a
    TOD below a day); without a type, or of a type unknown here, the value is
    guessed from its look.
    """
    kind = None if type_name is None else kind_of_type(type_name)
    value = parse_value(kind, text)
    if (
        type_name is not None
        and type_name.strip().upper() in _TOD_TYPES
        and isinstance(value, timedelta)
        and value > timedelta(milliseconds=MAX_TOD_MS)
    ):
        return None
    return value


def date_form(text: str) -> DateForm | None:
    """Which form a DATE or DT value's text proves its server writes (None: no proof).

    An integer from :data:`DOUBLE_BITS_FROM` up is a double's bytes; a number
    with a fraction point or an exponent is the decimal form. ``0`` is the same
    in every form: no proof. Any other integer is taken as the plain count of
    seconds: as a double's bytes it would be a subnormal double (no date a
    PLC holds), and a decimal server prints one only with no decimals
    (``NUM_OF_DECIMALS`` = 0) -- and then reads a count of seconds right too.
    """
    text = text.strip()
    if _UNSIGNED.fullmatch(text):
        try:
            number = int(text)
        except ValueError:  # beyond Python's digits for an int: no value at all
            return None
        if number >= DOUBLE_BITS_FROM:
            return DateForm.DOUBLE_BITS
        return DateForm.SECONDS if number else None
    if _NUMBER.fullmatch(text) and any(mark in text for mark in ".,eE"):
        return DateForm.DECIMAL
    return None


def learn_date_form(known: DateForm | None, text: str) -> DateForm | None:
    """Return the server's DATE/DT form after ``text``, ``known`` the form before.

    The double's bytes and the decimal form are proven by one value (see
    :func:`date_form`) and replace what was known; the plain count of seconds
    only fills a form not known yet (its integers also come from a decimal
    server printing no decimals), and a text that proves nothing keeps what
    was known: one variable's ``0`` never turns a server's form around.
    """
    form = date_form(text)
    if form is None or (form is DateForm.SECONDS and known is not None):
        return known
    return form


def parse_value(kind: ValueKind | None, text: str) -> Any:
    """Return the typed value of a text for a variable of ``kind`` (None if unfit).

    Without a kind (a variable ``LIST:`` did not name), a quoted text is a
    string, ``true``/``false`` a bool, a number an int or float, and anything
    else the text itself.
    """
    parse = _infer if kind is None else _PARSERS[kind]
    try:
        return parse(text.strip())
    except (ArithmeticError, ValueError):
        # Whatever number a server sends (beyond a date's range, a 5,000-digit
        # integer), that one value is unfit: None, never an exception that
        # would cost the connection.
        return None


def _infer(text: str) -> Any:
    """Guess the value of a text without a declared kind from its look."""
    if len(text) >= 2 and text[0] == text[-1] == '"':
        return text[1:-1]
    if text.lower() in {"true", "false"}:
        return text.lower() == "true"
    if _INTEGER.fullmatch(text):
        return int(text)
    number = _parse_number(text)
    return text if number is None else number


def _parse_bool(text: str) -> bool | None:
    lowered = text.lower()
    if lowered in _TRUE:
        return True
    if lowered in _FALSE:
        return False
    return None


def _parse_integer(text: str) -> int | None:
    if _INTEGER.fullmatch(text):
        return int(text)
    number = _parse_number(text)
    if number is not None and number.is_integer():
        return int(number)
    return None


def _parse_number(text: str) -> float | None:
    """Read a finite real: plain or scientific notation, decimal point or comma."""
    match = _NUMBER.fullmatch(text)
    if match is None:
        return None
    mantissa, exponent = match.groups()
    try:
        number = float(
            mantissa.replace(",", ".") + (f"e{exponent}" if exponent else "")
        )
    except ValueError:  # pragma: no cover - the pattern admits only numbers
        return None
    return number if math.isfinite(number) else None


def _unquote(text: str) -> str:
    if len(text) >= 2 and text[0] == text[-1] == '"':
        return text[1:-1]
    return text


def parse_milliseconds(text: str) -> int | None:
    """Read a TIME/TOD as milliseconds: integer, ``hh:mm:ss.zzz`` or IEC literal.

    None beyond the 32 bits of a TIME, whichever form said it.
    """
    millis = _milliseconds_of(text)
    return millis if millis is not None and 0 <= millis <= MAX_TIME_MS else None


def _milliseconds_of(text: str) -> int | None:
    if _INTEGER.fullmatch(text):
        return int(text)
    if match := _TOD_LITERAL.fullmatch(text):
        text = match.group(1)
    if match := CLOCK.fullmatch(text):
        hours, minutes, seconds, fraction = match.groups()
        return (int(hours) * 3600 + int(minutes) * 60 + int(seconds)) * 1000 + int(
            (fraction or "0").ljust(3, "0")
        )
    if match := _DURATION.fullmatch(text):
        if match.group(1):
            return None
        return _duration_milliseconds(match.group(2))
    number = _parse_number(text)
    if number is None or not 0 <= number <= MAX_TIME_MS:
        return None
    return round(number)


def _duration_milliseconds(text: str) -> int | None:
    """``1d2h3m4s5ms`` (underscores allowed) as milliseconds."""
    total = 0.0
    position = 0
    for part in _DURATION_PART.finditer(text):
        if part.start() != position:
            return None
        total += float(part.group(1)) * _MS_PER_UNIT[part.group(2).lower()]
        position = part.end()
    if position != len(text) or position == 0 or not total <= MAX_TIME_MS:
        return None
    return round(total)


def _from_seconds(text: str) -> datetime | None:
    """Read a DATE/DT number (any :class:`DateForm`) as an aware datetime.

    None for a moment before 1970 or after 9999, and for a NaN or infinity.
    """
    seconds: float | None
    if _UNSIGNED.fullmatch(text):
        number = int(text)
        seconds = _double_of(number) if number >= DOUBLE_BITS_FROM else number
    else:
        seconds = _parse_number(text)
    if seconds is None or not 0 <= seconds <= _LAST_SECOND:
        return None
    # Rounded to the millisecond, the last half millisecond would be 10000-01-01.
    millis = round(seconds * 1000)
    return EPOCH + timedelta(milliseconds=millis) if millis <= _LAST_MS else None


def _double_of(number: int) -> float | None:
    """Return the double an unsigned 64-bit integer holds (None beyond 64 bits)."""
    if number >= 2**64:
        return None
    value: float = struct.unpack("<d", number.to_bytes(8, "little"))[0]
    return value if math.isfinite(value) else None


def _parse_time(text: str) -> timedelta | None:
    """Read a TIME/TOD as a ``timedelta`` (whole milliseconds)."""
    millis = parse_milliseconds(text)
    return None if millis is None else timedelta(milliseconds=millis)


def _parse_date(text: str) -> date | None:
    if match := _DATE_TEXT.fullmatch(text):
        try:
            return date.fromisoformat(match.group(1))
        except ValueError:
            return None
    moment = _from_seconds(text)
    return None if moment is None else moment.date()


def _parse_datetime(text: str) -> datetime | None:
    if match := _DT_TEXT.fullmatch(text):
        day, hours, minutes, seconds, fraction = match.groups()
        try:
            return datetime.fromisoformat(day).replace(
                hour=int(hours),
                minute=int(minutes),
                second=int(seconds),
                microsecond=int((fraction or "0").ljust(6, "0")),
                tzinfo=UTC,
            )
        except ValueError:
            return None
    return _from_seconds(text)


_PARSERS: Final[Mapping[ValueKind, Callable[[str], Any]]] = MappingProxyType(
    {
        ValueKind.BOOL: _parse_bool,
        ValueKind.INTEGER: _parse_integer,
        ValueKind.REAL: _parse_number,
        ValueKind.STRING: _unquote,
        ValueKind.TIME: _parse_time,
        ValueKind.DATE: _parse_date,
        ValueKind.DATETIME: _parse_datetime,
    }
)
"""How :func:`parse_value` reads the (stripped) text of each kind."""
