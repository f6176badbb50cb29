"""A simulated PLC running on its own thread and event loop.

Home Assistant's CPU time per poll is measured on Home Assistant's event-loop thread;
the PLC's own work (parsing requests, rendering JSON) runs on this thread instead, so
it is not counted as Home Assistant's. Its PLCComS server, when started, runs there
too, on the same PLC memory. `LoopThread` is that thread and loop; the Mervis, FP-I4C
and Tekon benchmarks serve their simulators from one too.
"""

import asyncio
from collections.abc import Callable, Coroutine
import threading
from types import TracebackType
from typing import Any, Self

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


class PlcThread:
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
        self._program = program
        self._username = username
        self._password = password
        self._latency = latency
        self._latency_per_item = latency_per_item
        self._loop_thread = LoopThread("simulated-plc")
        self._simulator: Simulator | None = None
        self._plccoms: PlcComsServer | None = None

    async def __aenter__(self) -> Self:
        """Start the thread and the simulator on it."""
        self._loop_thread.start()
        self._simulator = await self._loop_thread.run(self._start())
        return self

    async def __aexit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        traceback: TracebackType | None,
    ) -> None:
        """Stop the PLCComS server and the simulator, then the thread."""
        if self._plccoms is not None:
            await self._loop_thread.run(self._plccoms.stop())
        if self._simulator is not None:
            await self._loop_thread.run(self._simulator.stop())
        await self._loop_thread.stop()

    async def _start(self) -> Simulator:
        simulator = Simulator(
            self._program, username=self._username, password=self._password
        )
        simulator.faults.latency = self._latency
        simulator.faults.latency_per_item = self._latency_per_item
        await simulator.start()
        return simulator

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

        self._plccoms = await self._loop_thread.run(start())
        return self._plccoms.port

    @property
    def simulator(self) -> Simulator:
        """The simulator; touch it only through `call`."""
        if self._simulator is None:
            raise RuntimeError("the PLC thread is not running")
        return self._simulator

    @property
    def url(self) -> str:
        """The PLC's base URL."""
        return self.simulator.url

    @property
    def requests(self) -> list[RequestRecord]:
        """Every request the PLC received, in arrival order."""
        return self.simulator.requests

    async def call[T](self, function: Callable[[Simulator], T]) -> T:
        """Run `function(simulator)` on the PLC's loop and return its result."""
        simulator = self.simulator

        async def run() -> T:
            return function(simulator)

        return await self._loop_thread.run(run())
