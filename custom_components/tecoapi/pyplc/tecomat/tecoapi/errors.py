"""What TecoApi's error answers mean: the library's exception, what to retry.

A documented error body is ``{"error": {"code": "400.005", "message": ...}}``
(the manual's §3.7, *Přehled chyb*); the code decides the exception, and a request that
failed for one name or for its size is read again in parts. Nothing here does
I/O.
"""

from collections.abc import Sequence
import re
from typing import Any, Final

from ...core.exceptions import (
    InvalidPathError,
    NoPublicVariablesError,
    PlcResponseError,
    TooManyItemsError,
    VariableListTooLargeError,
    VariableListUnreadableError,
    VariableNotFoundError,
)
from ...core.http import loads_json
from ...core.texts import Template, Text
from .body import decode_text

AUTH_CODES: Final = frozenset({"401.021", "403.022"})
# The PLC refused a name: empty (400.003), too long (400.007), a member too long
# (400.008).
_BAD_NAME_CODES: Final = frozenset({"400.003", "400.007", "400.008"})
# No public variable (400.006: the list is empty) or no public file (500.010: Mosaic
# writes one only for a program with a {PUBLIC_API} variable).
_NO_PUBLIC_CODES: Final = frozenset({"400.006", "500.010"})
# The public file over 128 KB (500.011): the program publishes too many variables.
_TOO_BIG_CODE: Final = "500.011"
# The public file there, but the PLC cannot read it (500.012).
_UNREADABLE_CODE: Final = "500.012"
# A value the PLC could not write (400.015) or a PutObject body it could not parse
# (400.009).
REJECTED_CODES: Final = frozenset({"400.009", "400.015"})
# 400.015's message names the value and the variable, which the error tells
# already; what it adds is the variable's type (manual §3.7: "Value VVV was not
# written to variable 'NNN' (type of variable is TTT)").
_REFUSED_TYPE: Final = re.compile(r"\(type(?: of variable is)? ([^()]+)\)\s*$")
_STRING_LENGTH: Final = re.compile(
    r"W?STRING\s*[\[(]\s*([0-9]+)\s*[\])]", re.IGNORECASE
)
_NOT_FOUND_NAME: Final = re.compile(r"Variable '(.*)' is not found")
_ALLOWED: Final = re.compile(r"(?:allowed|maximum is):?\s*([0-9]+)")


REFUSED_LENGTH: Final = Template(
    "tecoapi_refused_length",
    "the variable is a {type}, at most {most} characters; the text has {length}",
)
REFUSED_TYPE: Final = Template(
    "tecoapi_refused_type", "it does not fit the variable's type, {type}"
)
ARRAY_ELEMENT: Final = Template(
    "tecoapi_array_element",
    "an array element takes scalars of at most {length} characters",
)
"""Why a structure is refused for an array's element (PutObject's body limit)."""


def refusal(message: str, value: Any) -> Text | None:
    """Return what a refused write's message says beyond its value and variable.

    A text refused by a STRING of a length says the length and the text's: no
    answer of TecoApi tells a STRING's length before (GetList names roots only,
    GetObject answers values, ``attr`` has no length), so a text entity allows
    the 255 characters any STRING may have, and the refusal is where the user
    learns the variable's. None: the message says nothing of the kind (the
    PLC's own words tell why).
    """
    if (found := _REFUSED_TYPE.search(message)) is None:
        return None
    type_name = found.group(1).strip()
    if isinstance(value, str) and (length := _STRING_LENGTH.fullmatch(type_name)):
        return REFUSED_LENGTH(type=type_name, most=length.group(1), length=len(value))
    return REFUSED_TYPE(type=type_name)


def error_body(content: bytes) -> tuple[str, str] | None:
    """``(code, message)`` of a documented TecoApi error body, else None."""
    try:
        body = loads_json(content, decode_text)
    except (ValueError, RecursionError):
        return None
    error = body.get("error") if isinstance(body, dict) else None
    if not isinstance(error, dict) or not isinstance(error.get("code"), str):
        return None
    message = error.get("message")
    return error["code"], message if isinstance(message, str) else ""


def named(names: Sequence[str], err: PlcResponseError) -> str | None:
    """Return the requested name a not-found error names, if it is one of ``names``."""
    if not isinstance(err, VariableNotFoundError) or not err.path:
        return None
    wanted = err.path.lower()
    return next((name for name in names if name.lower() == wanted), None)


def split_helps(err: PlcResponseError) -> bool:
    """Whether reading a failed request in parts may succeed where it failed.

    A name that is missing or refused spoils only its request; so does a request
    too large for one answer (413) or for the server's request line (414).
    """
    return isinstance(
        err, VariableNotFoundError | InvalidPathError | TooManyItemsError
    ) or (err.status == 414)


def response_error(code: str, status: int, message: str) -> PlcResponseError:
    """Return the error that says what a TecoApi error code means.

    The PLC's code and message are its own words (``said``).
    """
    said = f"{code}: {message}" if message else code
    if code == "400.005":
        match = _NOT_FOUND_NAME.search(message)
        return VariableNotFoundError(
            message,
            path=match.group(1) if match else "",
            code=code,
            status=status,
            said=said,
        )
    if code in _BAD_NAME_CODES:
        return InvalidPathError(message, code=code, status=status, said=said)
    if code in _NO_PUBLIC_CODES:
        return NoPublicVariablesError(message, code=code, status=status, said=said)
    if code == _TOO_BIG_CODE:
        return VariableListTooLargeError(message, code=code, status=status, said=said)
    if code == _UNREADABLE_CODE:
        return VariableListUnreadableError(message, code=code, status=status, said=said)
    if status == 413:
        match = _ALLOWED.search(message)
        return TooManyItemsError(
            message,
            allowed=int(match.group(1)) if match else None,
            code=code,
            status=status,
            said=said,
        )
    return PlcResponseError(message, code=code, status=status, said=said)


def split_failed(names: list[str], err: PlcResponseError) -> list[list[str]]:
    """Return what to retry of a failed request: all but the missing name, or halves."""
    if len(names) == 1:
        return []
    if name := named(names, err):
        rest = [other for other in names if other != name]
        return [rest] if rest else []
    middle = len(names) // 2
    return [names[:middle], names[middle:]]
