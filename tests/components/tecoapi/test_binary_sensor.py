"""Binary sensors: read-only boolean points and the running-problem sensor."""

from freezegun.api import FrozenDateTimeFactory
from homeassistant.const import STATE_OFF, STATE_ON
from homeassistant.core import HomeAssistant
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry
from syrupy.assertion import SnapshotAssertion

from tests.components.tecoapi import memory_house
from tests.components.tecoapi.conftest import poll, snapshot_entities
from tests.fake_source import MemoryDevice
from tests.simulator import Simulator

PROBLEM = "binary_sensor.tecomat_cp_2080_running_problem"
WINDOW = "binary_sensor.rooms_bedroom_window_open"


@pytest.mark.primary_only
@pytest.mark.usefixtures("entity_registry_enabled_by_default")
async def test_binary_sensors(
    hass: HomeAssistant, program_entry: MockConfigEntry, snapshot: SnapshotAssertion
) -> None:
    """Every binary sensor of the shipped programs: registry entry and state."""
    await snapshot_entities(hass, snapshot, program_entry, "binary_sensor")


@pytest.mark.usefixtures("demo_entry")
async def test_boolean_point_follows_the_plc(
    hass: HomeAssistant, simulator: Simulator, freezer: FrozenDateTimeFactory
) -> None:
    """A read-only BOOL T_ApiObject shows the PLC's value."""
    assert hass.states.get(WINDOW).state == STATE_OFF

    simulator.set_value("Rooms.windowOpen.value", True)
    await poll(hass, freezer)

    assert hass.states.get(WINDOW).state == STATE_ON


@pytest.mark.parametrize("mode", ["HALT", "ERR"])
@pytest.mark.usefixtures("demo_entry")
async def test_running_problem_when_plc_is_not_running(
    hass: HomeAssistant,
    simulator: Simulator,
    freezer: FrozenDateTimeFactory,
    mode: str,
) -> None:
    """The problem sensor turns on in HALT or ERR and off again in RUN."""
    assert hass.states.get(PROBLEM).state == STATE_OFF
    assert hass.states.get(PROBLEM).attributes["device_class"] == "problem"

    simulator.mode = mode
    await poll(hass, freezer, 60)
    assert hass.states.get(PROBLEM).state == STATE_ON

    simulator.mode = "RUN"
    await poll(hass, freezer, 60)
    assert hass.states.get(PROBLEM).state == STATE_OFF


# --- the memory house (memory_house.py): through the in-memory source ---------


async def test_binary_sensor(
    hass: HomeAssistant, house: MemoryDevice, freezer: FrozenDateTimeFactory
) -> None:
    shown = memory_house.state(hass, "binary_sensor", "hall_motion")
    assert shown.state == "off"
    assert shown.attributes["device_class"] == "motion"
    house.values["m1"] = True
    await poll(hass, freezer)
    assert memory_house.state(hass, "binary_sensor", "hall_motion").state == "on"
