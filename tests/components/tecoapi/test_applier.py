"""What an entry asks for, applied in place (``applier.OptionsApplier``).

New intervals apply at once; another choice of entities selects anew from the
catalogue known, without reading the device again; the user's overrides
swap the source for one that discovers the points with them. (The first two,
through the entry's update listener, came from ``test_init``.)
"""

from datetime import timedelta
from typing import TYPE_CHECKING

from freezegun.api import FrozenDateTimeFactory
from homeassistant.config_entries import ConfigEntryState
from homeassistant.const import CONF_SCAN_INTERVAL
from homeassistant.core import HomeAssistant
from homeassistant.helpers import entity_registry as er
from pytest_homeassistant_custom_component.common import (
    MockConfigEntry,
    async_fire_time_changed,
)

from custom_components.tecoapi.applier import create_entry_source
from custom_components.tecoapi.const import (
    CONF_ATTRIBUTE_INTERVAL,
    CONF_EXCLUDE,
    DOMAIN,
)
from custom_components.tecoapi.options import PlcOptions
from custom_components.tecoapi.pyplc.core.models import PointOverride
from tests.components.tecoapi.conftest import setup_entry
from tests.simulator import Simulator

if TYPE_CHECKING:
    from custom_components.tecoapi.coordinator import PlcCoordinator

OUTSIDE = "sensor.tecomat_cp_2080_outside_temperature"
SETPOINT = "number.heating_living_room_setpoint"


async def test_scan_interval_applies_without_reload(
    hass: HomeAssistant,
    simulator: Simulator,
    config_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """A new polling interval is used at once by the same coordinator."""
    await setup_entry(hass, config_entry)
    coordinator = config_entry.runtime_data

    hass.config_entries.async_update_entry(
        config_entry,
        options={
            **config_entry.options,
            CONF_SCAN_INTERVAL: 30,
            CONF_ATTRIBUTE_INTERVAL: 20,
        },
    )
    await hass.async_block_till_done(wait_background_tasks=True)

    assert config_entry.runtime_data is coordinator
    assert coordinator.update_interval == timedelta(seconds=30)
    assert coordinator.source.metadata_interval == timedelta(seconds=20)
    simulator.clear_requests()
    freezer.tick(timedelta(seconds=10))
    async_fire_time_changed(hass)
    await hass.async_block_till_done(wait_background_tasks=True)
    assert simulator.requests == []

    freezer.tick(timedelta(seconds=21))
    async_fire_time_changed(hass)
    await hass.async_block_till_done(wait_background_tasks=True)
    assert "GetObject" in {request.service for request in simulator.requests}


async def test_filter_change_removes_entities_in_place(
    hass: HomeAssistant, simulator: Simulator, config_entry: MockConfigEntry
) -> None:
    """Excluding variables removes their entities, without reloading the entry."""
    await setup_entry(hass, config_entry)
    registry = er.async_get(hass)
    boiler = registry.async_get_entity_id("switch", DOMAIN, "SD 2080_heating.boileron")
    assert boiler is not None
    coordinator = config_entry.runtime_data
    discoveries = coordinator.source.statistics.discoveries

    hass.config_entries.async_update_entry(
        config_entry, options={CONF_EXCLUDE: ["heating.*"]}
    )
    await hass.async_block_till_done(wait_background_tasks=True)

    assert config_entry.state is ConfigEntryState.LOADED
    assert config_entry.runtime_data is coordinator
    assert registry.async_get(boiler) is None
    assert hass.states.get(boiler) is None
    assert hass.states.get("sensor.tecomat_cp_2080_outside_temperature") is not None
    assert not any(
        key.startswith("heating.") for key in config_entry.runtime_data.data.points
    )
    # Selected anew from the catalogue known: the program is not read again.
    assert coordinator.source.statistics.discoveries == discoveries


async def test_overrides_swap_the_source_for_one_that_applies_them(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    coordinator: PlcCoordinator = demo_entry.runtime_data
    old = coordinator.source
    changed = {"outsidetemp": PointOverride(unit="K")}
    assert hass.states.get(OUTSIDE).attributes["device_class"] == "temperature"

    await coordinator.applier.async_replace_overrides(changed)
    await hass.async_block_till_done()

    assert coordinator.source is not old
    assert coordinator.applier.overrides == changed
    assert coordinator.data.points["outsidetemp"].unit_of() == "K"
    # Kelvin is a temperature difference's unit: shown as one.
    assert hass.states.get(OUTSIDE).attributes["device_class"] == "temperature_delta"


async def test_a_source_is_made_as_the_options_say(
    hass: HomeAssistant, demo_entry: MockConfigEntry
) -> None:
    source = create_entry_source(
        hass,
        demo_entry,
        PlcOptions(attribute_interval=timedelta(seconds=45)),
        None,
    )
    try:
        assert source.metadata_interval == timedelta(seconds=45)
        assert source is not demo_entry.runtime_data.source
    finally:
        await source.close()
