"""Covers: GTSAP1 openers (blinds, gates), struct covers, the memory house's blind."""

from freezegun.api import FrozenDateTimeFactory
from homeassistant.components.cover import ATTR_CURRENT_POSITION, ATTR_POSITION
from homeassistant.const import ATTR_DEVICE_CLASS, ATTR_SUPPORTED_FEATURES
from homeassistant.core import HomeAssistant
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry
from syrupy.assertion import SnapshotAssertion

from custom_components.tecoapi.compat import CoverEntityFeature
from tests.components.tecoapi import memory_house
from tests.components.tecoapi.conftest import poll, snapshot_entities
from tests.components.tecoapi.typed import call, typed
from tests.fake_source import MemoryDevice
from tests.simulator import Simulator


@pytest.mark.primary_only
@pytest.mark.parametrize("program_entry", ["demo"], indirect=True)
async def test_covers(
    hass: HomeAssistant, program_entry: MockConfigEntry, snapshot: SnapshotAssertion
) -> None:
    """Every cover of the demo: registry entry and state."""
    await snapshot_entities(hass, snapshot, program_entry, "cover")


async def test_blind(
    hass: HomeAssistant,
    simulator: Simulator,
    demo_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """A GTSAP1 opener: moved by its target, stopped at its current position."""
    blind = typed(hass, "cover", "gtsap1:opener:stineni.obyvak_zaluzie")
    state = hass.states.get(blind)
    assert state.attributes[ATTR_DEVICE_CLASS] == "shutter"
    assert state.attributes[ATTR_SUPPORTED_FEATURES] & CoverEntityFeature.STOP
    base = "Stineni.OBYVAK_ZALUZIE_GTSAP1_OPENER"
    position = simulator.get_value(f"{base}_current")
    assert state.attributes[ATTR_CURRENT_POSITION] == position

    await call(hass, "cover", "set_cover_position", entity_id=blind, position=30)
    assert simulator.get_value(f"{base}_target") == 30

    # The PLC moves the blind down: it is closing.
    simulator.set_value(f"{base}_moving", True)
    simulator.set_value(f"{base}_current", 80)
    await poll(hass, freezer)
    assert hass.states.get(blind).state == "closing"

    await call(hass, "cover", "stop_cover", entity_id=blind)
    assert simulator.get_value(f"{base}_target") == 80

    await call(hass, "cover", "open_cover", entity_id=blind)
    assert simulator.get_value(f"{base}_target") == 100
    await call(hass, "cover", "close_cover", entity_id=blind)
    assert simulator.get_value(f"{base}_target") == 0


async def test_gate_and_a_blind_moved_by_its_position(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    """A gate is a gate; a blind without a separate target has no stop."""
    gate = hass.states.get(typed(hass, "cover", "gtsap1:opener:stineni.vjezd"))
    assert gate.attributes[ATTR_DEVICE_CLASS] == "gate"
    roof = typed(hass, "cover", "struct:cover:podkrovi.stresniokno")
    assert not hass.states.get(roof).attributes[ATTR_SUPPORTED_FEATURES] & (
        CoverEntityFeature.STOP
    )

    await call(
        hass, "cover", "set_cover_position", entity_id=roof, **{ATTR_POSITION: 40}
    )

    assert simulator.get_value("Podkrovi.stresniOkno.position.value") == 40


# --- the memory house (memory_house.py): through the in-memory source ---------


async def test_cover(hass: HomeAssistant, house: MemoryDevice) -> None:
    key = "gtsap1:opener:blind"
    assert memory_house.state(hass, "cover", key).attributes["current_position"] == 40
    await memory_house.call(hass, "cover", "close_cover", key)
    assert house.values["b2"] == 0
    assert memory_house.state(hass, "cover", key).state == "closing"
