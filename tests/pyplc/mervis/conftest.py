"""Fixtures of the Mervis tests: a simulated controller over real HTTP, and clients of it."""

from collections.abc import AsyncIterator, Awaitable, Callable
from typing import Any

import aiohttp
from aiohttp import web
import pytest

from custom_components.tecoapi.pyplc.core.pointmap import PointMap
from custom_components.tecoapi.pyplc.mervis import MervisClient, MervisSource
from custom_components.tecoapi.pyplc.mervis.vlist import load_vlist
from tests.simulator.mervis import MervisSimulator, Project, Switches

USER = "admin"
PASSWORD = "pa55-Wörd"

type StartMervis = Callable[..., Awaitable[MervisSimulator]]
type Handler = Callable[[web.Request], Awaitable[web.StreamResponse]]
type Serve = Callable[[Handler], Awaitable[str]]


@pytest.fixture
async def http(socket_enabled: None) -> AsyncIterator[aiohttp.ClientSession]:
    """An HTTP session (a client never closes the one it is given)."""
    async with aiohttp.ClientSession() as session:
        yield session


@pytest.fixture
async def start_mervis(socket_enabled: None) -> AsyncIterator[StartMervis]:
    """Start simulated controllers (the house unless told) with some switches."""
    started: list[MervisSimulator] = []

    async def start(
        project: Project | None = None,
        *,
        username: str | None = USER,
        password: str = PASSWORD,
        **switches: Any,
    ) -> MervisSimulator:
        sim = MervisSimulator(
            project, username=username, password=password, switches=Switches(**switches)
        )
        await sim.start()
        started.append(sim)
        return sim

    yield start
    for sim in started:
        await sim.stop()


@pytest.fixture
async def mervis(start_mervis: StartMervis) -> MervisSimulator:
    """The house, with credentials, every switch at its default."""
    return await start_mervis()


def client_of(
    http: aiohttp.ClientSession,
    sim: MervisSimulator,
    username: str = USER,
    password: str = PASSWORD,
    **kwargs: Any,
) -> MervisClient:
    """A client of a simulated controller."""
    return MervisClient(http, sim.url, username, password, **kwargs)


def source_of(
    http: aiohttp.ClientSession,
    sim: MervisSimulator,
    point_map: PointMap | None = None,
    **kwargs: Any,
) -> MervisSource:
    """A source of a simulated controller, its map the project's own ``.vlist``."""
    return MervisSource(
        client_of(http, sim, **kwargs),
        point_map if point_map is not None else load_vlist(sim.project.vlist()),
    )


@pytest.fixture
async def serve(socket_enabled: None) -> AsyncIterator[Serve]:
    """Serve one handler on 127.0.0.1 (a device that is no simulated controller)."""
    runners: list[web.AppRunner] = []

    async def start(handler: Handler) -> str:
        app = web.Application()
        app.router.add_route("*", "/{tail:.*}", handler)
        runner = web.AppRunner(app, access_log=None)
        await runner.setup()
        await web.TCPSite(runner, "127.0.0.1", 0).start()
        runners.append(runner)
        return f"http://127.0.0.1:{runner.addresses[0][1]}"

    yield start
    for runner in runners:
        await runner.cleanup()
