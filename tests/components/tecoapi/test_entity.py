"""Base entity behaviour: unique IDs, availability, values that stop fitting."""

from datetime import timedelta

from freezegun.api import FrozenDateTimeFactory
from homeassistant.const import STATE_UNKNOWN
from homeassistant.core import HomeAssistant, callback
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.tecoapi.const import (
    CONF_ATTRIBUTE_INTERVAL,
    CONF_INCLUDE,
)
from tests.components.tecoapi.conftest import make_entry, poll, setup_entry
from tests.simulator import Program, Simulator


async def test_values_that_no_longer_fit_show_unknown(
    hass: HomeAssistant,
    simulator: Simulator,
    demo_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """A program that changed a BOOL to a USINT: the entities show unknown, not junk."""
    source = simulator.program.to_mapping()
    lights = source["variables"]["lights"]
    lights["type"] = "ARRAY[0..5] OF T_ApiObject OF USINT"
    for light in lights["value"]:
        light["value"] = 1
    window = source["variables"]["Rooms"]["variables"]["windowOpen"]
    window["type"] = "T_ApiObject OF USINT"
    window["value"]["value"] = 1
    simulator.load_program(Program.from_mapping(source))

    await poll(hass, freezer)

    assert hass.states.get("switch.lights_kitchen_light").state == STATE_UNKNOWN
    assert hass.states.get("binary_sensor.rooms_bedroom_window_open").state == (
        STATE_UNKNOWN
    )
    assert hass.states.get("number.heating_living_room_setpoint").state == "21.5"


async def test_listener_without_a_key_hears_every_poll(
    hass: HomeAssistant, demo_entry: MockConfigEntry
) -> None:
    """Only keyed listeners are filtered; a listener without a key hears each update."""
    coordinator = demo_entry.runtime_data
    updates: list[frozenset[str]] = []

    @callback
    def record() -> None:
        updates.append(coordinator.data.changed)

    remove = coordinator.async_add_listener(record)
    await coordinator.async_refresh()
    await coordinator.async_refresh()
    remove()
    await coordinator.async_refresh()

    assert updates == [frozenset(), frozenset()]


async def test_include_filter_selects_variables(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    """Only variables matching an include pattern become entities."""
    entry = make_entry(simulator, **{CONF_INCLUDE: ["rooms.*", "outsidetemp"]})

    await setup_entry(hass, entry)

    assert sorted(entry.runtime_data.data.points) == [
        "outsidetemp",
        "rooms.bathroomhumidity",
        "rooms.bathroomtemp",
        "rooms.bedroomhumidity",
        "rooms.bedroomtemp",
        "rooms.kitchentemp",
        "rooms.livinghumidity",
        "rooms.livingtemp",
        "rooms.windowopen",
    ]


async def test_shorter_attribute_interval_applies_at_once(
    hass: HomeAssistant,
    simulator: Simulator,
    demo_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """A shorter attribute interval: the next attribute refresh comes sooner."""
    hass.config_entries.async_update_entry(
        demo_entry, options={CONF_ATTRIBUTE_INTERVAL: 10}
    )
    await hass.async_block_till_done()
    simulator.mode = "HALT"
    # A value changing keeps the polls from being quiet (a quiet poll reads
    # GetInfo at once): GetInfo comes on the attribute cadence alone.
    simulator.set_value("outsideTemp.value", 5.5)
    simulator.clear_requests()

    await poll(hass, freezer, 5)
    assert "GetInfo" not in {request.service for request in simulator.requests}

    simulator.set_value("outsideTemp.value", 6.5)
    await poll(hass, freezer, 5)
    assert "GetInfo" in {request.service for request in simulator.requests}
    assert hass.states.get("sensor.tecomat_cp_2080_mode").state == "halt"
    assert demo_entry.runtime_data.options.attribute_interval == timedelta(seconds=10)


@pytest.mark.primary_only
async def test_failing_listener_does_not_stop_the_others(
    hass: HomeAssistant,
    simulator: Simulator,
    demo_entry: MockConfigEntry,
    caplog: pytest.LogCaptureFixture,
) -> None:
    """A listener that raises is logged; the other listeners still hear.

    Home Assistant's coordinator guarantees it from 2026.10 (2026.2 stops at the
    first failing listener); the entities of this integration never raise there.
    """
    coordinator = demo_entry.runtime_data
    heard: list[float] = []

    @callback
    def broken() -> None:
        raise RuntimeError("listener bug")

    @callback
    def record() -> None:
        heard.append(coordinator.data.values["outsidetemp"])

    removers = [
        coordinator.async_add_listener(broken, "outsidetemp"),
        coordinator.async_add_listener(record, "outsidetemp"),
    ]
    simulator.set_value("outsideTemp.value", 1.5)
    await coordinator.async_refresh()
    for remove in removers:
        remove()

    assert heard == [1.5]
    assert "Unexpected error updating listener" in caplog.text
