"""One PLC added twice, through TecoApi and through PLCComS alone: told apart, no address.

The demo's docs suggest adding the PLC once more through *PLCComS only*. Both
entries reach the same program, so every device name is taken by the other
entry: the second entry's title says its way in (``… · PLCComS``), and so do
its devices' names and the entity IDs made from them (``Heating PLCComS``,
``climate.obyvak_thermostat_plccoms``) -- never the PLC's EPSNET address, the
identity PLCComS knows it by. Entries made before keep every entity's ID and
unique ID; their title and their devices' names say the way in unless the user
renamed them.
"""

from collections.abc import AsyncIterator
import re
from typing import Any

from homeassistant.config_entries import SOURCE_USER, ConfigEntry, ConfigEntryState
from homeassistant.const import CONF_HOST, CONF_PORT
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
from homeassistant.helpers import device_registry as dr, entity_registry as er
import pytest

from custom_components.tecoapi.const import DOMAIN
from tests.components.tecoapi.conftest import make_entry, setup_entry
from tests.simulator import Simulator
from tests.simulator.plccoms import PlcComsServer

IDENTITY = "EPSNET 127.0.0.1:61682"
"""The PLC's identity through PLCComS: its EPSNET address as the server reaches it."""
TITLE = "CP-2080 · FAMILY_HOUSE v1.3"
ADDRESS = re.compile(r"epsnet|127[._]0[._]0[._]1|61682", re.IGNORECASE)


@pytest.fixture
async def coms(simulator: Simulator) -> AsyncIterator[PlcComsServer]:
    """The demo PLC's PLCComS server."""
    async with PlcComsServer(simulator, scan_interval=None) as server:
        yield server


async def add_through_plccoms(hass: HomeAssistant, port: int) -> ConfigEntry:
    """Add the PLC as a user does: *PLCComS only*, its host and port; set it up."""
    result = await hass.config_entries.flow.async_init(
        DOMAIN, context={"source": SOURCE_USER}
    )
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {"next_step_id": "plccoms"}
    )
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {CONF_HOST: "127.0.0.1", CONF_PORT: port}
    )
    assert result["type"] is FlowResultType.CREATE_ENTRY
    await hass.async_block_till_done()
    entry: ConfigEntry = result["result"]
    assert entry.state is ConfigEntryState.LOADED
    return entry


def registered(hass: HomeAssistant, entry: ConfigEntry) -> dict[str, Any]:
    """An entry's title, its devices' names and its entities' IDs by unique ID."""
    devices = dr.async_entries_for_config_entry(dr.async_get(hass), entry.entry_id)
    entities = er.async_entries_for_config_entry(er.async_get(hass), entry.entry_id)
    return {
        "title": entry.title,
        "devices": sorted(device.name or "" for device in devices),
        "entities": {entity.unique_id: entity.entity_id for entity in entities},
    }


async def test_plccoms_beside_tecoapi_says_its_way_in_not_an_address(
    hass: HomeAssistant, simulator: Simulator, coms: PlcComsServer
) -> None:
    """The second entry's title, devices and new entity IDs; the first as it was."""
    tecoapi = await setup_entry(hass, make_entry(simulator))
    first = registered(hass, tecoapi)

    plccoms = await add_through_plccoms(hass, coms.port)

    second = registered(hass, plccoms)
    assert plccoms.unique_id == IDENTITY
    assert second["title"] == f"{TITLE} · PLCComS"
    assert [name for name in second["devices"] if ADDRESS.search(name)] == []
    assert {"Tecomat CP-2080 PLCComS", "Heating PLCComS", "Lights PLCComS"} <= set(
        second["devices"]
    )
    assert "Obývák thermostat PLCComS" in second["devices"]
    entity_ids = set(second["entities"].values())
    assert [entity_id for entity_id in entity_ids if ADDRESS.search(entity_id)] == []
    assert {
        "climate.obyvak_thermostat_plccoms",
        "sensor.tecomat_cp_2080_plccoms_mode",
        "number.heating_plccoms_living_room_setpoint",
    } <= entity_ids
    # Each name is one entity's: none had to be numbered apart.
    assert [
        entity_id for entity_id in entity_ids if re.search(r"_\d+$", entity_id)
    ] == []
    # The same entities as TecoApi's, by their point keys.
    assert {
        unique_id.removeprefix(f"{IDENTITY}_") for unique_id in second["entities"]
    } == {
        unique_id.removeprefix(f"{simulator.serial_number}_")
        for unique_id in first["entities"]
    }
    # The TecoApi entry is as it was.
    assert registered(hass, tecoapi) == first
    assert first["title"] == TITLE


def as_before(hass: HomeAssistant, entry: ConfigEntry) -> dict[str, str]:
    """Rename an unloaded PLCComS entry's registry as the release before named it.

    Its devices carried the PLC's address where they now say the way in
    (``Heating EPSNET 127.0.0.1:61682``), the entity IDs made from them too
    (``climate.obyvak_thermostat_epsnet_127_0_0_1_61682``), and its title was
    its TecoApi entry's. Returns the entity IDs by unique ID.
    """
    devices, entities = dr.async_get(hass), er.async_get(hass)
    for device in dr.async_entries_for_config_entry(devices, entry.entry_id):
        if device.name and device.name.endswith(" PLCComS"):
            old = device.name.removesuffix(" PLCComS") + f" {IDENTITY}"
            devices.async_update_device(device.id, name=old)
    old_ids = {}
    for entity in er.async_entries_for_config_entry(entities, entry.entry_id):
        old_id = entity.entity_id.replace("plccoms", "epsnet_127_0_0_1_61682")
        if old_id != entity.entity_id:
            entities.async_update_entity(entity.entity_id, new_entity_id=old_id)
        old_ids[entity.unique_id] = old_id
    hass.config_entries.async_update_entry(entry, title=TITLE)
    return old_ids


async def test_an_existing_plccoms_entry_keeps_its_entity_ids(
    hass: HomeAssistant, simulator: Simulator, coms: PlcComsServer
) -> None:
    """An upgrade: every entity ID and unique ID stays; the address leaves the names."""
    await setup_entry(hass, make_entry(simulator))
    plccoms = await add_through_plccoms(hass, coms.port)
    assert await hass.config_entries.async_unload(plccoms.entry_id)
    old_ids = as_before(hass, plccoms)
    assert "climate.obyvak_thermostat_epsnet_127_0_0_1_61682" in old_ids.values()

    assert await hass.config_entries.async_setup(plccoms.entry_id)
    await hass.async_block_till_done()

    now = registered(hass, plccoms)
    assert now["entities"] == old_ids
    for entity_id in old_ids.values():
        entity = er.async_get(hass).async_get(entity_id)
        assert entity is not None
        assert entity.disabled_by is not None or hass.states.get(entity_id), entity_id
    # Not renamed by the user: the title and the devices' names say the way in.
    assert now["title"] == f"{TITLE} · PLCComS"
    assert [name for name in now["devices"] if ADDRESS.search(name)] == []
    assert "Heating PLCComS" in now["devices"]
    assert "Obývák thermostat PLCComS" in now["devices"]


async def test_a_title_the_user_gave_stays(
    hass: HomeAssistant, simulator: Simulator, coms: PlcComsServer
) -> None:
    """Only a title the config flow gave is retitled."""
    plccoms = await add_through_plccoms(hass, coms.port)
    hass.config_entries.async_update_entry(plccoms, title="Dům přes PLCComS")

    await hass.config_entries.async_reload(plccoms.entry_id)
    await hass.async_block_till_done()

    assert plccoms.state is ConfigEntryState.LOADED
    assert plccoms.title == "Dům přes PLCComS"
