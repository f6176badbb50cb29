"""Fixtures of the Tekon library's tests: the simulated gateway, a client session, a source."""

from collections.abc import AsyncIterator

import aiohttp
import pytest

from custom_components.tecoapi.pyplc import Snapshot
from custom_components.tecoapi.pyplc.tekon import TekonClient, TekonSource
from tests.pyplc.conftest import Clock
from tests.simulator.tekon import TekonGateway


def key(name: str) -> str:
    """The point key of an item's name."""
    return name.lower()


@pytest.fixture
async def gateway(socket_enabled: None) -> AsyncIterator[TekonGateway]:
    async with TekonGateway() as running:
        yield running


@pytest.fixture
async def http() -> AsyncIterator[aiohttp.ClientSession]:
    async with aiohttp.ClientSession() as session:
        yield session


@pytest.fixture
def clock() -> Clock:
    return Clock()


@pytest.fixture
async def source(
    gateway: TekonGateway, http: aiohttp.ClientSession, clock: Clock
) -> AsyncIterator[TekonSource]:
    made = TekonSource(TekonClient(http, gateway.url), clock=clock)
    yield made
    await made.close()


async def discovered(source: TekonSource, polled: frozenset[str]) -> Snapshot:
    """Discover, then poll once so that the polled points are subscribed."""
    await source.poll(())
    return await source.poll(polled)


def subscribed(gateway: TekonGateway) -> set[str]:
    """The items the gateway's one session subscribed."""
    (session,) = gateway.sessions.values()
    return set(session.subscribed)
