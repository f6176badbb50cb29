"""What an ``ERROR:`` line means: the library's exception for it, the name it is about.

Decided by the code of Teco's manual (chapter 5); an error without one of those
codes by its words. Nothing here does I/O.
"""

from collections.abc import Iterable
from typing import Any, Final

from ...core.exceptions import (
    PlcConnectionError,
    PlcError,
    PlcResponseError,
    PlcUnreachableError,
    ValueRejectedError,
    VariableNotFoundError,
)
from .protocol import PLC_COMMUNICATION_CODES, ErrorCode, ServerError

# An error without a code of the manual is read by its words: these say "no such
# variable" in English and Czech (without diacritics) messages.
_NOT_FOUND_WORDS: Final = (
    "not found",
    "unknown variable",
    "no such variable",
    "does not exist",
    "nenalezen",
    "neznam",
)
_MANUAL_CODES: Final = frozenset(ErrorCode)


class VariableDisabledError(PlcResponseError):
    """The server refused a variable as disabled (``ERROR:34``).

    ``path`` is the variable it named, or the one asked for.
    """

    def __init__(self, message: str, *, path: str = "", code: str = "") -> None:
        """Name the variable refused."""
        super().__init__(message, code=code)
        self.path = path


def named_in(error: ServerError, keys: Iterable[str]) -> str | None:
    """Return the lower-case name of ``keys`` an error is about, if it names one.

    The request the error quotes tells (``'GET:test'``); an error quoting none is
    searched for the longest name its text holds.
    """
    candidates = list(keys)
    variable = error.variable.lower()
    if variable:
        return variable if variable in candidates else None
    text = error.message.lower()
    named = [key for key in candidates if key in text]
    return max(named, key=len) if named else None


def error_for(
    error: ServerError, *, path: str, written: bool = False, value: Any = None
) -> PlcError:
    """Return the exception for an ERROR: line answering a command on ``path``.

    Decided by the manual's code; an error without one of those codes by its
    words. ``written`` for a SET: of ``value`` (a refusal is then a rejected
    value).
    """
    message = error.message or "ERROR"
    code = error.number
    # The server's own words, as its ERROR: line says them.
    said = f"ERROR:{error.code} {error.message}".strip()
    path = error.variable or path
    if code in PLC_COMMUNICATION_CODES:
        return PlcUnreachableError(
            f"PLCComS answers, but cannot reach its PLC (ERROR:{code} {message})",
            said=said,
        )
    if code == ErrorCode.TOO_MANY_CONNECTIONS:
        return PlcConnectionError(
            f"PLCComS refuses more connections (ERROR:{code} {message})"
        )
    if code == ErrorCode.UNKNOWN_VARIABLE or (
        code not in _MANUAL_CODES
        and any(word in message.lower() for word in _NOT_FOUND_WORDS)
    ):
        return VariableNotFoundError(message, path=path, code=error.code, said=said)
    if code == ErrorCode.DISABLED_VARIABLE:
        return VariableDisabledError(message, path=path, code=error.code)
    if written:
        return ValueRejectedError(
            message, path=path, value=value, code=error.code, said=said
        )
    return PlcResponseError(message, code=error.code, said=said)
