"""Who hears of an update: the polled keys follow the entities, and a poll tells
only the entities whose keys changed, unless its success flipped."""

from collections import Counter

from freezegun.api import FrozenDateTimeFactory
from homeassistant.core import HomeAssistant, callback
from homeassistant.helpers import entity_registry as er
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.tecoapi.coordinator import PlcCoordinator
from tests.components.tecoapi.conftest import poll
from tests.simulator import Simulator

OUTSIDE = "sensor.tecomat_cp_2080_outside_temperature"


def key_of(hass: HomeAssistant, entry: MockConfigEntry, entity_id: str) -> str:
    """The point key of one of the entry's entities."""
    registered = er.async_get(hass).async_get(entity_id)
    assert registered is not None
    return registered.unique_id.removeprefix(f"{entry.unique_id}_")


def listening(coordinator: PlcCoordinator, heard: Counter[str]) -> None:
    """Listen as an entity of the outside temperature does, and as a follower does."""

    @callback
    def outside() -> None:
        heard["outside"] += 1

    @callback
    def everything() -> None:
        heard["everything"] += 1

    coordinator.async_add_listener(outside, "outsidetemp")
    coordinator.async_add_listener(everything)


async def test_a_point_is_polled_while_an_entity_shows_it(
    hass: HomeAssistant, demo_entry: MockConfigEntry, freezer: FrozenDateTimeFactory
) -> None:
    """An entity removed stops the polling of its point, one added starts it again
    (the polled keys are kept between polls, not kept stale)."""
    coordinator: PlcCoordinator = demo_entry.runtime_data
    key = key_of(hass, demo_entry, OUTSIDE)
    assert key in coordinator.polled_keys

    er.async_get(hass).async_remove(OUTSIDE)
    await hass.async_block_till_done()
    assert key not in coordinator.polled_keys
    await poll(hass, freezer)
    assert key not in coordinator.source.read_plan.point_keys

    await hass.config_entries.async_reload(demo_entry.entry_id)
    await hass.async_block_till_done()
    assert key in demo_entry.runtime_data.polled_keys


async def test_a_poll_tells_the_entities_whose_keys_changed(
    demo_entry: MockConfigEntry,
    hass: HomeAssistant,
    simulator: Simulator,
    freezer: FrozenDateTimeFactory,
) -> None:
    """Nothing changed: only the listeners without keys hear (one added later too,
    not once removed); a changed value: its entity hears too, once."""
    coordinator: PlcCoordinator = demo_entry.runtime_data
    assert key_of(hass, demo_entry, OUTSIDE) == "outsidetemp"
    heard: Counter[str] = Counter()
    listening(coordinator, heard)

    await poll(hass, freezer)
    assert heard == {"everything": 1}

    @callback
    def late() -> None:
        heard["late"] += 1

    remove_late = coordinator.async_add_listener(late)
    await poll(hass, freezer)
    assert heard == {"everything": 2, "late": 1}
    remove_late()
    await poll(hass, freezer)
    assert heard == {"everything": 3, "late": 1}

    simulator.set_value("outsideTemp.value", -7.5)
    await poll(hass, freezer)
    assert heard == {"everything": 4, "late": 1, "outside": 1}
    state = hass.states.get(OUTSIDE)
    assert state is not None
    assert state.state == "-7.5"


async def test_a_failed_poll_and_its_recovery_tell_every_listener(
    demo_entry: MockConfigEntry,
    hass: HomeAssistant,
    simulator: Simulator,
    freezer: FrozenDateTimeFactory,
) -> None:
    """The success flipped: every entity hears (each shows itself unavailable, and
    available again), whatever its keys."""
    coordinator: PlcCoordinator = demo_entry.runtime_data
    heard: Counter[str] = Counter()
    listening(coordinator, heard)

    simulator.faults.drop_connection = True
    await poll(hass, freezer)
    assert not coordinator.last_update_success
    assert heard == {"everything": 1, "outside": 1}
    state = hass.states.get(OUTSIDE)
    assert state is not None
    assert state.state == "unavailable"

    simulator.faults.clear()
    await poll(hass, freezer)
    assert coordinator.last_update_success
    assert heard == {"everything": 2, "outside": 2}
    await poll(hass, freezer)
    assert heard == {"everything": 3, "outside": 2}


async def test_a_listener_that_fails_costs_the_others_nothing(
    demo_entry: MockConfigEntry,
    hass: HomeAssistant,
    simulator: Simulator,
    freezer: FrozenDateTimeFactory,
    caplog: pytest.LogCaptureFixture,
) -> None:
    coordinator: PlcCoordinator = demo_entry.runtime_data
    heard: Counter[str] = Counter()

    @callback
    def failing() -> None:
        raise RuntimeError("broken")

    coordinator.async_add_listener(failing, "outsidetemp")
    listening(coordinator, heard)
    simulator.set_value("outsideTemp.value", -7.5)

    await poll(hass, freezer)

    assert heard == {"everything": 1, "outside": 1}
    assert "Unexpected error updating listener" in caplog.text
