"""What every simulator shares: serving on a port, its lifecycle, its request log.

The protocols differ; the serving does not. :class:`Served` is a simulator
started and stopped on a TCP port (``async with``, ``port``, waits without
sleeping); :class:`HttpSimulator` serves an aiohttp application on it (HTTPS
with an SSL context), logs the requests that arrive, answers one at a time where
the device does (``serialize``), pauses like a slow device and drops a
connection without a byte of answer. TecoApi, Mervis, FP-I4C and Tekon are
HttpSimulators; PLCComS (TCP) is Served. ``stop_signal``, ``tls_context`` and
``run`` are what their command lines share.
"""

from abc import ABC, abstractmethod
import asyncio
from collections.abc import AsyncIterator, Awaitable, Callable
import contextlib
import logging
import signal
import ssl
import sys
from types import TracebackType
from typing import Any, Final, Self

from aiohttp import web

LOG_FORMAT: Final = "%(asctime)s %(levelname)s %(name)s: %(message)s"


class Progress:
    """Something a test waits for without sleeping: each ``notify`` wakes every waiter."""

    def __init__(self) -> None:
        """Nothing has happened yet."""
        self._event = asyncio.Event()

    def notify(self) -> None:
        """Something changed: every waiter checks its condition again."""
        event, self._event = self._event, asyncio.Event()
        event.set()

    async def wait_until(self, done: Callable[[], bool]) -> None:
        """Return once ``done()`` holds (checked at once and after every notify)."""
        while not done():
            await self._event.wait()


class Served(ABC):
    """A simulator listening on a TCP port: ``start``, ``stop``, ``async with``.

    ``start(host, port)`` (port 0 picks a free one) and an idempotent ``stop``
    are the subclass's; ``async with`` starts it on 127.0.0.1 with a free port.
    ``_progress`` wakes the tests waiting for something to arrive; it is made
    again at every start, as a simulator may be started again under another
    event loop.
    """

    def __init__(self) -> None:
        """Nothing listens before ``start``."""
        self._bound_host = "127.0.0.1"
        self._port = 0
        self._progress = Progress()

    @abstractmethod
    async def start(self, host: str = "127.0.0.1", port: int = 0) -> None:
        """Listen on host:port (0 picks a free port)."""

    @abstractmethod
    async def stop(self) -> None:
        """Stop listening; idempotent."""

    async def __aenter__(self) -> Self:
        """Start on 127.0.0.1 with a free port."""
        await self.start()
        return self

    async def __aexit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        traceback: TracebackType | None,
    ) -> None:
        """Stop."""
        await self.stop()

    @property
    def port(self) -> int:
        """The TCP port served (0 before start)."""
        return self._port


class ConnectionDroppedError(Exception):
    """Raised by a handler: the connection closes without a byte of answer.

    ``reset`` aborts it (TCP RST, as the simulator stopping or a broken link);
    otherwise it is closed (FIN, an answer lost after the work was done).
    """

    def __init__(self, *, reset: bool = True) -> None:
        """Drop the connection; ``reset`` aborts rather than closes it."""
        super().__init__("connection dropped")
        self.reset = reset


@web.middleware
async def _drop_connections(
    request: web.Request,
    handler: Callable[[web.Request], Awaitable[web.StreamResponse]],
) -> web.StreamResponse:
    """Turn a handler's :class:`ConnectionDroppedError` into a dropped connection."""
    try:
        return await handler(request)
    except ConnectionDroppedError as drop:
        transport = request.transport
        if drop.reset:
            if transport is not None:
                transport.abort()
            return web.Response(status=500)
        assert transport is not None
        transport.close()
        raise web.HTTPServiceUnavailable from None


async def serve(
    app: web.Application,
    host: str,
    port: int,
    ssl_context: ssl.SSLContext | None = None,
) -> tuple[web.AppRunner, int]:
    """Listen on host:port (0 picks a free port); return the runner and the port bound.

    HTTPS with an SSL context. A port that cannot be bound leaves nothing running;
    the runner's cleanup stops serving, giving open requests a second to end.
    """
    runner = web.AppRunner(
        app, access_log=None, handle_signals=False, shutdown_timeout=1.0
    )
    await runner.setup()
    try:
        await web.TCPSite(runner, host, port, ssl_context=ssl_context).start()
    except BaseException:
        await runner.cleanup()
        raise
    return runner, runner.addresses[0][1]


class HttpSimulator[RecordT](Served):
    """A simulated device's web server: an aiohttp application on a port.

    A subclass adds its routes (``_routes``) and answers its protocol; this base
    starts and stops it, names where it is (``port``, ``host``, ``url``), keeps
    ``requests`` (what the subclass ``_record``s, in arrival order) for
    ``wait_for_requests`` and ``clear_requests``, answers one request at a time
    when ``serialize`` is set (``async with self._turn()``), pauses like a slow
    device (``_pause``) and drops a connection when a handler raises
    :class:`ConnectionDroppedError`. ``stop`` sets ``_stopping`` first, so a
    paused or streaming request ends at once.
    """

    client_max_size: int = 1024**2
    """The largest request body the application reads (aiohttp's default)."""

    def __init__(self, *, serialize: bool = False) -> None:
        """Nothing listens before ``start``; ``serialize``: one request at a time."""
        super().__init__()
        self.requests: list[RecordT] = []
        self.serialize = serialize
        self._runner: web.AppRunner | None = None
        self._scheme = "http"
        self._stopping = asyncio.Event()
        self._busy = asyncio.Lock()

    @abstractmethod
    def _routes(self, app: web.Application) -> None:
        """Add the device's routes to its application."""

    def _starting(self) -> None:
        """Make afresh what requests wait for (called by ``start`` before it listens)."""

    def _stopped(self) -> None:
        """Let go whatever a request waits for (called by ``stop`` while running)."""

    # --- lifecycle ---------------------------------------------------------------------

    async def start(
        self,
        host: str = "127.0.0.1",
        port: int = 0,
        ssl_context: ssl.SSLContext | None = None,
    ) -> None:
        """Listen on host:port (0 picks a free port); HTTPS with an SSL context."""
        if self._runner is not None:
            raise RuntimeError("the simulator is already running")
        # Fresh primitives: a simulator may be started again under another event loop.
        self._progress = Progress()
        self._stopping = asyncio.Event()
        self._busy = asyncio.Lock()
        self._starting()
        app = web.Application(
            middlewares=[_drop_connections], client_max_size=self.client_max_size
        )
        self._routes(app)
        self._runner, self._port = await serve(app, host, port, ssl_context)
        self._scheme = "https" if ssl_context is not None else "http"
        self._bound_host = host

    async def stop(self) -> None:
        """Stop serving; paused and waiting requests lose their connection. Idempotent."""
        runner, self._runner = self._runner, None
        if runner is None:
            return
        self._stopping.set()
        self._stopped()
        await runner.cleanup()

    @property
    def host(self) -> str:
        """``127.0.0.1:PORT``, what a user types into the config flow."""
        return f"{self._bound_host}:{self._port}"

    @property
    def url(self) -> str:
        """``http://127.0.0.1:PORT`` (or https)."""
        return f"{self._scheme}://{self.host}"

    # --- the request log ---------------------------------------------------------------

    def clear_requests(self) -> None:
        """Forget the requests received so far."""
        self.requests.clear()

    async def wait_for_requests(self, count: int) -> None:
        """Wait until ``requests`` holds at least ``count`` records (no polling needed)."""
        await self._progress.wait_until(lambda: len(self.requests) >= count)

    def _record(self, record: RecordT) -> None:
        """Log a request that arrived and wake the tests waiting for it."""
        self.requests.append(record)
        self._progress.notify()

    # --- timing --------------------------------------------------------------------------

    @contextlib.asynccontextmanager
    async def _turn(self) -> AsyncIterator[None]:
        """One request at a time, like the device's web server (when ``serialize``)."""
        if not self.serialize:
            yield
            return
        async with self._busy:
            yield

    async def _pause(self, seconds: float) -> None:
        """Wait like a slow device; the connection drops if the simulator stops meanwhile."""
        if seconds <= 0:
            return
        with contextlib.suppress(TimeoutError):
            async with asyncio.timeout(seconds):
                await self._stopping.wait()
        if self._stopping.is_set():
            raise ConnectionDroppedError


# --- the command lines -----------------------------------------------------------------


def stop_signal() -> asyncio.Event:
    """An event SIGINT or SIGTERM sets (install it before printing where it serves)."""
    stop = asyncio.Event()
    loop = asyncio.get_running_loop()
    for signal_number in (signal.SIGINT, signal.SIGTERM):
        loop.add_signal_handler(signal_number, stop.set)
    return stop


def tls_context(cert: str | None, key: str | None) -> ssl.SSLContext | None:
    """The server's TLS context of a PEM certificate and its key (None: plain HTTP)."""
    if not cert:
        return None
    context = ssl.create_default_context(ssl.Purpose.CLIENT_AUTH)
    context.load_cert_chain(cert, key)
    return context


def run(
    serving: Callable[[], Awaitable[Any]],
    *,
    errors: tuple[type[Exception], ...] = (OSError,),
) -> int:
    """Log at INFO and serve; 0 once stopped, 1 after ``error: ...`` on stderr.

    ``errors`` are what a user gets wrong (a port taken, a program that does not
    load); anything else is a bug and keeps its traceback.
    """
    logging.basicConfig(level=logging.INFO, format=LOG_FORMAT)

    async def main() -> None:
        await serving()

    try:
        asyncio.run(main())
    except errors as err:
        print(f"error: {err}", file=sys.stderr)
        return 1
    return 0
