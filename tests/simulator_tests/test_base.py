"""The simulators' one base: every HTTP simulator starts, logs, waits and stops alike."""

import asyncio
from collections.abc import Awaitable, Callable
from concurrent.futures import ThreadPoolExecutor
from typing import Any

import aiohttp
from aiohttp import web
import pytest

from tests.simulator import Simulator
from tests.simulator.base import ConnectionDroppedError, HttpSimulator, run
from tests.simulator.fpi4c import FpI4cSimulator
from tests.simulator.mervis import MervisSimulator
from tests.simulator.tekon import TekonGateway

pytestmark = pytest.mark.usefixtures("socket_enabled")

type Make = Callable[[], HttpSimulator[Any]]

# Each simulator, and one request of its protocol (method, path, JSON body).
SIMULATORS: dict[str, tuple[Make, str, str, Any]] = {
    "tecoapi": (lambda: Simulator("manual"), "GET", "/TecoApi/GetInfo", None),
    "mervis": (MervisSimulator, "POST", "/values.cgi", {"ver": 1, "v": []}),
    "fpi4c": (FpI4cSimulator, "POST", "/plcpost", {"req": []}),
    "tekon": (TekonGateway, "GET", "/ServerInformation", None),
}


@pytest.fixture(params=list(SIMULATORS))
def simulator_kind(request: pytest.FixtureRequest) -> tuple[Make, str, str, Any]:
    """One HTTP simulator's maker and a request it answers."""
    kind: tuple[Make, str, str, Any] = SIMULATORS[request.param]
    return kind


async def test_every_simulator_starts_serves_and_stops_alike(
    simulator_kind: tuple[Make, str, str, Any],
) -> None:
    make, method, path, body = simulator_kind
    sim = make()
    assert sim.port == 0
    async with sim, aiohttp.ClientSession() as http:
        assert sim.port > 0
        assert sim.host == f"127.0.0.1:{sim.port}"
        assert sim.url == f"http://127.0.0.1:{sim.port}"
        with pytest.raises(RuntimeError, match="already running"):
            await sim.start()
        # A port taken: an error, and nothing left running.
        other = make()
        with pytest.raises(OSError):
            await other.start(port=sim.port)
        await other.stop()
        async with http.request(method, f"{sim.url}{path}", json=body):
            pass
        await sim.wait_for_requests(1)
        assert len(sim.requests) == 1
        sim.clear_requests()
        assert sim.requests == []
    await sim.stop()
    # Started again, it serves again.
    async with sim, aiohttp.ClientSession() as http:
        async with http.request(method, f"{sim.url}{path}", json=body):
            pass
        assert len(sim.requests) == 1


class _Dropping(HttpSimulator[str]):
    """A simulator whose every answer is lost: reset, closed, or after a long pause."""

    paused_out = False
    """A pause ended by the simulator stopping (not cancelled by aiohttp's shutdown)."""

    def _routes(self, app: web.Application) -> None:
        app.router.add_get("/{how}", self._handle)

    async def _handle(self, request: web.Request) -> web.Response:
        how = request.match_info["how"]
        self._record(how)
        if how == "pause":
            try:
                await self._pause(3600)
            except ConnectionDroppedError:
                self.paused_out = True
                raise
        raise ConnectionDroppedError(reset=how == "reset")


async def _answer_of(url: str) -> bytes:
    """Everything the server sends back to a GET (b"": not a byte)."""
    host, port = url.removeprefix("http://").split("/", 1)[0].split(":")
    reader, writer = await asyncio.open_connection(host, int(port))
    path = "/" + url.split("/", 3)[3]
    writer.write(f"GET {path} HTTP/1.1\r\nHost: {host}\r\n\r\n".encode())
    try:
        return await reader.read()
    except ConnectionResetError:
        return b""
    finally:
        writer.close()


@pytest.mark.parametrize("how", ["reset", "close"])
async def test_a_dropped_connection_carries_no_answer(how: str) -> None:
    async with _Dropping() as sim:
        assert await _answer_of(f"{sim.url}/{how}") == b""
        # The server goes on answering the next request.
        assert await _answer_of(f"{sim.url}/{how}") == b""
        assert sim.requests == [how, how]


async def test_stopping_ends_a_paused_request_at_once() -> None:
    sim = _Dropping()
    await sim.start()
    answer = asyncio.ensure_future(_answer_of(f"{sim.url}/pause"))
    await sim.wait_for_requests(1)
    await sim.stop()
    assert await answer == b""
    assert sim.paused_out


async def test_the_fpi4c_gateway_logs_every_request() -> None:
    async with FpI4cSimulator() as gateway, aiohttp.ClientSession() as http:
        async with http.post(f"{gateway.url}/plcpost", data="not json") as reply:
            assert (await reply.json(content_type=None))["err"] is True
        async with http.get(f"{gateway.url}/plcget?DT0") as reply:
            assert reply.status == 200
        gateway.get_form = False
        async with http.get(f"{gateway.url}/plcget?DT0") as reply:
            assert reply.status == 404
        # Refused or not, every request is logged; posts holds the answered ones.
        assert gateway.requests == ["plcpost", "plcget", "plcget"]
        assert gateway.posts == [
            {"req": [{"area": "DT", "type": "INT", "start": 0, "count": 1}]}
        ]


def test_run_exits_1_on_a_user_error_and_0_once_served(
    capsys: pytest.CaptureFixture[str],
) -> None:
    async def taken() -> None:
        raise OSError("address already in use")

    async def served() -> None:
        await asyncio.sleep(0)

    async def broken() -> None:
        raise ValueError("a bug")

    assert _run_apart(taken) == 1
    assert "error: address already in use" in capsys.readouterr().err
    assert _run_apart(served) == 0
    with pytest.raises(ValueError, match="a bug"):
        _run_apart(broken)


def _run_apart(serving: Callable[[], Awaitable[Any]]) -> int:
    """``run`` in a thread of its own, as a command line runs it.

    Its ``asyncio.run`` ends by clearing its thread's event loop: in the test's
    own thread that would leave the tests after it (on Home Assistant 2026.2's
    pytest-asyncio) without one.
    """
    with ThreadPoolExecutor(max_workers=1) as pool:
        return pool.submit(run, serving).result()
