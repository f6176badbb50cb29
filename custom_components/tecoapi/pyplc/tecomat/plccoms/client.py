"""A PLCComS client: Teco's push-capable text protocol, over asyncio TCP.

PLCComS has no authentication: use it only on a trusted network, and only when the
user asked for it. It imports nothing from Home Assistant.

Client API
----------
``PlcComsClient(host, port=5010, *, timeout=10.0, keepalive_interval=30.0,
keepalive_timeout=None, reconnect_delay=1.0, reconnect_max_delay=60.0,
max_line_length=4096, max_variables=100_000)``; ``async with`` connects and closes.

- ``await connect()`` -- opens the connection, reads ``LIST:`` and the run state
  (``GET:__PLC_RUN``; the server's fixed variables are always pushed, ``EN:``
  does not apply to them); raises ``PlcConnectionError`` when the server cannot
  be reached, ``PlcUnreachableError`` when it answers but cannot reach its PLC
  (``ERROR:10``). A connection on which the server enables every variable
  (``PF_VAR_DISABLED = No``: ``LIST:`` flags none ``*``) is disabled first
  (``DI:*``), so that only what the client enables is pushed. From then on the client keeps itself connected: a dropped connection
  (server restart) or a silent one (no answer to a keep-alive ``GET:__PLC_RUN``
  within ``keepalive_timeout`` after ``keepalive_interval`` without a line, or to
  any command within ``timeout``) is closed and opened again with exponential
  backoff (``reconnect_delay`` doubling up to ``reconnect_max_delay``); then
  ``LIST:`` is read again, every enabled variable is enabled again (with its
  delta) and read with ``GET:``, and the values are delivered as
  ``ValueChanged(pushed=False)``. A server that cannot reach its PLC
  (``ERROR:10``, 20, 21 to any command) is treated as a lost connection: it is
  opened again with backoff until the PLC answers, and ``failure`` says why
  the client is not connected meanwhile. ``await close()`` ends all of it.
- ``await list_variables() -> tuple[PlcComsVariable, ...]``; ``variables`` (by
  lower-case name), ``catalogue`` (a neutral ``Catalogue`` of ``Point`` with
  ``meta=None``; ``values`` empty, ``__*`` server variables left out).
- ``await get(names) -> dict[str, Any]`` -- values by the names as given, typed by
  each variable's kind (answers are matched by name, in any order).
- ``await set(name, value)``, ``await enable(names, delta=None)``,
  ``await disable(names)`` -- each followed by a ``GET:__PLC_RUN`` whose answer
  tells that the server has processed it (``SET:`` answers nothing on success;
  ``EN:``/``DI:`` answer ``WARNING:252``, older servers the values, neither of
  which is taken as an answer); an ``ERROR:`` before it raises. A DATE or DT is
  written in the form the server reads them in (:class:`~.protocol.DateForm`,
  learnt from the values it sent on this connection that prove it -- ``0``
  proves none; a variable is read first if none did, and the manual's default
  taken if that proves nothing either).
- ``await get_info(key=None) -> dict[str, str]`` -- ``GETINFO:`` keys and values.
- ``subscribe(callback) -> unsubscribe``: ``callback(event)`` for every
  ``ValueChanged`` (a ``DIFF:``, or a value read again after a reconnect),
  ``RunStateChanged`` (``__PLC_RUN``), ``ConnectionChanged`` and
  ``ProgramChanged`` (``LIST:`` differs after ``__PLC_RUN`` went 0 -> 1 or after a
  reconnect; the client has already read it and enabled its variables again).
- ``connected`` (set up and serving), ``plc_running`` (``__PLC_RUN``, None until
  known), ``enabled``, ``failure`` (why it is not connected) and ``health`` (a ``PlcComsHealth`` snapshot: connection,
  idle time, counters of lines, reconnects, stalls, discarded lines).

Errors follow the ``ERROR:`` line's code (the manual, chapter 5), not its text:
``PlcConnectionError`` (unreachable, dropped, stalled, not connected right now,
11: too many connections), ``PlcUnreachableError`` (10, 20, 21: the server cannot
talk to its PLC), ``VariableNotFoundError`` (a name not in ``LIST:``, or 33),
``VariableDisabledError`` (34), ``ValueRejectedError`` (an ``ERROR:`` answering a
``SET:``, 35 among them),
``InvalidValueError`` (a value the variable's kind cannot take, nothing sent),
``InvalidPathError`` (a name that cannot be sent), ``ResponseTooLargeError``
(``LIST:``/``GETINFO:`` beyond the configured bounds), ``PlcResponseError``
(another ``ERROR:``; one without a code of the manual is read by its words).
Bounds: a line over ``max_line_length`` bytes is discarded
and counted, never kept; answers are collected only for commands in flight, one
command at a time; callbacks run at once, nothing is queued.
"""

import asyncio
from collections.abc import Callable, Collection, Coroutine, Iterable, Mapping
import contextlib
from dataclasses import dataclass, field
from datetime import UTC, datetime
import logging
import math
import time
from types import TracebackType
from typing import Any, Final, Self

from ...core.exceptions import (
    InvalidPathError,
    InvalidValueError,
    PlcConnectionError,
    PlcError,
    PlcResponseError,
    PlcUnreachableError,
    ResponseTooLargeError,
    ValueRejectedError,
    VariableNotFoundError,
)
from ...core.models import Catalogue, Point, ValueKind
from ..points import tecomat_point
from .protocol import (
    DEFAULT_PORT,
    DISABLED_FLAG,
    ENCODING,
    HIDDEN_FLAG,
    MAX_LINE_LENGTH,
    PLC_COMMUNICATION_CODES,
    PLC_RUN,
    DateForm,
    ErrorCode,
    LineFramer,
    ServerError,
    format_value,
    kind_of_type,
    learn_date_form,
    parse_server_error,
    parse_value,
    parse_variable,
    plain_number,
    split_answer,
    split_line,
    split_list_entry,
)

_LOGGER = logging.getLogger(__name__)

# GETINFO: has a handful of keys; more than this is not an answer.
MAX_INFO_ENTRIES: Final = 256
_READ_CHUNK: Final = 65536
_PLC_RUN_KEY: Final = PLC_RUN.lower()
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
_FORBIDDEN_IN_NAMES: Final = frozenset(",: \t\r\n")
_DATE_KINDS: Final = frozenset({ValueKind.DATE, ValueKind.DATETIME})
_MANUAL_CODES: Final = frozenset(ErrorCode)


class VariableDisabledError(PlcResponseError):
    """The server refused a variable as disabled (``ERROR:34``).

    ``path`` is the variable it named, or the one asked for.
    """

    def __init__(self, message: str, *, path: str = "", code: str = "") -> None:
        """Name the variable refused."""
        super().__init__(message, code=code)
        self.path = path


@dataclass(frozen=True, slots=True)
class PlcComsVariable:
    """One ``LIST:`` entry: the name as the server spells it, its type and flags.

    The flags (``*`` disabled, ``~`` hidden) describe the connection's state, not
    the program: two entries with the same name and type are equal whatever
    their flags.
    """

    name: str
    type: str
    flags: str = field(default="", compare=False)

    @property
    def key(self) -> str:
        """The name in lower case: names are case-insensitive."""
        return self.name.lower()

    @property
    def kind(self) -> ValueKind | None:
        """The library's kind of the type (None for a type it does not know)."""
        return kind_of_type(self.type)

    @property
    def hidden(self) -> bool:
        """Whether the server lists it as hidden (``~``)."""
        return HIDDEN_FLAG in self.flags

    @property
    def enabled(self) -> bool:
        """Whether its changes are pushed to this connection (no ``*``)."""
        return DISABLED_FLAG not in self.flags


@dataclass(frozen=True, slots=True)
class ValueChanged:
    """A variable's new value: pushed (``DIFF:``) or read again after a reconnect.

    ``value`` is typed by the variable's kind (None if the text does not fit it);
    ``raw`` is the value's text on the wire for a push, "" for a value read again.
    """

    key: str
    name: str
    value: Any
    raw: str
    pushed: bool = True


@dataclass(frozen=True, slots=True)
class RunStateChanged:
    """``__PLC_RUN`` changed: the PLC runs its program, or it stopped (HALT/ERR)."""

    running: bool


@dataclass(frozen=True, slots=True)
class ConnectionChanged:
    """The client became ready (connected, listed, enabled) or lost its connection."""

    connected: bool
    reason: str = ""


@dataclass(frozen=True, slots=True)
class ProgramChanged:
    """``LIST:`` changed (a program download); the client has re-enabled its variables."""

    catalogue: Catalogue


type PlcComsEvent = ValueChanged | RunStateChanged | ConnectionChanged | ProgramChanged
type PlcComsCallback = Callable[[PlcComsEvent], None]


@dataclass(frozen=True, slots=True, kw_only=True)
class PlcComsHealth:
    """How the connection is doing, to decide whether push can be relied on.

    ``idle`` is seconds since the last line arrived (None before the first).
    Counters run for the client's life.
    """

    connected: bool
    plc_running: bool | None
    last_line_at: datetime | None
    idle: float | None
    lines_received: int
    lines_sent: int
    discarded_lines: int
    malformed_lines: int
    server_errors: int
    keepalives: int
    stalls: int
    reconnects: int
    reconnect_attempts: int
    last_error: str | None


def backoff_delay(attempt: int, base: float, maximum: float) -> float:
    """Return the wait before reconnect attempt ``attempt`` (from 0): doubling, capped."""
    return float(min(base * 2 ** min(attempt, 62), maximum))


def build_catalogue(
    variables: Iterable[PlcComsVariable],
    *,
    grouped: Mapping[str, Point] | None = None,
    members: Collection[str] = (),
) -> Catalogue:
    """Build a neutral catalogue of ``LIST:`` variables.

    Every variable of a known type is a point (key the lower-case name, path the
    server's spelling, no metadata); the server's own ``__*`` variables are left
    out, those of unknown types listed in ``skipped_roots``. ``roots`` are the
    first segments of the names, in order.

    A point standing for several variables (a T_ApiObject) is given in
    ``grouped`` by the key of the variable carrying its value, and takes that
    variable's place; the keys of its other variables are ``members``: they give
    no points of their own, but their roots count.
    """
    grouped = grouped or {}
    points: dict[str, Point] = {}
    roots: dict[str, str] = {}
    skipped: list[str] = []
    for variable in variables:
        if variable.name.startswith("__"):
            continue
        kind = variable.kind
        if kind is None:
            skipped.append(variable.name)
            continue
        key = variable.key
        if key in grouped:
            points[grouped[key].key] = grouped[key]
        elif key in points:
            continue
        elif key not in members:
            points[key] = tecomat_point(variable.name, kind)
        root = variable.name.split(".", 1)[0].split("[", 1)[0]
        roots.setdefault(root.lower(), root)
    return Catalogue(
        points=points,
        values={},
        roots=tuple(roots.values()),
        skipped_roots=tuple(skipped),
    )


class _Exchange:
    """The answer to one command being gathered from the lines the reader sees."""

    def __init__(self) -> None:
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


class _ListingExchange(_Exchange):
    """``COMMAND:`` lines until the bare ``COMMAND:``, at most ``limit`` entries.

    A subclass keeps the entries (:meth:`entry`) and says what they answer
    (:meth:`result`); an ``ERROR:`` fails the command.
    """

    def __init__(self, command: str, limit: int, noun: str) -> None:
        super().__init__()
        self.command = command
        self.limit = limit
        self._noun = noun

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

    def error(self, error: ServerError) -> None:
        super().error(error)
        self.fail(_error_for(error, path=""))


class _ListExchange(_ListingExchange):
    """``LIST:`` lines until the bare ``LIST:``, at most ``limit`` of them."""

    def __init__(self, limit: int, on_malformed: Callable[[str], None]) -> None:
        super().__init__("LIST", limit, "variables")
        self.entries: list[PlcComsVariable] = []
        self._on_malformed = on_malformed

    def entry(self, rest: str) -> None:
        entry = split_list_entry(rest)
        if entry is None:
            self._on_malformed(rest)
        elif not self.overflows(len(self.entries)):
            self.entries.append(PlcComsVariable(entry[0], entry[2], entry[1]))

    def result(self) -> tuple[PlcComsVariable, ...]:
        return tuple(self.entries)


class _InfoExchange(_ListingExchange):
    """``GETINFO:key,value`` lines until the bare ``GETINFO:`` (or the key asked for)."""

    def __init__(self, key: str | None) -> None:
        super().__init__("GETINFO", MAX_INFO_ENTRIES, "entries")
        self.key = key.lower() if key else None
        self.entries: dict[str, str] = {}

    def entry(self, rest: str) -> None:
        key, _, value = rest.partition(",")
        key = key.strip()
        if self.overflows(len(self.entries)):
            return
        self.entries[key] = value.strip()
        # One key asked for: its line is the answer (the terminator may not follow).
        if self.key is not None and key.lower() == self.key:
            self.finish(self.result())

    def result(self) -> dict[str, str]:
        return dict(self.entries)


class _GetExchange(_Exchange):
    """Answers to ``GET:`` of several names, in any order, until each is answered.

    An ``ERROR:`` stands for the name it mentions, or for one unnamed name; the
    answer completes when every name is answered or accounted for by an error.
    """

    def __init__(self, names: Iterable[str]) -> None:
        super().__init__()
        self.wanted: dict[str, str] = {name.lower(): name for name in names}
        self.values: dict[str, Any] = {}
        self.failed: dict[str, ServerError] = {}

    def take_value(self, name: str, value: Any) -> bool:
        key = name.lower()
        if key not in self.wanted or key in self.values or key in self.failed:
            return False
        self.values[key] = value
        self._check()
        return True

    def error(self, error: ServerError) -> None:
        super().error(error)
        open_keys = [key for key in self.wanted if key not in self.values | self.failed]
        named = _named_in(error, open_keys)
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
        self.fail(_error_for(error, path=self.wanted[missing]))


class _BarrierExchange(_Exchange):
    """The ``GET:__PLC_RUN`` sent after commands that answer only when they fail."""

    def take_value(self, name: str, value: Any) -> bool:
        if name.lower() != _PLC_RUN_KEY:
            return False
        self.finish(list(self.errors))
        return True


class _Connection:
    """One TCP connection: its streams, framer, reader task and command in flight."""

    def __init__(
        self,
        reader: asyncio.StreamReader,
        writer: asyncio.StreamWriter,
        max_line_length: int,
    ) -> None:
        self.reader = reader
        self.writer = writer
        self.framer = LineFramer(max_line_length)
        self.lost: asyncio.Future[str] = asyncio.get_running_loop().create_future()
        self.pending: _Exchange | None = None
        self.tasks: set[asyncio.Task[None]] = set()


def _named_in(error: ServerError, keys: Iterable[str]) -> str | None:
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


def _error_for(
    error: ServerError, *, path: str, written: bool = False, value: Any = None
) -> PlcError:
    """Return the exception for an ERROR: line answering a command on ``path``.

    Decided by the manual's code; an error without one of those codes by its
    words. ``written`` for a SET: of ``value`` (a refusal is then a rejected
    value).
    """
    message = error.message or "ERROR"
    code = error.number
    path = error.variable or path
    if code in PLC_COMMUNICATION_CODES:
        return PlcUnreachableError(
            f"PLCComS answers, but cannot reach its PLC (ERROR:{code} {message})"
        )
    if code == ErrorCode.TOO_MANY_CONNECTIONS:
        return PlcConnectionError(
            f"PLCComS refuses more connections (ERROR:{code} {message})"
        )
    if code == ErrorCode.UNKNOWN_VARIABLE or (
        code not in _MANUAL_CODES
        and any(word in message.lower() for word in _NOT_FOUND_WORDS)
    ):
        return VariableNotFoundError(message, path=path, code=error.code)
    if code == ErrorCode.DISABLED_VARIABLE:
        return VariableDisabledError(message, path=path, code=error.code)
    if written:
        return ValueRejectedError(message, path=path, value=value, code=error.code)
    return PlcResponseError(message, code=error.code)


def _check_name(name: str) -> str:
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


class PlcComsClient:
    """An async client of one PLCComS server (see the module's docstring)."""

    def __init__(
        self,
        host: str,
        port: int = DEFAULT_PORT,
        *,
        timeout: float = 10.0,
        keepalive_interval: float = 30.0,
        keepalive_timeout: float | None = None,
        reconnect_delay: float = 1.0,
        reconnect_max_delay: float = 60.0,
        max_line_length: int = MAX_LINE_LENGTH,
        max_variables: int = 100_000,
    ) -> None:
        """Prepare a client; nothing is sent until :meth:`connect`.

        The module's docstring says what each timing does; ``max_line_length`` and
        ``max_variables`` cap what a server can make the client hold.
        """
        if timeout <= 0 or keepalive_interval <= 0:
            raise ValueError("timeouts and intervals must be positive")
        self.host = host
        self.port = port
        self._timeout = timeout
        self._keepalive_interval = keepalive_interval
        self._keepalive_timeout = keepalive_timeout or timeout
        self._reconnect_delay = reconnect_delay
        self._reconnect_max_delay = max(reconnect_max_delay, reconnect_delay)
        self._max_line_length = max_line_length
        self._max_variables = max_variables
        # The wait between reconnect attempts; a test may replace it.
        self._sleep: Callable[[float], Any] = asyncio.sleep
        self._lock = asyncio.Lock()
        self._conn: _Connection | None = None
        self._supervisor: asyncio.Task[None] | None = None
        self._resync = asyncio.Event()
        self._ready = False
        self._closing = False
        self._callbacks: list[PlcComsCallback] = []
        self._variables: dict[str, PlcComsVariable] = {}
        self._listed: tuple[PlcComsVariable, ...] | None = None
        self._enabled: dict[str, tuple[str, float | None]] = {}
        self._plc_running: bool | None = None
        self._failure: PlcError | None = None
        # How the server writes DATE and DT (learnt from the values that prove it;
        # None: nothing did, writes take the manual's default).
        self._dates: DateForm | None = None
        self._last_line_monotonic: float | None = None
        self._last_line_at: datetime | None = None
        self._lines_received = 0
        self._lines_sent = 0
        self._discarded = 0
        self._malformed = 0
        self._server_errors = 0
        self._keepalives = 0
        self._stalls = 0
        self._reconnects = 0
        self._reconnect_attempts = 0
        self._last_error: str | None = None

    # --- state -------------------------------------------------------------------

    @property
    def connected(self) -> bool:
        """Whether the client is connected, listed and enabled: push can be relied on."""
        return self._ready

    @property
    def plc_running(self) -> bool | None:
        """``__PLC_RUN``: whether the PLC runs its program (None until known)."""
        return self._plc_running

    @property
    def variables(self) -> Mapping[str, PlcComsVariable]:
        """The last ``LIST:``, by lower-case name."""
        return dict(self._variables)

    @property
    def catalogue(self) -> Catalogue | None:
        """The last ``LIST:`` as a neutral catalogue (None before the first)."""
        return None if self._listed is None else build_catalogue(self._listed)

    @property
    def enabled(self) -> frozenset[str]:
        """The names enabled through :meth:`enable` (kept across reconnects)."""
        return frozenset(name for name, _ in self._enabled.values())

    @property
    def failure(self) -> PlcError | None:
        """Why the client is not connected now (None while it is, or before trying).

        A :class:`PlcUnreachableError` while the server answers but cannot reach
        its PLC; else the last failure of connecting or setting up.
        """
        return None if self._ready else self._failure

    @property
    def health(self) -> PlcComsHealth:
        """A snapshot of the connection's health and counters."""
        idle = (
            None
            if self._last_line_monotonic is None
            else time.monotonic() - self._last_line_monotonic
        )
        return PlcComsHealth(
            connected=self._ready,
            plc_running=self._plc_running,
            last_line_at=self._last_line_at,
            idle=idle,
            lines_received=self._lines_received,
            lines_sent=self._lines_sent,
            discarded_lines=self._discarded,
            malformed_lines=self._malformed,
            server_errors=self._server_errors,
            keepalives=self._keepalives,
            stalls=self._stalls,
            reconnects=self._reconnects,
            reconnect_attempts=self._reconnect_attempts,
            last_error=self._last_error,
        )

    def subscribe(self, callback: PlcComsCallback) -> Callable[[], None]:
        """Call ``callback(event)`` for every event; returns the unsubscribe function."""
        self._callbacks.append(callback)

        def unsubscribe() -> None:
            with contextlib.suppress(ValueError):
                self._callbacks.remove(callback)

        return unsubscribe

    # --- lifecycle -----------------------------------------------------------------

    async def connect(self) -> None:
        """Connect, read ``LIST:`` and the run state; keep connected from then on."""
        if self._supervisor is not None:
            raise RuntimeError("the client is already connected")
        self._closing = False
        await self._open()
        self._supervisor = asyncio.create_task(self._supervise())

    async def close(self) -> None:
        """Close the connection and stop reconnecting. Idempotent."""
        self._closing = True
        supervisor, self._supervisor = self._supervisor, None
        if supervisor is not None:
            supervisor.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await supervisor
        conn = self._conn
        if conn is not None:
            self._drop(conn, "closed by the client")
            await self._finish(conn)
            self._conn = None

    async def __aenter__(self) -> Self:
        """Connect."""
        await self.connect()
        return self

    async def __aexit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        traceback: TracebackType | None,
    ) -> None:
        """Close."""
        await self.close()

    # --- commands ------------------------------------------------------------------

    async def list_variables(self) -> tuple[PlcComsVariable, ...]:
        """``LIST:``: every variable with its type (flags cut from the names)."""
        conn = self._live()
        return await self._list(conn)

    async def get(self, names: Iterable[str]) -> dict[str, Any]:
        """``GET:`` each name; values by the names as given, typed by their kinds."""
        requested = [self._known(_check_name(name)) for name in names]
        if not requested:
            return {}
        conn = self._live()
        unique = list({name.lower(): name for name in requested}.values())
        values: dict[str, Any] = await self._command(
            conn, [f"GET:{name}" for name in unique], _GetExchange(unique)
        )
        return {name: values[name.lower()] for name in requested}

    async def set(self, name: str, value: Any) -> None:
        """``SET:`` a value; returns once the server took it, raises if it refused."""
        self._known(_check_name(name))
        variable = self._variables.get(name.lower())
        kind = variable.kind if variable else None
        text = format_value(
            kind, value, name=name, dates=self._dates or DateForm.DOUBLE_BITS
        )
        if kind in _DATE_KINDS and self._dates is None:
            # Learn the server's DATE/DT form from the variable's own value.
            await self.get([name])
            text = format_value(
                kind, value, name=name, dates=self._dates or DateForm.DOUBLE_BITS
            )
        conn = self._live()
        errors = await self._barrier(conn, [f"SET:{name},{text}"])
        if errors:
            raise _error_for(errors[0], path=name, written=True, value=value)

    async def enable(self, names: Iterable[str], delta: float | None = None) -> None:
        """``EN:`` each name: push its changes (of at least ``delta`` for a number).

        The names stay enabled across reconnects and program downloads (while
        ``LIST:`` holds them). A name ``LIST:`` does not hold raises
        VariableNotFoundError before anything is sent; ``*`` patterns are sent as
        they are.
        """
        requested = [self._known(_check_name(name)) for name in names]
        if delta is not None and (
            isinstance(delta, bool)
            or not isinstance(delta, int | float)
            or not math.isfinite(delta)
            or delta < 0
        ):
            raise InvalidValueError(
                ",".join(requested), delta, "a delta is a number >= 0"
            )
        if not requested:
            return
        conn = self._live()
        errors = await self._barrier(
            conn, [_enable_line(name, delta) for name in requested]
        )
        failed = self._failed_names(requested, errors)
        for name in requested:
            if name.lower() not in failed:
                self._enabled[name.lower()] = (name, delta)
        if errors:
            path = next(iter(failed.values()), requested[0])
            raise _error_for(errors[0], path=path)

    async def disable(self, names: Iterable[str]) -> None:
        """``DI:`` each name: stop pushing its changes."""
        requested = [_check_name(name) for name in names]
        for name in requested:
            self._enabled.pop(name.lower(), None)
        if not requested:
            return
        conn = self._live()
        errors = await self._barrier(conn, [f"DI:{name}" for name in requested])
        if errors:
            failed = self._failed_names(requested, errors)
            raise _error_for(errors[0], path=next(iter(failed.values()), requested[0]))

    async def get_info(self, key: str | None = None) -> dict[str, str]:
        """``GETINFO:`` (all keys, or one): the server's and the PLC's facts."""
        if key is not None:
            _check_name(key)
        conn = self._live()
        info: dict[str, str] = await self._command(
            conn, [f"GETINFO:{key or ''}"], _InfoExchange(key)
        )
        return info

    # --- internals: commands ---------------------------------------------------------

    def _live(self) -> _Connection:
        """Return the connection commands may use; raise PlcConnectionError otherwise."""
        conn = self._conn
        if conn is None or conn.lost.done() or not self._ready:
            raise PlcConnectionError(
                f"Not connected to PLCComS at {self.host}:{self.port}"
            )
        return conn

    def _known(self, name: str) -> str:
        """Return the name if ``LIST:`` holds it (patterns and ``__*`` always pass)."""
        if (
            self._listed is not None
            and "*" not in name
            and not name.startswith("__")
            and name.lower() not in self._variables
        ):
            raise VariableNotFoundError(
                f"{name!r} is not a PLCComS variable", path=name
            )
        return name

    @staticmethod
    def _failed_names(names: list[str], errors: list[ServerError]) -> dict[str, str]:
        """Return the names the errors mention, by lower-case name."""
        by_key = {name.lower(): name for name in names}
        failed: dict[str, str] = {}
        for error in errors:
            key = _named_in(error, by_key)
            if key is not None:
                failed[key] = by_key[key]
        return failed

    async def _list(self, conn: _Connection) -> tuple[PlcComsVariable, ...]:
        variables: tuple[PlcComsVariable, ...] = await self._command(
            conn, ["LIST:"], _ListExchange(self._max_variables, self._count_malformed)
        )
        self._listed = variables
        self._variables = {}
        for variable in variables:
            self._variables.setdefault(variable.key, variable)
        return variables

    async def _barrier(self, conn: _Connection, lines: list[str]) -> list[ServerError]:
        """Send commands that answer only on failure; the errors they caused."""
        errors: list[ServerError] = await self._command(
            conn, [*lines, f"GET:{PLC_RUN}"], _BarrierExchange()
        )
        return errors

    async def _command(
        self,
        conn: _Connection,
        lines: list[str],
        exchange: _Exchange,
        deadline: float | None = None,
    ) -> Any:
        """Send lines and await their answer; one command in flight at a time.

        No answer within the timeout means the connection stalled: it is closed
        (and opened again by the supervisor).
        """
        timeout = deadline or self._timeout
        try:
            async with asyncio.timeout(timeout), self._lock:
                if conn.lost.done():
                    raise PlcConnectionError(
                        f"PLCComS connection lost: {conn.lost.result()}"
                    )
                conn.pending = exchange
                try:
                    await self._send(conn, lines)
                    return await exchange.future
                finally:
                    conn.pending = None
        except TimeoutError as err:
            if self._drop(conn, f"no answer within {timeout:g} s"):
                self._stalls += 1
            raise PlcConnectionError(
                f"PLCComS at {self.host}:{self.port} did not answer within {timeout:g} s"
            ) from err

    async def _send(self, conn: _Connection, lines: list[str]) -> None:
        data = "".join(f"{line}\n" for line in lines).encode(ENCODING)
        try:
            conn.writer.write(data)
            await conn.writer.drain()
        except (OSError, RuntimeError) as err:
            self._drop(conn, f"sending failed: {type(err).__name__}")
            raise PlcConnectionError(
                f"Cannot send to PLCComS at {self.host}:{self.port}"
            ) from err
        self._lines_sent += len(lines)
        _LOGGER.debug("PLCComS <- %s", lines)

    # --- internals: connection -----------------------------------------------------

    async def _open(self) -> None:
        """Open a connection and set it up; PlcConnectionError if it fails."""
        try:
            async with asyncio.timeout(self._timeout):
                reader, writer = await asyncio.open_connection(self.host, self.port)
        except (OSError, TimeoutError) as err:
            self._last_error = f"cannot connect: {type(err).__name__}"
            self._failure = PlcConnectionError(
                f"Cannot reach PLCComS at {self.host}:{self.port}: {_describe(err)}"
            )
            raise self._failure from err
        conn = _Connection(reader, writer, self._max_line_length)
        self._conn = conn
        # A restarted server may write dates otherwise (PLCComS.ini changed):
        # its form is learnt again from what this connection reads.
        self._dates = None
        self._last_line_monotonic = time.monotonic()
        self._spawn(conn, self._read(conn))
        try:
            await self._setup(conn)
        except BaseException as err:
            self._last_error = str(err)
            self._drop(
                conn,
                f"setup failed: {err}",
                err if isinstance(err, PlcError) else None,
            )
            await self._finish(conn)
            raise
        self._spawn(conn, self._keepalive(conn))
        self._set_ready(True, "")

    async def _setup(self, conn: _Connection) -> None:
        """Read LIST: and the run state, enable what was enabled, read it again.

        A server that enables every variable for a new connection has them
        disabled first: only what this client enables is pushed.
        """
        before = self._listed
        variables = await self._list(conn)
        resend = [
            (name, delta)
            for key, (name, delta) in self._enabled.items()
            if "*" in name or key in self._variables or name.startswith("__")
        ]
        unwanted = any(
            variable.enabled
            and not variable.name.startswith("__")
            and variable.key not in self._enabled
            for variable in variables
        )
        errors = await self._barrier(
            conn,
            [
                *(["DI:*"] if unwanted else []),
                *(_enable_line(name, delta) for name, delta in resend),
            ],
        )
        for error in errors:
            _LOGGER.debug("PLCComS refused to enable again: %s", error.message)
        readable = [name for name, _ in resend if "*" not in name]
        if readable:
            with contextlib.suppress(VariableNotFoundError):
                values = await self._command(
                    conn, [f"GET:{name}" for name in readable], _GetExchange(readable)
                )
                for key, value in values.items():
                    variable = self._variables.get(key)
                    name = variable.name if variable else key
                    self._emit(ValueChanged(key, name, value, "", pushed=False))
        if before is not None and before != variables:
            self._emit(ProgramChanged(build_catalogue(variables)))

    def _spawn(self, conn: _Connection, coroutine: Coroutine[Any, Any, None]) -> None:
        task: asyncio.Task[None] = asyncio.create_task(coroutine)
        conn.tasks.add(task)
        task.add_done_callback(conn.tasks.discard)

    async def _finish(self, conn: _Connection) -> None:
        """Wait for a dropped connection's tasks and socket to end."""
        current = asyncio.current_task()
        tasks = [task for task in conn.tasks if task is not current]
        for task in tasks:
            task.cancel()
        await asyncio.gather(*tasks, return_exceptions=True)
        with contextlib.suppress(OSError, TimeoutError):
            async with asyncio.timeout(self._timeout):
                await conn.writer.wait_closed()

    def _drop(
        self, conn: _Connection, reason: str, failure: PlcError | None = None
    ) -> bool:
        """Close a connection at once; whether it was still open.

        ``failure`` is why, for :attr:`failure` (a lost connection by default).
        """
        if conn.lost.done():
            return False
        _LOGGER.debug(
            "PLCComS connection to %s:%s closed: %s", self.host, self.port, reason
        )
        conn.lost.set_result(reason)
        conn.writer.transport.abort()
        if conn.pending is not None:
            conn.pending.fail(PlcConnectionError(f"PLCComS connection lost: {reason}"))
        current = asyncio.current_task()
        for task in conn.tasks:
            if task is not current:
                task.cancel()
        if conn is self._conn:
            self._last_error = reason
            self._failure = failure or PlcConnectionError(
                f"PLCComS connection lost: {reason}"
            )
            self._set_ready(False, reason)
        return True

    def _set_ready(self, ready: bool, reason: str) -> None:
        if ready == self._ready:
            return
        self._ready = ready
        self._emit(ConnectionChanged(ready, reason))

    async def _supervise(self) -> None:
        """Reconnect when the connection is lost; set up again when the PLC restarts."""
        while not self._closing:
            conn = self._conn
            assert conn is not None
            resync: asyncio.Future[Any] = asyncio.ensure_future(self._resync.wait())
            try:
                lost: asyncio.Future[Any] = conn.lost
                await asyncio.wait({lost, resync}, return_when=asyncio.FIRST_COMPLETED)
            finally:
                resync.cancel()
            if not conn.lost.done():
                self._resync.clear()
                try:
                    await self._setup(conn)
                except PlcError as err:
                    self._drop(conn, f"setting up again failed: {err}")
                continue
            await self._finish(conn)
            await self._reconnect()

    async def _reconnect(self) -> None:
        """Open a new connection, waiting longer after each failed attempt."""
        attempt = 0
        while not self._closing:
            await self._sleep(
                backoff_delay(attempt, self._reconnect_delay, self._reconnect_max_delay)
            )
            self._reconnect_attempts += 1
            try:
                await self._open()
            except PlcError as err:
                _LOGGER.debug(
                    "PLCComS reconnect attempt %d failed: %s", attempt + 1, err
                )
                attempt += 1
                continue
            self._reconnects += 1
            self._resync.clear()
            return

    async def _keepalive(self, conn: _Connection) -> None:
        """Ask ``GET:__PLC_RUN`` when the server has been quiet; a silent one is dropped."""
        while not conn.lost.done():
            last = self._last_line_monotonic or time.monotonic()
            idle = time.monotonic() - last
            if idle < self._keepalive_interval:
                await asyncio.sleep(self._keepalive_interval - idle)
                continue
            self._keepalives += 1
            with contextlib.suppress(PlcError):
                await self._command(
                    conn,
                    [f"GET:{PLC_RUN}"],
                    _GetExchange([PLC_RUN]),
                    self._keepalive_timeout,
                )

    async def _read(self, conn: _Connection) -> None:
        """Read lines until the connection ends; each is handled as it arrives."""
        try:
            while data := await conn.reader.read(_READ_CHUNK):
                discarded = conn.framer.discarded
                lines = conn.framer.feed(data)
                if conn.framer.discarded != discarded:
                    self._discarded += conn.framer.discarded - discarded
                    _LOGGER.debug(
                        "PLCComS sent a line over %d bytes", self._max_line_length
                    )
                for line in lines:
                    self._on_line(conn, line)
        except OSError as err:
            self._drop(conn, f"connection error: {_describe(err)}")
            return
        except Exception:
            # A bug here must not leave a connection nobody reads: drop it, and
            # the supervisor opens a new one.
            _LOGGER.exception("Handling a PLCComS line failed")
            self._drop(conn, "internal error")
            return
        self._drop(conn, "closed by the server")

    # --- internals: lines ----------------------------------------------------------

    def _count_malformed(self, text: str) -> None:
        self._malformed += 1
        _LOGGER.debug("PLCComS sent a line this client cannot read: %r", text)

    def _on_line(self, conn: _Connection, raw: bytes) -> None:
        """Handle one line from the server."""
        self._lines_received += 1
        self._last_line_monotonic = time.monotonic()
        self._last_line_at = datetime.now(UTC)
        text = raw.decode(ENCODING, errors="replace")
        if not text.strip():
            return
        parts = split_line(text)
        if parts is None:
            self._count_malformed(text)
            return
        command, rest = parts
        match command:
            case "DIFF" | "GET":
                self._on_value(conn, command, rest)
            case "LIST" | "GETINFO":
                if conn.pending is None or not conn.pending.take(command, rest):
                    _LOGGER.debug("PLCComS sent an answer nobody asked for: %r", text)
            case "ERROR":
                error = parse_server_error(command, rest)
                _LOGGER.debug("PLCComS ERROR: %s %s", error.code, error.message)
                self._server_errors += 1
                if error.number in PLC_COMMUNICATION_CODES:
                    self._on_plc_unreachable(conn, error)
                elif conn.pending is not None:
                    conn.pending.error(error)
            case "WARNING" | "EN" | "DI":
                # Notices (WARNING:252 answers EN:/DI:; older servers answered
                # them with the values): never a value, never another's answer.
                _LOGGER.debug("PLCComS notice: %r", text)
            case _:
                self._count_malformed(text)

    def _on_plc_unreachable(self, conn: _Connection, error: ServerError) -> None:
        """Fail the command and start over later: the server cannot reach its PLC.

        The connection is dropped and opened again with backoff; the setup then
        reads everything again once the PLC answers (nothing pushed is missed).
        """
        failure = _error_for(error, path="")
        if conn.pending is not None:
            conn.pending.fail(failure)
        self._drop(conn, str(failure), failure)

    def _on_value(self, conn: _Connection, command: str, rest: str) -> None:
        """Handle a ``GET:`` answer or a ``DIFF:`` push."""
        answer = split_answer(rest)
        if answer is None:
            self._count_malformed(f"{command}:{rest}")
            return
        name, text = answer
        key = name.lower()
        variable = self._variables.get(key)
        if variable is not None:
            value = parse_variable(variable.type, text)
            if variable.kind in _DATE_KINDS:
                self._dates = learn_date_form(self._dates, text)
        else:
            kind = ValueKind.BOOL if key == _PLC_RUN_KEY else None
            value = parse_value(kind, text)
        if key == _PLC_RUN_KEY:
            self._on_run_state(value)
        if command == "GET":
            if conn.pending is None or not conn.pending.take_value(name, value):
                _LOGGER.debug("PLCComS answered GET: %s nobody waits for", name)
            return
        if key != _PLC_RUN_KEY:
            self._emit(
                ValueChanged(key, variable.name if variable else name, value, text)
            )

    def _on_run_state(self, value: Any) -> None:
        """``__PLC_RUN``: notify a change; 0 -> 1 means LIST: must be read again."""
        if not isinstance(value, bool):
            return
        before, self._plc_running = self._plc_running, value
        if before is None or before == value:
            return
        self._emit(RunStateChanged(value))
        if value and self._ready:
            self._resync.set()

    def _emit(self, event: PlcComsEvent) -> None:
        for callback in list(self._callbacks):
            try:
                callback(event)
            except Exception:
                _LOGGER.exception("A PLCComS subscriber failed on %s", event)


def _describe(err: BaseException) -> str:
    """Describe an exception briefly, for logs and ``last_error``."""
    return str(err) or type(err).__name__


def _enable_line(name: str, delta: float | None) -> str:
    """``EN:name`` or ``EN:name delta``."""
    return f"EN:{name}" if not delta else f"EN:{name} {plain_number(delta)}"
