"""Fixtures of the FP-I4C tests: the demo's gateway over HTTP, its map, a source."""

from collections.abc import AsyncIterator, Callable
from dataclasses import dataclass
from typing import Any

import aiohttp
from aiohttp import web
import pytest

from custom_components.tecoapi.pyplc.core.pointmap import PointMap, load_csv
from custom_components.tecoapi.pyplc.panasonic import (
    FpI4cClient,
    FpI4cSource,
    check_point,
)
from tests.simulator.fpi4c import EXAMPLE_CSV, FpI4cSimulator, demo_stations

type MakeSource = Callable[..., FpI4cSource]


def example_map() -> PointMap:
    """The documentation's example map (the demo's)."""
    return load_csv(EXAMPLE_CSV.read_text(encoding="utf-8"), check_point)


@pytest.fixture
async def gateway(socket_enabled: None) -> AsyncIterator[FpI4cSimulator]:
    """The demo's gateway: a heating plant at station 1, a garage at station 2."""
    async with FpI4cSimulator(demo_stations(), station=1) as simulator:
        yield simulator


@pytest.fixture
async def http() -> AsyncIterator[aiohttp.ClientSession]:
    async with aiohttp.ClientSession() as session:
        yield session


@pytest.fixture
def make_source(gateway: FpI4cSimulator, http: aiohttp.ClientSession) -> MakeSource:
    """Make a source of the gateway: the example map unless told another."""

    def make(
        point_map: PointMap | None = None,
        *,
        interface: int | None = None,
        station: int | None = None,
        **settings: Any,
    ) -> FpI4cSource:
        client = FpI4cClient(http, gateway.url, interface=interface, timeout=5)
        return FpI4cSource(
            client,
            point_map or example_map(),
            identity="gateway",
            station=station,
            **settings,
        )

    return make


@dataclass
class Scripted:
    """A server answering each POST by the test's script (a gateway misbehaving)."""

    answer: Callable[[dict[str, Any]], dict[str, Any]] = lambda body: {}
    url: str = ""


@pytest.fixture
async def scripted(socket_enabled: None) -> AsyncIterator[Scripted]:
    server = Scripted()

    async def handle(request: web.Request) -> web.Response:
        return web.json_response(server.answer(await request.json()))

    app = web.Application()
    app.router.add_post("/plcpost", handle)
    runner = web.AppRunner(app, access_log=None)
    await runner.setup()
    site = web.TCPSite(runner, "127.0.0.1", 0)
    await site.start()
    server.url = f"http://127.0.0.1:{runner.addresses[0][1]}"
    yield server
    await runner.cleanup()
