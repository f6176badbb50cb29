"""Fixtures and a raw HTTP helper for the simulator's own tests."""

import base64
from collections.abc import AsyncIterator, Mapping
from dataclasses import dataclass
import json
import textwrap
from typing import Any

import aiohttp
import pytest
from yarl import URL

from tests.conftest import SIM_PASSWORD, SIM_USERNAME
from tests.simulator import Simulator

CRLF = "\r\n"


@dataclass(frozen=True, slots=True)
class Reply:
    """What came back from the simulator, unparsed."""

    status: int
    headers: Mapping[str, str]
    body: bytes
    challenges: list[str]

    def json(self) -> Any:
        """The body as JSON."""
        return json.loads(self.body)

    @property
    def error_code(self) -> str:
        """The `error.code` of an error body."""
        return str(self.json()["error"]["code"])

    @property
    def error_message(self) -> str:
        """The `error.message` of an error body."""
        return str(self.json()["error"]["message"])


def basic_authorization(username: str, password: str) -> str:
    """An `Authorization: Basic ...` value."""
    return "Basic " + base64.b64encode(f"{username}:{password}".encode()).decode()


def manual_text(text: str) -> bytes:
    """A JSON body as printed in the manual: dedented, CRLF lines, final CRLF."""
    lines = textwrap.dedent(text).strip("\n").split("\n")
    return (CRLF.join(line.rstrip() for line in lines) + CRLF).encode()


async def fetch(
    session: aiohttp.ClientSession,
    sim: Simulator,
    target: str,
    *,
    method: str = "GET",
    data: bytes | None = None,
    headers: Mapping[str, str] | None = None,
    basic: bool = True,
) -> Reply:
    """Send `target` exactly as written (no re-encoding), with Basic credentials."""
    sent = dict(headers or {})
    if basic:
        sent.setdefault(
            "Authorization", basic_authorization(SIM_USERNAME, SIM_PASSWORD)
        )
    async with session.request(
        method, URL(sim.url + target, encoded=True), data=data, headers=sent
    ) as response:
        return Reply(
            response.status,
            response.headers,
            await response.read(),
            response.headers.getall("WWW-Authenticate", []),
        )


@pytest.fixture
async def session() -> AsyncIterator[aiohttp.ClientSession]:
    """A plain aiohttp session."""
    async with aiohttp.ClientSession() as client:
        yield client


@pytest.fixture
async def manual_plc(socket_enabled: None) -> AsyncIterator[Simulator]:
    """The manual's program, offering Basic and Digest (the manual's examples use Basic)."""
    async with Simulator(
        "manual", username=SIM_USERNAME, password=SIM_PASSWORD, auth="both"
    ) as sim:
        yield sim


@pytest.fixture
async def demo_plc(socket_enabled: None) -> AsyncIterator[Simulator]:
    """The demo program, offering Basic and Digest."""
    async with Simulator(
        "demo", username=SIM_USERNAME, password=SIM_PASSWORD, auth="both"
    ) as sim:
        yield sim
