"""Climate: GTSAP1 thermostats of each type, struct thermostats, the memory house's."""

from freezegun.api import FrozenDateTimeFactory
from homeassistant.components.climate import (
    ATTR_HVAC_ACTION,
    ATTR_HVAC_MODES,
    ATTR_MAX_TEMP,
    ATTR_MIN_TEMP,
    ATTR_TARGET_TEMP_STEP,
    SERVICE_SET_HVAC_MODE,
    SERVICE_SET_TEMPERATURE,
)
from homeassistant.const import ATTR_TEMPERATURE
from homeassistant.core import HomeAssistant
from homeassistant.helpers import entity_registry as er
from homeassistant.helpers.entity_platform import async_get_platforms
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry
from syrupy.assertion import SnapshotAssertion

from custom_components.tecoapi.climate import PlcClimate
from custom_components.tecoapi.compat import HVACAction, HVACMode
from custom_components.tecoapi.const import DOMAIN
from tests.components.tecoapi import memory_house
from tests.components.tecoapi.conftest import (
    make_entry,
    poll,
    setup_entry,
    snapshot_entities,
)
from tests.components.tecoapi.typed import call, typed
from tests.conftest import SIM_PASSWORD, SIM_USERNAME
from tests.fake_source import MemoryDevice
from tests.simulator import Program, Simulator, load_program


@pytest.mark.primary_only
@pytest.mark.parametrize("program_entry", ["demo"], indirect=True)
async def test_climates(
    hass: HomeAssistant, program_entry: MockConfigEntry, snapshot: SnapshotAssertion
) -> None:
    """Every thermostat of the demo: registry entry and state."""
    await snapshot_entities(hass, snapshot, program_entry, "climate")


@pytest.mark.parametrize(
    ("key", "modes", "flags"),
    [
        (
            "gtsap1:thermostat:termostaty.obyvak",
            {"heat", "cool", "heat_cool", "off"},
            ("heatmode", "coolmode"),
        ),
        ("gtsap1:thermostat:termostaty.loznice", {"heat", "off"}, ("heatmode",)),
        ("gtsap1:thermostat:termostaty.pracovna", {"cool", "off"}, ("coolmode",)),
    ],
    ids=["both", "heating", "cooling"],
)
async def test_thermostat_modes(
    hass: HomeAssistant,
    simulator: Simulator,
    demo_entry: MockConfigEntry,
    *,
    key: str,
    modes: set[str],
    flags: tuple[str, ...],
) -> None:
    """The thermostat's type gives its modes; a mode switches the block's flags."""
    climate = typed(hass, "climate", key)
    state = hass.states.get(climate)
    assert set(state.attributes[ATTR_HVAC_MODES]) == modes
    base = "Termostaty." + key.rsplit(".", 1)[1].upper() + "_GTSAP1_THERMOSTAT"

    await call(
        hass, "climate", SERVICE_SET_HVAC_MODE, entity_id=climate, hvac_mode="off"
    )
    assert all(simulator.get_value(f"{base}_{flag}") is False for flag in flags)
    assert hass.states.get(climate).state == HVACMode.OFF

    mode = HVACMode.HEAT if "heat" in modes else HVACMode.COOL
    await call(
        hass, "climate", SERVICE_SET_HVAC_MODE, entity_id=climate, hvac_mode=mode
    )
    assert simulator.get_value(f"{base}_{flags[0]}") is True
    assert hass.states.get(climate).state == mode


def installers_thermostats() -> Program:
    """The demo, its thermostat blocks as installers leave them: every flag there.

    A GTSAP1 block has ``heatmode``, ``coolmode``, ``heat`` and ``cool`` whatever its
    ``type``: the heating-only bedroom's cooling flags are on, the cooling-only
    study's heating flags too.
    """
    source = load_program("demo").to_mapping()
    thermostats = source["variables"]["Termostaty"]["variables"]
    for block, flags in (
        ("LOZNICE", ("coolmode", "cool")),
        ("PRACOVNA", ("heatmode", "heat")),
    ):
        for flag in flags:
            thermostats[f"{block}_GTSAP1_THERMOSTAT_{flag}"] = {
                "type": "BOOL",
                "value": True,
            }
    return Program.from_mapping(source)


@pytest.mark.parametrize(
    ("block", "mode", "own", "foreign"),
    [
        ("loznice", HVACMode.HEAT, ("heatmode", "heat"), ("coolmode", "cool")),
        ("pracovna", HVACMode.COOL, ("coolmode", "cool"), ("heatmode", "heat")),
    ],
    ids=["heating", "cooling"],
)
async def test_a_thermostat_offers_only_what_its_type_does(
    hass: HomeAssistant,
    socket_enabled: None,
    *,
    block: str,
    mode: HVACMode,
    own: tuple[str, str],
    foreign: tuple[str, str],
) -> None:
    """``type`` 2 heats and 1 cools, whatever flags the block carries besides.

    The other direction's flags are neither offered, nor read, nor written: off
    switches the thermostat's own mode flag off and leaves the other alone.
    """
    base = f"Termostaty.{block.upper()}_GTSAP1_THERMOSTAT"
    own_mode, own_action = own
    foreign_mode = foreign[0]
    async with Simulator(
        installers_thermostats(), username=SIM_USERNAME, password=SIM_PASSWORD
    ) as simulator:
        simulator.set_value(f"{base}_{own_action}", False)
        await setup_entry(hass, make_entry(simulator))
        climate = typed(hass, "climate", f"gtsap1:thermostat:termostaty.{block}")
        state = hass.states.get(climate)
        assert state.attributes[ATTR_HVAC_MODES] == [mode, HVACMode.OFF]
        assert state.state == mode
        # Its own action flag is off: idle, whatever the other direction's says.
        assert state.attributes[ATTR_HVAC_ACTION] == HVACAction.IDLE

        await call(
            hass, "climate", SERVICE_SET_HVAC_MODE, entity_id=climate, hvac_mode="off"
        )
        assert simulator.get_value(f"{base}_{own_mode}") is False
        assert simulator.get_value(f"{base}_{foreign_mode}") is True
        assert hass.states.get(climate).state == HVACMode.OFF

        await call(hass, "climate", "turn_on", entity_id=climate)
        assert simulator.get_value(f"{base}_{own_mode}") is True
        assert simulator.get_value(f"{base}_{foreign_mode}") is True
        assert hass.states.get(climate).state == mode


async def test_thermostat_setpoint_range_and_action(
    hass: HomeAssistant,
    simulator: Simulator,
    demo_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """The block's range bounds the target, in half degrees; heat is the action."""
    climate = typed(hass, "climate", "gtsap1:thermostat:termostaty.loznice")
    base = "Termostaty.LOZNICE_GTSAP1_THERMOSTAT"
    state = hass.states.get(climate)
    assert state.attributes[ATTR_MIN_TEMP] == simulator.get_value(f"{base}_mintemp")
    assert state.attributes[ATTR_MAX_TEMP] == simulator.get_value(f"{base}_maxtemp")
    assert state.attributes[ATTR_TARGET_TEMP_STEP] == 0.5

    await call(
        hass, "climate", SERVICE_SET_TEMPERATURE, entity_id=climate, temperature=21.5
    )
    assert simulator.get_value(f"{base}_setpoint") == 21.5
    assert hass.states.get(climate).attributes[ATTR_TEMPERATURE] == 21.5

    simulator.set_value(f"{base}_heatmode", True)
    simulator.set_value(f"{base}_heat", True)
    await poll(hass, freezer)
    assert hass.states.get(climate).attributes[ATTR_HVAC_ACTION] == HVACAction.HEATING
    simulator.set_value(f"{base}_heat", False)
    await poll(hass, freezer)
    assert hass.states.get(climate).attributes[ATTR_HVAC_ACTION] == HVACAction.IDLE


async def test_struct_thermostat_honours_the_setpoint_attributes(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    """Our convention: the setpoint T_ApiObject's minValue/maxValue are the range."""
    climate = typed(hass, "climate", "struct:climate:detskypokoj.thermostat")
    state = hass.states.get(climate)
    assert state.attributes[ATTR_MIN_TEMP] == simulator.get_value(
        "detskyPokoj.thermostat.setpoint.attr.minValue"
    )
    assert state.attributes[ATTR_MAX_TEMP] == simulator.get_value(
        "detskyPokoj.thermostat.setpoint.attr.maxValue"
    )
    assert state.attributes["current_temperature"] == simulator.get_value(
        "detskyPokoj.thermostat.temperature.value"
    )


# --- the memory house (memory_house.py): through the in-memory source ---------


async def test_climate(hass: HomeAssistant, house: MemoryDevice) -> None:
    key = "gtsap1:thermostat:room"
    shown = memory_house.state(hass, "climate", key)
    assert shown.attributes["hvac_modes"] == ["heat", "off"]
    assert shown.attributes["current_temperature"] == 21.5
    await memory_house.call(hass, "climate", "set_temperature", key, temperature=23.5)
    assert house.values["t3"] == 23.5


def climate_entity(hass: HomeAssistant, entity_id: str) -> PlcClimate:
    """The thermostat's entity object, as Home Assistant holds it."""
    platform = next(
        platform
        for platform in async_get_platforms(hass, DOMAIN)
        if platform.domain == "climate"
    )
    entity = platform.entities[entity_id]
    assert isinstance(entity, PlcClimate)
    return entity


async def test_climate_gives_the_native_temperatures(
    hass: HomeAssistant, house: MemoryDevice
) -> None:
    """What 2026.11 reads (native_*) is what older releases show (the old names)."""
    key = "gtsap1:thermostat:room"
    thermostat = climate_entity(hass, memory_house.entity(hass, "climate", key))
    assert thermostat.native_current_temperature == 21.5
    assert thermostat.current_temperature == 21.5
    await memory_house.call(hass, "climate", "set_temperature", key, temperature=23.5)
    assert thermostat.native_target_temperature == 23.5
    assert memory_house.state(hass, "climate", key).attributes["temperature"] == 23.5
    assert PlcClimate._attr_native_temperature_unit == "°C"


async def test_a_renamed_entity_keeps_showing_and_writing(
    hass: HomeAssistant, house: MemoryDevice, freezer: FrozenDateTimeFactory
) -> None:
    """A new entity ID: the state moves to it, polls and writes go on under it.

    2026.11 changes it in place and calls async_entity_id_changed (called here as
    it would be); older releases remove the entity and add it again.
    """
    key = "gtsap1:thermostat:room"
    old = memory_house.entity(hass, "climate", key)
    er.async_get(hass).async_update_entity(old, new_entity_id="climate.renamed")
    await hass.async_block_till_done()
    assert hass.states.get(old) is None
    assert memory_house.entity(hass, "climate", key) == "climate.renamed"
    climate_entity(hass, "climate.renamed").async_entity_id_changed(old)
    house.values["t2"] = 19.0
    await poll(hass, freezer)
    assert (
        memory_house.state(hass, "climate", key).attributes["current_temperature"]
        == 19.0
    )
    await memory_house.call(hass, "climate", "set_temperature", key, temperature=22.0)
    assert house.values["t3"] == 22.0
