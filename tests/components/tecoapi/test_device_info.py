"""The devices entities sit on: the source's own, its groups' and typed devices' own.

Against the simulated PLC's demo: the PLC's device says what the PLC tells of
itself; a group (a top-level struct) is a device under it, and so is a typed
device of its own; with everything on the PLC's device, the entities move
there and keep their IDs. A second device of the same name says what tells it
apart, never an address.
"""

from dataclasses import replace
from typing import TYPE_CHECKING

from homeassistant.core import HomeAssistant
from homeassistant.helpers import (
    area_registry as ar,
    device_registry as dr,
    entity_registry as er,
)
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.tecoapi.compat import entry_device
from custom_components.tecoapi.const import DOMAIN, DeviceGrouping
from custom_components.tecoapi.device_info import (
    area_named,
    async_place_entities,
    device_info_for,
    name_suffix,
    plc_device_info,
)
from custom_components.tecoapi.options import PlcOptions
from tests.components.tecoapi.catalogues import INFO
from tests.components.tecoapi.typed import SERIAL

if TYPE_CHECKING:
    from custom_components.tecoapi.coordinator import PlcCoordinator


def _device(hass: HomeAssistant, entry: MockConfigEntry, ident: str) -> dr.DeviceEntry:
    device = entry_device(hass, entry.entry_id, identifier=(DOMAIN, ident))
    assert device is not None, ident
    return device


async def test_the_plc_its_groups_and_typed_devices_are_devices(
    hass: HomeAssistant, demo_entry: MockConfigEntry
) -> None:
    coordinator: PlcCoordinator = demo_entry.runtime_data
    plc = _device(hass, demo_entry, SERIAL)
    info = plc_device_info(coordinator)
    heating = _device(hass, demo_entry, f"{SERIAL}_heating")
    light = _device(hass, demo_entry, f"{SERIAL}_gtsap1:light:kuchyne_linka")

    assert (plc.manufacturer, plc.model, plc.serial_number) == (
        "Teco a.s.",
        "CP-2080",
        coordinator.data.info.serial_number,
    )
    assert plc.name == coordinator.device_name == info["name"]
    assert plc.configuration_url == coordinator.source.configuration_url
    assert heating.via_device_id == plc.id
    assert heating.model == coordinator.data.info.program_name
    assert light.via_device_id == plc.id
    # A point of a group sits on its group's device, a typed device on its own.
    assert device_info_for(coordinator, "heating.livingsetpoint")["identifiers"] == {
        (DOMAIN, f"{SERIAL}_heating")
    }
    assert device_info_for(coordinator, "outsidetemp")["identifiers"] == {
        (DOMAIN, SERIAL)
    }


async def test_everything_moves_to_the_plc_s_device_and_keeps_its_id(
    hass: HomeAssistant, demo_entry: MockConfigEntry
) -> None:
    coordinator: PlcCoordinator = demo_entry.runtime_data
    entities = er.async_get(hass)
    setpoint = entities.async_get_entity_id(
        "number", DOMAIN, f"{SERIAL}_heating.livingsetpoint"
    )
    assert setpoint is not None

    await coordinator.applier.async_apply_options(
        PlcOptions(devices=DeviceGrouping.SINGLE), []
    )
    async_place_entities(coordinator)

    moved = entities.async_get(setpoint)
    assert moved is not None
    assert moved.device_id == _device(hass, demo_entry, SERIAL).id


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
