"""Changing a discovered point in the options: TecoApi, PLCComS alone, a Tekon gateway.

Each system's options open on a menu (the settings, *Change a point*, points
returned to what the device says); a point changed there is what its entity
is at once: a plain Tecomat variable made writable is a number written by
TecoApi (PutObject) or PLCComS (``SET:``), its value checked by its type before
anything is sent; a Tekon contact inverted reads the right way round. Against
the simulators on 127.0.0.1.
"""

from collections.abc import AsyncIterator
from typing import Any, Final

from homeassistant.components.number import (
    ATTR_MAX,
    ATTR_MIN,
)
from homeassistant.config_entries import ConfigEntry
from homeassistant.const import ATTR_DEVICE_CLASS, STATE_ON
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
from homeassistant.exceptions import ServiceValidationError
from homeassistant.helpers import entity_registry as er
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry
import voluptuous as vol

from custom_components.tecoapi.const import (
    CONF_PLAIN_VARIABLES,
    CONF_TRANSPORT,
    DOMAIN,
)
from custom_components.tecoapi.flows.point_class import CLASS_STEP
from custom_components.tecoapi.flows.point_override import CONF_POINT
from custom_components.tecoapi.overrides import async_load_overrides
from custom_components.tecoapi.pyplc.core.models import PointOverride
from tests.components.tecoapi.conftest import make_entry, setup_entry
from tests.components.tecoapi.flows.test_config_tekon import add_gateway
from tests.components.tecoapi.overridden import (
    change_point,
    offered,
    open_point,
    open_step,
    suggested,
)
from tests.components.tecoapi.test_number import set_value
from tests.simulator import Program, Simulator
from tests.simulator.plccoms import PlcComsServer
from tests.simulator.tekon import TekonGateway
from tests.simulator.tekon.building import CONTROLLER, METERS

SERIAL: Final = "SD 2080"
EPSNET: Final = "EPSNET 127.0.0.1:61682"
DOOR: Final = f"{CONTROLLER}.Дверь подъезда"
ENERGY: Final = f"{METERS}.Электросчётчик.Энергия"
OVERRIDE_MENU: Final = ["settings", "override_point", "remove_overrides"]


@pytest.fixture
async def coms(simulator: Simulator) -> AsyncIterator[PlcComsServer]:
    async with PlcComsServer(simulator, scan_interval=None) as server:
        yield server


@pytest.fixture
async def gateway(socket_enabled: None) -> AsyncIterator[TekonGateway]:
    async with TekonGateway() as running:
        yield running


async def tecoapi_entry(hass: HomeAssistant, simulator: Simulator) -> MockConfigEntry:
    """The demo PLC through TecoApi, its plain variables enabled."""
    return await setup_entry(
        hass, make_entry(simulator, **{CONF_PLAIN_VARIABLES: "enabled"})
    )


async def plccoms_entry(hass: HomeAssistant, coms: PlcComsServer) -> MockConfigEntry:
    """The demo PLC through PLCComS alone, its plain variables enabled."""
    return await setup_entry(
        hass,
        MockConfigEntry(
            domain=DOMAIN,
            title="CP-2080 · FAMILY_HOUSE v1.3",
            unique_id=EPSNET,
            data={CONF_TRANSPORT: "plccoms", "host": "127.0.0.1", "port": coms.port},
            options={CONF_PLAIN_VARIABLES: "enabled"},
        ),
    )


async def tekon_entry(hass: HomeAssistant, gateway: TekonGateway) -> ConfigEntry:
    result = await add_gateway(hass, gateway.url)
    entry: ConfigEntry = result["result"]
    await hass.async_block_till_done(wait_background_tasks=True)
    return entry


def entity_of(hass: HomeAssistant, domain: str, unique_id: str) -> str | None:
    return er.async_get(hass).async_get_entity_id(domain, DOMAIN, unique_id)


# --- TecoApi ----------------------------------------------------------------------------


async def test_tecoapi_options_open_on_a_menu_and_settings_keep_their_form(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    entry = await tecoapi_entry(hass, simulator)

    result = await hass.config_entries.options.async_init(entry.entry_id)

    assert result["type"] is FlowResultType.MENU
    assert result["step_id"] == "tecoapi_menu"
    assert result["menu_options"] == OVERRIDE_MENU
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {"next_step_id": "settings"}
    )
    assert (result["type"], result["step_id"]) == (FlowResultType.FORM, "tecoapi")


async def test_a_plain_tecoapi_variable_made_writable_is_a_number_written_by_putobject(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    entry = await tecoapi_entry(hass, simulator)
    unique_id = f"{SERIAL}_doorbellcount"
    sensor = entity_of(hass, "sensor", unique_id)
    assert sensor is not None
    options = dict(entry.options)

    opened = await open_point(hass, entry, "doorbellCount")
    assert suggested(opened) == {"writable": False}
    result = await change_point(hass, entry, "doorbellcount", writable=True)

    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert entry.options == options
    assert await async_load_overrides(hass, entry.entry_id) == {
        "doorbellcount": PointOverride(writable=True)
    }
    # The same unique ID on the number platform; the sensor's entry is gone.
    assert entity_of(hass, "sensor", unique_id) is None
    number = entity_of(hass, "number", unique_id)
    assert number is not None
    state = hass.states.get(number)
    assert state is not None
    assert state.state == "1287"
    assert (state.attributes[ATTR_MIN], state.attributes[ATTR_MAX]) == (
        -2147483648,
        4294967295,
    )
    simulator.clear_requests()
    await set_value(hass, number, 1300)
    services = [request.service for request in simulator.requests if request.authorized]
    assert services == ["PutObject", "GetObject"]
    assert simulator.get_value("doorbellCount") == 1300
    # Beyond its type (TecoApi tells no IEC type: DINT..UDINT): nothing is sent.
    simulator.clear_requests()
    with pytest.raises(ServiceValidationError):
        await set_value(hass, number, 2**32)
    assert simulator.requests == []


async def test_an_unchanged_form_changes_nothing(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    entry = await tecoapi_entry(hass, simulator)
    source = entry.runtime_data.source
    simulator.clear_requests()

    result = await change_point(hass, entry, "doorbellcount")

    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert entry.runtime_data.source is source
    assert await async_load_overrides(hass, entry.entry_id) == {}


async def test_the_picker_searches_without_custom_values_and_takes_one_point(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    """As the map editor's: nothing chosen beforehand, no item added from the search."""
    entry = await tecoapi_entry(hass, simulator)
    manager = hass.config_entries.options
    result = await open_step(hass, entry, "override_point")
    (field,) = result["data_schema"].schema
    # Optional and without a default: the frontend fills a required choice with
    # its first option, which Submit would then change.
    assert isinstance(field, vol.Optional)
    assert field.default is vol.UNDEFINED
    choice = result["data_schema"].schema[CONF_POINT].config
    assert not choice.get("custom_value")
    assert choice["multiple"] is True
    labels = {option["value"]: option["label"] for option in choice["options"]}
    assert labels["outsidetemp"] == "Outside temperature (outsideTemp)"
    assert labels["doorbellcount"] == "doorbellCount"
    # A write-only point (a button) or a record has nothing to change.
    assert all(key in entry.runtime_data.data.points for key in labels)

    result = await manager.async_configure(result["flow_id"], {})
    assert result["errors"] == {CONF_POINT: "point_one"}
    result = await manager.async_configure(
        result["flow_id"], {CONF_POINT: ["outsidetemp", "doorbellcount"]}
    )
    assert result["errors"] == {CONF_POINT: "point_one"}
    result = await manager.async_configure(
        result["flow_id"], {CONF_POINT: ["outsidetemp"]}
    )
    assert result["step_id"] == "point_override"
    assert result["description_placeholders"] == {
        "point": "Outside temperature (outsideTemp)"
    }


async def test_a_point_gone_while_the_picker_was_shown_is_said_to_be_unknown(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    """A new program without the point chosen, read while the form stood open."""
    entry = await tecoapi_entry(hass, simulator)
    manager = hass.config_entries.options
    result = await open_step(hass, entry, "override_point")
    simulator.load_program("manual")
    await entry.runtime_data.async_refresh()
    assert "outsidetemp" not in entry.runtime_data.data.points

    result = await manager.async_configure(
        result["flow_id"], {CONF_POINT: ["outsidetemp"]}
    )
    assert result["errors"] == {CONF_POINT: "override_point_unknown"}


@pytest.mark.parametrize(
    ("point", "changes", "errors"),
    [
        ("outsidetemp", {"min": 30, "max": 10}, {"min": "override_range"}),
        ("doorbellcount", {"max": 10}, {"max": "override_range_half"}),
        ("doorbellcount", {"step": 0}, {"step": "override_step"}),
        (
            "doorbellcount",
            {"unit": "kWh", "state_class": "measurement"},
            {"state_class": "point_class_state"},
        ),
        (
            "doorbellcount",
            {"unit": "W", "device_class": "energy"},
            {"device_class": "point_class_unit"},
        ),
        (
            "outsidetemp",
            {"device_class": "humidity"},
            {"device_class": "point_class_unit"},
        ),
    ],
)
async def test_a_change_the_point_or_home_assistant_does_not_take_is_refused(
    hass: HomeAssistant,
    simulator: Simulator,
    point: str,
    changes: dict[str, Any],
    errors: dict[str, str],
) -> None:
    entry = await tecoapi_entry(hass, simulator)

    result = await change_point(hass, entry, point, **changes)

    assert result["type"] is FlowResultType.FORM
    assert result["errors"] == errors
    assert await async_load_overrides(hass, entry.entry_id) == {}


async def test_each_point_s_form_offers_what_it_may_change_and_its_classes_next(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    """A flag, a number and a text: their forms, then the classes of their platform.

    The classes are the step a map's point form ends with too
    (flows/point_class.py): a read-only flag's among a binary sensor's, a
    number's with a unit among Home Assistant's numeric ones and a state
    class; a counter without a unit a state class only; a switch none.
    """
    entry = await tecoapi_entry(hass, simulator)
    manager = hass.config_entries.options

    result = await open_point(hass, entry, "alarmarmed")
    schema = {str(key): value for key, value in result["data_schema"].schema.items()}
    assert set(schema) == {"writable", "invert", "platform"}
    assert schema["platform"].config["options"] == ["switch", "binary_sensor"]
    result = await manager.async_configure(
        result["flow_id"], {"writable": False, "invert": False}
    )
    assert result["step_id"] == CLASS_STEP
    assert offered(result) == {"device_class": "binary_sensor"}
    hass.config_entries.options.async_abort(result["flow_id"])
    # Made writable, a switch: no class to ask.
    result = await change_point(hass, entry, "alarmarmed", writable=True)
    assert result["type"] is FlowResultType.CREATE_ENTRY

    number = await open_point(hass, entry, "watermeter")
    fields = {str(key) for key in number["data_schema"].schema}
    assert fields == {"writable", "unit", "min", "max", "step", "platform"}
    number = await manager.async_configure(
        number["flow_id"], {**suggested(number), "unit": "m³"}
    )
    assert offered(number) == {"device_class": "number", "state_class": None}
    assert number["description_placeholders"] == {"point": "waterMeter", "unit": "m³"}
    hass.config_entries.options.async_abort(number["flow_id"])
    counter = await open_point(hass, entry, "doorbellcount")
    counter = await manager.async_configure(counter["flow_id"], suggested(counter))
    assert offered(counter) == {"state_class": None}

    text = await open_point(hass, entry, "installernote")
    schema = {str(key): value for key, value in text["data_schema"].schema.items()}
    assert set(schema) == {"writable", "platform"}
    assert schema["platform"].config["options"] == ["text", "sensor"]


async def test_a_writable_point_shown_only_is_a_sensor_and_back_again(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    """A T_ApiObject's setpoint shown only; returned to what the PLC says."""
    entry = await tecoapi_entry(hass, simulator)
    unique_id = f"{SERIAL}_heating.livingsetpoint"
    number = entity_of(hass, "number", unique_id)
    assert number is not None

    await change_point(hass, entry, "heating.livingsetpoint", platform="sensor")

    assert entity_of(hass, "number", unique_id) is None
    sensor = entity_of(hass, "sensor", unique_id)
    assert sensor is not None
    shown = str(simulator.get_value("Heating.livingSetpoint.value"))
    assert hass.states.get(sensor).state == shown  # type: ignore[union-attr]

    manager = hass.config_entries.options
    result = await open_step(hass, entry, "remove_overrides")
    choice = result["data_schema"].schema[CONF_POINT].config
    assert choice["options"] == [
        {
            "value": "heating.livingsetpoint",
            "label": "Living room setpoint (Heating.livingSetpoint)",
        }
    ]
    assert suggested(result) == {}
    result = await manager.async_configure(
        result["flow_id"], {CONF_POINT: ["heating.livingsetpoint"]}
    )
    await hass.async_block_till_done(wait_background_tasks=True)

    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert await async_load_overrides(hass, entry.entry_id) == {}
    assert entity_of(hass, "sensor", unique_id) is None
    assert entity_of(hass, "number", unique_id) == number


async def test_nothing_to_return_says_so(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    entry = await tecoapi_entry(hass, simulator)

    result = await open_step(hass, entry, "remove_overrides")

    assert (result["type"], result["reason"]) == (FlowResultType.ABORT, "no_overrides")


async def test_a_point_is_changed_only_while_the_device_s_points_are_known(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    """An entry not set up (its device away) has no points to pick."""
    entry = make_entry(simulator)
    entry.add_to_hass(hass)

    result = await open_step(hass, entry, "override_point")

    assert (result["type"], result["reason"]) == (
        FlowResultType.ABORT,
        "override_unavailable",
    )


async def test_a_point_gone_with_a_new_program_while_its_form_is_open(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    entry = await tecoapi_entry(hass, simulator)
    result = await open_point(hass, entry, "doorbellcount")
    program = simulator.program.to_mapping()
    del program["variables"]["doorbellCount"]
    simulator.load_program(Program.from_mapping(program))
    await entry.runtime_data.async_refresh()
    await hass.async_block_till_done(wait_background_tasks=True)

    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {"writable": True}
    )

    assert (result["type"], result["reason"]) == (
        FlowResultType.ABORT,
        "override_unavailable",
    )


# --- PLCComS alone ---------------------------------------------------------------------------


async def test_a_plain_variable_through_plccoms_made_writable_is_set_as_its_type_allows(
    hass: HomeAssistant, coms: PlcComsServer, simulator: Simulator
) -> None:
    entry = await plccoms_entry(hass, coms)
    result = await hass.config_entries.options.async_init(entry.entry_id)
    assert (result["step_id"], result["menu_options"]) == (
        "plccoms_menu",
        OVERRIDE_MENU,
    )
    hass.config_entries.options.async_abort(result["flow_id"])

    result = await change_point(hass, entry, "doorbellcount", writable=True)

    assert result["type"] is FlowResultType.CREATE_ENTRY
    unique_id = f"{EPSNET}_doorbellcount"
    assert entity_of(hass, "sensor", unique_id) is None
    number = entity_of(hass, "number", unique_id)
    assert number is not None
    state = hass.states.get(number)
    assert state is not None
    # LIST: names it a UDINT: its range is the type's.
    assert (state.attributes[ATTR_MIN], state.attributes[ATTR_MAX]) == (0, 4294967295)
    sent = len(coms.commands)
    await set_value(hass, number, 1300)
    assert "SET:doorbellCount,1300" in coms.commands[sent:]
    assert simulator.get_value("doorbellCount") == 1300
    sent = len(coms.commands)
    with pytest.raises(ServiceValidationError):
        await set_value(hass, number, -1)
    assert [line for line in coms.commands[sent:] if line.startswith("SET:")] == []


# --- Tekon ----------------------------------------------------------------------------------


async def test_a_tekon_contact_inverted_reads_the_right_way_round(
    hass: HomeAssistant, gateway: TekonGateway
) -> None:
    """A door channel that is 0 while the door is open, shown as a door: open."""
    entry = await tekon_entry(hass, gateway)
    result = await hass.config_entries.options.async_init(entry.entry_id)
    assert (result["step_id"], result["menu_options"]) == ("tekon_menu", OVERRIDE_MENU)
    hass.config_entries.options.async_abort(result["flow_id"])
    unique_id = f"{entry.unique_id}_{DOOR.lower()}"
    door = entity_of(hass, "binary_sensor", unique_id)
    assert door is not None
    assert hass.states.get(door).state == "off"  # type: ignore[union-attr]

    result = await change_point(hass, entry, DOOR, invert=True, device_class="door")

    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert entity_of(hass, "binary_sensor", unique_id) == door
    state = hass.states.get(door)
    assert state is not None
    assert state.state == STATE_ON
    assert state.attributes[ATTR_DEVICE_CLASS] == "door"
    # The gateway's value is what it was.
    assert gateway.value(DOOR) == "0"


async def test_a_tekon_channel_whose_rights_are_read_only_is_not_made_writable(
    hass: HomeAssistant, gateway: TekonGateway
) -> None:
    entry = await tekon_entry(hass, gateway)

    result = await change_point(hass, entry, ENERGY, writable=True)

    assert result["errors"] == {"writable": "override_not_writable"}
    assert await async_load_overrides(hass, entry.entry_id) == {}
