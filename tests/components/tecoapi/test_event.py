"""Events: a GTSAP1 button's clicks and long presses, the memory house's button."""

from typing import Any

from freezegun.api import FrozenDateTimeFactory
from homeassistant.components.event import ATTR_EVENT_TYPE
from homeassistant.core import Event, HomeAssistant, callback
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry
from syrupy.assertion import SnapshotAssertion

from tests.components.tecoapi import memory_house
from tests.components.tecoapi.conftest import poll, snapshot_entities
from tests.components.tecoapi.typed import typed
from tests.fake_source import MemoryDevice
from tests.simulator import Simulator


@pytest.mark.primary_only
@pytest.mark.parametrize("program_entry", ["demo"], indirect=True)
async def test_events(
    hass: HomeAssistant, program_entry: MockConfigEntry, snapshot: SnapshotAssertion
) -> None:
    """Every event entity of the demo: registry entry and state."""
    await snapshot_entities(hass, snapshot, program_entry, "event")


def record_events(hass: HomeAssistant, entity_id: str) -> list[str]:
    """The event types an event entity fires from now on, in order."""
    fired: list[str] = []

    @callback
    def record(event: Event[Any]) -> None:
        if event.data["entity_id"] == entity_id and event.data["new_state"] is not None:
            fired.append(event.data["new_state"].attributes[ATTR_EVENT_TYPE])

    hass.bus.async_listen("state_changed", record)
    return fired


CLICKS = "DVERE_TLACITKO_GTSAP1_BUTTON_CLICKCNT"


PRESSES = "DVERE_TLACITKO_GTSAP1_BUTTON_PRESSCNT"


async def test_button_events_one_per_increment(
    hass: HomeAssistant,
    simulator: Simulator,
    demo_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """Clicks and long presses: an event per increment.

    Nothing fires at start-up, after a counter reset, or for a counter that did
    not move; a wrap-around of the counter counts its increment.
    """
    button = typed(hass, "event", "gtsap1:button:dvere_tlacitko")
    assert hass.states.get(button).state == "unknown"
    fired = record_events(hass, button)

    simulator.set_value(CLICKS, simulator.get_value(CLICKS) + 1)
    await poll(hass, freezer)
    assert fired == ["click"]
    simulator.set_value(PRESSES, simulator.get_value(PRESSES) + 1)
    await poll(hass, freezer)
    assert fired == ["click", "long_press"]

    fired.clear()
    simulator.set_value(CLICKS, 65535)  # a jump: not clicks (a counter set)
    await poll(hass, freezer)
    simulator.set_value(CLICKS, 0)  # 65535 → 0: one increment
    await poll(hass, freezer)
    assert fired == ["click"]

    fired.clear()
    simulator.set_value(CLICKS, 40)
    simulator.set_value(PRESSES, 0)  # a reset
    await poll(hass, freezer)
    await poll(hass, freezer)
    assert fired == []


@pytest.mark.primary_only
async def test_button_increments_missed_between_polls_fire_each(
    hass: HomeAssistant,
    simulator: Simulator,
    demo_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """Three clicks and a long press between two polls: four events.

    (Home Assistant 2026.2 gives events of the same instant one timestamp, so
    with the test's frozen clock it shows them as one state.)
    """
    button = typed(hass, "event", "gtsap1:button:dvere_tlacitko")
    fired = record_events(hass, button)

    simulator.set_value(CLICKS, simulator.get_value(CLICKS) + 3)
    simulator.set_value(PRESSES, simulator.get_value(PRESSES) + 1)
    await poll(hass, freezer)

    assert sorted(fired) == ["click", "click", "click", "long_press"]


# --- the memory house (memory_house.py): through the in-memory source ---------


async def test_event(
    hass: HomeAssistant, house: MemoryDevice, freezer: FrozenDateTimeFactory
) -> None:
    key = "gtsap1:button:door"
    assert memory_house.state(hass, "event", key).state == "unknown"
    house.values["d1"] = 5
    await poll(hass, freezer)
    shown = memory_house.state(hass, "event", key)
    assert shown.attributes["event_type"] == "click"
    assert shown.state != "unknown"
