"""A PLCComS connection that keeps itself open: the client's lower half.

:class:`Connection` is one TCP connection (its streams, line framer, reader task
and the command in flight); :class:`SupervisedConnection` opens one, sends
commands on it one at a time, reads its lines, asks ``GET:__PLC_RUN`` when it
goes quiet, and opens a new one with backoff when it is lost. What a line
means, and what a new connection is set up with, is its subclass's
(:class:`~.client.PlcComsClient`): :meth:`SupervisedConnection._on_line` and
:meth:`SupervisedConnection._setup`. The client's module docstring describes the
behaviour as a whole.

Two seams let a caller stand between the client and the world: ``sleep`` is
the wait between reconnect attempts (``asyncio.sleep``), ``open_connection``
opens the TCP streams (``asyncio.open_connection``; what it returns to read
from needs only ``read``, :class:`StreamSource`).
"""

from abc import ABC, abstractmethod
import asyncio
from collections.abc import Awaitable, Callable, Coroutine
import contextlib
import logging
import time
from types import TracebackType
from typing import TYPE_CHECKING, Any, Final, Protocol, Self

from ...core.backoff import Backoff
from ...core.exceptions import PlcConnectionError, PlcError
from ...core.models import WireCounts
from .events import ConnectionChanged, PlcComsCallback, PlcComsEvent
from .exchanges import Exchange, GetExchange
from .protocol import ENCODING, PLC_RUN, LineFramer

if TYPE_CHECKING:
    from datetime import datetime

_LOGGER = logging.getLogger(__name__)

_READ_CHUNK: Final = 65536


class StreamSource(Protocol):
    """What a connection reads the server's bytes from (an ``asyncio.StreamReader``)."""

    async def read(self, n: int = -1) -> bytes:
        """Return up to ``n`` bytes as they arrive; b"" once the server closed."""


type OpenConnection = Callable[
    [str, int], Awaitable[tuple[StreamSource, asyncio.StreamWriter]]
]
"""Opens a TCP connection to ``(host, port)``: its streams to read and write."""

type Sleep = Callable[[float], Awaitable[object]]
"""Waits so many seconds."""


class Connection:
    """One TCP connection: its streams, framer, reader task and command in flight."""

    def __init__(
        self,
        reader: StreamSource,
        writer: asyncio.StreamWriter,
        max_line_length: int,
    ) -> None:
        """Take an opened connection's streams."""
        self.reader = reader
        self.writer = writer
        self.framer = LineFramer(max_line_length)
        self.lost: asyncio.Future[str] = asyncio.get_running_loop().create_future()
        self.pending: Exchange | None = None
        self.tasks: set[asyncio.Task[None]] = set()


class SupervisedConnection(ABC):
    """The connection of a client to one PLCComS server, kept open (see the module)."""

    def __init__(
        self,
        host: str,
        port: int,
        *,
        timeout: float,
        keepalive_interval: float,
        keepalive_timeout: float | None,
        reconnect_delay: float,
        reconnect_max_delay: float,
        max_line_length: int,
        sleep: Sleep = asyncio.sleep,
        open_connection: OpenConnection = asyncio.open_connection,
    ) -> None:
        """Prepare the connection; nothing is opened until :meth:`connect`.

        ``sleep`` waits between reconnect attempts and ``open_connection`` opens
        each connection (the module's seams).
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
        self._sleep = sleep
        self._open_connection = open_connection
        self._lock = asyncio.Lock()
        self._conn: Connection | None = None
        self._supervisor: asyncio.Task[None] | None = None
        self._resync = asyncio.Event()
        self._ready = False
        self._closing = False
        self._callbacks: list[PlcComsCallback] = []
        self._failure: PlcError | None = None
        self._last_line_monotonic: float | None = None
        self._last_line_at: datetime | None = None
        self._lines_received = 0
        self.wire = WireCounts()
        """The command lines sent (each a request)."""
        self._discarded = 0
        self._malformed = 0
        self._server_errors = 0
        self._keepalives = 0
        self._stalls = 0
        self._reconnects = 0
        self._reconnect_attempts = 0
        self._last_error: str | None = None
        self._commands = 0

    @abstractmethod
    async def _setup(self, conn: Connection) -> None:
        """Set up a new connection, or the same one after the PLC restarted."""

    @abstractmethod
    def _on_line(self, conn: Connection, raw: bytes) -> None:
        """Handle one line from the server."""

    @abstractmethod
    def _new_connection(self) -> None:
        """Forget what a new connection learns again (before it is set up)."""

    # --- state -------------------------------------------------------------------

    @property
    def connected(self) -> bool:
        """Whether the client is connected, listed and enabled: push can be relied on."""
        return self._ready

    @property
    def failure(self) -> PlcError | None:
        """Why the client is not connected now (None while it is, or before trying).

        A :class:`PlcUnreachableError` while the server answers but cannot reach
        its PLC; else the last failure of connecting or setting up.
        """
        return None if self._ready else self._failure

    @property
    def commands_pending(self) -> int:
        """How many commands are sent and not yet answered, or wait their turn."""
        return self._commands

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

    # --- internals: commands ---------------------------------------------------------

    def _live(self) -> Connection:
        """Return the connection commands may use; raise PlcConnectionError otherwise."""
        conn = self._conn
        if conn is None or conn.lost.done() or not self._ready:
            raise PlcConnectionError(
                f"Not connected to PLCComS at {self.host}:{self.port}"
            )
        return conn

    async def _command(
        self,
        conn: Connection,
        lines: list[str],
        exchange: Exchange,
        deadline: float | None = None,
    ) -> Any:
        """Send lines and await their answer; one command in flight at a time.

        No answer within the timeout means the connection stalled: it is closed
        (and opened again by the supervisor).
        """
        timeout = deadline or self._timeout
        self._commands += 1
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
        finally:
            self._commands -= 1

    async def _send(self, conn: Connection, lines: list[str]) -> None:
        data = "".join(f"{line}\n" for line in lines).encode(ENCODING)
        try:
            conn.writer.write(data)
            await conn.writer.drain()
        except (OSError, RuntimeError) as err:
            self._drop(conn, f"sending failed: {type(err).__name__}")
            raise PlcConnectionError(
                f"Cannot send to PLCComS at {self.host}:{self.port}"
            ) from err
        self.wire.requests += len(lines)
        _LOGGER.debug("PLCComS <- %s", lines)

    # --- internals: connection -----------------------------------------------------

    async def _open(self) -> None:
        """Open a connection and set it up; PlcConnectionError if it fails."""
        try:
            async with asyncio.timeout(self._timeout):
                reader, writer = await self._open_connection(self.host, self.port)
        except (OSError, TimeoutError) as err:
            self._last_error = f"cannot connect: {type(err).__name__}"
            self._failure = PlcConnectionError(
                f"Cannot reach PLCComS at {self.host}:{self.port}: {_describe(err)}"
            )
            raise self._failure from err
        conn = Connection(reader, writer, self._max_line_length)
        self._conn = conn
        self._new_connection()
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

    def _spawn(self, conn: Connection, coroutine: Coroutine[Any, Any, None]) -> None:
        task: asyncio.Task[None] = asyncio.create_task(coroutine)
        conn.tasks.add(task)
        task.add_done_callback(conn.tasks.discard)

    async def _finish(self, conn: Connection) -> None:
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
        self, conn: Connection, reason: str, failure: PlcError | None = None
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
        backoff = Backoff(self._reconnect_delay, self._reconnect_max_delay)
        while not self._closing:
            await self._sleep(backoff.failed())
            self._reconnect_attempts += 1
            try:
                await self._open()
            except PlcError as err:
                _LOGGER.debug(
                    "PLCComS reconnect attempt %d failed: %s", backoff.failures, err
                )
                continue
            self._reconnects += 1
            self._resync.clear()
            return

    async def _keepalive(self, conn: Connection) -> None:
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
                    GetExchange([PLC_RUN]),
                    self._keepalive_timeout,
                )

    async def _read(self, conn: Connection) -> None:
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

    def _emit(self, event: PlcComsEvent) -> None:
        for callback in list(self._callbacks):
            try:
                callback(event)
            except Exception:
                _LOGGER.exception("A PLCComS subscriber failed on %s", event)


def _describe(err: BaseException) -> str:
    """Describe an exception briefly, for logs and ``last_error``."""
    return str(err) or type(err).__name__
