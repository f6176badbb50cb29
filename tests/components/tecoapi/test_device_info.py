"""The devices entities sit on: the source's own, its groups' and typed devices' own.

Against the simulated PLC's demo: the PLC's device says what the PLC tells of
itself; a group (a top-level struct) is a device under it, and so is a typed
device of its own; with everything on the PLC's device, the entities move
there and keep their IDs. A second device of the same name says what tells it
apart, never an address. (The PLC's device, its groups, everything on one
device and a second PLC's names came from ``test_init``.)
"""

from dataclasses import replace

from homeassistant.core import HomeAssistant
from homeassistant.helpers import (
    area_registry as ar,
    device_registry as dr,
    entity_registry as er,
)
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.tecoapi.compat import AREA_IN_ENTITY_ID, entry_device
from custom_components.tecoapi.const import CONF_DEVICES, DOMAIN, DeviceGrouping
from custom_components.tecoapi.device_info import area_named, name_suffix
from tests.components.tecoapi.catalogues import INFO
from tests.components.tecoapi.conftest import entity_id_of, make_entry, setup_entry
from tests.conftest import SIM_PASSWORD, SIM_USERNAME
from tests.simulator import Simulator


async def test_one_device_per_plc(hass: HomeAssistant, simulator: Simulator) -> None:
    """The PLC is one device: Teco a.s., its type, serial, firmware, MAC and web page.

    With the devices option on ``single``, every entity sits on it.
    """
    config_entry = await setup_entry(
        hass, make_entry(simulator, **{CONF_DEVICES: DeviceGrouping.SINGLE})
    )

    devices = dr.async_entries_for_config_entry(
        dr.async_get(hass), config_entry.entry_id
    )
    assert len(devices) == 1
    device = devices[0]
    assert device.identifiers == {(DOMAIN, simulator.serial_number)}
    assert device.manufacturer == "Teco a.s."
    assert device.model == "CP-2080"
    assert device.name == "Tecomat CP-2080"
    assert device.serial_number == "SD 2080"
    assert device.sw_version == "Fx2 CP2080I v1.1"
    assert device.connections == {(dr.CONNECTION_NETWORK_MAC, "00:0a:14:2c:80:17")}
    assert device.configuration_url == simulator.url
    entities = er.async_entries_for_device(
        er.async_get(hass), device.id, include_disabled_entities=True
    )
    assert len(entities) == len(
        er.async_entries_for_config_entry(er.async_get(hass), config_entry.entry_id)
    )


async def test_groups_are_devices_under_the_plc(
    hass: HomeAssistant, simulator: Simulator, config_entry: MockConfigEntry
) -> None:
    """Each top-level struct, program instance or array is a device under the PLC.

    Top-level variables stay on the PLC's device; a group named like a room
    gives its room's area to the lights, blinds and thermostats in it (itself
    only where entity IDs do not start with the area: it is nothing but the
    room, and its entities' IDs would say the room twice). Its name has its
    accents back.
    """
    await setup_entry(hass, config_entry)
    devices = dr.async_get(hass)
    plc = entry_device(
        hass, config_entry.entry_id, identifier=(DOMAIN, simulator.serial_number)
    )
    assert plc is not None
    assert plc.name == "Tecomat CP-2080"
    groups = {
        device.name: device
        for device in dr.async_entries_for_config_entry(devices, config_entry.entry_id)
        if device.id != plc.id
    }
    assert {"Rooms", "Heating", "Energy", "Ventilation", "Lights", "Blinds"} <= set(
        groups
    )
    assert all(device.via_device_id == plc.id for device in groups.values())
    rooms = groups["Rooms"]
    assert rooms.identifiers == {(DOMAIN, f"{simulator.serial_number}_rooms")}
    assert rooms.area_id is None
    kids = groups["Dětský pokoj"]
    area_id = ar.async_get(hass).async_get_area_by_name("Dětský pokoj")
    assert area_id is not None
    assert kids.area_id == (None if AREA_IN_ENTITY_ID else area_id.id)
    thermostat = devices.async_get(
        er.async_get(hass)
        .async_get(
            entity_id_of(
                hass, "climate", "SD 2080_struct:climate:detskypokoj.thermostat"
            )
        )
        .device_id
    )
    assert thermostat.area_id == area_id.id
    assert thermostat.via_device_id == plc.id
    registry = er.async_get(hass)
    living = registry.async_get(
        entity_id_of(hass, "sensor", "SD 2080_rooms.livingtemp")
    )
    outside = registry.async_get("sensor.tecomat_cp_2080_outside_temperature")
    assert living is not None
    assert outside is not None
    assert living.device_id == rooms.id
    assert outside.device_id == plc.id


async def test_everything_on_the_plc_device_keeps_entities_and_drops_groups(
    hass: HomeAssistant, simulator: Simulator, config_entry: MockConfigEntry
) -> None:
    """Switching the devices option to one device moves entities, keeping them.

    The group devices are left empty and leave the registry; an entity ID the user
    chose stays.
    """
    await setup_entry(hass, config_entry)
    registry = er.async_get(hass)
    living = entity_id_of(hass, "sensor", "SD 2080_rooms.livingtemp")
    registry.async_update_entity(living, new_entity_id="sensor.living_room_air")
    entities = len(er.async_entries_for_config_entry(registry, config_entry.entry_id))
    devices = dr.async_get(hass)
    assert len(dr.async_entries_for_config_entry(devices, config_entry.entry_id)) > 1

    hass.config_entries.async_update_entry(
        config_entry, options={CONF_DEVICES: DeviceGrouping.SINGLE}
    )
    await hass.async_block_till_done()

    remaining = dr.async_entries_for_config_entry(devices, config_entry.entry_id)
    assert [device.name for device in remaining] == ["Tecomat CP-2080"]
    assert (
        len(er.async_entries_for_config_entry(registry, config_entry.entry_id))
        == entities
    )
    moved = registry.async_get("sensor.living_room_air")
    assert moved is not None
    assert moved.device_id == remaining[0].id
    assert hass.states.get("sensor.living_room_air") is not None


async def test_a_second_plc_of_the_same_type_gets_its_own_name(
    hass: HomeAssistant, simulator: Simulator, config_entry: MockConfigEntry
) -> None:
    """Two CP-2080s: the second one's device names (and entity IDs) carry its serial."""
    await setup_entry(hass, config_entry)
    second = Simulator("demo", username=SIM_USERNAME, password=SIM_PASSWORD)
    second.serial_number = "SD 2081"
    await second.start()
    try:
        await setup_entry(hass, make_entry(second))
        second_entry = hass.config_entries.async_entry_for_domain_unique_id(
            DOMAIN, "SD 2081"
        )
        assert second_entry is not None
        device = entry_device(
            hass, second_entry.entry_id, identifier=(DOMAIN, "SD 2081")
        )
        assert device is not None
        assert device.name == "Tecomat CP-2080 SD 2081"
        assert hass.states.get("sensor.tecomat_cp_2080_sd_2081_outside_temperature")
        assert hass.states.get("sensor.tecomat_cp_2080_outside_temperature")
        # Its groups too: both programs have a Heating struct.
        heating = entry_device(
            hass, second_entry.entry_id, identifier=(DOMAIN, "SD 2081_heating")
        )
        assert heating is not None
        assert heating.name == "Heating SD 2081"
        registry = er.async_get(hass)
        second_ids = [
            entity.entity_id
            for entity in er.async_entries_for_config_entry(
                registry, second_entry.entry_id
            )
        ]
        assert "number.heating_sd_2081_living_room_setpoint" in second_ids
        assert not [entity_id for entity_id in second_ids if entity_id.endswith("_2")]
    finally:
        await second.stop()


async def test_a_room_s_area_is_the_one_there_is_however_spelled(
    hass: HomeAssistant,
) -> None:
    ar.async_get(hass).async_create("Detsky pokoj")

    assert area_named(hass, "Dětský pokoj") == "Detsky pokoj"
    assert area_named(hass, "Kuchyň") == "Kuchyň"
    assert area_named(hass, None) is None


def test_a_second_device_is_told_apart_by_its_way_in_else_its_identity() -> None:
    assert name_suffix(INFO) == "SN 1"
    assert name_suffix(replace(INFO, way_in="PLCComS")) == "PLCComS"
