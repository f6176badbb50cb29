"""Shared fixtures: a simulated Tecomat PLC on 127.0.0.1 and Home Assistant helpers."""

from collections.abc import AsyncIterator

import pytest

# phcc ships its own top-level `custom_components` package; importing ours here,
# with the project root first on sys.path (pytest `pythonpath = .`), makes Home
# Assistant find this integration.
import custom_components.tecoapi  # noqa: F401
from tests.simulator import Simulator

SIM_USERNAME = "admin"
SIM_PASSWORD = "s3cret-Pa55"


@pytest.fixture
async def simulator(socket_enabled: None) -> AsyncIterator[Simulator]:
    """A running simulator with the `demo` program, Digest auth, on 127.0.0.1."""
    sim = Simulator("demo", username=SIM_USERNAME, password=SIM_PASSWORD)
    await sim.start()
    try:
        yield sim
    finally:
        await sim.stop()


@pytest.fixture
async def manual_simulator(socket_enabled: None) -> AsyncIterator[Simulator]:
    """A running simulator with the manual's example program."""
    sim = Simulator("manual", username=SIM_USERNAME, password=SIM_PASSWORD)
    await sim.start()
    try:
        yield sim
    finally:
        await sim.stop()
