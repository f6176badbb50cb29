"""PLC mode HALT/ERR: point entities unavailable, a repair issue, back in RUN."""

from freezegun.api import FrozenDateTimeFactory
from homeassistant.const import STATE_UNAVAILABLE
from homeassistant.core import HomeAssistant
from homeassistant.helpers import issue_registry as ir
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.tecoapi.const import DOMAIN
from tests.components.tecoapi.conftest import make_entry, poll, setup_entry
from tests.simulator import Simulator

OUTSIDE = "sensor.tecomat_cp_2080_outside_temperature"
SETPOINT = "number.heating_living_room_setpoint"
LIGHT = "switch.lights_kitchen_light"
MODE = "sensor.tecomat_cp_2080_mode"
PROBLEM = "binary_sensor.tecomat_cp_2080_running_problem"
PROGRAM = "sensor.tecomat_cp_2080_user_program"


def not_running_issue(
    hass: HomeAssistant, entry: MockConfigEntry
) -> ir.IssueEntry | None:
    """The entry's "PLC not running" repair issue, if raised."""
    return ir.async_get(hass).async_get_issue(
        DOMAIN, f"plc_not_running_{entry.entry_id}"
    )


async def test_halt_and_err_make_points_unavailable_and_raise_an_issue(
    hass: HomeAssistant,
    simulator: Simulator,
    demo_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """HALT: points unavailable, status shown, a warning; ERR: an error; RUN: all back."""
    simulator.mode = "HALT"

    await poll(hass, freezer, 60)

    for entity_id in (OUTSIDE, SETPOINT, LIGHT):
        assert hass.states.get(entity_id).state == STATE_UNAVAILABLE
    assert hass.states.get(MODE).state == "halt"
    assert hass.states.get(PROBLEM).state == "on"
    assert hass.states.get(PROGRAM).state == "FAMILY_HOUSE v1.3"
    issue = not_running_issue(hass, demo_entry)
    assert issue is not None
    assert issue.severity is ir.IssueSeverity.WARNING
    assert not issue.is_fixable
    assert issue.translation_key == "plc_not_running"
    assert issue.translation_placeholders == {
        "name": demo_entry.title,
        "mode": "HALT",
    }

    # While the program is stopped, a poll asks only for the mode.
    simulator.clear_requests()
    simulator.mode = "ERR"
    await poll(hass, freezer)

    assert [request.service for request in simulator.requests] == ["GetInfo"]
    assert hass.states.get(MODE).state == "err"
    issue = not_running_issue(hass, demo_entry)
    assert issue is not None
    assert issue.severity is ir.IssueSeverity.ERROR
    assert issue.translation_placeholders == {"name": demo_entry.title, "mode": "ERR"}

    # Running again: the first poll reads the values too, the issue goes away.
    simulator.set_value("outsideTemp.value", -1.5)
    simulator.mode = "RUN"
    await poll(hass, freezer)

    assert not_running_issue(hass, demo_entry) is None
    assert hass.states.get(OUTSIDE).state == "-1.5"
    assert hass.states.get(SETPOINT).state == "21.5"
    assert hass.states.get(LIGHT).state == "on"
    assert hass.states.get(MODE).state == "run"
    assert hass.states.get(PROBLEM).state == "off"


async def test_plc_halted_at_setup(hass: HomeAssistant, simulator: Simulator) -> None:
    """Set up while the PLC is halted: entities exist but are unavailable."""
    simulator.mode = "HALT"
    entry = await setup_entry(hass, make_entry(simulator))

    assert hass.states.get(OUTSIDE).state == STATE_UNAVAILABLE
    assert hass.states.get(MODE).state == "halt"
    assert not_running_issue(hass, entry) is not None


async def test_unloading_clears_the_issue(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    """Nobody watches an unloaded PLC: its issue goes; a removed entry leaves none."""
    simulator.mode = "ERR"
    entry = await setup_entry(hass, make_entry(simulator))
    assert not_running_issue(hass, entry) is not None

    assert await hass.config_entries.async_unload(entry.entry_id)
    assert not_running_issue(hass, entry) is None

    await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    assert not_running_issue(hass, entry) is not None

    await hass.config_entries.async_remove(entry.entry_id)
    await hass.async_block_till_done()
    assert not_running_issue(hass, entry) is None


async def test_a_halt_shows_on_the_next_poll(
    hass: HomeAssistant,
    simulator: Simulator,
    demo_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """A stopped program changes no value: the next (quiet) poll reads GetInfo."""
    simulator.mode = "HALT"

    await poll(hass, freezer, 5)

    assert hass.states.get(MODE).state == "halt"
    assert hass.states.get(OUTSIDE).state == STATE_UNAVAILABLE
    assert not_running_issue(hass, demo_entry) is not None
