"""A Tekon gateway in Home Assistant: devices, entities, sessions, changes, writes.

Every test adds the simulated gateway's small building through the config flow
and drives Home Assistant's clock: one poll a second (the source's default).
"""

from collections.abc import AsyncIterator
import json
import logging
from typing import Any

from freezegun.api import FrozenDateTimeFactory
from homeassistant.components.binary_sensor import BinarySensorDeviceClass
from homeassistant.components.event import EventDeviceClass
from homeassistant.components.sensor import SensorDeviceClass
from homeassistant.config_entries import ConfigEntry
from homeassistant.const import (
    ATTR_ENTITY_ID,
    CONF_HOST,
    CONF_VERIFY_SSL,
    EVENT_STATE_CHANGED,
    STATE_UNAVAILABLE,
    STATE_UNKNOWN,
    EntityCategory,
)
from homeassistant.core import Event, EventStateChangedData, HomeAssistant, callback
from homeassistant.exceptions import HomeAssistantError, ServiceValidationError
from homeassistant.helpers import device_registry as dr, entity_registry as er
from homeassistant.helpers.storage import Store
from homeassistant.setup import async_setup_component
import pytest
from pytest_homeassistant_custom_component.common import (
    MockConfigEntry,
    async_capture_events,
)
from pytest_homeassistant_custom_component.components.diagnostics import (
    get_diagnostics_for_config_entry,
)
from pytest_homeassistant_custom_component.typing import ClientSessionGenerator

from custom_components.tecoapi.compat import entry_device
from custom_components.tecoapi.const import CONF_TRANSPORT, DOMAIN
from custom_components.tecoapi.pyplc.tekon import AddressItem
from custom_components.tecoapi.pyplc.tekon.source import identity_of
from tests.components.tecoapi.conftest import FROZEN_TIME, entity_id_of, poll
from tests.components.tecoapi.flows.test_config_tekon import add_gateway
from tests.components.tecoapi.test_services import read, write
from tests.simulator.tekon import TekonGateway, channel, lift_state
from tests.simulator.tekon.building import (
    CONTROLLER,
    DISCRETE,
    LIFT,
    METERS,
    lift_parts,
)

SETPOINT = f"{CONTROLLER}.Уставка"
DOOR = f"{CONTROLLER}.Дверь подъезда"
FIRE = f"{CONTROLLER}.Пожарная сигнализация"
LIGHT = f"{CONTROLLER}.Освещение"
INTERCOM = f"{CONTROLLER}.Переговорное устройство"
TEMPERATURE = f"{CONTROLLER}.Температура"
DISPLAY = f"{CONTROLLER}.Табло"
LIFT_STATE = f"{LIFT}.Состояние"
SHAFT_DOOR = f"{LIFT}.Дверь шахты"
ENERGY = f"{METERS}.Электросчётчик.Энергия"
BATTERY_FAIL = "DBMonitoring.KIR_BatteryFail"
BESIDE = 2
"""Points read beside the items' own: the intercom's call state and its calls."""


@pytest.fixture
async def gateway(socket_enabled: None) -> AsyncIterator[TekonGateway]:
    async with TekonGateway() as running:
        yield running


@pytest.fixture
async def entry(
    hass: HomeAssistant, gateway: TekonGateway, freezer: FrozenDateTimeFactory
) -> ConfigEntry:
    """The gateway added through the config flow, its values shown."""
    freezer.move_to(FROZEN_TIME)
    result = await add_gateway(hass, gateway.url)
    added: ConfigEntry = result["result"]
    await hass.async_block_till_done(wait_background_tasks=True)
    return added


def logged(caplog: pytest.LogCaptureFixture) -> list[tuple[int, str]]:
    """(level, message) the integration logged at info or above."""
    return [
        (record.levelno, record.getMessage())
        for record in caplog.records
        if record.name.startswith("custom_components.tecoapi")
        and record.levelno >= logging.INFO
    ]


def entity(hass: HomeAssistant, entry: ConfigEntry, domain: str, name: str) -> str:
    """The entity ID of an item's entity on a platform."""
    return entity_id_of(hass, domain, f"{entry.unique_id}_{name.lower()}")


def state(hass: HomeAssistant, entity_id: str) -> Any:
    found = hass.states.get(entity_id)
    assert found is not None, entity_id
    return found


async def include_only(hass: HomeAssistant, entry: ConfigEntry, *patterns: str) -> None:
    """Make entities of the items the patterns match only (the options, applied)."""
    hass.config_entries.async_update_entry(
        entry, options={**entry.options, "include": list(patterns)}
    )
    await hass.async_block_till_done(wait_background_tasks=True)


def subscribed(gateway: TekonGateway) -> set[str]:
    (session,) = gateway.sessions.values()
    return set(session.subscribed)


async def test_controllers_and_devices_are_devices_under_the_gateway(
    hass: HomeAssistant, entry: ConfigEntry
) -> None:
    def device(key: str) -> dr.DeviceEntry:
        found = entry_device(hass, entry.entry_id, identifier=(DOMAIN, key))
        assert found is not None, key
        return found

    gateway = device(str(entry.unique_id))
    assert (gateway.manufacturer, gateway.model, gateway.name) == (
        "Tekon",
        "ASUD.SCADA OPC-HTTP",
        "ASUD.SCADA OPC gateway",
    )
    assert gateway.sw_version == "2.2.0.41"
    # Its link opens the one page it serves without a session.
    assert gateway.configuration_url == f"{entry.data[CONF_HOST]}/ServerInformation"
    controller = device(f"{entry.unique_id}_{CONTROLLER.lower()}")
    assert (controller.name, controller.serial_number, controller.via_device_id) == (
        "КУН-IP8 - 1",
        "0451-КУН",
        gateway.id,
    )
    lift = device(f"{entry.unique_id}_{LIFT.lower()}")
    assert (lift.name, lift.serial_number, lift.via_device_id) == (
        "Лифт 1",
        "Л-0017",
        controller.id,
    )
    meter = device(f"{entry.unique_id}_{METERS.lower()}.электросчётчик")
    assert meter.via_device_id == gateway.id
    assert meter.manufacturer == "Tekon"


async def test_channels_become_entities_by_their_properties(
    hass: HomeAssistant, entry: ConfigEntry
) -> None:
    door = state(hass, entity(hass, entry, "binary_sensor", DOOR))
    assert (door.state, door.attributes["device_class"]) == (
        "off",
        BinarySensorDeviceClass.DOOR,
    )
    assert door.attributes["friendly_name"] == "КУН-IP8 - 1 Дверь подъезда открыта"
    fire = state(hass, entity(hass, entry, "binary_sensor", FIRE))
    assert fire.attributes["device_class"] == BinarySensorDeviceClass.SMOKE
    assert state(hass, entity(hass, entry, "switch", LIGHT)).state == "on"
    assert state(hass, entity(hass, entry, "button", INTERCOM)).state == "unknown"
    temperature = state(hass, entity(hass, entry, "sensor", TEMPERATURE))
    assert (temperature.state, temperature.attributes["unit_of_measurement"]) == (
        "21.5",
        "°C",
    )
    setpoint = state(hass, entity(hass, entry, "number", SETPOINT))
    assert (setpoint.state, setpoint.attributes["min"], setpoint.attributes["max"]) == (
        "20.0",
        15.0,
        28.0,
    )
    assert state(hass, entity(hass, entry, "text", DISPLAY)).state == "Добро пожаловать"
    assert state(hass, entity(hass, entry, "sensor", ENERGY)).attributes[
        "device_class"
    ] == ("energy")
    lift = state(hass, entity(hass, entry, "sensor", LIFT_STATE))
    assert lift.state == "Норма"
    assert {
        key: lift.attributes[key] for key in ("State", "Floor", "Direction", "Door")
    } == {
        "State": "Норма",
        "Floor": "1",
        "Direction": "нет",
        "Door": "закрыта",
    }
    # A device's status (its unique ID as before) says whether it exchanges data,
    # as the seed reads it (above 0); the score the gateway gives is beside.
    status_id = entity(hass, entry, "sensor", f"{CONTROLLER}.Status")
    status = state(hass, status_id)
    assert (status.state, status.attributes["score"]) == ("exchanging", 10)
    assert status.attributes["device_class"] == SensorDeviceClass.ENUM
    assert status.attributes["options"] == ["exchanging", "no_data_exchange"]
    assert {
        key: status.attributes[key]
        for key in ("install_address", "ip_address", "registration_number")
    } == {
        "install_address": "ул. Лесная, 5, подъезд 1",
        "ip_address": "192.168.10.21",
        "registration_number": "0451-КУН",
    }
    registry_entry = er.async_get(hass).async_get(status_id)
    assert registry_entry is not None
    assert registry_entry.entity_category is EntityCategory.DIAGNOSTIC


async def test_values_show_after_setup_though_nothing_changed(
    hass: HomeAssistant,
    socket_enabled: None,
    freezer: FrozenDateTimeFactory,
) -> None:
    """The seed's gateway sends a value once it changed: the source asks for them.

    The entities show the gateway's values once set up, before any poll; the
    values are asked for once per subscription, not per poll.
    """
    freezer.move_to(FROZEN_TIME)
    async with TekonGateway() as gateway:
        await add_gateway(hass, gateway.url)
        await hass.async_block_till_done(wait_background_tasks=True)
        (session,) = gateway.sessions
        entry = hass.config_entries.async_entries(DOMAIN)[0]
        energy = state(hass, entity(hass, entry, "sensor", ENERGY))
        assert energy.state == "1520.5"
        assert state(hass, entity(hass, entry, "binary_sensor", DOOR)).state == "off"
        # The entry's session: discovery, then the entities' points subscribed
        # and their values asked for before the updates that bring them.
        assert gateway.requests[-4:] == [
            "GetUpdatesText",
            "SubscriberText",
            "ReadAllItemsValues",
            "GetUpdatesText",
        ]
        gateway.clear_requests()
        for _ in range(3):
            await poll(hass, freezer, 1)
        assert gateway.requests == ["GetUpdatesText"] * 3
        assert list(gateway.sessions) == [session]
        await hass.config_entries.async_unload(entry.entry_id)


async def test_channels_newly_included_show_their_values_at_once(
    hass: HomeAssistant,
    entry: ConfigEntry,
    gateway: TekonGateway,
    freezer: FrozenDateTimeFactory,
) -> None:
    await include_only(hass, entry, f"{LIFT}.*")
    unique_id = f"{entry.unique_id}_{ENERGY.lower()}"
    assert er.async_get(hass).async_get_entity_id("sensor", DOMAIN, unique_id) is None
    gateway.clear_requests()
    await include_only(hass, entry, f"{LIFT}.*", f"{METERS}.*")
    # Nothing changed on the gateway: the value asked for after subscribing.
    assert state(hass, entity(hass, entry, "sensor", ENERGY)).state == "1520.5"
    assert gateway.calls["ReadAllItemsValues"] == 1
    await poll(hass, freezer, 1)
    await poll(hass, freezer, 1)
    assert gateway.calls["ReadAllItemsValues"] == 1


async def test_a_change_shows_within_one_interval(
    hass: HomeAssistant,
    entry: ConfigEntry,
    gateway: TekonGateway,
    freezer: FrozenDateTimeFactory,
) -> None:
    gateway.set_value(DOOR, "1")
    gateway.set_value(LIFT_STATE, lift_state("Движение", 3, "вверх"))
    gateway.clear_requests()
    await poll(hass, freezer, 1)
    assert state(hass, entity(hass, entry, "binary_sensor", DOOR)).state == "on"
    lift = state(hass, entity(hass, entry, "sensor", LIFT_STATE))
    assert (lift.state, lift.attributes["Floor"]) == ("Движение", "3")
    # One request per interval, and nothing else.
    assert gateway.requests == ["GetUpdatesText"]
    await poll(hass, freezer, 1)
    assert gateway.requests == ["GetUpdatesText", "GetUpdatesText"]


async def test_every_change_between_two_polls_is_a_state_and_fires_automations(
    hass: HomeAssistant,
    entry: ConfigEntry,
    gateway: TekonGateway,
    freezer: FrozenDateTimeFactory,
) -> None:
    """A door that opened and closed within one poll: two states, a `to: on` trigger."""
    door = entity(hass, entry, "binary_sensor", DOOR)
    assert await async_setup_component(
        hass,
        "automation",
        {
            "automation": {
                "trigger": {"platform": "state", "entity_id": door, "to": "on"},
                "action": {"event": "door_opened"},
            }
        },
    )
    fired = async_capture_events(hass, "door_opened")
    shown: list[str] = []

    @callback
    def changed(event: Event[EventStateChangedData]) -> None:
        if event.data["entity_id"] == door and (new := event.data["new_state"]):
            shown.append(new.state)

    hass.bus.async_listen(EVENT_STATE_CHANGED, changed)
    gateway.set_value(DOOR, "1")
    gateway.set_value(DOOR, "0")
    gateway.clear_requests()
    await poll(hass, freezer, 1)
    assert shown == ["on", "off"]
    assert len(fired) == 1
    # Still one request a poll.
    assert gateway.requests == ["GetUpdatesText"]


async def test_an_intercom_rings_beside_its_call_button(
    hass: HomeAssistant,
    entry: ConfigEntry,
    gateway: TekonGateway,
    freezer: FrozenDateTimeFactory,
) -> None:
    """Channel 3001: its calls (a doorbell's events), its call state and its button."""
    button = entity(hass, entry, "button", INTERCOM)
    call = entity_id_of(
        hass, "binary_sensor", f"{entry.unique_id}_{INTERCOM.lower()}#call"
    )
    ring = entity_id_of(hass, "event", f"{entry.unique_id}_{INTERCOM.lower()}#ring")
    assert state(hass, ring).attributes["device_class"] == EventDeviceClass.DOORBELL
    # The call state is there for the user who wants it (its calls say a call).
    registry = er.async_get(hass)
    shown = registry.async_get(call)
    assert shown is not None
    assert shown.disabled_by is er.RegistryEntryDisabler.INTEGRATION
    registry.async_update_entity(call, disabled_by=None)
    await hass.config_entries.async_reload(entry.entry_id)
    await hass.async_block_till_done(wait_background_tasks=True)
    assert state(hass, call).state == "off"
    rings: list[str] = []
    calls: list[str] = []

    @callback
    def changed(event: Event[EventStateChangedData]) -> None:
        new = event.data["new_state"]
        if new is not None and event.data["entity_id"] == ring:
            rings.append(new.attributes.get("event_type", ""))
        if new is not None and event.data["entity_id"] == call:
            calls.append(new.state)

    hass.bus.async_listen(EVENT_STATE_CHANGED, changed)
    # A call that came and went within one poll, then one that stays.
    gateway.set_value(INTERCOM, "1")
    gateway.set_value(INTERCOM, "0")
    await poll(hass, freezer, 1)
    assert (rings, calls) == (["ring"], ["on", "off"])
    gateway.set_value(INTERCOM, "1")
    await poll(hass, freezer, 1)
    assert (rings, calls) == (["ring", "ring"], ["on", "off", "on"])
    assert state(hass, call).state == "on"
    # Pressing the button calls: it writes 1.
    await hass.services.async_call(
        "button", "press", {ATTR_ENTITY_ID: button}, blocking=True
    )
    assert gateway.writes[-1] == (INTERCOM, "1")


async def test_an_upgrade_keeps_the_intercom_s_button(
    hass: HomeAssistant, gateway: TekonGateway, freezer: FrozenDateTimeFactory
) -> None:
    """The button's unique ID and entity ID stay; its call state and calls are new."""
    freezer.move_to(FROZEN_TIME)
    identity = identity_of(
        [
            AddressItem(name=item.name, item_id=0, properties={})
            for item in gateway.building.items
        ]
    )
    entry = MockConfigEntry(
        domain=DOMAIN,
        title="ASUD.SCADA OPC-HTTP",
        unique_id=identity,
        data={CONF_HOST: gateway.url, CONF_VERIFY_SSL: True, CONF_TRANSPORT: "tekon"},
    )
    entry.add_to_hass(hass)
    registry = er.async_get(hass)
    old = registry.async_get_or_create(
        "button",
        DOMAIN,
        f"{identity}_{INTERCOM.lower()}",
        config_entry=entry,
        suggested_object_id="domofon",
    )
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done(wait_background_tasks=True)
    kept = registry.async_get(old.entity_id)
    assert kept is not None
    assert (kept.entity_id, kept.unique_id, kept.domain) == (
        "button.domofon",
        f"{identity}_{INTERCOM.lower()}",
        "button",
    )
    assert state(hass, "button.domofon").state != STATE_UNAVAILABLE
    new = {
        (registry_entry.domain, registry_entry.unique_id)
        for registry_entry in er.async_entries_for_config_entry(
            registry, entry.entry_id
        )
        if registry_entry.unique_id.startswith(f"{identity}_{INTERCOM.lower()}")
    }
    assert new == {
        ("button", f"{identity}_{INTERCOM.lower()}"),
        ("binary_sensor", f"{identity}_{INTERCOM.lower()}#call"),
        ("event", f"{identity}_{INTERCOM.lower()}#ring"),
    }


async def test_an_api_2_1_gateway_is_read_and_written(
    hass: HomeAssistant, gateway: TekonGateway, freezer: FrozenDateTimeFactory
) -> None:
    """API 2.1 has no Text reads and writes (seed: history): by ItemID instead."""
    gateway.api_version = "2.1"
    freezer.move_to(FROZEN_TIME)
    entry: ConfigEntry = (await add_gateway(hass, gateway.url))["result"]
    await hass.async_block_till_done(wait_background_tasks=True)
    setpoint = entity(hass, entry, "number", SETPOINT)
    assert state(hass, setpoint).state == "20.0"
    await hass.services.async_call(
        "number", "set_value", {ATTR_ENTITY_ID: setpoint, "value": 22.5}, blocking=True
    )
    assert gateway.writes == [(SETPOINT, "22.5")]
    assert (await read(hass, entry.entry_id, SETPOINT))["value"] == 22.5
    gateway.set_value(DOOR, "1")
    await poll(hass, freezer, 1)
    assert state(hass, entity(hass, entry, "binary_sensor", DOOR)).state == "on"
    assert state(hass, setpoint).state == "22.5"


async def test_only_what_is_enabled_is_subscribed(
    hass: HomeAssistant,
    entry: ConfigEntry,
    gateway: TekonGateway,
    freezer: FrozenDateTimeFactory,
) -> None:
    # Every item: the intercom's for its call state and its calls.
    assert subscribed(gateway) == {item.name for item in gateway.building.items}
    # The options' patterns work on the items' names (any case).
    hass.config_entries.async_update_entry(
        entry, options={**entry.options, "include": [f"{LIFT}.*"]}
    )
    await hass.async_block_till_done()
    await poll(hass, freezer, 1)
    assert subscribed(gateway) == {
        LIFT_STATE,
        SHAFT_DOOR,
        f"{LIFT}.Status",
        f"{CONTROLLER}.Status",  # the lift's health needs its controller's
    }
    er.async_get(hass).async_update_entity(
        entity(hass, entry, "binary_sensor", SHAFT_DOOR),
        disabled_by=er.RegistryEntryDisabler.USER,
    )
    await hass.config_entries.async_reload(entry.entry_id)
    await hass.async_block_till_done(wait_background_tasks=True)
    await poll(hass, freezer, 1)
    assert SHAFT_DOOR not in subscribed(gateway)


async def test_a_lost_session_costs_no_availability(
    hass: HomeAssistant,
    entry: ConfigEntry,
    gateway: TekonGateway,
    freezer: FrozenDateTimeFactory,
) -> None:
    states: list[str] = []

    def heard(event: Event[Any]) -> None:
        if (new := event.data["new_state"]) is not None:
            states.append(new.state)

    hass.bus.async_listen(EVENT_STATE_CHANGED, heard)
    gateway.expire_sessions()
    gateway.set_value(TEMPERATURE, "22.5")
    gateway.clear_requests()
    await poll(hass, freezer, 1)
    assert state(hass, entity(hass, entry, "sensor", TEMPERATURE)).state == "22.5"
    assert STATE_UNAVAILABLE not in states
    assert gateway.calls["NewSession"] == 1
    assert gateway.calls["GetAddressSpace"] == 0


async def test_an_unavailable_opc_server_makes_entities_unavailable_until_it_is_back(
    hass: HomeAssistant,
    entry: ConfigEntry,
    gateway: TekonGateway,
    freezer: FrozenDateTimeFactory,
    caplog: pytest.LogCaptureFixture,
) -> None:
    """Logged once when it goes, once when it is back: as the gateway, not a PLC."""
    temperature = entity(hass, entry, "sensor", TEMPERATURE)
    caplog.clear()
    gateway.opc_available = False
    await poll(hass, freezer, 1)
    assert state(hass, temperature).state == STATE_UNAVAILABLE
    gateway.set_value(TEMPERATURE, "19.5")
    gateway.opc_available = True
    for _ in range(5):  # backing off: 1, 2 s
        await poll(hass, freezer, 1)
    assert state(hass, temperature).state == "19.5"
    assert state(hass, entity(hass, entry, "switch", LIGHT)).state == "on"
    reason = "The gateway's OPC server is unavailable (being restarted?)"
    assert logged(caplog) == [
        (logging.INFO, f"The gateway {entry.title} is unavailable: {reason}"),
        (logging.INFO, f"The gateway {entry.title} is available again"),
    ]


async def test_configuration_mode_follows_added_and_removed_channels(
    hass: HomeAssistant,
    entry: ConfigEntry,
    gateway: TekonGateway,
    freezer: FrozenDateTimeFactory,
    caplog: pytest.LogCaptureFixture,
) -> None:
    display = entity(hass, entry, "text", DISPLAY)
    leak = channel(
        f"{CONTROLLER}.Протечка", DISCRETE, "1", description="Протечка в подвале"
    )
    points = len(gateway.building.items) + BESIDE
    caplog.clear()
    gateway.configuration_mode(add=[leak], remove=[DISPLAY], first=True)
    await poll(hass, freezer, 1)
    await poll(hass, freezer, 1)
    # A new address space, in the gateway's words (it runs no program).
    told = f"tells other points now ({points}, {points} before): they were read again"
    assert (logging.INFO, f"The gateway {entry.title} {told}") in logged(caplog)
    assert not [message for _, message in logged(caplog) if "program" in message]
    registry = er.async_get(hass)
    assert registry.async_get(display) is None
    assert hass.states.get(display) is None
    new = state(hass, entity(hass, entry, "binary_sensor", leak.name))
    assert (new.state, new.attributes["device_class"]) == (
        "on",
        BinarySensorDeviceClass.MOISTURE,
    )
    # The channels kept keep their entities and values.
    assert state(hass, entity(hass, entry, "switch", LIGHT)).state == "on"


async def test_writes_go_to_the_gateway_by_name(
    hass: HomeAssistant,
    entry: ConfigEntry,
    gateway: TekonGateway,
    freezer: FrozenDateTimeFactory,
) -> None:
    await hass.services.async_call(
        "switch",
        "turn_off",
        {ATTR_ENTITY_ID: entity(hass, entry, "switch", LIGHT)},
        blocking=True,
    )
    await hass.services.async_call(
        "button",
        "press",
        {ATTR_ENTITY_ID: entity(hass, entry, "button", INTERCOM)},
        blocking=True,
    )
    await hass.services.async_call(
        "number",
        "set_value",
        {ATTR_ENTITY_ID: entity(hass, entry, "number", SETPOINT), "value": 22.5},
        blocking=True,
    )
    await hass.services.async_call(
        "text",
        "set_value",
        {
            ATTR_ENTITY_ID: entity(hass, entry, "text", DISPLAY),
            "value": "Лифт на ремонте",
        },
        blocking=True,
    )
    assert gateway.writes == [
        (LIGHT, "0"),
        (INTERCOM, "1"),
        (SETPOINT, "22.5"),
        (DISPLAY, "Лифт на ремонте"),
    ]
    await poll(hass, freezer, 1)
    assert state(hass, entity(hass, entry, "switch", LIGHT)).state == "off"
    assert state(hass, entity(hass, entry, "number", SETPOINT)).state == "22.5"


async def test_writes_disabled_in_the_gateway_are_a_translated_error(
    hass: HomeAssistant,
    entry: ConfigEntry,
    gateway: TekonGateway,
    freezer: FrozenDateTimeFactory,
) -> None:
    gateway.writes_enabled = False
    light = entity(hass, entry, "switch", LIGHT)
    with pytest.raises(HomeAssistantError) as err:
        await hass.services.async_call(
            "switch", "turn_off", {ATTR_ENTITY_ID: light}, blocking=True
        )
    assert err.value.translation_key == "writes_disabled"
    assert err.value.translation_placeholders == {"path": LIGHT}
    await poll(hass, freezer, 1)
    assert state(hass, light).state == "on"
    assert gateway.value(LIGHT) == "1"


async def test_a_value_s_quality_decides_its_entity_alone(
    hass: HomeAssistant,
    entry: ConfigEntry,
    gateway: TekonGateway,
    freezer: FrozenDateTimeFactory,
) -> None:
    setpoint = entity(hass, entry, "number", SETPOINT)
    temperature = entity(hass, entry, "sensor", TEMPERATURE)
    gateway.set_value(SETPOINT, quality=0x18)
    gateway.set_value(TEMPERATURE, "21.0", quality=0x44)
    await poll(hass, freezer, 1)
    assert state(hass, setpoint).state == STATE_UNAVAILABLE
    uncertain = state(hass, temperature)
    assert uncertain.state == "21.0"
    assert (
        uncertain.attributes["quality"],
        uncertain.attributes["quality_reason"],
    ) == (
        "uncertain",
        "last_usable",
    )
    assert state(hass, entity(hass, entry, "switch", LIGHT)).state == "on"
    gateway.set_value(SETPOINT, "20")
    gateway.set_value(TEMPERATURE, "21.0")
    await poll(hass, freezer, 1)
    assert state(hass, setpoint).state == "20.0"
    assert "quality" not in state(hass, temperature).attributes


async def test_a_value_of_unknown_quality_is_unknown_and_says_so(
    hass: HomeAssistant,
    entry: ConfigEntry,
    gateway: TekonGateway,
    freezer: FrozenDateTimeFactory,
) -> None:
    """Quality 0x00 is the seed's DA_QUALITY_UNCKNOWN: no value, not a failure."""
    temperature = entity(hass, entry, "sensor", TEMPERATURE)
    gateway.set_value(TEMPERATURE, "0", quality=0x00)
    await poll(hass, freezer, 1)
    unknown = state(hass, temperature)
    assert unknown.state == STATE_UNKNOWN
    assert (
        unknown.attributes["quality"],
        unknown.attributes["quality_reason"],
    ) == ("unknown", "unknown")
    with pytest.raises(HomeAssistantError, match="unknown"):
        await read(hass, entry.entry_id, TEMPERATURE)
    gateway.set_value(TEMPERATURE, "21.5")
    await poll(hass, freezer, 1)
    assert state(hass, temperature).state == "21.5"
    assert "quality" not in state(hass, temperature).attributes


async def test_a_device_whose_status_drops_takes_its_entities_and_those_below(
    hass: HomeAssistant,
    entry: ConfigEntry,
    gateway: TekonGateway,
    freezer: FrozenDateTimeFactory,
) -> None:
    lift = entity(hass, entry, "sensor", LIFT_STATE)
    lift_status = entity(hass, entry, "sensor", f"{LIFT}.Status")
    light = entity(hass, entry, "switch", LIGHT)
    controller_status = entity(hass, entry, "sensor", f"{CONTROLLER}.Status")
    gateway.set_value(f"{LIFT}.Status", "0")
    await poll(hass, freezer, 1)
    assert state(hass, lift).state == STATE_UNAVAILABLE
    # The status tells: it is shown.
    assert state(hass, lift_status).state == "no_data_exchange"
    assert state(hass, light).state == "on"
    gateway.set_value(f"{LIFT}.Status", "10")
    gateway.set_value(f"{CONTROLLER}.Status", "0", quality=0x18)
    await poll(hass, freezer, 1)
    assert state(hass, lift).state == STATE_UNAVAILABLE
    assert state(hass, lift_status).state == STATE_UNAVAILABLE
    assert state(hass, light).state == STATE_UNAVAILABLE
    # A bad status's own value is not shown.
    assert state(hass, controller_status).state == STATE_UNAVAILABLE
    gateway.set_value(f"{CONTROLLER}.Status", "0")
    await poll(hass, freezer, 1)
    assert state(hass, controller_status).state == "no_data_exchange"
    assert state(hass, light).state == STATE_UNAVAILABLE
    gateway.set_value(f"{CONTROLLER}.Status", "10")
    await poll(hass, freezer, 1)
    assert state(hass, lift).state == "Норма"
    assert state(hass, light).state == "on"
    assert not entry.runtime_data.data.point_available("no such point")


async def test_the_address_space_is_kept_beside_the_entry(
    hass: HomeAssistant,
    entry: ConfigEntry,
    gateway: TekonGateway,
    freezer: FrozenDateTimeFactory,
) -> None:
    kept = await Store[dict[str, Any]](
        hass, 1, f"{DOMAIN}.source_cache.{entry.entry_id}"
    ).async_load()
    assert kept is not None
    assert (kept["hash"], kept["identity"]) == (
        gateway.building.hash(),
        entry.unique_id,
    )
    assert len(kept["items"]) == len(gateway.building.items)
    gateway.clear_requests()
    await hass.config_entries.async_reload(entry.entry_id)
    await hass.async_block_till_done(wait_background_tasks=True)
    assert "GetAddressSpace" not in gateway.requests
    assert "GetAddressSpaceHash" in gateway.requests
    await hass.config_entries.async_unload(entry.entry_id)
    gateway.configuration_mode(remove=[DISPLAY])
    gateway.clear_requests()
    await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done(wait_background_tasks=True)
    assert gateway.calls["GetAddressSpace"] == 1
    assert (
        er.async_get(hass).async_get_entity_id(
            "text", DOMAIN, f"{entry.unique_id}_{DISPLAY.lower()}"
        )
        is None
    )


async def test_diagnostics_redact_the_session_and_the_gateway_s_address(
    hass: HomeAssistant,
    entry: ConfigEntry,
    gateway: TekonGateway,
    freezer: FrozenDateTimeFactory,
    hass_client: ClientSessionGenerator,
) -> None:
    gateway.opc_available = False
    await poll(hass, freezer, 1)  # a failure whose message is kept
    gateway.opc_available = True
    for _ in range(3):
        await poll(hass, freezer, 1)
    session_id = entry.runtime_data.source.client.session_id
    assert session_id
    diagnostics = await get_diagnostics_for_config_entry(hass, hass_client, entry)
    text = json.dumps(diagnostics, ensure_ascii=False)
    assert session_id not in text
    assert "127.0.0.1" not in text
    assert str(gateway.port) not in text
    assert diagnostics["entry"]["data"]["host"] == "**REDACTED**"
    assert diagnostics["catalogue"]["points"] == len(gateway.building.items) + BESIDE
    assert diagnostics["recent_errors"][0]["error"] == "ServiceUnavailableError"
    source = diagnostics["source"]
    assert source["subscription"]["session_id"] == "**REDACTED**"
    assert source["subscription"]["sessions"] == 2
    assert source["address_space"]["hash"] == gateway.building.hash()


async def test_the_actions_read_any_item_by_its_name(
    hass: HomeAssistant,
    entry: ConfigEntry,
    gateway: TekonGateway,
) -> None:
    """A dispatcher reads channels that are not entities (filtered out) too."""
    await include_only(hass, entry, f"{LIFT}.*")
    assert TEMPERATURE not in subscribed(gateway)
    assert await read(hass, entry.entry_id, TEMPERATURE) == {
        "path": TEMPERATURE,
        "value": 21.5,
    }
    # Any case; an item with no channel type; a lift's state as its parts.
    assert (await read(hass, entry.entry_id, ENERGY.upper()))["value"] == 1520.5
    assert (await read(hass, entry.entry_id, "DBMonitoring.ConnectFailDevices"))[
        "value"
    ] == 0
    assert (await read(hass, entry.entry_id, LIFT_STATE))["value"] == {
        "text": "Норма",
        "parts": lift_parts(),
    }
    assert gateway.calls["ReadItemValueSyncText"] == 4
    with pytest.raises(ServiceValidationError) as unknown:
        await read(hass, entry.entry_id, f"{CONTROLLER}.Нет такого")
    assert unknown.value.translation_key == "variable_not_found"
    # A value of bad quality is no value: the action says why.
    gateway.set_value(ENERGY, quality=0x18)
    with pytest.raises(HomeAssistantError) as bad:
        await read(hass, entry.entry_id, ENERGY)
    assert bad.value.translation_key == "read_failed"
    assert "comm_failure" in str(bad.value.translation_placeholders)


async def test_the_actions_write_any_item_checked_as_its_entity(
    hass: HomeAssistant,
    entry: ConfigEntry,
    gateway: TekonGateway,
) -> None:
    await include_only(hass, entry, f"{LIFT}.*")
    await write(hass, entry.entry_id, SETPOINT, 22.5)
    await write(hass, entry.entry_id, DISPLAY, '"Лифт на ремонте"')
    assert gateway.writes == [(SETPOINT, "22.5"), (DISPLAY, "Лифт на ремонте")]
    refused = {
        SETPOINT: (40, "out_of_range"),
        DOOR: (True, "read_only"),
        LIFT_STATE: ('"up"', "read_only"),
        f"{CONTROLLER}.Нет такого": (1, "variable_not_found"),
    }
    for path, (value, key) in refused.items():
        with pytest.raises(ServiceValidationError) as err:
            await write(hass, entry.entry_id, path, value)
        assert err.value.translation_key == key, path
    assert len(gateway.writes) == 2
    gateway.writes_enabled = False
    with pytest.raises(HomeAssistantError) as disabled:
        await write(hass, entry.entry_id, SETPOINT, 21)
    assert disabled.value.translation_key == "writes_disabled"
    assert gateway.value(SETPOINT) == "22.5"


async def test_a_vt_ui4_offers_and_takes_every_value_of_its_type(
    hass: HomeAssistant, entry: ConfigEntry, gateway: TekonGateway
) -> None:
    """A VT_UI4 is 0..4294967295, not a DINT's range: 3,000,000,000 is written."""
    number = entity(hass, entry, "number", BATTERY_FAIL)
    shown = state(hass, number)
    assert (shown.attributes["min"], shown.attributes["max"]) == (0, 4294967295)
    await hass.services.async_call(
        "number",
        "set_value",
        {ATTR_ENTITY_ID: number, "value": 3_000_000_000},
        blocking=True,
    )
    assert gateway.writes == [(BATTERY_FAIL, "3000000000")]
