"""The contract every registered system keeps in Home Assistant, one suite for all.

Whatever a system speaks, a user adding it meets the same things, through
Home Assistant's public API only (its flows, its services, its states):

- the flow: the user step's menu offers the system; its form asks what the
  descriptor's connect form names; the answers create an entry of the
  system's title and data, and no credential reaches the log;
- the creation: the entities of the simulator's demo appear, their unique IDs
  the entry's identity and the point's key in lower case, on a device of the
  system's manufacturer;
- a poll: a value changed on the device shows after the coordinator's refresh;
- a write: a service call on a writable entity changes the device's value;
- the errors: a value out of range is a translated ServiceValidationError and
  the device keeps its value; a read-only point refused by the actions (or the
  actions refused, for a system that takes no paths); the device stopped
  makes the entities unavailable, started again available on the next poll;
  wrong credentials (a system that signs in) are a form error, and a password
  changed on the device starts a reauthentication that takes the new one.

The suite is parametrised over every descriptor in the library's registry:
a system registered without a recipe here fails (``RECIPES``). Each system's
own test files keep only its quirks.
"""

from collections.abc import AsyncIterator, Awaitable, Callable
import contextlib
from dataclasses import dataclass
from datetime import timedelta
import logging
from typing import Any

from homeassistant.config_entries import (
    SOURCE_REAUTH,
    SOURCE_USER,
    ConfigEntry,
    ConfigEntryState,
)
from homeassistant.const import (
    ATTR_CONFIG_ENTRY_ID,
    ATTR_ENTITY_ID,
    ATTR_UNIT_OF_MEASUREMENT,
    CONF_HOST,
    CONF_PASSWORD,
    CONF_PORT,
    CONF_USERNAME,
    CONF_VERIFY_SSL,
    STATE_UNAVAILABLE,
)
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
from homeassistant.exceptions import ServiceValidationError
from homeassistant.helpers import device_registry as dr, entity_registry as er
import pytest
from pytest_homeassistant_custom_component.typing import ClientSessionGenerator

from custom_components.tecoapi.compat import entry_device
from custom_components.tecoapi.const import CONF_TRANSPORT, DOMAIN
from custom_components.tecoapi.pyplc import PlcAuthenticationError
from custom_components.tecoapi.pyplc.core.descriptor import (
    CONF_POINT_MAP,
    Capability,
    SourceDescriptor,
)
from custom_components.tecoapi.pyplc.core.registry import source, sources
from tests.components.tecoapi.file_upload import upload
from tests.conftest import SIM_PASSWORD, SIM_USERNAME
from tests.simulator import Simulator
from tests.simulator.fpi4c import EXAMPLE_CSV, FpI4cSimulator, demo_stations
from tests.simulator.mervis import HOUSE_NAME, MervisSimulator, house
from tests.simulator.plccoms import PlcComsServer
from tests.simulator.tekon import TekonGateway
from tests.simulator.tekon.building import CONTROLLER
from tests.waits import connected

NEW_PASSWORD = "n3w-Secret-9"
WAIT = 10.0
"""Seconds a client reconnecting by itself may take (real time)."""


@dataclass(frozen=True, slots=True, kw_only=True)
class Call:
    """A service call on one entity of the entry, by its point's key."""

    domain: str
    service: str
    key: str
    data: dict[str, Any]


@dataclass(kw_only=True)
class System:
    """A system's simulator, running, and what the contract needs to know of it."""

    answers: Callable[[], Awaitable[dict[str, Any]]]
    """The connect form as a user fills it (an upload made afresh)."""
    title: str
    unique_id: str
    data: dict[str, Any]
    """The entry's data, as the flow stores it."""
    manufacturer: str
    model: str
    entities: dict[str, str]
    """Point keys of the demo and the platform each one's entity is on."""
    values: dict[str, tuple[str, str | None]]
    """The state and unit of measurement some of them show once set up."""
    entity_count: int
    """How many entities the demo gives the entry (its own status ones included)."""
    change: Callable[[], Awaitable[None]]
    """Change a value on the device, as the device itself would."""
    changed: tuple[str, str]
    """The key whose entity shows the change, and the state it shows."""
    write: Call
    write_shown: str
    """The state the written entity shows at once, before any poll."""
    written: Callable[[], bool]
    """Whether the device holds what ``write`` wrote."""
    out_of_range: Call
    held: Callable[[], Any]
    """What the device holds for the point ``write`` and ``out_of_range`` reach."""
    read_only: tuple[str, Any] | None
    """A read-only path and a value for the write action (a system taking paths)."""
    stop: Callable[[], Awaitable[None]]
    restart: Callable[[ConfigEntry], Awaitable[None]]
    """Start the stopped device again, where it was (the entry's client back)."""
    prepare: Callable[[HomeAssistant, ConfigEntry], Awaitable[None]] | None = None
    """What a user does in the options before the entry has a writable point."""
    change_password: Callable[[str], None] | None = None
    """Change the password on the device (a system that signs in)."""
    auth_error: dict[str, str] | None = None
    """The form's error for wrong credentials (a system that signs in)."""
    reauth_step: str | None = None
    """The step of its reauthentication (a system that signs in)."""
    secrets: tuple[str, ...] = ()


type Recipe = Callable[
    [HomeAssistant, ClientSessionGenerator],
    contextlib.AbstractAsyncContextManager[System],
]


def _tecomat_demo(sim: Simulator) -> dict[str, Any]:
    """What both Tecomat transports show of the demo program, and how it is written."""
    return {
        "manufacturer": "Teco a.s.",
        "model": "CP-2080",
        "entities": {
            "outsidetemp": "sensor",
            "heating.livingsetpoint": "number",
            "lights[5]": "switch",
            "ventilation.filter.clogged": "binary_sensor",
        },
        "values": {
            "outsidetemp": ("4.5", "°C"),
            "heating.livingsetpoint": ("21.5", "°C"),
            "lights[5]": ("on", None),
            "ventilation.filter.clogged": ("off", None),
        },
        "entity_count": 169,
        "changed": ("outsidetemp", "7.0"),
        "write": Call(
            domain="number",
            service="set_value",
            key="heating.livingsetpoint",
            data={"value": 22.5},
        ),
        "write_shown": "22.5",
        "written": lambda: sim.get_value("Heating.livingSetpoint.value") == 22.5,
        "out_of_range": Call(
            domain="number",
            service="set_value",
            key="heating.livingsetpoint",
            data={"value": 40},
        ),
        "held": lambda: sim.get_value("Heating.livingSetpoint.value"),
        "read_only": ("outsideTemp.value", "5"),
    }


@contextlib.asynccontextmanager
async def _tecoapi(
    hass: HomeAssistant, hass_client: ClientSessionGenerator
) -> AsyncIterator[System]:
    async with Simulator("demo", username=SIM_USERNAME, password=SIM_PASSWORD) as sim:
        port = sim.port

        async def answers() -> dict[str, Any]:
            return {
                CONF_HOST: sim.host,
                CONF_USERNAME: SIM_USERNAME,
                CONF_PASSWORD: SIM_PASSWORD,
                CONF_VERIFY_SSL: True,
            }

        async def change() -> None:
            sim.set_value("outsideTemp.value", 7.0)

        def change_password(password: str) -> None:
            sim.password = password

        yield System(
            answers=answers,
            title="CP-2080 · FAMILY_HOUSE v1.3",
            unique_id="SD 2080",
            data={
                CONF_HOST: sim.url,
                CONF_USERNAME: SIM_USERNAME,
                CONF_PASSWORD: SIM_PASSWORD,
                CONF_VERIFY_SSL: True,
            },
            **_tecomat_demo(sim),
            change=change,
            stop=sim.stop,
            restart=lambda entry: sim.start(port=port),
            change_password=change_password,
            auth_error={"base": "invalid_auth"},
            reauth_step="reauth_tecoapi",
            secrets=(SIM_PASSWORD, NEW_PASSWORD),
        )


@contextlib.asynccontextmanager
async def _plccoms(
    hass: HomeAssistant, hass_client: ClientSessionGenerator
) -> AsyncIterator[System]:
    sim = Simulator("demo", username=SIM_USERNAME, password=SIM_PASSWORD)
    async with PlcComsServer(sim, scan_interval=None) as coms:
        port = coms.port

        async def answers() -> dict[str, Any]:
            return {CONF_HOST: "127.0.0.1", CONF_PORT: port}

        async def change() -> None:
            sim.set_value("outsideTemp.value", 7.0)
            await coms.scan()

        async def restart(entry: ConfigEntry) -> None:
            """Start the server again; the client comes back by itself (its backoff)."""
            await coms.start(port=port)
            client = entry.runtime_data.source.client
            await connected(client, WAIT)

        yield System(
            answers=answers,
            # The way in said: the same PLC's TecoApi entry has the title without.
            title="CP-2080 · FAMILY_HOUSE v1.3 · PLCComS",
            unique_id="EPSNET 127.0.0.1:61682",
            data={CONF_TRANSPORT: "plccoms", CONF_HOST: "127.0.0.1", CONF_PORT: port},
            **_tecomat_demo(sim),
            change=change,
            stop=coms.stop,
            restart=restart,
        )


MERVIS_USER = "panel"
MERVIS_PASSWORD = "Heslo-123"


@contextlib.asynccontextmanager
async def _mervis(
    hass: HomeAssistant, hass_client: ClientSessionGenerator
) -> AsyncIterator[System]:
    async with MervisSimulator(
        house(), username=MERVIS_USER, password=MERVIS_PASSWORD
    ) as sim:
        port = sim.port

        async def answers() -> dict[str, Any]:
            return {
                CONF_HOST: sim.host,
                CONF_USERNAME: MERVIS_USER,
                CONF_PASSWORD: MERVIS_PASSWORD,
                CONF_VERIFY_SSL: True,
                CONF_POINT_MAP: await upload(
                    hass, hass_client, "house.vlist", sim.project.vlist()
                ),
            }

        async def change() -> None:
            sim.project.set("koupelna.temperature", 22.75)

        async def prepare(hass: HomeAssistant, entry: ConfigEntry) -> None:
            """Mark the boost time writable, 0 to 2 hours, as a user does."""
            result = await hass.config_entries.options.async_init(entry.entry_id)
            result = await hass.config_entries.options.async_configure(
                result["flow_id"], {"next_step_id": "edit_point"}
            )
            result = await hass.config_entries.options.async_configure(
                result["flow_id"], {"point": ["boost"]}
            )
            assert result["step_id"] == "mervis_point"
            assert result["data_schema"] is not None
            filled = {
                str(key): (key.description or {}).get("suggested_value", key.default())
                if callable(key.default)
                else (key.description or {}).get("suggested_value")
                for key in result["data_schema"].schema
            }
            filled = {key: value for key, value in filled.items() if value is not None}
            result = await hass.config_entries.options.async_configure(
                result["flow_id"], {**filled, "writable": True, "min": 0, "max": 7200}
            )
            assert result["type"] is FlowResultType.CREATE_ENTRY, result.get("errors")
            await hass.async_block_till_done()

        def change_password(password: str) -> None:
            sim.password = password
            sim.switches.accept_plain = False
            sim.expire_sessions()

        yield System(
            answers=answers,
            title=f"Mervis · {HOUSE_NAME} · {sim.host}",
            unique_id=f"Mervis {HOUSE_NAME} @ {sim.host}",
            data={
                CONF_HOST: sim.url,
                CONF_USERNAME: MERVIS_USER,
                CONF_PASSWORD: MERVIS_PASSWORD,
                CONF_VERIFY_SSL: True,
                CONF_TRANSPORT: "mervis",
            },
            manufacturer="Unipi Technology",
            model="Mervis",
            entities={"koupelna.temperature": "sensor", "boost": "number"},
            values={"koupelna.temperature": ("21.5", None), "boost": ("1800.0", "s")},
            entity_count=41,
            change=change,
            changed=("koupelna.temperature", "22.75"),
            write=Call(
                domain="number", service="set_value", key="boost", data={"value": 5400}
            ),
            write_shown="5400.0",
            written=lambda: sim.project.get("boost") == timedelta(minutes=90),
            out_of_range=Call(
                domain="number", service="set_value", key="boost", data={"value": 9000}
            ),
            held=lambda: sim.project.get("boost"),
            read_only=None,
            stop=sim.stop,
            restart=lambda entry: sim.start(port=port),
            prepare=prepare,
            change_password=change_password,
            auth_error={"base": "mervis_invalid_auth"},
            reauth_step="reauth_mervis",
            secrets=(MERVIS_PASSWORD, NEW_PASSWORD),
        )


@contextlib.asynccontextmanager
async def _fpi4c(
    hass: HomeAssistant, hass_client: ClientSessionGenerator
) -> AsyncIterator[System]:
    async with FpI4cSimulator(demo_stations(), station=1) as gateway:
        port = gateway.port

        async def answers() -> dict[str, Any]:
            return {
                CONF_HOST: gateway.url,
                CONF_POINT_MAP: await upload(
                    hass,
                    hass_client,
                    "map.csv",
                    EXAMPLE_CSV.read_text(encoding="utf-8"),
                ),
            }

        async def change() -> None:
            gateway.set(1, "DT0", "INT", 700)

        yield System(
            answers=answers,
            title=f"FP-I4C · 127.0.0.1:{port}",
            unique_id=f"127.0.0.1:{port}",
            data={CONF_HOST: gateway.url, CONF_TRANSPORT: "fpi4c"},
            manufacturer="Panasonic",
            model="FP-I4C",
            entities={"boiler_temp": "sensor", "room_setpoint": "number"},
            values={"boiler_temp": ("65.2", "°C"), "room_setpoint": ("21.5", "°C")},
            entity_count=24,
            change=change,
            changed=("boiler_temp", "70.0"),
            write=Call(
                domain="number",
                service="set_value",
                key="room_setpoint",
                data={"value": 22.0},
            ),
            write_shown="22.0",
            written=lambda: gateway.get(1, "DT101", "INT") == 220,
            out_of_range=Call(
                domain="number",
                service="set_value",
                key="room_setpoint",
                data={"value": 40.0},
            ),
            held=lambda: gateway.get(1, "DT101", "INT"),
            read_only=None,
            stop=gateway.stop,
            restart=lambda entry: gateway.start(port=port),
        )


TEKON_SETPOINT = f"{CONTROLLER}.Уставка"
TEKON_TEMPERATURE = f"{CONTROLLER}.Температура"
TEKON_DOOR = f"{CONTROLLER}.Дверь подъезда"


@contextlib.asynccontextmanager
async def _tekon(
    hass: HomeAssistant, hass_client: ClientSessionGenerator
) -> AsyncIterator[System]:
    async with TekonGateway() as gateway:
        port = gateway.port

        async def answers() -> dict[str, Any]:
            return {CONF_HOST: gateway.url, CONF_VERIFY_SSL: True}

        async def change() -> None:
            gateway.set_value(TEKON_TEMPERATURE, "19.5")

        yield System(
            answers=answers,
            title="ASUD.SCADA OPC-HTTP",
            unique_id="OPC-2DD15E0B5358",
            data={
                CONF_HOST: gateway.url,
                CONF_VERIFY_SSL: True,
                CONF_TRANSPORT: "tekon",
            },
            manufacturer="Tekon",
            model="ASUD.SCADA OPC-HTTP",
            entities={
                TEKON_TEMPERATURE.lower(): "sensor",
                TEKON_SETPOINT.lower(): "number",
            },
            values={
                TEKON_TEMPERATURE.lower(): ("21.5", "°C"),
                TEKON_SETPOINT.lower(): ("20.0", "°C"),
            },
            # An entity per item; the intercom's call state and calls beside its button.
            entity_count=19,
            change=change,
            changed=(TEKON_TEMPERATURE.lower(), "19.5"),
            write=Call(
                domain="number",
                service="set_value",
                key=TEKON_SETPOINT.lower(),
                data={"value": 22.5},
            ),
            write_shown="22.5",
            written=lambda: gateway.value(TEKON_SETPOINT) == "22.5",
            out_of_range=Call(
                domain="number",
                service="set_value",
                key=TEKON_SETPOINT.lower(),
                data={"value": 40},
            ),
            held=lambda: gateway.value(TEKON_SETPOINT),
            read_only=(TEKON_DOOR, True),
            stop=gateway.stop,
            restart=lambda entry: gateway.start(port=port),
        )


RECIPES: dict[str, Recipe] = {
    "tecoapi": _tecoapi,
    "plccoms": _plccoms,
    "mervis": _mervis,
    "fpi4c": _fpi4c,
    "tekon": _tekon,
}
"""Each registered system's simulator and facts: a system registered needs one."""

SYSTEMS = [descriptor.name for descriptor in sources()]
SIGNING_IN = [
    descriptor.name
    for descriptor in sources()
    if Capability.CREDENTIALS in descriptor.capabilities
]


def test_every_registered_system_has_a_recipe() -> None:
    assert set(SYSTEMS) - set(RECIPES) == set(), "a registered system has no recipe"
    assert set(RECIPES) - set(SYSTEMS) == set(), "a recipe of no registered system"


@contextlib.asynccontextmanager
async def running(
    name: str, hass: HomeAssistant, hass_client: ClientSessionGenerator
) -> AsyncIterator[System]:
    if (recipe := RECIPES.get(name)) is None:
        pytest.fail(f"the registered system {name!r} has no recipe in the contract")
    async with recipe(hass, hass_client) as system:
        try:
            yield system
        finally:
            # Unloaded while the device still answers: no failure at teardown.
            for entry in hass.config_entries.async_entries(DOMAIN):
                await hass.config_entries.async_unload(entry.entry_id)
            await hass.async_block_till_done()


async def open_form(
    hass: HomeAssistant, descriptor: SourceDescriptor
) -> dict[str, Any]:
    """Open the user flow and choose the system from its menu."""
    result = await hass.config_entries.flow.async_init(
        DOMAIN, context={"source": SOURCE_USER}
    )
    assert result["type"] is FlowResultType.MENU
    assert descriptor.name in result["menu_options"]
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {"next_step_id": descriptor.name}
    )
    assert result["type"] is FlowResultType.FORM
    assert result["step_id"] == descriptor.connect.step_id
    assert result["errors"] == {}
    return dict(result)


def entity_id(hass: HomeAssistant, entry: ConfigEntry, domain: str, key: str) -> str:
    """The entity ID of a point's entity, by its documented unique ID."""
    found = er.async_get(hass).async_get_entity_id(
        domain, DOMAIN, f"{entry.unique_id}_{key}"
    )
    assert found is not None, (domain, key)
    return found


def state(hass: HomeAssistant, entity: str) -> str:
    shown = hass.states.get(entity)
    assert shown is not None, entity
    return shown.state


async def refresh(hass: HomeAssistant, entry: ConfigEntry) -> None:
    """Poll the device now, as the entry's interval would."""
    await entry.runtime_data.async_refresh()
    await hass.async_block_till_done()


async def call(hass: HomeAssistant, entry: ConfigEntry, what: Call) -> None:
    await hass.services.async_call(
        what.domain,
        what.service,
        {ATTR_ENTITY_ID: entity_id(hass, entry, what.domain, what.key), **what.data},
        blocking=True,
    )


def auth_rule(descriptor: SourceDescriptor) -> dict[str, str]:
    """The form error the descriptor shows for rejected credentials."""
    rule = next(
        rule
        for rule in descriptor.errors
        if issubclass(PlcAuthenticationError, rule.error)
    )
    return {rule.field: rule.key}


async def the_flow(
    hass: HomeAssistant, descriptor: SourceDescriptor, system: System
) -> ConfigEntry:
    """The user flow from the menu to a created entry, set up.

    A system that signs in refuses wrong credentials first: a form error, the
    form kept, no entry.
    """
    result = await open_form(hass, descriptor)
    assert {str(key) for key in result["data_schema"].schema} == {
        item.key for item in descriptor.connect.fields
    }
    if Capability.CREDENTIALS in descriptor.capabilities:
        result = dict(
            await hass.config_entries.flow.async_configure(
                result["flow_id"],
                {**await system.answers(), CONF_PASSWORD: "wrong"},
            )
        )
        assert result["type"] is FlowResultType.FORM
        assert result["errors"] == system.auth_error == auth_rule(descriptor)
        assert not hass.config_entries.async_entries(DOMAIN)
    result = dict(
        await hass.config_entries.flow.async_configure(
            result["flow_id"], await system.answers()
        )
    )
    await hass.async_block_till_done(wait_background_tasks=True)
    assert result["type"] is FlowResultType.CREATE_ENTRY, result.get("errors")
    assert result["title"] == system.title
    entry: ConfigEntry = result["result"]
    assert entry.state is ConfigEntryState.LOADED
    assert entry.unique_id == system.unique_id
    assert {key: entry.data[key] for key in system.data} == system.data
    return entry


def the_creation(hass: HomeAssistant, entry: ConfigEntry, system: System) -> None:
    """The demo's entities, by their documented unique IDs, on the system's device."""
    registered = er.async_entries_for_config_entry(er.async_get(hass), entry.entry_id)
    assert len(registered) == system.entity_count
    assert all(item.unique_id.startswith(f"{entry.unique_id}_") for item in registered)
    # The key of a unique ID is in lower case, whatever the device calls the point.
    keys = [item.unique_id.removeprefix(f"{entry.unique_id}_") for item in registered]
    assert [key for key in keys if key != key.lower()] == []
    for key, domain in system.entities.items():
        assert state(hass, entity_id(hass, entry, domain, key)) != STATE_UNAVAILABLE
    for key, (value, unit) in system.values.items():
        shown = hass.states.get(entity_id(hass, entry, system.entities[key], key))
        assert shown is not None
        assert (shown.state, shown.attributes.get(ATTR_UNIT_OF_MEASUREMENT)) == (
            value,
            unit,
        ), key
    device = entry_device(
        hass, entry.entry_id, identifier=(DOMAIN, str(entry.unique_id))
    )
    assert device is not None
    assert (device.manufacturer, device.model) == (system.manufacturer, system.model)
    # Each demo entity sits on the system's device or on one under it.
    devices = {device.id} | {
        item.id
        for item in dr.async_entries_for_config_entry(
            dr.async_get(hass), entry.entry_id
        )
        if item.via_device_id is not None
    }
    for key, domain in system.entities.items():
        item = er.async_get(hass).async_get(entity_id(hass, entry, domain, key))
        assert item is not None
        assert item.device_id in devices, key


async def a_poll(hass: HomeAssistant, entry: ConfigEntry, system: System) -> None:
    """A value changed on the device shows after the coordinator's refresh."""
    key, shown = system.changed
    entity = entity_id(hass, entry, "sensor", key)
    assert state(hass, entity) != shown
    await system.change()
    await refresh(hass, entry)
    assert state(hass, entity) == shown


async def a_write(hass: HomeAssistant, entry: ConfigEntry, system: System) -> None:
    """A service call writes the device, and its entity shows the value at once."""
    assert not system.written()
    await call(hass, entry, system.write)
    assert system.written()
    written = entity_id(hass, entry, system.write.domain, system.write.key)
    assert state(hass, written) == system.write_shown


async def a_refused_value(
    hass: HomeAssistant,
    descriptor: SourceDescriptor,
    entry: ConfigEntry,
    system: System,
) -> None:
    """Out of range, read-only: translated errors, the device and the entity unchanged.

    A system that takes no paths refuses the write action itself.
    """
    await refresh(hass, entry)
    held = system.held()
    entity = entity_id(hass, entry, system.out_of_range.domain, system.out_of_range.key)
    shown = state(hass, entity)
    with pytest.raises(ServiceValidationError) as raised:
        await call(hass, entry, system.out_of_range)
    assert raised.value.translation_key == "out_of_range"
    assert system.held() == held
    assert state(hass, entity) == shown
    action: dict[str, Any] = {ATTR_CONFIG_ENTRY_ID: entry.entry_id}
    if Capability.PATHS in descriptor.capabilities:
        assert system.read_only is not None
        path, value = system.read_only
        action |= {"path": path, "value": value}
        expected = "read_only"
    else:
        action |= {"path": "anything", "value": 1}
        expected = "paths_not_supported"
    with pytest.raises(ServiceValidationError) as raised:
        await hass.services.async_call(DOMAIN, "write_variable", action, blocking=True)
    assert (raised.value.translation_domain, raised.value.translation_key) == (
        DOMAIN,
        expected,
    )
    assert system.held() == held
    await refresh(hass, entry)
    assert state(hass, entity) == shown


async def the_device_stopped(
    hass: HomeAssistant, entry: ConfigEntry, system: System
) -> None:
    """Stopped: the entities unavailable; started again: back on the next poll."""
    entities = [
        entity_id(hass, entry, domain, key) for key, domain in system.entities.items()
    ]
    await system.stop()
    await refresh(hass, entry)
    assert [state(hass, entity) for entity in entities] == [STATE_UNAVAILABLE] * len(
        entities
    )
    await system.restart(entry)
    await refresh(hass, entry)
    assert STATE_UNAVAILABLE not in [state(hass, entity) for entity in entities]
    assert entry.state is ConfigEntryState.LOADED


async def a_changed_password(
    hass: HomeAssistant,
    descriptor: SourceDescriptor,
    entry: ConfigEntry,
    system: System,
) -> None:
    """The password changed on the device: unavailable, reauth, the new one taken."""
    assert system.change_password is not None
    username = entry.data[CONF_USERNAME]
    system.change_password(NEW_PASSWORD)
    await refresh(hass, entry)
    key, domain = next(iter(system.entities.items()))
    entity = entity_id(hass, entry, domain, key)
    assert state(hass, entity) == STATE_UNAVAILABLE
    flows = hass.config_entries.flow.async_progress_by_handler(DOMAIN)
    assert [
        (flow["context"]["source"], flow["context"]["entry_id"]) for flow in flows
    ] == [(SOURCE_REAUTH, entry.entry_id)]
    result: dict[str, Any] = dict(
        await hass.config_entries.flow.async_configure(flows[0]["flow_id"])
    )
    assert result["step_id"] == system.reauth_step == descriptor.words.reauth_step_id
    assert (
        {str(key) for key in result["data_schema"].schema}
        == {CONF_USERNAME, CONF_PASSWORD}
        == {item.key for item in descriptor.credentials}
    )
    result = dict(
        await hass.config_entries.flow.async_configure(
            result["flow_id"], {CONF_USERNAME: username, CONF_PASSWORD: "wrong"}
        )
    )
    assert result["errors"] == system.auth_error
    result = dict(
        await hass.config_entries.flow.async_configure(
            result["flow_id"], {CONF_USERNAME: username, CONF_PASSWORD: NEW_PASSWORD}
        )
    )
    assert result["type"] is FlowResultType.ABORT
    assert result["reason"] == "reauth_successful"
    await hass.async_block_till_done()
    assert entry.data[CONF_PASSWORD] == NEW_PASSWORD
    assert entry.state is ConfigEntryState.LOADED
    assert state(hass, entity) != STATE_UNAVAILABLE


@pytest.mark.parametrize("name", SYSTEMS)
async def test_a_system_added_polled_written_refused_stopped_and_signed_in_again(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    socket_enabled: None,
    uploads: None,
    caplog: pytest.LogCaptureFixture,
    *,
    name: str,
) -> None:
    """The whole contract on one entry of each system (one setup: CI time)."""
    descriptor = source(name)
    caplog.set_level(logging.DEBUG)
    async with running(name, hass, hass_client) as system:
        entry = await the_flow(hass, descriptor, system)
        if system.prepare is not None:
            await system.prepare(hass, entry)
        the_creation(hass, entry, system)
        await a_poll(hass, entry, system)
        await a_write(hass, entry, system)
        await a_refused_value(hass, descriptor, entry, system)
        await the_device_stopped(hass, entry, system)
        if Capability.CREDENTIALS in descriptor.capabilities:
            await a_changed_password(hass, descriptor, entry, system)
        else:
            assert system.change_password is None
        # Not a credential in the log, from the form to the reauthentication.
        for secret in system.secrets:
            assert secret not in caplog.text
