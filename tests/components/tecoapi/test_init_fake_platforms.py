"""Every platform, driven by the in-memory source (no simulator, no network).

The memory source (``tests/fake_source.py``) serves a small house from a CSV
map: plain points of every kind, and GTSAP1 families the library types as a
light, a blind, a thermostat and a button. Each test reads what an entity shows
and, where the platform writes, what reached the device -- raw, through the
map's scale. Value quality and device health come from the device too.
"""

from collections.abc import AsyncIterator
from datetime import UTC, date, datetime, time, timedelta
from typing import Any

from freezegun.api import FrozenDateTimeFactory
from homeassistant.const import ATTR_ENTITY_ID, STATE_UNAVAILABLE
from homeassistant.core import HomeAssistant
from homeassistant.exceptions import ServiceValidationError
from homeassistant.helpers import entity_registry as er
from homeassistant.helpers.entity_platform import async_get_platforms
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.tecoapi.climate import PlcClimate
from custom_components.tecoapi.compat import entry_device
from custom_components.tecoapi.const import CONF_TRANSPORT, DOMAIN
from custom_components.tecoapi.point_maps import async_save_point_map
from custom_components.tecoapi.pyplc import PlcConnectionError
from custom_components.tecoapi.pyplc.core.descriptor import CONF_POINT_MAP
from tests.components.tecoapi.conftest import FROZEN_TIME, poll, setup_entry
from tests.fake_source import (
    BAD,
    NAME,
    UNCERTAIN,
    MemoryDevice,
    house_device,
    house_map,
    memory_registered,
)

IDENTITY = "MEM-0001"


async def set_up_house(
    hass: HomeAssistant, parents: dict[str, str] | None = None
) -> MemoryDevice:
    """The memory house, set up as the config flow stores it (the source registered)."""
    device = house_device(IDENTITY)
    device.parents.update(parents or {})
    map_id = await async_save_point_map(hass, house_map())
    entry = MockConfigEntry(
        domain=DOMAIN,
        title="M1",
        unique_id=IDENTITY,
        data={"host": IDENTITY, CONF_TRANSPORT: NAME, CONF_POINT_MAP: map_id},
    )
    await setup_entry(hass, entry)
    return device


@pytest.fixture
async def house(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory
) -> AsyncIterator[MemoryDevice]:
    """The memory house."""
    freezer.move_to(FROZEN_TIME)
    with memory_registered():
        yield await set_up_house(hass)


def entity(hass: HomeAssistant, domain: str, key: str) -> str:
    """The entity ID of a point or typed device of the house."""
    entity_id = er.async_get(hass).async_get_entity_id(
        domain, DOMAIN, f"{IDENTITY}_{key}"
    )
    assert entity_id is not None, key
    return entity_id


def state(hass: HomeAssistant, domain: str, key: str) -> Any:
    found = hass.states.get(entity(hass, domain, key))
    assert found is not None
    return found


async def call(
    hass: HomeAssistant, domain: str, service: str, key: str, **data: Any
) -> None:
    await hass.services.async_call(
        domain,
        service,
        {ATTR_ENTITY_ID: entity(hass, domain, key), **data},
        blocking=True,
    )


async def test_binary_sensor(
    hass: HomeAssistant, house: MemoryDevice, freezer: FrozenDateTimeFactory
) -> None:
    shown = state(hass, "binary_sensor", "hall_motion")
    assert shown.state == "off"
    assert shown.attributes["device_class"] == "motion"
    house.values["m1"] = True
    await poll(hass, freezer)
    assert state(hass, "binary_sensor", "hall_motion").state == "on"


async def test_switch(hass: HomeAssistant, house: MemoryDevice) -> None:
    assert state(hass, "switch", "garden_pump").state == "on"
    await call(hass, "switch", "turn_off", "garden_pump")
    assert house.values["m2"] is False
    assert state(hass, "switch", "garden_pump").state == "off"


async def test_sensors_show_scaled_values_units_and_durations(
    hass: HomeAssistant, house: MemoryDevice
) -> None:
    temperature = state(hass, "sensor", "boiler_temp")
    assert temperature.state == "65.2"
    assert temperature.attributes["unit_of_measurement"] == "°C"
    assert temperature.attributes["device_class"] == "temperature"
    assert state(hass, "sensor", "starts").state == "1234"
    runtime = state(hass, "sensor", "runtime")
    assert runtime.attributes["device_class"] == "duration"
    # Shown in hours (the suggested unit of a duration).
    assert runtime.attributes["unit_of_measurement"] == "h"
    assert float(runtime.state) == pytest.approx(13 + 17 / 60)


async def test_number_writes_through_the_scale_and_keeps_to_its_range(
    hass: HomeAssistant, house: MemoryDevice
) -> None:
    setpoint = state(hass, "number", "boiler_setpoint")
    assert setpoint.state == "60.0"
    assert (setpoint.attributes["min"], setpoint.attributes["max"]) == (30, 80)
    assert setpoint.attributes["step"] == 0.5
    await call(hass, "number", "set_value", "boiler_setpoint", value=70.5)
    assert house.values["m4"] == 705
    # The map's own step (5 %), not the rule for a 0-100 real (0.1).
    assert state(hass, "number", "fan_level").attributes["step"] == 5
    with pytest.raises(ServiceValidationError):
        await call(hass, "number", "set_value", "fan_level", value=101)
    assert house.values["m11"] == 40.0


async def test_text_keeps_to_its_length(
    hass: HomeAssistant, house: MemoryDevice
) -> None:
    assert state(hass, "text", "display_text").state == "Hello"
    await call(hass, "text", "set_value", "display_text", value="Dobrý den")
    assert house.values["m6"] == "Dobrý den"
    # The text entity's length is the type's: Home Assistant refuses before
    # the write path is asked.
    assert state(hass, "text", "display_text").attributes["max"] == 16
    with pytest.raises(ValueError, match="too long"):
        await call(hass, "text", "set_value", "display_text", value="x" * 17)
    assert house.values["m6"] == "Dobrý den"


async def test_date_time_and_datetime(hass: HomeAssistant, house: MemoryDevice) -> None:
    assert state(hass, "date", "holiday_from").state == "2026-12-20"
    assert state(hass, "time", "wake_up").state == "06:30:00"
    assert state(hass, "datetime", "last_service").state == "2026-03-01T08:00:00+00:00"
    await call(hass, "date", "set_value", "holiday_from", date=date(2027, 1, 2))
    await call(hass, "time", "set_value", "wake_up", time=time(7, 15))
    await call(
        hass,
        "datetime",
        "set_value",
        "last_service",
        datetime=datetime(2026, 4, 1, 9, 30, tzinfo=UTC),
    )
    assert house.values["m7"] == date(2027, 1, 2)
    assert house.values["m8"] == timedelta(hours=7, minutes=15)
    assert house.values["m9"] == datetime(2026, 4, 1, 9, 30, tzinfo=UTC)


async def test_light(hass: HomeAssistant, house: MemoryDevice) -> None:
    key = "gtsap1:light:kitchen"
    assert state(hass, "light", key).state == "off"
    await call(hass, "light", "turn_on", key, brightness=128)
    assert house.values["k1"] is True
    assert house.values["k4"] == 50


async def test_cover(hass: HomeAssistant, house: MemoryDevice) -> None:
    key = "gtsap1:opener:blind"
    assert state(hass, "cover", key).attributes["current_position"] == 40
    await call(hass, "cover", "close_cover", key)
    assert house.values["b2"] == 0
    assert state(hass, "cover", key).state == "closing"


async def test_climate(hass: HomeAssistant, house: MemoryDevice) -> None:
    key = "gtsap1:thermostat:room"
    shown = state(hass, "climate", key)
    assert shown.attributes["hvac_modes"] == ["heat", "off"]
    assert shown.attributes["current_temperature"] == 21.5
    await call(hass, "climate", "set_temperature", key, temperature=23.5)
    assert house.values["t3"] == 23.5


def climate_entity(hass: HomeAssistant, entity_id: str) -> PlcClimate:
    """The thermostat's entity object, as Home Assistant holds it."""
    platform = next(
        platform
        for platform in async_get_platforms(hass, DOMAIN)
        if platform.domain == "climate"
    )
    entity = platform.entities[entity_id]
    assert isinstance(entity, PlcClimate)
    return entity


async def test_climate_gives_the_native_temperatures(
    hass: HomeAssistant, house: MemoryDevice
) -> None:
    """What 2026.11 reads (native_*) is what older releases show (the old names)."""
    key = "gtsap1:thermostat:room"
    thermostat = climate_entity(hass, entity(hass, "climate", key))
    assert thermostat.native_current_temperature == 21.5
    assert thermostat.current_temperature == 21.5
    await call(hass, "climate", "set_temperature", key, temperature=23.5)
    assert thermostat.native_target_temperature == 23.5
    assert state(hass, "climate", key).attributes["temperature"] == 23.5
    assert PlcClimate._attr_native_temperature_unit == "°C"


async def test_a_renamed_entity_keeps_showing_and_writing(
    hass: HomeAssistant, house: MemoryDevice, freezer: FrozenDateTimeFactory
) -> None:
    """A new entity ID: the state moves to it, polls and writes go on under it.

    2026.11 changes it in place and calls async_entity_id_changed (called here as
    it would be); older releases remove the entity and add it again.
    """
    key = "gtsap1:thermostat:room"
    old = entity(hass, "climate", key)
    er.async_get(hass).async_update_entity(old, new_entity_id="climate.renamed")
    await hass.async_block_till_done()
    assert hass.states.get(old) is None
    assert entity(hass, "climate", key) == "climate.renamed"
    climate_entity(hass, "climate.renamed").async_entity_id_changed(old)
    house.values["t2"] = 19.0
    await poll(hass, freezer)
    assert state(hass, "climate", key).attributes["current_temperature"] == 19.0
    await call(hass, "climate", "set_temperature", key, temperature=22.0)
    assert house.values["t3"] == 22.0


async def test_event(
    hass: HomeAssistant, house: MemoryDevice, freezer: FrozenDateTimeFactory
) -> None:
    key = "gtsap1:button:door"
    assert state(hass, "event", key).state == "unknown"
    house.values["d1"] = 5
    await poll(hass, freezer)
    shown = state(hass, "event", key)
    assert shown.attributes["event_type"] == "click"
    assert shown.state != "unknown"


async def test_a_bad_value_costs_its_entity_only(
    hass: HomeAssistant, house: MemoryDevice, freezer: FrozenDateTimeFactory
) -> None:
    house.quality["m3"] = BAD
    house.values["m5"] = 1240
    await poll(hass, freezer)
    assert state(hass, "sensor", "boiler_temp").state == STATE_UNAVAILABLE
    assert state(hass, "sensor", "starts").state == "1240"
    del house.quality["m3"]
    await poll(hass, freezer)
    assert state(hass, "sensor", "boiler_temp").state == "65.2"


async def test_an_uncertain_value_is_shown_with_its_reason(
    hass: HomeAssistant, house: MemoryDevice, freezer: FrozenDateTimeFactory
) -> None:
    house.quality["m3"] = UNCERTAIN
    await poll(hass, freezer)
    shown = state(hass, "sensor", "boiler_temp")
    assert shown.state == "65.2"
    assert shown.attributes["quality"] == "uncertain"
    assert shown.attributes["quality_reason"] == "last_usable"


async def test_a_device_offline_takes_its_own_entities_only(
    hass: HomeAssistant, house: MemoryDevice, freezer: FrozenDateTimeFactory
) -> None:
    house.offline["boiler"] = "no data exchange"
    await poll(hass, freezer)
    assert state(hass, "sensor", "boiler_temp").state == STATE_UNAVAILABLE
    assert state(hass, "number", "boiler_setpoint").state == STATE_UNAVAILABLE
    assert state(hass, "switch", "garden_pump").state == "on"
    house.offline.clear()
    await poll(hass, freezer)
    assert state(hass, "sensor", "boiler_temp").state == "65.2"


async def test_a_failed_poll_makes_everything_unavailable_until_the_next_good_one(
    hass: HomeAssistant, house: MemoryDevice, freezer: FrozenDateTimeFactory
) -> None:
    house.fail = PlcConnectionError("gone")
    await poll(hass, freezer)
    assert state(hass, "switch", "garden_pump").state == STATE_UNAVAILABLE
    house.fail = None
    await poll(hass, freezer)
    assert state(hass, "switch", "garden_pump").state == "on"


async def test_a_pushed_value_shows_without_a_poll(
    hass: HomeAssistant, house: MemoryDevice
) -> None:
    entry = hass.config_entries.async_entries(DOMAIN)[0]
    source = entry.runtime_data.source
    requests = house.requests
    source.push_value("m1", True)
    await hass.async_block_till_done()
    assert state(hass, "binary_sensor", "hall_motion").state == "on"
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
    temperature = er.async_get(hass).async_get(entity(hass, "sensor", "boiler_temp"))
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
    assert state(hass, "sensor", "boiler_temp").state == STATE_UNAVAILABLE
    assert state(hass, "switch", "garden_pump").state == "on"


async def test_what_the_map_asks_a_point_to_be_shown_as(
    hass: HomeAssistant, house: MemoryDevice
) -> None:
    """A writable flag only shown, as a safety sensor; a % that is a moisture."""
    alarm = state(hass, "binary_sensor", "alarm_armed")
    assert alarm.state == "on"
    assert alarm.attributes["device_class"] == "safety"
    assert (
        er.async_get(hass).async_get_entity_id(
            "switch", DOMAIN, f"{IDENTITY}_alarm_armed"
        )
        is None
    )
    assert state(hass, "sensor", "tank_level").attributes["device_class"] == "moisture"


async def test_a_writable_duration_is_a_number_of_seconds(
    hass: HomeAssistant, house: MemoryDevice
) -> None:
    boost = state(hass, "number", "boost")
    assert boost.state == "600.0"
    assert boost.attributes["unit_of_measurement"] == "s"
    await call(hass, "number", "set_value", "boost", value=900)
    assert house.values["m15"] == timedelta(minutes=15)
