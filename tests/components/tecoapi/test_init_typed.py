"""Typed devices of the family house as a whole: discovery, polling, program downloads.

The demo program holds GTSAP1 families and structs in our convention; the tests
of each platform's typed entities sit in test_light.py, test_cover.py,
test_climate.py, test_event.py. Here: a contact, socket, relay and display
together; a typed entity's points not offered twice, yet polled; typed devices
with plain variables ignored; a new program changing them live.
"""

from freezegun.api import FrozenDateTimeFactory
from homeassistant.components.light import ATTR_SUPPORTED_COLOR_MODES
from homeassistant.const import (
    ATTR_DEVICE_CLASS,
    ATTR_UNIT_OF_MEASUREMENT,
    STATE_UNAVAILABLE,
)
from homeassistant.core import HomeAssistant
from homeassistant.helpers import entity_registry as er
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.tecoapi.const import CONF_PLAIN_VARIABLES, PlainVariables
from tests.components.tecoapi.conftest import (
    entity_id_of,
    make_entry,
    poll,
    setup_entry,
)
from tests.components.tecoapi.typed import SERIAL, call, typed
from tests.simulator import Program, Simulator


async def test_contact_socket_relay_and_display(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    """A contact is a door; a socket an outlet; a display shows its symbol's class."""
    contact = hass.states.get(typed(hass, "binary_sensor", "gtsap1:contact:vstup"))
    assert contact.attributes[ATTR_DEVICE_CLASS] == "door"
    socket = typed(hass, "switch", "gtsap1:socket:terasa")
    assert hass.states.get(socket).attributes[ATTR_DEVICE_CLASS] == "outlet"
    relay = typed(hass, "switch", "gtsap1:relay:zavlaha")
    assert ATTR_DEVICE_CLASS not in hass.states.get(relay).attributes

    await call(hass, "switch", "turn_on", entity_id=socket)
    assert simulator.get_value("TERASA_GTSAP1_SOCKET_onoff") is True
    await call(hass, "switch", "turn_off", entity_id=relay)
    assert simulator.get_value("ZAVLAHA_GTSAP1_RELAY_onoff") is False

    display = hass.states.get(typed(hass, "sensor", "gtsap1:display:obyvak"))
    assert display.attributes[ATTR_DEVICE_CLASS] == "carbon_dioxide"
    assert display.attributes[ATTR_UNIT_OF_MEASUREMENT] == "ppm"
    assert float(display.state) == simulator.get_value("OBYVAK_GTSAP1_DISPLAY_value")


async def test_points_of_typed_devices_are_not_offered_twice(
    hass: HomeAssistant, demo_entry: MockConfigEntry
) -> None:
    """The variables a typed entity is built from stay reachable, disabled."""
    registry = er.async_get(hass)
    for domain, key in (
        ("switch", "detskypokoj.light.onoff"),
        ("number", "detskypokoj.thermostat.setpoint"),
        ("binary_sensor", "obyvak_strop_gtsap1_light_onoff"),
    ):
        entry = registry.async_get(entity_id_of(hass, domain, f"{SERIAL}_{key}"))
        assert entry is not None
        assert entry.disabled_by is er.RegistryEntryDisabler.INTEGRATION, key


async def test_typed_entities_are_polled_without_their_plain_entities(
    hass: HomeAssistant,
    simulator: Simulator,
    demo_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """A typed entity's points are polled although their own entities are disabled."""
    light = typed(hass, "light", "gtsap1:light:chodba")
    simulator.set_value("CHODBA_GTSAP1_LIGHT_onoff", True)

    await poll(hass, freezer)

    assert hass.states.get(light).state == "on"
    assert "CHODBA_GTSAP1_LIGHT_name" not in " ".join(
        request.query for request in simulator.requests[-3:]
    )


async def test_ignored_plain_variables_still_make_gtsap1_devices(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    """GTSAP1 variables are plain: ignoring plain variables keeps their typed devices."""
    entry = await setup_entry(
        hass,
        make_entry(simulator, **{CONF_PLAIN_VARIABLES: PlainVariables.IGNORED}),
    )
    registry = er.async_get(hass)
    assert registry.async_get_entity_id(
        "light", "tecoapi", f"{SERIAL}_gtsap1:light:chodba"
    )
    assert (
        registry.async_get_entity_id(
            "binary_sensor", "tecoapi", f"{SERIAL}_chodba_gtsap1_light_onoff"
        )
        is None
    )
    assert entry.runtime_data.data.devices


async def test_program_downloads_add_remove_and_change_typed_devices(
    hass: HomeAssistant,
    simulator: Simulator,
    demo_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """A new program: a light vanishes, a socket appears, a light becomes dimmable.

    The dimmable light keeps its registry entry (the same entity ID).
    """
    registry = er.async_get(hass)
    chodba = typed(hass, "light", "gtsap1:light:chodba")
    chodba_entry = registry.async_get(chodba)
    source = simulator.program.to_mapping()
    variables = source["variables"]
    for prop in ("onoff", "name", "type"):
        variables.pop(f"KUCHYNE_LINKA_GTSAP1_LIGHT_{prop}", None)
    for prop in ("dimtype", "dimlevel", "rgb"):
        variables.pop(f"KUCHYNE_LINKA_GTSAP1_LIGHT_{prop}", None)
    variables["GARAZ_GTSAP1_SOCKET_onoff"] = {"type": "BOOL", "value": True}
    variables["CHODBA_GTSAP1_LIGHT_type"] = {"type": "BOOL", "value": True}
    variables["CHODBA_GTSAP1_LIGHT_dimlevel"] = {"type": "REAL", "value": 30.0}
    variables["CHODBA_GTSAP1_LIGHT_tgtlevel"] = {"type": "REAL", "value": 30.0}
    simulator.load_program(Program.from_mapping(source))

    await poll(hass, freezer, 60)

    assert (
        registry.async_get_entity_id(
            "light", "tecoapi", f"{SERIAL}_gtsap1:light:kuchyne_linka"
        )
        is None
    )
    socket = typed(hass, "switch", "gtsap1:socket:garaz")
    assert hass.states.get(socket).state == "on"
    after = registry.async_get(chodba)
    assert after is not None
    assert chodba_entry is not None
    assert after.id == chodba_entry.id
    state = hass.states.get(chodba)
    assert state.attributes[ATTR_SUPPORTED_COLOR_MODES] == ["brightness"]
    assert state.state != STATE_UNAVAILABLE
