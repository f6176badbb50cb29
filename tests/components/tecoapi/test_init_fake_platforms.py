"""The memory house as a whole (in-memory source: no simulator, no network).

Each platform's own test of the house sits in its test_<platform>.py; here what
is about the integration: value quality and device health from the device, a
failed poll, a pushed value, the devices the source declares.
"""

from collections.abc import AsyncIterator

from freezegun.api import FrozenDateTimeFactory
from homeassistant.const import STATE_UNAVAILABLE
from homeassistant.core import HomeAssistant
from homeassistant.helpers import entity_registry as er
import pytest

from custom_components.tecoapi.compat import entry_device
from custom_components.tecoapi.const import DOMAIN
from custom_components.tecoapi.pyplc import PlcConnectionError
from tests.components.tecoapi import memory_house
from tests.components.tecoapi.conftest import FROZEN_TIME, poll, set_up_house
from tests.components.tecoapi.memory_house import IDENTITY
from tests.fake_source import BAD, UNCERTAIN, MemoryDevice, memory_registered


async def test_a_bad_value_costs_its_entity_only(
    hass: HomeAssistant, house: MemoryDevice, freezer: FrozenDateTimeFactory
) -> None:
    house.quality["m3"] = BAD
    house.values["m5"] = 1240
    await poll(hass, freezer)
    assert memory_house.state(hass, "sensor", "boiler_temp").state == STATE_UNAVAILABLE
    assert memory_house.state(hass, "sensor", "starts").state == "1240"
    del house.quality["m3"]
    await poll(hass, freezer)
    assert memory_house.state(hass, "sensor", "boiler_temp").state == "65.2"


async def test_an_uncertain_value_is_shown_with_its_reason(
    hass: HomeAssistant, house: MemoryDevice, freezer: FrozenDateTimeFactory
) -> None:
    house.quality["m3"] = UNCERTAIN
    await poll(hass, freezer)
    shown = memory_house.state(hass, "sensor", "boiler_temp")
    assert shown.state == "65.2"
    assert shown.attributes["quality"] == "uncertain"
    assert shown.attributes["quality_reason"] == "last_usable"


async def test_a_device_offline_takes_its_own_entities_only(
    hass: HomeAssistant, house: MemoryDevice, freezer: FrozenDateTimeFactory
) -> None:
    house.offline["boiler"] = "no data exchange"
    await poll(hass, freezer)
    assert memory_house.state(hass, "sensor", "boiler_temp").state == STATE_UNAVAILABLE
    assert (
        memory_house.state(hass, "number", "boiler_setpoint").state == STATE_UNAVAILABLE
    )
    assert memory_house.state(hass, "switch", "garden_pump").state == "on"
    house.offline.clear()
    await poll(hass, freezer)
    assert memory_house.state(hass, "sensor", "boiler_temp").state == "65.2"


async def test_a_failed_poll_makes_everything_unavailable_until_the_next_good_one(
    hass: HomeAssistant, house: MemoryDevice, freezer: FrozenDateTimeFactory
) -> None:
    house.fail = PlcConnectionError("gone")
    await poll(hass, freezer)
    assert memory_house.state(hass, "switch", "garden_pump").state == STATE_UNAVAILABLE
    house.fail = None
    await poll(hass, freezer)
    assert memory_house.state(hass, "switch", "garden_pump").state == "on"


async def test_a_pushed_value_shows_without_a_poll(
    hass: HomeAssistant, house: MemoryDevice
) -> None:
    entry = hass.config_entries.async_entries(DOMAIN)[0]
    source = entry.runtime_data.source
    requests = house.requests
    source.push_value("m1", True)
    await hass.async_block_till_done()
    assert memory_house.state(hass, "binary_sensor", "hall_motion").state == "on"
    assert house.requests == requests


async def test_the_devices_the_source_declares_are_devices_under_its_own(
    hass: HomeAssistant, house: MemoryDevice
) -> None:
    entry_id = hass.config_entries.async_entries(DOMAIN)[0].entry_id
    source_device = entry_device(hass, entry_id, identifier=(DOMAIN, IDENTITY))
    boiler = entry_device(hass, entry_id, identifier=(DOMAIN, f"{IDENTITY}_boiler"))
    assert source_device is not None
    assert boiler is not None
    assert boiler.name == "Boiler"
    assert boiler.manufacturer == "Memory & Co."
    assert boiler.via_device_id == source_device.id
    temperature = er.async_get(hass).async_get(
        memory_house.entity(hass, "sensor", "boiler_temp")
    )
    assert temperature is not None
    assert temperature.device_id == boiler.id


@pytest.fixture
async def plant_house(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory
) -> AsyncIterator[MemoryDevice]:
    """The house whose boiler is a station under a plant (a device with none of its own points)."""
    freezer.move_to(FROZEN_TIME)
    with memory_registered():
        yield await set_up_house(hass, {"boiler": "plant"})


async def test_a_device_sits_under_the_one_the_source_says_and_follows_its_health(
    hass: HomeAssistant, plant_house: MemoryDevice, freezer: FrozenDateTimeFactory
) -> None:
    entry_id = hass.config_entries.async_entries(DOMAIN)[0].entry_id
    plant = entry_device(hass, entry_id, identifier=(DOMAIN, f"{IDENTITY}_plant"))
    boiler = entry_device(hass, entry_id, identifier=(DOMAIN, f"{IDENTITY}_boiler"))
    assert plant is not None
    assert boiler is not None
    assert boiler.via_device_id == plant.id
    assert boiler.model == "Station"
    # The plant stops talking: the boiler under it has no live values either.
    plant_house.offline["plant"] = "no data exchange"
    await poll(hass, freezer)
    assert memory_house.state(hass, "sensor", "boiler_temp").state == STATE_UNAVAILABLE
    assert memory_house.state(hass, "switch", "garden_pump").state == "on"


async def test_what_the_map_asks_a_point_to_be_shown_as(
    hass: HomeAssistant, house: MemoryDevice
) -> None:
    """A writable flag only shown, as a safety sensor; a % that is a moisture."""
    alarm = memory_house.state(hass, "binary_sensor", "alarm_armed")
    assert alarm.state == "on"
    assert alarm.attributes["device_class"] == "safety"
    assert (
        er.async_get(hass).async_get_entity_id(
            "switch", DOMAIN, f"{IDENTITY}_alarm_armed"
        )
        is None
    )
    assert (
        memory_house.state(hass, "sensor", "tank_level").attributes["device_class"]
        == "moisture"
    )
