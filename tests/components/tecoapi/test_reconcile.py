"""A new PLC program (a Mosaic download) reconciled live, without reloading the entry.

And the entry's title, which names the PLC's type and program.
"""

from collections import Counter
import logging
from typing import Any

from freezegun.api import FrozenDateTimeFactory
from homeassistant.components.number import ATTR_MAX
from homeassistant.config_entries import ConfigEntryState
from homeassistant.const import ATTR_UNIT_OF_MEASUREMENT
from homeassistant.core import HomeAssistant
from homeassistant.helpers import device_registry as dr, entity_registry as er
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.tecoapi.const import DOMAIN
from custom_components.tecoapi.pyplc import PlcMode, SourceInfo
from custom_components.tecoapi.reconcile import entry_title
from tests.components.tecoapi.conftest import poll
from tests.simulator import Program, Simulator

SERIAL = "SD 2080"


def registry_keys(hass: HomeAssistant, entry: MockConfigEntry) -> set[tuple[str, str]]:
    """(domain, point key) of every registry entry of the entry."""
    registry = er.async_get(hass)
    return {
        (entity.domain, entity.unique_id.removeprefix(f"{SERIAL}_"))
        for entity in er.async_entries_for_config_entry(registry, entry.entry_id)
    }


def api_object(value: Any, **attr: Any) -> dict[str, Any]:
    """A T_ApiObject's initial value, enabled and visible."""
    return {"value": value, "attr": {"enable": True, "visibility": True, **attr}}


def new_program(simulator: Simulator) -> Program:
    """The demo, re-downloaded with changes of every kind."""
    source = simulator.program.to_mapping()
    variables = source["variables"]
    del variables["outsideTemp"]  # a sensor vanishes
    del variables["Heating"]["variables"]["boilerStarts"]  # a disabled one too
    variables["Rooms"]["variables"]["studyTemp"] = {  # a new sensor
        "type": "T_ApiObject",
        "value": api_object(20.5, readOnly=True, title="Study temperature", units="°C"),
    }
    variables["garageDoor"] = {  # a new switch
        "type": "T_ApiObject OF BOOL",
        "value": api_object(False, readOnly=False, title="Garage door"),
    }
    heating = variables["Heating"]["variables"]
    heating["livingSetpoint"]["value"]["attr"]["readOnly"] = True  # number → sensor
    heating["bedroomSetpoint"]["value"]["attr"]["maxValue"] = 24.0  # a new range
    energy = variables["Energy"]["variables"]
    energy["powerNow"]["value"]["attr"]["units"] = "kW"  # a new unit
    energy["powerNow"]["value"]["value"] = 1.432
    rooms = variables["Rooms"]["variables"]
    rooms["kitchenTemp"]["value"]["attr"]["title"] = "Kitchen air"  # a new title
    return Program.from_mapping(source)


async def test_new_program_is_reconciled_live(
    hass: HomeAssistant,
    simulator: Simulator,
    demo_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
    caplog: pytest.LogCaptureFixture,
) -> None:
    """Added, removed, moved and changed points: the registry follows, no reload."""
    registry = er.async_get(hass)
    coordinator = demo_entry.runtime_data
    before = registry_keys(hass, demo_entry)
    power = registry.async_get("sensor.energy_house_power")
    assert power is not None
    assert ("binary_sensor", "heating.boilerstarts") not in before  # it is a sensor
    assert ("sensor", "heating.boilerstarts") in before  # disabled by default
    stamp = simulator.stamp

    simulator.load_program(new_program(simulator))
    assert simulator.stamp != stamp
    # The next value poll misses outsideTemp (400.005): GetInfo shows the new
    # stamp, and the program is discovered again within the same poll.
    await poll(hass, freezer)

    assert demo_entry.state is ConfigEntryState.LOADED
    assert demo_entry.runtime_data is coordinator
    assert coordinator.data.info.program_stamp == simulator.stamp
    after = registry_keys(hass, demo_entry)
    assert after == (
        before
        - {
            ("sensor", "outsidetemp"),
            ("sensor", "heating.boilerstarts"),
            ("number", "heating.livingsetpoint"),
        }
        | {
            ("sensor", "rooms.studytemp"),
            ("switch", "garagedoor"),
            ("sensor", "heating.livingsetpoint"),
        }
    )
    unique_ids = Counter(
        entity.unique_id
        for entity in er.async_entries_for_config_entry(registry, demo_entry.entry_id)
    )
    assert max(unique_ids.values()) == 1

    assert hass.states.get("sensor.tecomat_cp_2080_outside_temperature") is None
    assert hass.states.get("number.heating_living_room_setpoint") is None
    assert hass.states.get("sensor.heating_living_room_setpoint").state == "21.5"
    assert hass.states.get("sensor.rooms_study_temperature").state == "20.5"
    assert hass.states.get("switch.tecomat_cp_2080_garage_door").state == "off"
    # Same registry entry and entity ID; the entity was re-created with the new
    # native unit, which Home Assistant converts to the unit the user saw so far
    # (1.432 kW shows as 1432 W, not as 1.432 W).
    power_after = registry.async_get("sensor.energy_house_power")
    assert power_after is not None
    assert power_after.id == power.id
    state = hass.states.get("sensor.energy_house_power")
    assert float(state.state) == 1432.0
    assert state.attributes[ATTR_UNIT_OF_MEASUREMENT] == "W"
    assert hass.states.get("sensor.rooms_kitchen_temperature").name == (
        "Rooms Kitchen air"
    )
    assert (
        hass.states.get("number.heating_bedroom_setpoint").attributes[ATTR_MAX] == 24.0
    )

    # The new entities are polled from now on; nothing is created twice.
    simulator.set_value("Rooms.studyTemp.value", 21.0)
    simulator.set_value("garageDoor.value", True)
    await poll(hass, freezer)
    assert hass.states.get("sensor.rooms_study_temperature").state == "21.0"
    assert hass.states.get("switch.tecomat_cp_2080_garage_door").state == "on"
    assert registry_keys(hass, demo_entry) == after
    assert [
        record.getMessage()
        for record in caplog.records
        if record.levelno >= logging.WARNING
        and record.name.startswith(("homeassistant", "custom_components"))
    ] == []


async def test_a_group_the_new_program_drops_loses_its_device(
    hass: HomeAssistant,
    simulator: Simulator,
    demo_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """A program without the Ventilation struct: its device goes with its entities."""
    devices = dr.async_get(hass)

    def group_names() -> set[str | None]:
        return {
            device.name
            for device in dr.async_entries_for_config_entry(
                devices, demo_entry.entry_id
            )
        }

    assert "Ventilation" in group_names()
    source = simulator.program.to_mapping()
    del source["variables"]["ventilation"]
    simulator.load_program(Program.from_mapping(source))

    await poll(hass, freezer, 60)

    assert demo_entry.runtime_data.source.statistics.program_changes == 1
    assert "Ventilation" not in group_names()
    assert {"Tecomat CP-2080", "Rooms", "Heating"} <= group_names()


async def test_program_change_without_missing_variables_waits_for_getinfo(
    hass: HomeAssistant,
    simulator: Simulator,
    demo_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """Only an added variable: found at the next GetInfo.

    That is the next quiet poll (no value changed) or the attribute interval.
    """
    source = simulator.program.to_mapping()
    source["variables"]["garageDoor"] = {
        "type": "T_ApiObject OF BOOL",
        "value": api_object(True, readOnly=True, title="Garage door open"),
    }
    simulator.load_program(Program.from_mapping(source))
    simulator.set_value("outsideTemp.value", -2.5)
    garage = "binary_sensor.tecomat_cp_2080_garage_door_open"

    await poll(hass, freezer, 5)
    assert hass.states.get(garage) is None
    assert "GetInfo" not in {request.service for request in simulator.requests[-3:]}

    await poll(hass, freezer, 5)
    assert hass.states.get(garage).state == "on"
    assert demo_entry.runtime_data.source.statistics.program_changes == 1


async def test_recompiled_program_with_the_same_variables(
    hass: HomeAssistant,
    simulator: Simulator,
    demo_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """Only the code changed: discovered again, every entity stays as it was."""
    registry = er.async_get(hass)
    entries = {
        entity.entity_id: entity
        for entity in er.async_entries_for_config_entry(registry, demo_entry.entry_id)
    }
    source = simulator.program.to_mapping()
    source["program"]["compiled"] = "2026-03-14T09:55:00.000Z"
    simulator.load_program(Program.from_mapping(source))

    await poll(hass, freezer, 60)

    coordinator = demo_entry.runtime_data
    assert coordinator.source.statistics.program_changes == 1
    assert coordinator.data.info.program_stamp == simulator.stamp
    assert {
        entity.entity_id: entity
        for entity in er.async_entries_for_config_entry(registry, demo_entry.entry_id)
    } == entries
    assert hass.states.get("sensor.tecomat_cp_2080_program_compiled").state == (
        "2026-03-14T09:55:00+00:00"
    )


async def test_program_changed_while_home_assistant_was_away(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    """Setting up against a new program removes the vanished points' entries."""
    await hass.config_entries.async_unload(demo_entry.entry_id)
    await hass.async_block_till_done()
    simulator.load_program(new_program(simulator))

    await hass.config_entries.async_setup(demo_entry.entry_id)
    await hass.async_block_till_done()

    keys = registry_keys(hass, demo_entry)
    assert ("sensor", "outsidetemp") not in keys
    assert ("sensor", "heating.boilerstarts") not in keys
    assert ("number", "heating.livingsetpoint") not in keys
    assert ("sensor", "heating.livingsetpoint") in keys
    assert ("sensor", "rooms.studytemp") in keys


async def test_root_skipped_by_discovery_keeps_its_entities(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    """A root GetObject rejects at discovery is not treated as gone for good."""
    await hass.config_entries.async_unload(demo_entry.entry_id)
    await hass.async_block_till_done()
    simulator.faults.rejected_by_object = {"Rooms"}

    await hass.config_entries.async_setup(demo_entry.entry_id)
    await hass.async_block_till_done()

    assert demo_entry.runtime_data.data.catalogue.skipped_groups == ("Rooms",)
    assert ("sensor", "rooms.livingtemp") in registry_keys(hass, demo_entry)


async def test_write_to_a_vanished_variable_checks_the_program(
    hass: HomeAssistant,
    simulator: Simulator,
    demo_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """A write answered 400.005 makes the next poll read GetInfo (and rediscover)."""
    source = simulator.program.to_mapping()
    del source["variables"]["displayMessage"]
    simulator.load_program(Program.from_mapping(source))
    coordinator = demo_entry.runtime_data

    try:
        await coordinator.async_write("displaymessage", "Hello")
    except Exception as err:  # noqa: BLE001 - asserted below
        error: Exception | None = err
    else:
        error = None
    assert error is not None
    assert getattr(error, "translation_key", None) == "write_failed"

    simulator.clear_requests()
    await poll(hass, freezer)

    assert simulator.requests[0].service == "GetInfo"
    assert "displaymessage" not in coordinator.data.points
    assert hass.states.get("text.tecomat_cp_2080_hall_display_message") is None
    registry = er.async_get(hass)
    assert (
        registry.async_get_entity_id("text", DOMAIN, f"{SERIAL}_displaymessage") is None
    )


def renamed_program(simulator: Simulator, name: str) -> Program:
    """The demo, downloaded again under another program name."""
    source = simulator.program.to_mapping()
    source["program"]["name"] = name
    return Program.from_mapping(source)


async def test_new_program_name_retitles_the_entry(
    hass: HomeAssistant,
    simulator: Simulator,
    demo_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """The title the config flow gave follows the program's new name, live."""
    coordinator = demo_entry.runtime_data
    assert demo_entry.title == "CP-2080 · FAMILY_HOUSE v1.3"

    simulator.load_program(renamed_program(simulator, "FAMILY_HOUSE v1.4"))
    await poll(hass, freezer, 60)

    assert coordinator.source.statistics.program_changes == 1
    assert demo_entry.title == "CP-2080 · FAMILY_HOUSE v1.4"
    assert demo_entry.state is ConfigEntryState.LOADED
    assert demo_entry.runtime_data is coordinator
    assert hass.states.get("sensor.tecomat_cp_2080_user_program").state == (
        "FAMILY_HOUSE v1.4"
    )


async def test_renamed_entry_keeps_its_title_after_a_new_program(
    hass: HomeAssistant,
    simulator: Simulator,
    demo_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """A title the user chose is never replaced by the program's name."""
    hass.config_entries.async_update_entry(demo_entry, title="Our house")
    await hass.async_block_till_done()

    simulator.load_program(renamed_program(simulator, "FAMILY_HOUSE v1.4"))
    await poll(hass, freezer, 60)

    assert demo_entry.runtime_data.source.statistics.program_changes == 1
    assert demo_entry.title == "Our house"
    assert hass.states.get("sensor.tecomat_cp_2080_user_program").state == (
        "FAMILY_HOUSE v1.4"
    )


@pytest.mark.parametrize(
    ("plc_type", "program_name", "title"),
    [
        ("CP-2080", "DOC_TECOAPI v1.0", "CP-2080 · DOC_TECOAPI v1.0"),
        (None, "DOC_TECOAPI v1.0", "DOC_TECOAPI v1.0"),
        (None, None, "PP 0004"),
    ],
)
def test_entry_title(
    plc_type: str | None, program_name: str | None, title: str
) -> None:
    """The title names type and program, whatever GetInfo leaves out."""
    info = SourceInfo(
        identity="PP 0004",
        name="Tecomat PLC",
        manufacturer="Teco a.s.",
        family=None,
        model=plc_type,
        serial_number="PP 0004",
        firmware=None,
        mac=None,
        mode=PlcMode.RUNNING,
        program_name=program_name,
        program_compiled=None,
        program_stamp=None,
        time=None,
        api_version=None,
    )
    assert entry_title(info) == title
