"""PlcComsSource with the user's overrides: a plain variable written by ``SET:``.

``LIST:`` names each variable's IEC type, so a write is checked by it before
anything is sent (a UDINT is never negative). Against the simulated PLC's
PLCComS on 127.0.0.1.
"""

from collections.abc import AsyncIterator

import pytest

from custom_components.tecoapi.pyplc import InvalidValueError
from custom_components.tecoapi.pyplc.core.models import PointOverride
from custom_components.tecoapi.pyplc.tecomat.plccoms.client import PlcComsClient
from custom_components.tecoapi.pyplc.tecomat.plccoms.events import (
    PlcComsEvent,
    ProgramChanged,
)
from custom_components.tecoapi.pyplc.tecomat.plccoms.source import PlcComsSource
from tests.pyplc.conftest import Clock, Heard
from tests.simulator import Program, Simulator
from tests.simulator.plccoms import PlcComsServer

pytestmark = pytest.mark.usefixtures("socket_enabled")

OVERRIDES = {"doorbellcount": PointOverride(writable=True)}


@pytest.fixture
async def sim() -> Simulator:
    return Simulator("demo", username="admin", password="s3cret-Pa55")


@pytest.fixture
async def coms(sim: Simulator) -> AsyncIterator[PlcComsServer]:
    async with PlcComsServer(sim, scan_interval=None) as server:
        yield server


@pytest.fixture
async def source(coms: PlcComsServer) -> AsyncIterator[PlcComsSource]:
    """A source of the demo PLC's PLCComS with the user's overrides, discovered."""
    changed = PlcComsSource(
        PlcComsClient("127.0.0.1", coms.port, timeout=1.0, reconnect_delay=0.01),
        clock=Clock(),
        overrides=OVERRIDES,
    )
    await changed.poll(())
    yield changed
    await changed.close()


async def test_a_plain_variable_has_its_type_and_is_writable_as_the_user_made_it(
    source: PlcComsSource,
) -> None:
    point = (await source.poll(())).catalogue.points["doorbellcount"]

    assert point.writable
    assert not point.described
    assert (point.type.bits, point.type.signed) == (32, False)


async def test_a_plain_variable_made_writable_is_set(
    source: PlcComsSource, coms: PlcComsServer, sim: Simulator
) -> None:
    sent = len(coms.commands)

    snapshot = await source.write("doorbellcount", 1300)

    assert "SET:doorbellCount,1300" in coms.commands[sent:]
    assert sim.get_value("doorbellCount") == 1300
    assert snapshot is not None
    assert snapshot.values == {"doorbellcount": 1300}


@pytest.mark.parametrize("value", [-1, 2**32])
async def test_a_value_its_type_cannot_hold_is_refused_before_anything_is_sent(
    source: PlcComsSource, coms: PlcComsServer, sim: Simulator, value: int
) -> None:
    sent = len(coms.commands)

    with pytest.raises(InvalidValueError):
        await source.write("doorbellcount", value)

    assert coms.commands[sent:] == []
    assert sim.get_value("doorbellCount") == 1287


async def test_a_new_program_keeps_what_the_user_changed(
    source: PlcComsSource, coms: PlcComsServer, sim: Simulator
) -> None:
    program = sim.program.to_mapping()
    program["variables"]["garageDoor"] = {"type": "BOOL", "value": True}
    sim.load_program(Program.from_mapping(program))
    events = Heard[PlcComsEvent](source.client.subscribe)

    await coms.scan()  # __PLC_RUN 0
    await coms.scan()  # __PLC_RUN 1: the client reads LIST: again
    await events.wait_for(lambda event: isinstance(event, ProgramChanged))
    snapshot = await source.poll(())

    assert snapshot.program_changed
    assert snapshot.catalogue.points["doorbellcount"].writable
    assert "garagedoor" in snapshot.catalogue.points
    await source.write("doorbellcount", 5)
    assert sim.get_value("doorbellCount") == 5
