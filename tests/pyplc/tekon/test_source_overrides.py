"""The Tekon source with the user's overrides, against the simulated gateway over HTTP.

A channel made inverted, a channel made writable where its access rights allow
a write (seed 003: property 5, else 3), never where they say read only.
"""

from collections.abc import AsyncIterator

import aiohttp
import pytest

from custom_components.tecoapi.pyplc import ReadOnlyError
from custom_components.tecoapi.pyplc.core.models import PointOverride
from custom_components.tecoapi.pyplc.core.overrides import (
    NOT_WRITABLE,
    OverrideError,
    check_override,
)
from custom_components.tecoapi.pyplc.tekon import TekonClient, TekonSource
from tests.pyplc.conftest import Clock
from tests.simulator.tekon import TekonGateway, channel
from tests.simulator.tekon.building import (
    CONTROLLER,
    DISCRETE,
    NUMBER,
    READ_WRITE,
    VT_R4,
    small_building,
)

DOOR = f"{CONTROLLER}.Дверь подъезда"
GATE = f"{CONTROLLER}.Ворота"
"""A discrete channel whose access rights say read and write."""
OVERRIDES = {
    DOOR.lower(): PointOverride(invert=True, device_class="door", writable=True),
    GATE.lower(): PointOverride(writable=True),
}


@pytest.fixture
async def gateway(socket_enabled: None) -> AsyncIterator[TekonGateway]:
    building = small_building()
    building.add([channel(GATE, DISCRETE, "0", access=READ_WRITE)])
    async with TekonGateway(building) as running:
        yield running


@pytest.fixture
async def source(gateway: TekonGateway) -> AsyncIterator[TekonSource]:
    async with aiohttp.ClientSession() as http:
        made = TekonSource(
            TekonClient(http, gateway.url), clock=Clock(), overrides=OVERRIDES
        )
        yield made
        await made.close()


async def test_a_channel_made_inverted_shows_its_opposite(
    gateway: TekonGateway, source: TekonSource
) -> None:
    polled = frozenset({DOOR.lower()})
    await source.poll(())
    snapshot = await source.poll(polled)

    door = snapshot.catalogue.points[DOOR.lower()]
    assert (door.invert, door.device_class) == (True, "door")
    # The gateway's value as it is; shown as its opposite: the door is open.
    assert snapshot.values[DOOR.lower()] is False
    assert door.flag(snapshot.values[DOOR.lower()]) is True


async def test_a_channel_whose_rights_are_read_only_is_never_made_writable(
    gateway: TekonGateway, source: TekonSource
) -> None:
    snapshot = await source.poll(())
    described = source.discovered_point(DOOR.lower())
    assert described is not None

    with pytest.raises(OverrideError) as raised:
        check_override(described, OVERRIDES[DOOR.lower()])
    assert raised.value.reason == NOT_WRITABLE
    # What it does take (the inversion) applies; the write does not.
    assert not snapshot.catalogue.points[DOOR.lower()].writable
    gateway.clear_requests()
    with pytest.raises(ReadOnlyError):
        await source.write(DOOR.lower(), True)
    assert gateway.requests == []


async def test_a_discrete_channel_whose_rights_allow_a_write_is_written(
    gateway: TekonGateway, source: TekonSource
) -> None:
    snapshot = await source.poll(())
    described = source.discovered_point(GATE.lower())
    assert described is not None
    assert not described.writable
    assert snapshot.catalogue.points[GATE.lower()].writable

    await source.write(GATE.lower(), True)

    assert gateway.writes == [(GATE, "1")]
    assert gateway.value(GATE) == "1"


async def test_a_new_address_space_keeps_what_the_user_changed(
    gateway: TekonGateway, source: TekonSource
) -> None:
    polled = frozenset({DOOR.lower()})
    await source.poll(())
    await source.poll(polled)
    gateway.configuration_mode(
        add=[channel("Дом 1.Новый", NUMBER, "1", vartype=VT_R4)], first=True
    )

    snapshot = await source.poll(polled)

    assert snapshot.program_changed
    assert snapshot.catalogue.points[DOOR.lower()].invert
    assert snapshot.catalogue.points[GATE.lower()].writable
    assert snapshot.catalogue.points["дом 1.новый"].override is None
