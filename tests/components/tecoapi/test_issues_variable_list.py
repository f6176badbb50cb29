"""A PLC that cannot serve its public variables: 500.011 and 500.012, each with its cure.

The manual's error table (seed 000, §3.7): 500.011 *Public file 'FFF' is too big*
(over 128 KB: the program publishes too many variables), 500.012 *Reading of
public file 'FFF' failed* (the PLC cannot read it). Neither means "no public
variables", the 500.010 a program without ``{PUBLIC_API}`` answers. A PLC that
starts answering one (a new program downloaded) makes its entities unavailable
with the translated reason and raises a repair issue that says what to do; the
first good poll brings both back. The simulated PLC answers them from its
program's ``publicFile``.
"""

import dataclasses

from freezegun.api import FrozenDateTimeFactory
from homeassistant.config_entries import ConfigEntryState
from homeassistant.const import STATE_UNAVAILABLE
from homeassistant.core import HomeAssistant
from homeassistant.helpers import issue_registry as ir
from homeassistant.helpers.update_coordinator import UpdateFailed
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.tecoapi.const import DOMAIN
from tests.components.tecoapi.conftest import make_entry, poll, setup_entry
from tests.simulator import Simulator

OUTSIDE = "sensor.tecomat_cp_2080_outside_temperature"

# The simulator's publicFile state, the code the PLC answers, the translation key.
FAILURES = {
    "too big": ("too_big", "500.011", "variable_list_too_big"),
    "unreadable": ("unreadable", "500.012", "variable_list_unreadable"),
}


def variable_list_issue(
    hass: HomeAssistant, entry: MockConfigEntry
) -> ir.IssueEntry | None:
    """The entry's "cannot serve its variables" repair issue, if raised."""
    return ir.async_get(hass).async_get_issue(DOMAIN, f"variable_list_{entry.entry_id}")


def break_public_file(sim: Simulator, state: str) -> None:
    """Download the same program with its public file ``too_big`` or ``unreadable``."""
    sim.load_program(dataclasses.replace(sim.program, public_file=state))


@pytest.mark.parametrize("failure", FAILURES.values(), ids=FAILURES.keys())
async def test_a_plc_that_starts_answering_it_raises_an_issue_until_fixed(
    hass: HomeAssistant,
    simulator: Simulator,
    demo_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
    failure: tuple[str, str, str],
) -> None:
    """Entities unavailable with the translated reason, an issue; then all back."""
    state, code, key = failure
    assert variable_list_issue(hass, demo_entry) is None
    break_public_file(simulator, state)

    await poll(hass, freezer)

    assert hass.states.get(OUTSIDE).state == STATE_UNAVAILABLE
    coordinator = demo_entry.runtime_data
    failed = coordinator.last_exception
    assert isinstance(failed, UpdateFailed)
    assert failed.translation_key == key
    # The PLC's own words, said to be its (translated: tests/test_translations_czech.py).
    assert failed.translation_placeholders["error"].startswith(
        f"the device says: {code}: "
    )
    issue = variable_list_issue(hass, demo_entry)
    assert issue is not None
    assert issue.translation_key == key
    assert issue.severity is ir.IssueSeverity.ERROR
    assert not issue.is_fixable
    assert issue.translation_placeholders == {
        "name": demo_entry.title,
        "error": failed.translation_placeholders["error"],
    }

    # The PLC unreachable meanwhile tells nothing of its list: the issue stays.
    simulator.faults.drop_connection = True
    await poll(hass, freezer)
    assert isinstance(coordinator.last_exception, UpdateFailed)
    assert coordinator.last_exception.translation_key == "cannot_connect"
    assert variable_list_issue(hass, demo_entry) is not None
    simulator.faults.clear()

    # The program downloaded again, its public file fine: the first poll mends all.
    simulator.load_program("demo")
    simulator.set_value("outsideTemp.value", -3.5)
    await poll(hass, freezer, 60)

    assert hass.states.get(OUTSIDE).state == "-3.5"
    assert variable_list_issue(hass, demo_entry) is None


@pytest.mark.parametrize(
    ("state", "code", "key"), FAILURES.values(), ids=FAILURES.keys()
)
async def test_at_setup_it_is_the_retry_s_reason_and_an_issue(
    hass: HomeAssistant, simulator: Simulator, state: str, code: str, key: str
) -> None:
    """Set up while the PLC answers it: retried, the reason translated, an issue."""
    break_public_file(simulator, state)
    entry = await setup_entry(hass, make_entry(simulator))

    assert entry.state is ConfigEntryState.SETUP_RETRY
    assert entry.reason is not None
    assert code in entry.reason
    words = "too big" if state == "too_big" else "cannot read"
    assert words in entry.reason
    assert "no variables" not in entry.reason
    issue = variable_list_issue(hass, entry)
    assert issue is not None
    assert issue.translation_key == key

    # Fixed: the next setup clears what the failed one raised.
    simulator.load_program("demo")
    await hass.config_entries.async_reload(entry.entry_id)
    await hass.async_block_till_done()

    assert entry.state is ConfigEntryState.LOADED
    assert variable_list_issue(hass, entry) is None


async def test_unloading_clears_the_issue(
    hass: HomeAssistant, simulator: Simulator, freezer: FrozenDateTimeFactory
) -> None:
    """Nobody watches an unloaded PLC: its issue goes with it."""
    entry = await setup_entry(hass, make_entry(simulator))
    break_public_file(simulator, "too_big")
    await poll(hass, freezer)
    assert variable_list_issue(hass, entry) is not None

    assert await hass.config_entries.async_unload(entry.entry_id)

    assert variable_list_issue(hass, entry) is None
