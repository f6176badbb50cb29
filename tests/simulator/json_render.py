"""JSON printed the way a Tecomat PLC prints it.

The layout reproduces the manual's transcripts byte for byte (their Content-Length
values check it): CRLF line ends and a final CRLF, two spaces per level, a nested
container starts on the line after its key, one array element per line, REAL and
LREAL values with six decimals (`1000.000000`), non-ASCII text as UTF-8.

Real devices differ (`Printing`): Windows-1250 text (a character it lacks becomes
`?`, as a Windows program would write it), REALs the short way (`29.0`, `-0.0`).
"""

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
import json
from typing import Final

from .errors import TecoError

CRLF: Final = "\r\n"
INDENT: Final = "  "


@dataclass(frozen=True, slots=True)
class Printing:
    """How a device prints its answers: the manual's way by default."""

    encoding: str = "utf-8"
    short_reals: bool = False

    def encode(self, text: str) -> bytes:
        """The body's bytes in the device's encoding."""
        return text.encode(self.encoding, errors="replace")


MANUAL: Final = Printing()


def real_text(value: float, *, short: bool = False) -> str:
    """A REAL: six decimals (`29.000000`), or short (`29.0`, `21.5`, `-0.0`)."""
    text = f"{value:.6f}"
    if short:
        text = text.rstrip("0")
        if text.endswith("."):
            text += "0"
    return text


def scalar_text(value: object, *, short_reals: bool = False) -> str:
    """One JSON scalar: booleans, integers plain, reals with 6 decimals, strings."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return real_text(value, short=short_reals)
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)
    raise TypeError(f"not a PLC scalar: {value!r}")


def _lines(
    value: object, depth: int, out: list[str], key: str, printing: Printing = MANUAL
) -> None:
    """Append the lines of `value`, introduced by `key` (already quoted) if given."""
    pad = INDENT * depth
    head = f"{pad}{key}:" if key else ""
    if isinstance(value, Mapping | list | tuple):
        opening, closing = ("{", "}") if isinstance(value, Mapping) else ("[", "]")
        if not value:
            out.append(f"{head} {opening}{closing}" if key else pad + opening + closing)
            return
        if key:
            out.append(head)
        out.append(pad + opening)
        if isinstance(value, Mapping):
            _members(value.items(), depth + 1, out, printing)
        else:
            for index, element in enumerate(value):
                _lines(element, depth + 1, out, "", printing)
                if index < len(value) - 1:
                    out[-1] += ","
        out.append(pad + closing)
    else:
        text = scalar_text(value, short_reals=printing.short_reals)
        out.append(f"{head} {text}" if key else pad + text)


def _members(
    items: Iterable[tuple[str, object]], depth: int, out: list[str], printing: Printing
) -> None:
    """Append `"key": value` members separated by commas."""
    members = list(items)
    for index, (key, member) in enumerate(members):
        _lines(member, depth, out, json.dumps(key, ensure_ascii=False), printing)
        if index < len(members) - 1:
            out[-1] += ","


def render(value: Mapping[str, object], printing: Printing = MANUAL) -> bytes:
    """A whole response body for a JSON object."""
    out: list[str] = []
    _lines(value, 0, out, "", printing)
    return printing.encode(CRLF.join(out) + CRLF)


def render_name_list(names: Sequence[str], *, as_array: bool) -> bytes:
    """GetList's body: `{"a": {}, ...}` or `[{ "a": {} }, ...]` as in chapter 3.3."""
    if not names:
        return ("[]" if as_array else "{}").encode() + CRLF.encode()
    quoted = [json.dumps(name, ensure_ascii=False) for name in names]
    if as_array:
        rows = [f"{INDENT}{{ {name}: {{}} }}" for name in quoted]
        opening, closing = "[", "]"
    else:
        rows = [f"{INDENT}{name}: {{}}" for name in quoted]
        opening, closing = "{", "}"
    body = f",{CRLF}".join(rows)
    return f"{opening}{CRLF}{body}{CRLF}{closing}{CRLF}".encode()


def render_error(error: TecoError, time: str, printing: Printing = MANUAL) -> bytes:
    """An error body exactly as chapter 3.7 prints it (`"error": {` on one line)."""
    lines = [
        "{",
        f'{INDENT}"error": {{',
        f'{INDENT * 2}"code": {scalar_text(error.code)},',
        f'{INDENT * 2}"message": {scalar_text(error.message)},',
        f'{INDENT * 2}"time": {scalar_text(time)}',
        f"{INDENT}}}",
        "}",
    ]
    return printing.encode(CRLF.join(lines) + CRLF)
