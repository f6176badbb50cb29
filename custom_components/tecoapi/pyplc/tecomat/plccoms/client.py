"""A PLCComS client: Teco's push-capable text protocol, over asyncio TCP.

PLCComS has no authentication: use it only on a trusted network, and only when the
user asked for it. It imports nothing from Home Assistant.

Client API
----------
``PlcComsClient(host, port=5010, *, timeout=10.0, keepalive_interval=30.0,
keepalive_timeout=None, reconnect_delay=1.0, reconnect_max_delay=60.0,
max_line_length=4096, max_variables=100_000, sleep=asyncio.sleep,
open_connection=asyncio.open_connection)``; ``async with`` connects and closes
(``sleep`` and ``open_connection`` are the seams of :mod:`.connection`).

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
  lower-case name), ``catalogue`` (a neutral ``Catalogue`` of ``Point`` without
  attributes; ``values`` empty, ``__*`` server variables left out).
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
  known), ``enabled``, ``failure`` (why it is not connected), ``commands_pending``
  (sent and unanswered, or waiting their turn) and ``health`` (a ``PlcComsHealth`` snapshot: connection,
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

The parts, each a module of this package: :mod:`.protocol` and
:mod:`.formatting` (the wire, no I/O), :mod:`.connection` (one TCP connection,
and the supervised connection this client is built on: commands one at a
time, the reader, keep-alive and reconnecting), :mod:`.exchanges` (a
command's answer gathered from the lines), :mod:`.errors` (what an ``ERROR:``
means), :mod:`.events` and :mod:`.variables` (``LIST:`` entries and their
catalogue). This module gives the commands, the setup of a connection and
the meaning of each line.
"""

import asyncio
from collections.abc import Iterable, Mapping, Sequence
import contextlib
from datetime import UTC, datetime
import logging
import math
import time
from typing import Any, Final

from ...core.exceptions import (
    InvalidValueError,
    VariableNotFoundError,
)
from ...core.models import Catalogue, ValueKind
from .connection import Connection, OpenConnection, Sleep, SupervisedConnection
from .errors import error_for, named_in
from .events import (
    PlcComsHealth,
    ProgramChanged,
    RunStateChanged,
    ValueChanged,
)
from .exchanges import (
    BarrierExchange,
    GetExchange,
    InfoExchange,
    ListExchange,
    check_name,
    enable_line,
)
from .formatting import format_value
from .protocol import (
    DEFAULT_PORT,
    ENCODING,
    MAX_LINE_LENGTH,
    PLC_COMMUNICATION_CODES,
    PLC_RUN,
    DateForm,
    ServerError,
    learn_date_form,
    parse_server_error,
    parse_value,
    parse_variable,
    split_answer,
    split_line,
)
from .variables import PlcComsVariable, build_catalogue

_LOGGER = logging.getLogger(__name__)

_PLC_RUN_KEY: Final = PLC_RUN.lower()
_DATE_KINDS: Final = frozenset({ValueKind.DATE, ValueKind.DATETIME})


class PlcComsClient(SupervisedConnection):
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
        sleep: Sleep = asyncio.sleep,
        open_connection: OpenConnection = asyncio.open_connection,
    ) -> None:
        """Prepare a client; nothing is sent until :meth:`connect`.

        The module's docstring says what each timing does; ``max_line_length`` and
        ``max_variables`` cap what a server can make the client hold; ``sleep`` and
        ``open_connection`` are the seams of :mod:`.connection`.
        """
        super().__init__(
            host,
            port,
            timeout=timeout,
            keepalive_interval=keepalive_interval,
            keepalive_timeout=keepalive_timeout,
            reconnect_delay=reconnect_delay,
            reconnect_max_delay=reconnect_max_delay,
            max_line_length=max_line_length,
            sleep=sleep,
            open_connection=open_connection,
        )
        self._max_variables = max_variables
        self._variables: dict[str, PlcComsVariable] = {}
        self._listed: tuple[PlcComsVariable, ...] | None = None
        self._enabled: dict[str, tuple[str, float | None]] = {}
        self._plc_running: bool | None = None
        # How the server writes DATE and DT (learnt from the values that prove it;
        # None: nothing did, writes take the manual's default).
        self._dates: DateForm | None = None

    # --- state -------------------------------------------------------------------

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
            lines_sent=self.wire.requests,
            discarded_lines=self._discarded,
            malformed_lines=self._malformed,
            server_errors=self._server_errors,
            keepalives=self._keepalives,
            stalls=self._stalls,
            reconnects=self._reconnects,
            reconnect_attempts=self._reconnect_attempts,
            last_error=self._last_error,
        )

    # --- commands ------------------------------------------------------------------

    async def list_variables(self) -> tuple[PlcComsVariable, ...]:
        """``LIST:``: every variable with its type (flags cut from the names)."""
        conn = self._live()
        return await self._list(conn)

    async def get(self, names: Iterable[str]) -> dict[str, Any]:
        """``GET:`` each name; values by the names as given, typed by their kinds."""
        requested = [self._known(check_name(name)) for name in names]
        if not requested:
            return {}
        conn = self._live()
        unique = list({name.lower(): name for name in requested}.values())
        values: dict[str, Any] = await self._command(
            conn, [f"GET:{name}" for name in unique], GetExchange(unique)
        )
        return {name: values[name.lower()] for name in requested}

    async def set(self, name: str, value: Any) -> None:
        """``SET:`` a value; returns once the server took it, raises if it refused."""
        await self.set_many([(name, value)])

    async def set_many(self, items: Sequence[tuple[str, Any]]) -> None:
        """``SET:`` several values, one line each, then one barrier for them all.

        Every name and value is checked before a line is sent. The server
        answers a SET only when it refuses it (the manual): the first refusal
        is raised, naming its variable, once the barrier came back.
        """
        names = [self._known(check_name(name)) for name, _ in items]
        kinds = [self._kind(name) for name in names]
        values = [value for _, value in items]
        lines = self._set_lines(names, kinds, values)
        dated = [
            name for name, kind in zip(names, kinds, strict=True) if kind in _DATE_KINDS
        ]
        if dated and self._dates is None:
            # Learn the server's DATE/DT form from the variables' own values.
            await self.get(dated)
            lines = self._set_lines(names, kinds, values)
        conn = self._live()
        errors = await self._barrier(conn, lines)
        if errors:
            error = errors[0]
            by_name = {name.lower(): (name, value) for name, value in items}
            name, value = by_name.get(error.variable.lower(), items[0])
            raise error_for(error, path=name, written=True, value=value)

    def _kind(self, name: str) -> ValueKind | None:
        """Return the kind ``LIST:`` gave a variable (None: not listed)."""
        variable = self._variables.get(name.lower())
        return variable.kind if variable else None

    def _set_lines(
        self, names: list[str], kinds: list[ValueKind | None], values: list[Any]
    ) -> list[str]:
        """Spell ``SET:`` lines; a value its variable cannot take is refused."""
        dates = self._dates or DateForm.DOUBLE_BITS
        return [
            f"SET:{name},{format_value(kind, value, name=name, dates=dates)}"
            for name, kind, value in zip(names, kinds, values, strict=True)
        ]

    async def enable(self, names: Iterable[str], delta: float | None = None) -> None:
        """``EN:`` each name: push its changes (of at least ``delta`` for a number).

        The names stay enabled across reconnects and program downloads (while
        ``LIST:`` holds them). A name ``LIST:`` does not hold raises
        VariableNotFoundError before anything is sent; ``*`` patterns are sent as
        they are.
        """
        requested = [self._known(check_name(name)) for name in names]
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
            conn, [enable_line(name, delta) for name in requested]
        )
        failed = self._failed_names(requested, errors)
        for name in requested:
            if name.lower() not in failed:
                self._enabled[name.lower()] = (name, delta)
        if errors:
            path = next(iter(failed.values()), requested[0])
            raise error_for(errors[0], path=path)

    async def disable(self, names: Iterable[str]) -> None:
        """``DI:`` each name: stop pushing its changes."""
        requested = [check_name(name) for name in names]
        for name in requested:
            self._enabled.pop(name.lower(), None)
        if not requested:
            return
        conn = self._live()
        errors = await self._barrier(conn, [f"DI:{name}" for name in requested])
        if errors:
            failed = self._failed_names(requested, errors)
            raise error_for(errors[0], path=next(iter(failed.values()), requested[0]))

    async def get_info(self, key: str | None = None) -> dict[str, str]:
        """``GETINFO:`` (all keys, or one): the server's and the PLC's facts."""
        if key is not None:
            check_name(key)
        conn = self._live()
        info: dict[str, str] = await self._command(
            conn, [f"GETINFO:{key or ''}"], InfoExchange(key)
        )
        return info

    # --- internals: commands ---------------------------------------------------------
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
            key = named_in(error, by_key)
            if key is not None:
                failed[key] = by_key[key]
        return failed

    async def _list(self, conn: Connection) -> tuple[PlcComsVariable, ...]:
        variables: tuple[PlcComsVariable, ...] = await self._command(
            conn, ["LIST:"], ListExchange(self._max_variables, self._count_malformed)
        )
        self._listed = variables
        self._variables = {}
        for variable in variables:
            self._variables.setdefault(variable.key, variable)
        return variables

    async def _barrier(self, conn: Connection, lines: list[str]) -> list[ServerError]:
        """Send commands that answer only on failure; the errors they caused."""
        errors: list[ServerError] = await self._command(
            conn, [*lines, f"GET:{PLC_RUN}"], BarrierExchange()
        )
        return errors

    # --- internals: connection -----------------------------------------------------

    def _new_connection(self) -> None:
        # A restarted server may write dates otherwise (PLCComS.ini changed):
        # its form is learnt again from what this connection reads.
        self._dates = None

    async def _setup(self, conn: Connection) -> None:
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
                *(enable_line(name, delta) for name, delta in resend),
            ],
        )
        for error in errors:
            _LOGGER.debug("PLCComS refused to enable again: %s", error.message)
        readable = [name for name, _ in resend if "*" not in name]
        if readable:
            with contextlib.suppress(VariableNotFoundError):
                values = await self._command(
                    conn, [f"GET:{name}" for name in readable], GetExchange(readable)
                )
                for key, value in values.items():
                    variable = self._variables.get(key)
                    name = variable.name if variable else key
                    self._emit(ValueChanged(key, name, value, "", pushed=False))
        if before is not None and before != variables:
            self._emit(ProgramChanged(build_catalogue(variables)))

    # --- internals: lines ----------------------------------------------------------

    def _count_malformed(self, text: str) -> None:
        self._malformed += 1
        _LOGGER.debug("PLCComS sent a line this client cannot read: %r", text)

    def _on_line(self, conn: Connection, raw: bytes) -> None:
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

    def _on_plc_unreachable(self, conn: Connection, error: ServerError) -> None:
        """Fail the command and start over later: the server cannot reach its PLC.

        The connection is dropped and opened again with backoff; the setup then
        reads everything again once the PLC answers (nothing pushed is missed).
        """
        failure = error_for(error, path="")
        if conn.pending is not None:
            conn.pending.fail(failure)
        self._drop(conn, str(failure), failure)

    def _on_value(self, conn: Connection, command: str, rest: str) -> None:
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
