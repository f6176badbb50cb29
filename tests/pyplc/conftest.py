"""Fixtures for the client tests: sessions, clients and simulators of every setup."""

import asyncio
from collections.abc import AsyncIterator, Awaitable, Callable
import contextlib
from datetime import UTC, datetime, timedelta
import ssl
from typing import Any

import aiohttp
import pytest

from custom_components.tecoapi.pyplc.tecomat import TecoApiClient
from tests.conftest import SIM_PASSWORD, SIM_USERNAME, Certificate
from tests.simulator import Simulator

type StartSimulator = Callable[..., Awaitable[Simulator]]

START = datetime(2026, 3, 14, 10, 0, tzinfo=UTC)
"""Where a test's :class:`Clock` starts."""


class Clock:
    """A clock the test moves by hand (a source's ``clock``)."""

    def __init__(self) -> None:
        self.now = START

    def __call__(self) -> datetime:
        return self.now

    def tick(self, seconds: float) -> None:
        self.now += timedelta(seconds=seconds)


WAIT = 5.0
"""Safety net: a broken client or source fails the test instead of hanging it."""


class Heard[T]:
    """What a subscription delivered, awaitable by condition.

    ``subscribe`` is a client's or source's ``subscribe``; ``unsubscribe`` is what
    it returned.
    """

    def __init__(
        self, subscribe: Callable[[Callable[[T], None]], Callable[[], None]]
    ) -> None:
        self.items: list[T] = []
        self._arrived = asyncio.Event()
        self.unsubscribe = subscribe(self._take)

    def _take(self, item: T) -> None:
        self.items.append(item)
        arrived, self._arrived = self._arrived, asyncio.Event()
        arrived.set()

    async def wait_for(
        self, condition: Callable[[T], bool], count: int = 1, *, start: int = 0
    ) -> T:
        """The `count`-th item from index `start` on that meets `condition`."""
        async with asyncio.timeout(WAIT):
            index = start
            while True:
                while index < len(self.items):
                    if condition(self.items[index]):
                        count -= 1
                        if count == 0:
                            return self.items[index]
                    index += 1
                await self._arrived.wait()

    async def nth(self, count: int) -> T:
        """The `count`-th item delivered (from 1)."""
        return await self.wait_for(lambda _: True, count)


class HeaderLog:
    """The Authorization headers a session sent, in order (from a trace config)."""

    def __init__(self) -> None:
        self.authorizations: list[str | None] = []
        self.accepts: list[str | None] = []
        self.trace = aiohttp.TraceConfig()
        self.trace.on_request_headers_sent.append(self._sent)

    async def _sent(
        self,
        session: aiohttp.ClientSession,
        context: Any,
        params: aiohttp.TraceRequestHeadersSentParams,
    ) -> None:
        self.authorizations.append(params.headers.get("Authorization"))
        self.accepts.append(params.headers.get("Accept"))


@pytest.fixture
def header_log() -> HeaderLog:
    return HeaderLog()


@pytest.fixture
async def session(header_log: HeaderLog) -> AsyncIterator[aiohttp.ClientSession]:
    """A plain aiohttp session, as Home Assistant would inject one."""
    async with aiohttp.ClientSession(trace_configs=[header_log.trace]) as session:
        yield session


def make_client(
    session: aiohttp.ClientSession, sim: Simulator, **options: Any
) -> TecoApiClient:
    """A client of a simulator with the test credentials."""
    return TecoApiClient(session, sim.url, SIM_USERNAME, SIM_PASSWORD, **options)


@pytest.fixture
def client(session: aiohttp.ClientSession, simulator: Simulator) -> TecoApiClient:
    """A client of the demo simulator."""
    return make_client(session, simulator)


@pytest.fixture
def manual_client(
    session: aiohttp.ClientSession, manual_simulator: Simulator
) -> TecoApiClient:
    """A client of the manual's simulator."""
    return make_client(session, manual_simulator)


@pytest.fixture
async def start_simulator(socket_enabled: None) -> AsyncIterator[StartSimulator]:
    """Start simulators of any setup on 127.0.0.1; all are stopped afterwards."""
    async with contextlib.AsyncExitStack() as stack:

        async def start(
            program: Any = "manual",
            *,
            ssl_context: ssl.SSLContext | None = None,
            **options: Any,
        ) -> Simulator:
            options.setdefault("username", SIM_USERNAME)
            options.setdefault("password", SIM_PASSWORD)
            sim = Simulator(program, **options)
            await sim.start(ssl_context=ssl_context)
            stack.push_async_callback(sim.stop)
            return sim

        yield start


@pytest.fixture
def server_tls(certificate: Certificate) -> ssl.SSLContext:
    """The PLC's side of TLS with the self-signed certificate."""
    return certificate.server_context()
