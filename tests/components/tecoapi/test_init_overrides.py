"""What the user changed of discovered points stays: a restart, a new program, a rediscovery.

The changes are kept in a store beside the entry (``tecoapi.overrides.<entry
ID>``); the entry's data and options stay as they were. An energy counter the
program publishes as a plain LREAL becomes what the Energy dashboard takes (kWh,
total increasing) by its unit alone; a count of starts keeps its history as a
total without a unit.
"""

import logging
from typing import Any, Final

from freezegun.api import FrozenDateTimeFactory
from homeassistant.components.sensor import ATTR_STATE_CLASS
from homeassistant.const import (
    ATTR_DEVICE_CLASS,
    ATTR_UNIT_OF_MEASUREMENT,
    STATE_OFF,
    STATE_ON,
)
from homeassistant.core import HomeAssistant
from homeassistant.helpers import entity_registry as er
import pytest

from custom_components.tecoapi.const import CONF_PLAIN_VARIABLES, DOMAIN
from custom_components.tecoapi.overrides import async_load_overrides
from custom_components.tecoapi.pyplc.core.models import PointOverride
from tests.components.tecoapi.conftest import FROZEN_TIME, make_entry, poll, setup_entry
from tests.components.tecoapi.flows.test_config_tekon import add_gateway
from tests.components.tecoapi.overridden import as_stored, change_point
from tests.simulator import Program, Simulator
from tests.simulator.tekon import TekonGateway, channel
from tests.simulator.tekon.building import CONTROLLER, DISCRETE

SERIAL: Final = "SD 2080"
DOOR: Final = f"{CONTROLLER}.Дверь подъезда"


def with_plain(simulator: Simulator, **variables: dict[str, Any]) -> None:
    """Load the demo program with more plain variables (a newer program)."""
    program = simulator.program.to_mapping()
    program["variables"].update(variables)
    simulator.load_program(Program.from_mapping(program))


def entity_of(hass: HomeAssistant, domain: str, key: str) -> str | None:
    return er.async_get(hass).async_get_entity_id(domain, DOMAIN, f"{SERIAL}_{key}")


async def test_a_plain_energy_counter_given_its_unit_is_what_the_energy_dashboard_takes(
    hass: HomeAssistant, simulator: Simulator, caplog: pytest.LogCaptureFixture
) -> None:
    with_plain(
        simulator,
        energyMeter={"type": "LREAL", "value": 1520.5},
        burnerStarts={"type": "UDINT", "value": 4711},
    )
    entry = await setup_entry(
        hass, make_entry(simulator, **{CONF_PLAIN_VARIABLES: "enabled"})
    )
    meter = entity_of(hass, "sensor", "energymeter")
    assert meter is not None
    assert ATTR_STATE_CLASS not in hass.states.get(meter).attributes  # type: ignore[union-attr]
    caplog.clear()

    await change_point(hass, entry, "energymeter", unit="kWh")
    await change_point(hass, entry, "burnerstarts", state_class="total_increasing")

    state = hass.states.get(meter)
    assert state is not None
    assert state.state == "1520.5"
    assert (
        state.attributes[ATTR_UNIT_OF_MEASUREMENT],
        state.attributes[ATTR_DEVICE_CLASS],
        state.attributes[ATTR_STATE_CLASS],
    ) == ("kWh", "energy", "total_increasing")
    starts = hass.states.get(entity_of(hass, "sensor", "burnerstarts") or "")
    assert starts is not None
    assert starts.attributes[ATTR_STATE_CLASS] == "total_increasing"
    assert ATTR_UNIT_OF_MEASUREMENT not in starts.attributes
    # Home Assistant's sensor took both as they are (it warns otherwise).
    assert [
        record.getMessage()
        for record in caplog.records
        if record.name.startswith("homeassistant.components.sensor")
        and record.levelno >= logging.WARNING
    ] == []
    assert entity_of(hass, "sensor", "energymeter") == meter


async def test_a_point_changed_stays_so_after_a_restart_and_a_new_program(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    entry = await setup_entry(
        hass, make_entry(simulator, **{CONF_PLAIN_VARIABLES: "enabled"})
    )
    await change_point(hass, entry, "doorbellcount", writable=True)
    number = entity_of(hass, "number", "doorbellcount")
    assert number is not None
    stored = as_stored(entry)

    assert await hass.config_entries.async_reload(entry.entry_id)
    await hass.async_block_till_done()

    assert entity_of(hass, "number", "doorbellcount") == number
    assert entity_of(hass, "sensor", "doorbellcount") is None
    assert hass.states.get(number).state == "1287"  # type: ignore[union-attr]
    assert as_stored(entry) == stored

    # A Mosaic download with another variable: the changed one stays writable.
    with_plain(simulator, garageDoor={"type": "BOOL", "value": True})
    await entry.runtime_data.async_refresh()
    await hass.async_block_till_done(wait_background_tasks=True)

    assert "garagedoor" in entry.runtime_data.data.catalogue.points
    assert entity_of(hass, "number", "doorbellcount") == number
    assert entry.runtime_data.data.catalogue.points["doorbellcount"].writable


async def test_a_change_waits_for_its_point_to_come_back(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    """A program without the variable keeps the change for the one that has it again."""
    entry = await setup_entry(
        hass, make_entry(simulator, **{CONF_PLAIN_VARIABLES: "enabled"})
    )
    await change_point(hass, entry, "doorbellcount", writable=True)
    original = simulator.program.to_mapping()
    without = simulator.program.to_mapping()
    del without["variables"]["doorbellCount"]
    simulator.load_program(Program.from_mapping(without))
    await entry.runtime_data.async_refresh()
    await hass.async_block_till_done(wait_background_tasks=True)
    assert entity_of(hass, "number", "doorbellcount") is None
    assert await async_load_overrides(hass, entry.entry_id) == {
        "doorbellcount": PointOverride(writable=True)
    }

    simulator.load_program(Program.from_mapping(original))
    await entry.runtime_data.async_refresh()
    await hass.async_block_till_done(wait_background_tasks=True)

    assert entity_of(hass, "number", "doorbellcount") is not None


async def test_an_entry_removed_takes_its_changes_with_it(
    hass: HomeAssistant, simulator: Simulator, hass_storage: dict[str, Any]
) -> None:
    entry = await setup_entry(hass, make_entry(simulator))
    await change_point(hass, entry, "outsidetemp", unit="K")
    key = f"{DOMAIN}.overrides.{entry.entry_id}"
    assert hass_storage[key]["data"] == {"points": {"outsidetemp": {"unit": "K"}}}
    assert hass_storage[key]["version"] == 1

    await hass.config_entries.async_remove(entry.entry_id)
    await hass.async_block_till_done()

    assert key not in hass_storage


@pytest.mark.usefixtures("socket_enabled")
async def test_a_tekon_contact_stays_inverted_in_a_new_address_space(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory
) -> None:
    """The gateway's OPC server went through configuration mode: read again."""
    async with TekonGateway() as gateway:
        freezer.move_to(FROZEN_TIME)
        result = await add_gateway(hass, gateway.url)
        entry = result["result"]
        await hass.async_block_till_done(wait_background_tasks=True)
        await change_point(hass, entry, DOOR, invert=True, device_class="door")
        door = er.async_get(hass).async_get_entity_id(
            "binary_sensor", DOMAIN, f"{entry.unique_id}_{DOOR.lower()}"
        )
        assert door is not None
        assert hass.states.get(door).state == STATE_ON  # type: ignore[union-attr]
        catalogue = entry.runtime_data.data.catalogue

        gateway.configuration_mode(
            add=[channel(f"{CONTROLLER}.Протечка", DISCRETE, "1")], first=True
        )
        await poll(hass, freezer, 1)
        await poll(hass, freezer, 1)

        assert entry.runtime_data.data.catalogue is not catalogue
        assert hass.states.get(door).state == STATE_ON  # type: ignore[union-attr]
        gateway.set_value(DOOR, "1")
        await poll(hass, freezer, 1)
        assert hass.states.get(door).state == STATE_OFF  # type: ignore[union-attr]
        await hass.config_entries.async_unload(entry.entry_id)
