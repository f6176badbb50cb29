"""Numbers: writable numeric points, their ranges, and the validated write path."""

from datetime import timedelta
from typing import Any

from freezegun.api import FrozenDateTimeFactory
from homeassistant.components.number import (
    ATTR_MAX,
    ATTR_MIN,
    ATTR_MODE,
    ATTR_STEP,
    ATTR_VALUE,
    DOMAIN as NUMBER_DOMAIN,
    SERVICE_SET_VALUE,
    NumberMode,
)
from homeassistant.const import (
    ATTR_DEVICE_CLASS,
    ATTR_ENTITY_ID,
    ATTR_UNIT_OF_MEASUREMENT,
)
from homeassistant.core import HomeAssistant
from homeassistant.exceptions import HomeAssistantError, ServiceValidationError
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry
from syrupy.assertion import SnapshotAssertion

from custom_components.tecoapi.const import DOMAIN
from tests.components.tecoapi import memory_house
from tests.components.tecoapi.conftest import StateWrites, poll, snapshot_entities
from tests.fake_source import MemoryDevice
from tests.simulator import Simulator

LIVING_SETPOINT = "number.heating_living_room_setpoint"
CURVE_SHIFT = "number.heating_curve_shift"
LIVING_BLIND = "number.blinds_living_room_blind"
REQUESTED = "number.main_requested_temperature"


@pytest.mark.primary_only
@pytest.mark.usefixtures("entity_registry_enabled_by_default")
async def test_numbers(
    hass: HomeAssistant, program_entry: MockConfigEntry, snapshot: SnapshotAssertion
) -> None:
    """Every number of the shipped programs: registry entry and state."""
    await snapshot_entities(hass, snapshot, program_entry, "number")


async def set_value(hass: HomeAssistant, entity_id: str, value: Any) -> None:
    """Call number.set_value and wait for it."""
    await hass.services.async_call(
        NUMBER_DOMAIN,
        SERVICE_SET_VALUE,
        {ATTR_ENTITY_ID: entity_id, ATTR_VALUE: value},
        blocking=True,
    )


async def test_manual_requested_temperature(
    hass: HomeAssistant,
    manual_simulator: Simulator,
    manual_program_entry: MockConfigEntry,
) -> None:
    """The manual's requested temperature: a number 10 to 30 °C that writes the PLC."""
    state = hass.states.get(REQUESTED)
    assert state.state == "23.0"
    assert state.name == "Main requested temperature"
    assert state.attributes[ATTR_MIN] == 10.0
    assert state.attributes[ATTR_MAX] == 30.0
    # A temperature setpoint steps by half a degree.
    assert state.attributes[ATTR_STEP] == 0.5
    assert state.attributes[ATTR_MODE] == NumberMode.SLIDER
    assert state.attributes[ATTR_UNIT_OF_MEASUREMENT] == "°C"
    assert state.attributes[ATTR_DEVICE_CLASS] == "temperature"

    await set_value(hass, REQUESTED, 24.5)

    assert manual_simulator.get_value("Main.myObject3.value") == 24.5
    assert hass.states.get(REQUESTED).state == "24.5"


@pytest.mark.usefixtures("demo_entry")
async def test_set_value_writes_once_and_confirms(
    hass: HomeAssistant, simulator: Simulator, state_writes: StateWrites
) -> None:
    """One SetObject for the write, then one poll confirms; the entity shows it."""
    simulator.clear_requests()

    await set_value(hass, LIVING_SETPOINT, 22.5)

    assert simulator.get_value("Heating.livingSetpoint.value") == 22.5
    assert hass.states.get(LIVING_SETPOINT).state == "22.5"
    services = [request.service for request in simulator.requests]
    assert services[0] == "SetObject"
    assert set(services[1:]) == {"GetObject"}
    assert state_writes == {LIVING_SETPOINT: 1}


@pytest.mark.usefixtures("demo_entry")
async def test_integer_point_gets_an_integer(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    """An INT point: step 1, and 3.0 from the UI is written as the integer 3."""
    assert hass.states.get(CURVE_SHIFT).attributes[ATTR_STEP] == 1

    await set_value(hass, CURVE_SHIFT, 3.0)

    assert simulator.get_value("Heating.curveShift.value") == 3
    assert hass.states.get(CURVE_SHIFT).state == "3"


@pytest.mark.usefixtures("demo_entry")
async def test_fraction_for_an_integer_is_refused(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    """1.5 for an INT point: a translated validation error, nothing written."""
    with pytest.raises(ServiceValidationError) as raised:
        await set_value(hass, CURVE_SHIFT, 1.5)

    assert raised.value.translation_domain == DOMAIN
    assert raised.value.translation_key == "invalid_value"
    assert simulator.get_value("Heating.curveShift.value") == 0
    assert hass.states.get(CURVE_SHIFT).state == "0"


async def test_out_of_range_write_is_refused_by_the_coordinator(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    """The coordinator's write path refuses a value outside [min, max] itself."""
    coordinator = demo_entry.runtime_data

    with pytest.raises(ServiceValidationError) as raised:
        await coordinator.async_write("heating.livingsetpoint", 40.0)

    assert raised.value.translation_key == "out_of_range"
    assert str(raised.value) == (
        "40.0 is outside the allowed range of Heating.livingSetpoint (15 to 28)"
    )
    assert simulator.get_value("Heating.livingSetpoint.value") == 21.5
    assert hass.states.get(LIVING_SETPOINT).state == "21.5"


@pytest.mark.usefixtures("demo_entry")
async def test_point_made_read_only_at_runtime_is_refused(
    hass: HomeAssistant, simulator: Simulator, freezer: FrozenDateTimeFactory
) -> None:
    """readOnly set by the PLC program: after the attribute refresh, writes are refused."""
    simulator.set_value("Heating.livingSetpoint.attr.readOnly", True)
    await poll(hass, freezer, 60)

    with pytest.raises(ServiceValidationError) as raised:
        await set_value(hass, LIVING_SETPOINT, 22.0)

    assert raised.value.translation_key == "read_only"
    assert str(raised.value) == "Heating.livingSetpoint is read-only"
    assert simulator.get_value("Heating.livingSetpoint.value") == 21.5
    assert hass.states.get(LIVING_SETPOINT).state == "21.5"


@pytest.mark.usefixtures("demo_entry")
async def test_range_follows_the_attributes(
    hass: HomeAssistant, simulator: Simulator, freezer: FrozenDateTimeFactory
) -> None:
    """min/max 0/0 means no range: the type's, a box instead of a slider.

    TecoApi's JSON says no IEC type: an integer may be any of DINT..UDINT (a
    DWORD takes up to 4294967295).
    """
    state = hass.states.get(LIVING_BLIND)
    assert (state.attributes[ATTR_MIN], state.attributes[ATTR_MAX]) == (0, 100)
    assert state.attributes[ATTR_MODE] == NumberMode.SLIDER

    simulator.set_value("blinds[0].attr.maxValue", 0.0)
    await poll(hass, freezer, 60)

    state = hass.states.get(LIVING_BLIND)
    assert (state.attributes[ATTR_MIN], state.attributes[ATTR_MAX]) == (
        -2147483648,
        4294967295,
    )
    assert state.attributes[ATTR_MODE] == NumberMode.BOX


@pytest.mark.usefixtures("demo_entry")
async def test_value_the_plc_refuses(
    hass: HomeAssistant, simulator: Simulator, freezer: FrozenDateTimeFactory
) -> None:
    """A value outside the PLC type (USINT, no attr range) is refused by the PLC."""
    simulator.set_value("blinds[0].attr.maxValue", 0.0)
    await poll(hass, freezer, 60)

    with pytest.raises(ServiceValidationError) as raised:
        await set_value(hass, LIVING_BLIND, 300)

    assert raised.value.translation_key == "value_rejected"
    # The PLC's message adds the type; the value and the path are said once.
    assert raised.value.translation_placeholders["message"] == (
        "it does not fit the variable's type, USINT"
    )
    assert simulator.get_value("blinds[0].value") == 100
    assert hass.states.get(LIVING_BLIND).state == "100"


@pytest.mark.usefixtures("demo_entry")
async def test_unreachable_plc_on_write(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    """A dropped connection on write raises a HomeAssistantError, not a validation one."""
    simulator.faults.drop_connection = True

    with pytest.raises(HomeAssistantError) as raised:
        await set_value(hass, LIVING_SETPOINT, 22.0)
    simulator.faults.clear()

    assert not isinstance(raised.value, ServiceValidationError)
    assert raised.value.translation_key == "write_failed"
    assert simulator.get_value("Heating.livingSetpoint.value") == 21.5
    assert hass.states.get(LIVING_SETPOINT).state == "21.5"


# --- the memory house (memory_house.py): through the in-memory source ---------


async def test_number_writes_through_the_scale_and_keeps_to_its_range(
    hass: HomeAssistant, house: MemoryDevice
) -> None:
    setpoint = memory_house.state(hass, "number", "boiler_setpoint")
    assert setpoint.state == "60.0"
    assert (setpoint.attributes["min"], setpoint.attributes["max"]) == (30, 80)
    assert setpoint.attributes["step"] == 0.5
    await memory_house.call(hass, "number", "set_value", "boiler_setpoint", value=70.5)
    assert house.values["m4"] == 705
    # The map's own step (5 %), not the rule for a 0-100 real (0.1).
    assert memory_house.state(hass, "number", "fan_level").attributes["step"] == 5
    with pytest.raises(ServiceValidationError):
        await memory_house.call(hass, "number", "set_value", "fan_level", value=101)
    assert house.values["m11"] == 40.0


async def test_a_writable_duration_is_a_number_of_seconds(
    hass: HomeAssistant, house: MemoryDevice
) -> None:
    boost = memory_house.state(hass, "number", "boost")
    assert boost.state == "600.0"
    assert boost.attributes["unit_of_measurement"] == "s"
    await memory_house.call(hass, "number", "set_value", "boost", value=900)
    assert house.values["m15"] == timedelta(minutes=15)
