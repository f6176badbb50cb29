"""Push through Home Assistant: the coordinator over the PLCComS-backed sources.

The integration does not build these sources yet (its config flow and
`connection.create_source` are being changed elsewhere); here `create_source` is
patched, as the freshness benchmark does, to show what the coordinator does with
them unchanged: pushed values and modes reach the entities at once.

The clock is frozen here, and with it the event loop's timers: the sources hand
each burst on at once (`batch_window=0`) instead of after their 10 ms window.
"""

import asyncio
from collections.abc import AsyncIterator, Callable
from datetime import timedelta
from typing import Any
from unittest.mock import patch

from freezegun.api import FrozenDateTimeFactory
from homeassistant.const import (
    CONF_HOST,
    CONF_PASSWORD,
    CONF_USERNAME,
    EVENT_STATE_CHANGED,
    STATE_UNAVAILABLE,
)
from homeassistant.core import Event, HomeAssistant, callback
from homeassistant.helpers import entity_registry as er
from homeassistant.helpers.aiohttp_client import async_get_clientsession
from homeassistant.util import dt as dt_util
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.tecoapi.pytecoapi import (
    PlcComsClient,
    PlcComsSource,
    PushedTecoApiSession,
    TecoApiClient,
)
from custom_components.tecoapi.pytecoapi.plccoms import ConnectionChanged
from custom_components.tecoapi.pytecoapi.source import PlcSource
from tests.integration.conftest import make_entry, poll, setup_entry
from tests.simulator import Simulator
from tests.simulator.plccoms import PlcComsServer

OUTSIDE = "sensor.tecomat_cp_2080_outside_temperature"
LIGHT = "switch.tecomat_cp_2080_kitchen_light"
MODE = "sensor.tecomat_cp_2080_mode"
WAIT = 5.0


@pytest.fixture
async def coms(simulator: Simulator) -> AsyncIterator[PlcComsServer]:
    """The demo PLC's PLCComS server, scanning when a test says so."""
    async with PlcComsServer(simulator, scan_interval=None) as server:
        yield server


def sources(port: int, *, alone: bool = False) -> Callable[..., PlcSource]:
    """A `create_source` building a PLCComS-backed source, as the integration will."""

    def create_source(
        hass: HomeAssistant, data: dict[str, Any], *, metadata_interval: timedelta
    ) -> PlcSource:
        plccoms = PlcComsClient("127.0.0.1", port, timeout=2.0)
        if alone:
            return PlcComsSource(
                plccoms,
                metadata_interval=metadata_interval,
                clock=dt_util.utcnow,
                batch_window=0,
            )
        return PushedTecoApiSession(
            TecoApiClient(
                async_get_clientsession(hass),
                data[CONF_HOST],
                data[CONF_USERNAME],
                data[CONF_PASSWORD],
            ),
            plccoms,
            metadata_interval=metadata_interval,
            clock=dt_util.utcnow,
            run_blocking=hass.async_add_executor_job,
            batch_window=0,
        )

    return create_source


async def state_of(hass: HomeAssistant, entity_id: str, state: str) -> None:
    """Wait until an entity shows a state (already, or by a state change)."""
    if (current := hass.states.get(entity_id)) is not None and current.state == state:
        return
    shown = asyncio.get_running_loop().create_future()

    @callback
    def changed(event: Event[Any]) -> None:
        new = event.data["new_state"]
        if (
            event.data["entity_id"] == entity_id
            and new is not None
            and new.state == state
            and not shown.done()
        ):
            shown.set_result(None)

    unsubscribe = hass.bus.async_listen(EVENT_STATE_CHANGED, changed)
    try:
        async with asyncio.timeout(WAIT):
            await shown
    finally:
        unsubscribe()


async def connected(client: PlcComsClient) -> None:
    """Wait until a PLCComS client is connected."""
    if client.connected:
        return
    ready = asyncio.get_running_loop().create_future()

    def heard(event: Any) -> None:
        if (
            isinstance(event, ConnectionChanged)
            and event.connected
            and not ready.done()
        ):
            ready.set_result(None)

    unsubscribe = client.subscribe(heard)
    try:
        async with asyncio.timeout(WAIT):
            await ready
    finally:
        unsubscribe()


@pytest.mark.usefixtures("entity_registry_enabled_by_default")
async def test_pushed_values_and_modes_reach_the_entities_at_once(
    hass: HomeAssistant,
    simulator: Simulator,
    coms: PlcComsServer,
    freezer: FrozenDateTimeFactory,
) -> None:
    with patch("custom_components.tecoapi.create_source", sources(coms.port)):
        entry = await setup_entry(hass, make_entry(simulator))
    source = entry.runtime_data.source
    assert isinstance(source, PushedTecoApiSession)
    await connected(source.coms)
    await poll(hass, freezer)  # enables the polled points, reads TecoApi once
    simulator.clear_requests()

    simulator.set_value("outsideTemp.value", -4.0)
    simulator.set_value("lights[1].value", False)
    await coms.scan()
    await state_of(hass, OUTSIDE, "-4.0")
    await state_of(hass, LIGHT, "off")

    simulator.mode = "HALT"
    await coms.scan()
    await state_of(hass, MODE, "halt")
    await state_of(hass, OUTSIDE, STATE_UNAVAILABLE)

    # Values came by push, the mode by one GetInfo: no value poll of TecoApi.
    assert [r.service for r in simulator.requests if r.authorized] == ["GetInfo"]


@pytest.mark.usefixtures("entity_registry_enabled_by_default")
async def test_plccoms_alone_gives_the_entities_tecoapi_gives(
    hass: HomeAssistant,
    simulator: Simulator,
    coms: PlcComsServer,
    freezer: FrozenDateTimeFactory,
) -> None:
    """The same entities (names from T_ApiObject titles), keyed by the PLCComS identity."""
    tecoapi = await setup_entry(hass, make_entry(simulator))
    registry = er.async_get(hass)
    expected = {
        entry.unique_id.removeprefix(f"{simulator.serial_number}_"): entry.original_name
        for entry in er.async_entries_for_config_entry(registry, tecoapi.entry_id)
    }
    await hass.config_entries.async_remove(tecoapi.entry_id)
    await hass.async_block_till_done()

    identity = "EPSNET 127.0.0.1:61682"
    alone = MockConfigEntry(
        domain=tecoapi.domain, title="PLCComS", unique_id=identity, data=tecoapi.data
    )
    with patch(
        "custom_components.tecoapi.create_source", sources(coms.port, alone=True)
    ):
        await setup_entry(hass, alone)
    points = {
        entry.unique_id.removeprefix(f"{identity}_"): entry.original_name
        for entry in er.async_entries_for_config_entry(registry, alone.entry_id)
    }

    # Status entities' keys hold a dash, point keys never do.
    def point_entities(names: dict[str, str | None]) -> dict[str, str | None]:
        return {key: name for key, name in names.items() if "-" not in key}

    assert point_entities(points) == point_entities(expected)

    source = alone.runtime_data.source
    assert isinstance(source, PlcComsSource)
    await poll(hass, freezer)  # enables the polled points
    simulator.set_value("outsideTemp.value", 8.5)
    await coms.scan()
    outside = registry.async_get_entity_id(
        "sensor", "tecoapi", f"{identity}_outsidetemp"
    )
    assert outside is not None
    await state_of(hass, outside, "8.5")
