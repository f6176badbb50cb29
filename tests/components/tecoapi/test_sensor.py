"""Sensors: read-only points and the PLC status."""

from freezegun.api import FrozenDateTimeFactory
from homeassistant.components.sensor import SensorDeviceClass, SensorStateClass
from homeassistant.const import (
    ATTR_DEVICE_CLASS,
    ATTR_UNIT_OF_MEASUREMENT,
    EntityCategory,
)
from homeassistant.core import HomeAssistant
from homeassistant.helpers import entity_registry as er
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry
from syrupy.assertion import SnapshotAssertion

from custom_components.tecoapi.const import DOMAIN
from tests.components.tecoapi import memory_house
from tests.components.tecoapi.conftest import poll, snapshot_entities
from tests.fake_source import MemoryDevice
from tests.simulator import Simulator


@pytest.mark.primary_only
@pytest.mark.usefixtures("entity_registry_enabled_by_default")
async def test_sensors(
    hass: HomeAssistant, program_entry: MockConfigEntry, snapshot: SnapshotAssertion
) -> None:
    """Every sensor of the shipped programs: registry entry and state."""
    await snapshot_entities(hass, snapshot, program_entry, "sensor")


@pytest.mark.usefixtures("manual_program_entry")
async def test_manual_chapter_5_3_temperatures(hass: HomeAssistant) -> None:
    """The manual's outside and inside temperatures are °C temperature sensors."""
    for entity_id, title, value in (
        ("sensor.main_outside_temperature", "outside temperature", "-0.5"),
        ("sensor.main_inside_temperature", "inside temperature", "22.1"),
    ):
        state = hass.states.get(entity_id)
        assert state.state == value
        # On the device of the manual's program instance Main.
        assert state.name == f"Main {title}"
        assert state.attributes[ATTR_UNIT_OF_MEASUREMENT] == "°C"
        assert state.attributes[ATTR_DEVICE_CLASS] == SensorDeviceClass.TEMPERATURE
        assert state.attributes["state_class"] == SensorStateClass.MEASUREMENT


@pytest.mark.usefixtures("demo_entry")
async def test_units_map_to_device_and_state_classes(hass: HomeAssistant) -> None:
    """Energy totals increase, % is a humidity only for a humidity."""
    expected = {
        "sensor.energy_electricity_consumed": (
            "kWh",
            "energy",
            "total_increasing",
        ),
        "sensor.energy_house_power": ("W", "power", "measurement"),
        "sensor.rooms_living_room_humidity": ("%", "humidity", "measurement"),
        "sensor.energy_last_meter_reading": (None, "timestamp", None),
        "sensor.heating_next_boiler_service": (None, "date", None),
        # A TIME is a duration, graphable, shown in hours (see below).
        "sensor.heating_boiler_runtime_today": ("h", "duration", "measurement"),
    }
    for entity_id, (unit, device_class, state_class) in expected.items():
        attributes = hass.states.get(entity_id).attributes
        assert (
            attributes.get(ATTR_UNIT_OF_MEASUREMENT),
            attributes.get(ATTR_DEVICE_CLASS),
            attributes.get("state_class"),
        ) == (unit, device_class, state_class), entity_id
    assert hass.states.get("sensor.energy_last_meter_reading").state == (
        "2026-03-14T08:00:00+00:00"
    )


@pytest.mark.usefixtures("demo_entry")
async def test_a_running_time_is_shown_in_hours_and_minutes(
    hass: HomeAssistant,
) -> None:
    """A read-only TIME is read in seconds and shown as hours with two decimals.

    The frontend spells a duration in hours as hours and minutes (``3 h 41 min``);
    in seconds it would show ``13,287 s``.
    """
    entity_id = "sensor.heating_boiler_runtime_today"
    state = hass.states.get(entity_id)

    # 03:41:27.000
    assert float(state.state) == pytest.approx(13287 / 3600)
    assert state.attributes[ATTR_UNIT_OF_MEASUREMENT] == "h"
    options = er.async_get(hass).async_get(entity_id).options["sensor"]
    assert options["suggested_display_precision"] == 2


@pytest.mark.usefixtures("demo_entry")
async def test_hidden_and_plain_variables_are_disabled_by_default(
    hass: HomeAssistant,
) -> None:
    """visibility=false and plain variables create disabled entities.

    A plain variable is named by its path below its group's device (Ventilation).
    """
    registry = er.async_get(hass)
    for unique_id in ("SD 2080_heating.boilerstarts", "SD 2080_doorbellcount"):
        entity_id = registry.async_get_entity_id("sensor", DOMAIN, unique_id)
        assert entity_id is not None
        assert (
            registry.async_get(entity_id).disabled_by
            is er.RegistryEntryDisabler.INTEGRATION
        )
        assert hass.states.get(entity_id) is None
    plain = registry.async_get(
        registry.async_get_entity_id(
            "sensor", DOMAIN, "SD 2080_ventilation.filter.lastchange"
        )
    )
    assert plain.original_name == "filter.lastChange"


@pytest.mark.usefixtures("demo_entry")
async def test_plc_status_sensors(
    hass: HomeAssistant, simulator: Simulator, freezer: FrozenDateTimeFactory
) -> None:
    """Mode, program and the clock's offset come from GetInfo as diagnostic sensors."""
    registry = er.async_get(hass)
    status = {
        "sensor.tecomat_cp_2080_mode": "run",
        "sensor.tecomat_cp_2080_user_program": "FAMILY_HOUSE v1.3",
        "sensor.tecomat_cp_2080_program_compiled": "2026-03-14T09:26:53+00:00",
        "sensor.tecomat_cp_2080_clock_offset": "0",
    }
    for entity_id, value in status.items():
        assert hass.states.get(entity_id).state == value
        assert (
            registry.async_get(entity_id).entity_category is EntityCategory.DIAGNOSTIC
        )
    assert hass.states.get("sensor.tecomat_cp_2080_mode").attributes["options"] == [
        "run",
        "halt",
        "err",
    ]

    simulator.mode = "ERR"
    await poll(hass, freezer, 60)

    assert hass.states.get("sensor.tecomat_cp_2080_mode").state == "err"


# --- the memory house (memory_house.py): through the in-memory source ---------


async def test_sensors_show_scaled_values_units_and_durations(
    hass: HomeAssistant, house: MemoryDevice
) -> None:
    temperature = memory_house.state(hass, "sensor", "boiler_temp")
    assert temperature.state == "65.2"
    assert temperature.attributes["unit_of_measurement"] == "°C"
    assert temperature.attributes["device_class"] == "temperature"
    starts = memory_house.state(hass, "sensor", "starts")
    assert starts.state == "1234"
    # A count without a unit, its history a total as its map's state_class says.
    assert starts.attributes["state_class"] == "total_increasing"
    assert "unit_of_measurement" not in starts.attributes
    runtime = memory_house.state(hass, "sensor", "runtime")
    assert runtime.attributes["device_class"] == "duration"
    # Shown in hours (the suggested unit of a duration).
    assert runtime.attributes["unit_of_measurement"] == "h"
    assert float(runtime.state) == pytest.approx(13 + 17 / 60)
