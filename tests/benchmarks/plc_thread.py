"""A simulated PLC running on its own thread and event loop.

Home Assistant's CPU time per poll is measured on Home Assistant's event-loop thread;
the PLC's own work (parsing requests, rendering JSON) runs on this thread instead, so
it is not counted as Home Assistant's. Its PLCComS server, when started, runs there
too, on the same PLC memory. `LoopThread` is that thread and loop; `SimulatorThread`
starts a simulator on one, serves from it and stops it (the PLC's, and the Mervis,
FP-I4C and Tekon benchmarks' simulators).
"""

import asyncio
from collections.abc import Callable, Coroutine
import threading
from types import TracebackType
from typing import Any, Protocol, Self

from tests.simulator import Program, RequestRecord, Simulator
from tests.simulator.plccoms import PlcComsServer


class LoopThread:
    """An event loop running in a daemon thread of its own.

    A simulator served from it does its work off Home Assistant's event-loop thread,
    so that work is not counted as Home Assistant's.
    """

    def __init__(self, name: str) -> None:
        """Prepare the loop and its thread (named ``name``); `start` starts them."""
        self._loop = asyncio.new_event_loop()
        self._thread = threading.Thread(
            target=self._loop.run_forever, name=name, daemon=True
        )

    def start(self) -> None:
        """Start running the loop."""
        self._thread.start()

    async def run[T](self, coroutine: Coroutine[Any, Any, T]) -> T:
        """Run a coroutine on this thread's loop and wait for it from the caller's."""
        return await asyncio.wrap_future(
            asyncio.run_coroutine_threadsafe(coroutine, self._loop)
        )

    async def stop(self) -> None:
        """Stop the loop, wait for its thread, close the loop."""
        self._loop.call_soon_threadsafe(self._loop.stop)
        await asyncio.to_thread(self._thread.join)
        self._loop.close()


class Stoppable(Protocol):
    """A simulator: started on its thread's loop, and stopped there."""

    async def stop(self) -> None:
        """Stop serving."""


class SimulatorThread[S: Stoppable]:
    """A simulator served on 127.0.0.1 from a thread and event loop of its own.

    ``start`` makes and starts the simulator (on that loop) when the thread is
    entered; it is stopped there, then the thread, on leaving. Everything that
    touches the simulator goes through `run` or `call` (they run on its loop).
    """

    def __init__(self, name: str, start: Callable[[], Coroutine[Any, Any, S]]) -> None:
        """Prepare the thread (named ``name``) that ``start`` starts a simulator on."""
        self._start = start
        self._loop_thread = LoopThread(name)
        self._served: S | None = None

    async def __aenter__(self) -> Self:
        """Start the thread and the simulator on it."""
        self._loop_thread.start()
        self._served = await self._loop_thread.run(self._start())
        return self

    async def __aexit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        traceback: TracebackType | None,
    ) -> None:
        """Stop the simulator, then the thread."""
        if self._served is not None:
            await self._loop_thread.run(self._served.stop())
        await self._loop_thread.stop()

    @property
    def served(self) -> S:
        """The simulator; touch it only through `run` or `call`."""
        if self._served is None:
            raise RuntimeError("the simulator's thread is not running")
        return self._served

    async def run[T](self, coroutine: Coroutine[Any, Any, T]) -> T:
        """Run a coroutine on the simulator's loop and return its result."""
        return await self._loop_thread.run(coroutine)

    async def call[T](self, function: Callable[[S], T]) -> T:
        """Run ``function(simulator)`` on the simulator's loop and return its result."""
        served = self.served

        async def run() -> T:
            return function(served)

        return await self._loop_thread.run(run())


class PlcThread(SimulatorThread[Simulator]):
    """A `Simulator` serving on 127.0.0.1 from a thread of its own.

    Everything that touches the simulator goes through `call` (it runs on the PLC's
    loop); `requests` may be read from any thread between requests.
    """

    def __init__(
        self,
        program: Program,
        *,
        username: str,
        password: str,
        latency: float = 0.0,
        latency_per_item: float = 0.0,
    ) -> None:
        """Prepare a PLC running `program` with the given latency model (seconds)."""

        async def start() -> Simulator:
            simulator = Simulator(program, username=username, password=password)
            simulator.faults.latency = latency
            simulator.faults.latency_per_item = latency_per_item
            await simulator.start()
            return simulator

        super().__init__("simulated-plc", start)
        self._plccoms: PlcComsServer | None = None

    async def __aexit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        traceback: TracebackType | None,
    ) -> None:
        """Stop the PLCComS server, then the simulator and the thread."""
        if self._plccoms is not None:
            await self.run(self._plccoms.stop())
        await super().__aexit__(exc_type, exc, traceback)

    async def start_plccoms(self, scan_interval: float = 0.1) -> int:
        """Start a PLCComS server of this PLC on 127.0.0.1; its port.

        It detects changes every `scan_interval` seconds, as the real server polls
        the PLC every 100 ms.
        """
        simulator = self.simulator

        async def start() -> PlcComsServer:
            server = PlcComsServer(simulator, scan_interval=scan_interval)
            await server.start()
            return server

        self._plccoms = await self.run(start())
        return self._plccoms.port

    @property
    def simulator(self) -> Simulator:
        """The simulator; touch it only through `call`."""
        return self.served

    @property
    def url(self) -> str:
        """The PLC's base URL."""
        return self.simulator.url

    @property
    def requests(self) -> list[RequestRecord]:
        """Every request the PLC received, in arrival order."""
        return self.simulator.requests
