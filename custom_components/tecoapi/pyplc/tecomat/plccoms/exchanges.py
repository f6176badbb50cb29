"""A PLCComS command's answer, gathered from the lines a connection reads.

Each command in flight has one :class:`Exchange`: the reader offers it the
lines it sees (``LIST:``/``GETINFO:`` entries, ``GET:`` answers, ``ERROR:``), and
it completes its future with the answer or the error. Nothing here does I/O.
"""

import asyncio
from collections.abc import Callable, Iterable
from typing import Any, Final, override

from ...core.exceptions import InvalidPathError, ResponseTooLargeError
from .errors import error_for, named_in
from .formatting import plain_number
from .protocol import (
    ENCODING,
    PLC_RUN,
    ServerError,
    split_list_entry,
)
from .variables import PlcComsVariable

# GETINFO: has a handful of keys; more than this is not an answer.
MAX_INFO_ENTRIES: Final = 256
_PLC_RUN_KEY: Final = PLC_RUN.lower()
_FORBIDDEN_IN_NAMES: Final = frozenset(",: \t\r\n")


class Exchange:
    """The answer to one command being gathered from the lines the reader sees."""

    def __init__(self) -> None:
        """Wait for the answer (on the running loop)."""
        self.future: asyncio.Future[Any] = asyncio.get_running_loop().create_future()
        self.errors: list[ServerError] = []

    def take(self, command: str, rest: str) -> bool:
        """Offer a LIST:/GETINFO: line; whether it belonged to this answer."""
        return False

    def take_value(self, name: str, value: Any) -> bool:
        """Offer a GET: answer; whether it belonged to this answer."""
        return False

    def error(self, error: ServerError) -> None:
        """Take an ERROR: that arrived while this command was in flight."""
        self.errors.append(error)

    def finish(self, result: Any) -> None:
        """Complete with a result (once)."""
        if not self.future.done():
            self.future.set_result(result)

    def fail(self, error: BaseException) -> None:
        """Complete with an error (once)."""
        if not self.future.done():
            self.future.set_exception(error)


class ListingExchange(Exchange):
    """``COMMAND:`` lines until the bare ``COMMAND:``, at most ``limit`` entries.

    A subclass keeps the entries (:meth:`entry`) and says what they answer
    (:meth:`result`); an ``ERROR:`` fails the command.
    """

    def __init__(self, command: str, limit: int, noun: str) -> None:
        """Gather ``command``'s entries (``noun`` names them in the error)."""
        super().__init__()
        self.command = command
        self.limit = limit
        self._noun = noun

    @override
    def take(self, command: str, rest: str) -> bool:
        if command != self.command:
            return False
        if rest.strip():
            self.entry(rest)
        else:
            self.finish(self.result())
        return True

    def entry(self, rest: str) -> None:
        """Take one line's text after ``COMMAND:``."""
        raise NotImplementedError

    def result(self) -> Any:
        """Return the answer of the entries taken."""
        raise NotImplementedError

    def overflows(self, count: int) -> bool:
        """Whether ``count`` entries already fill the limit (the command then fails)."""
        if count < self.limit:
            return False
        self.fail(
            ResponseTooLargeError(
                f"{self.command}: holds more than {self.limit} {self._noun}",
                limit=self.limit,
                received=count + 1,
                code=self.command,
            )
        )
        return True

    @override
    def error(self, error: ServerError) -> None:
        super().error(error)
        self.fail(error_for(error, path=""))


class ListExchange(ListingExchange):
    """``LIST:`` lines until the bare ``LIST:``, at most ``limit`` of them."""

    def __init__(self, limit: int, on_malformed: Callable[[str], None]) -> None:
        """Gather variables; a line that is none goes to ``on_malformed``."""
        super().__init__("LIST", limit, "variables")
        self.entries: list[PlcComsVariable] = []
        self._on_malformed = on_malformed

    @override
    def entry(self, rest: str) -> None:
        entry = split_list_entry(rest)
        if entry is None:
            self._on_malformed(rest)
        elif not self.overflows(len(self.entries)):
            self.entries.append(PlcComsVariable(entry[0], entry[2], entry[1]))

    @override
    def result(self) -> tuple[PlcComsVariable, ...]:
        return tuple(self.entries)


class InfoExchange(ListingExchange):
    """``GETINFO:key,value`` lines until the bare ``GETINFO:`` (or the key asked for)."""

    def __init__(self, key: str | None) -> None:
        """Gather every key, or ``key`` alone."""
        super().__init__("GETINFO", MAX_INFO_ENTRIES, "entries")
        self.key = key.lower() if key else None
        self.entries: dict[str, str] = {}

    @override
    def entry(self, rest: str) -> None:
        key, _, value = rest.partition(",")
        key = key.strip()
        if self.overflows(len(self.entries)):
            return
        self.entries[key] = value.strip()
        # One key asked for: its line is the answer (the terminator may not follow).
        if self.key is not None and key.lower() == self.key:
            self.finish(self.result())

    @override
    def result(self) -> dict[str, str]:
        return dict(self.entries)


class GetExchange(Exchange):
    """Answers to ``GET:`` of several names, in any order, until each is answered.

    An ``ERROR:`` stands for the name it mentions, or for one unnamed name; the
    answer completes when every name is answered or accounted for by an error.
    """

    def __init__(self, names: Iterable[str]) -> None:
        """Wait for each of ``names``."""
        super().__init__()
        self.wanted: dict[str, str] = {name.lower(): name for name in names}
        self.values: dict[str, Any] = {}
        self.failed: dict[str, ServerError] = {}

    @override
    def take_value(self, name: str, value: Any) -> bool:
        key = name.lower()
        if key not in self.wanted or key in self.values or key in self.failed:
            return False
        self.values[key] = value
        self._check()
        return True

    @override
    def error(self, error: ServerError) -> None:
        super().error(error)
        open_keys = [key for key in self.wanted if key not in self.values | self.failed]
        named = named_in(error, open_keys)
        if named is not None:
            self.failed[named] = error
        self._check()

    def _check(self) -> None:
        unnamed = len(self.errors) - len(self.failed)
        if len(self.values) + len(self.failed) + unnamed < len(self.wanted):
            return
        if not self.errors:
            self.finish(dict(self.values))
            return
        missing = next(
            (key for key in self.wanted if key not in self.values),
            next(iter(self.wanted)),
        )
        error = self.failed.get(missing, self.errors[0])
        self.fail(error_for(error, path=self.wanted[missing]))


class BarrierExchange(Exchange):
    """The ``GET:__PLC_RUN`` sent after commands that answer only when they fail."""

    @override
    def take_value(self, name: str, value: Any) -> bool:
        if name.lower() != _PLC_RUN_KEY:
            return False
        self.finish(list(self.errors))
        return True


def check_name(name: str) -> str:
    """Return a name one command line can carry; raise InvalidPathError otherwise."""
    if not isinstance(name, str) or not name.strip():
        raise InvalidPathError(f"Not a variable name: {name!r}")
    if any(char in _FORBIDDEN_IN_NAMES for char in name):
        raise InvalidPathError(f"A variable name cannot hold {name!r}")
    try:
        name.encode(ENCODING)
    except UnicodeEncodeError as err:
        raise InvalidPathError(f"Not a Windows-1250 name: {name!r}") from err
    return name


def enable_line(name: str, delta: float | None) -> str:
    """``EN:name`` or ``EN:name delta``."""
    return f"EN:{name}" if not delta else f"EN:{name} {plain_number(delta)}"
