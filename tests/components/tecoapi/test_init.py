"""Setting up, unloading and reconfiguring a TecoApi entry."""

from datetime import timedelta
import logging

from freezegun.api import FrozenDateTimeFactory
from homeassistant.config_entries import SOURCE_REAUTH, ConfigEntryState
from homeassistant.const import (
    CONF_SCAN_INTERVAL,
)
from homeassistant.core import HomeAssistant
from homeassistant.exceptions import HomeAssistantError
from homeassistant.helpers import (
    area_registry as ar,
    device_registry as dr,
    entity_registry as er,
)
import pytest
from pytest_homeassistant_custom_component.common import (
    MockConfigEntry,
    async_fire_time_changed,
)

from custom_components.tecoapi.compat import AREA_IN_ENTITY_ID, entry_device
from custom_components.tecoapi.const import (
    CONF_DEVICES,
    CONF_EXCLUDE,
    CONF_PLAIN_VARIABLES,
    DOMAIN,
    DeviceGrouping,
    PlainVariables,
)
from tests.components.tecoapi.conftest import (
    entity_id_of,
    entry_data,
    make_entry,
    setup_entry,
)
from tests.conftest import SIM_PASSWORD, SIM_USERNAME
from tests.simulator import Simulator


async def test_setup_and_unload(
    hass: HomeAssistant, simulator: Simulator, config_entry: MockConfigEntry
) -> None:
    """The entry loads with its coordinator, and unloads without leftovers."""
    await setup_entry(hass, config_entry)

    assert config_entry.state is ConfigEntryState.LOADED
    coordinator = config_entry.runtime_data
    assert coordinator.data.info.serial_number == simulator.serial_number
    assert hass.states.get("sensor.tecomat_cp_2080_outside_temperature") is not None

    assert await hass.config_entries.async_unload(config_entry.entry_id)
    await hass.async_block_till_done()

    assert config_entry.state is ConfigEntryState.NOT_LOADED
    assert hass.states.get("sensor.tecomat_cp_2080_outside_temperature").state == (
        "unavailable"
    )


async def test_home_assistant_s_loggers_are_left_as_they_are(
    hass: HomeAssistant, config_entry: MockConfigEntry
) -> None:
    """No filter of ours sits on another component's logger (Home Assistant's own).

    How Home Assistant logs what happens in it (the websocket API's line for a
    refused call among them) is its decision; only the integration's own
    loggers (``custom_components.tecoapi.*``) are ours to shape.
    """
    await setup_entry(hass, config_entry)
    ours = "custom_components.tecoapi"

    foreign = {
        name: [repr(known) for known in logger.filters]
        for name, logger in logging.Logger.manager.loggerDict.items()
        if isinstance(logger, logging.Logger)
        and name != ours
        and not name.startswith(f"{ours}.")
        # A filter is an object or a function: its __module__ says whose.
        and any(
            str(getattr(known, "__module__", "")).startswith(ours)
            for known in logger.filters
        )
    }
    assert foreign == {}


async def test_one_device_per_plc(hass: HomeAssistant, simulator: Simulator) -> None:
    """The PLC is one device: Teco a.s., its type, serial, firmware, MAC and web page.

    With the devices option on ``single``, every entity sits on it.
    """
    config_entry = await setup_entry(
        hass, make_entry(simulator, **{CONF_DEVICES: DeviceGrouping.SINGLE})
    )

    devices = dr.async_entries_for_config_entry(
        dr.async_get(hass), config_entry.entry_id
    )
    assert len(devices) == 1
    device = devices[0]
    assert device.identifiers == {(DOMAIN, simulator.serial_number)}
    assert device.manufacturer == "Teco a.s."
    assert device.model == "CP-2080"
    assert device.name == "Tecomat CP-2080"
    assert device.serial_number == "SD 2080"
    assert device.sw_version == "Fx2 CP2080I v1.1"
    assert device.connections == {(dr.CONNECTION_NETWORK_MAC, "00:0a:14:2c:80:17")}
    assert device.configuration_url == simulator.url
    entities = er.async_entries_for_device(
        er.async_get(hass), device.id, include_disabled_entities=True
    )
    assert len(entities) == len(
        er.async_entries_for_config_entry(er.async_get(hass), config_entry.entry_id)
    )


async def test_groups_are_devices_under_the_plc(
    hass: HomeAssistant, simulator: Simulator, config_entry: MockConfigEntry
) -> None:
    """Each top-level struct, program instance or array is a device under the PLC.

    Top-level variables stay on the PLC's device; a group named like a room
    gives its room's area to the lights, blinds and thermostats in it (itself
    only where entity IDs do not start with the area: it is nothing but the
    room, and its entities' IDs would say the room twice). Its name has its
    accents back.
    """
    await setup_entry(hass, config_entry)
    devices = dr.async_get(hass)
    plc = entry_device(
        hass, config_entry.entry_id, identifier=(DOMAIN, simulator.serial_number)
    )
    assert plc is not None
    assert plc.name == "Tecomat CP-2080"
    groups = {
        device.name: device
        for device in dr.async_entries_for_config_entry(devices, config_entry.entry_id)
        if device.id != plc.id
    }
    assert {"Rooms", "Heating", "Energy", "Ventilation", "Lights", "Blinds"} <= set(
        groups
    )
    assert all(device.via_device_id == plc.id for device in groups.values())
    rooms = groups["Rooms"]
    assert rooms.identifiers == {(DOMAIN, f"{simulator.serial_number}_rooms")}
    assert rooms.area_id is None
    kids = groups["Dětský pokoj"]
    area_id = ar.async_get(hass).async_get_area_by_name("Dětský pokoj")
    assert area_id is not None
    assert kids.area_id == (None if AREA_IN_ENTITY_ID else area_id.id)
    thermostat = devices.async_get(
        er.async_get(hass)
        .async_get(
            entity_id_of(
                hass, "climate", "SD 2080_struct:climate:detskypokoj.thermostat"
            )
        )
        .device_id
    )
    assert thermostat.area_id == area_id.id
    assert thermostat.via_device_id == plc.id
    registry = er.async_get(hass)
    living = registry.async_get(
        entity_id_of(hass, "sensor", "SD 2080_rooms.livingtemp")
    )
    outside = registry.async_get("sensor.tecomat_cp_2080_outside_temperature")
    assert living is not None
    assert outside is not None
    assert living.device_id == rooms.id
    assert outside.device_id == plc.id


async def test_everything_on_the_plc_device_keeps_entities_and_drops_groups(
    hass: HomeAssistant, simulator: Simulator, config_entry: MockConfigEntry
) -> None:
    """Switching the devices option to one device moves entities, keeping them.

    The group devices are left empty and leave the registry; an entity ID the user
    chose stays.
    """
    await setup_entry(hass, config_entry)
    registry = er.async_get(hass)
    living = entity_id_of(hass, "sensor", "SD 2080_rooms.livingtemp")
    registry.async_update_entity(living, new_entity_id="sensor.living_room_air")
    entities = len(er.async_entries_for_config_entry(registry, config_entry.entry_id))
    devices = dr.async_get(hass)
    assert len(dr.async_entries_for_config_entry(devices, config_entry.entry_id)) > 1

    hass.config_entries.async_update_entry(
        config_entry, options={CONF_DEVICES: DeviceGrouping.SINGLE}
    )
    await hass.async_block_till_done()

    remaining = dr.async_entries_for_config_entry(devices, config_entry.entry_id)
    assert [device.name for device in remaining] == ["Tecomat CP-2080"]
    assert (
        len(er.async_entries_for_config_entry(registry, config_entry.entry_id))
        == entities
    )
    moved = registry.async_get("sensor.living_room_air")
    assert moved is not None
    assert moved.device_id == remaining[0].id
    assert hass.states.get("sensor.living_room_air") is not None


async def test_a_second_plc_of_the_same_type_gets_its_own_name(
    hass: HomeAssistant, simulator: Simulator, config_entry: MockConfigEntry
) -> None:
    """Two CP-2080s: the second one's device names (and entity IDs) carry its serial."""
    await setup_entry(hass, config_entry)
    second = Simulator("demo", username=SIM_USERNAME, password=SIM_PASSWORD)
    second.serial_number = "SD 2081"
    await second.start()
    try:
        await setup_entry(hass, make_entry(second))
        second_entry = hass.config_entries.async_entry_for_domain_unique_id(
            DOMAIN, "SD 2081"
        )
        assert second_entry is not None
        device = entry_device(
            hass, second_entry.entry_id, identifier=(DOMAIN, "SD 2081")
        )
        assert device is not None
        assert device.name == "Tecomat CP-2080 SD 2081"
        assert hass.states.get("sensor.tecomat_cp_2080_sd_2081_outside_temperature")
        assert hass.states.get("sensor.tecomat_cp_2080_outside_temperature")
        # Its groups too: both programs have a Heating struct.
        heating = entry_device(
            hass, second_entry.entry_id, identifier=(DOMAIN, "SD 2081_heating")
        )
        assert heating is not None
        assert heating.name == "Heating SD 2081"
        registry = er.async_get(hass)
        second_ids = [
            entity.entity_id
            for entity in er.async_entries_for_config_entry(
                registry, second_entry.entry_id
            )
        ]
        assert "number.heating_sd_2081_living_room_setpoint" in second_ids
        assert not [entity_id for entity_id in second_ids if entity_id.endswith("_2")]
    finally:
        await second.stop()


async def test_unreachable_plc_retries_setup(
    hass: HomeAssistant, simulator: Simulator, closed_port: str
) -> None:
    """A PLC that does not answer at start: setup is retried (ConfigEntryNotReady)."""
    entry = MockConfigEntry(
        domain=DOMAIN,
        unique_id=simulator.serial_number,
        data=entry_data(simulator, host=f"http://{closed_port}"),
    )

    await setup_entry(hass, entry)

    assert entry.state is ConfigEntryState.SETUP_RETRY
    assert entry.reason is not None
    assert "Cannot reach the device" in entry.reason


async def test_rejected_credentials_start_reauth(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    """Credentials the PLC rejects at start fail setup and open a reauth flow."""
    entry = make_entry(simulator)
    entry.add_to_hass(hass)
    hass.config_entries.async_update_entry(
        entry, data=entry_data(simulator, password="wrong")
    )

    await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()

    assert entry.state is ConfigEntryState.SETUP_ERROR
    flows = hass.config_entries.flow.async_progress_by_handler(DOMAIN)
    assert [flow["context"]["source"] for flow in flows] == [SOURCE_REAUTH]
    assert flows[0]["context"]["entry_id"] == entry.entry_id


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
        config_entry, options={**config_entry.options, CONF_SCAN_INTERVAL: 30}
    )
    await hass.async_block_till_done(wait_background_tasks=True)

    assert config_entry.runtime_data is coordinator
    assert coordinator.update_interval == timedelta(seconds=30)
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


async def test_ignored_plain_variables_are_not_created(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    """With plain variables ignored, only T_ApiObjects and the status remain."""
    entry = make_entry(simulator, **{CONF_PLAIN_VARIABLES: PlainVariables.IGNORED})

    await setup_entry(hass, entry)

    points = entry.runtime_data.data.points.values()
    assert points
    assert all(point.described for point in points)
    registry = er.async_get(hass)
    assert (
        registry.async_get_entity_id("sensor", DOMAIN, "SD 2080_doorbellcount") is None
    )


async def test_point_moving_platform_leaves_no_orphan(
    hass: HomeAssistant, simulator: Simulator, config_entry: MockConfigEntry
) -> None:
    """A setpoint made read-only in the PLC becomes a sensor; the number is removed."""
    await setup_entry(hass, config_entry)
    registry = er.async_get(hass)
    unique_id = "SD 2080_heating.livingsetpoint"
    assert registry.async_get_entity_id("number", DOMAIN, unique_id) is not None

    simulator.set_value("Heating.livingSetpoint.attr.readOnly", True)
    await hass.config_entries.async_reload(config_entry.entry_id)
    await hass.async_block_till_done()

    assert registry.async_get_entity_id("number", DOMAIN, unique_id) is None
    assert registry.async_get_entity_id("sensor", DOMAIN, unique_id) is not None


async def test_credentials_never_logged(
    hass: HomeAssistant,
    simulator: Simulator,
    config_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
    caplog: pytest.LogCaptureFixture,
) -> None:
    """Setup, polls, a failed write and revoked credentials at DEBUG: no password."""
    caplog.set_level(logging.DEBUG)
    await setup_entry(hass, config_entry)
    freezer.tick(timedelta(seconds=5))
    async_fire_time_changed(hass)
    await hass.async_block_till_done(wait_background_tasks=True)
    simulator.faults.http_500 = True
    with pytest.raises(HomeAssistantError):
        await config_entry.runtime_data.async_write("lights[0]", True)
    simulator.faults.clear()
    simulator.password = "n3w-secret"
    freezer.tick(timedelta(seconds=5))
    async_fire_time_changed(hass)
    await hass.async_block_till_done(wait_background_tasks=True)

    assert "rejected the stored credentials" in caplog.text
    assert SIM_PASSWORD not in caplog.text
    assert "n3w-secret" not in caplog.text
