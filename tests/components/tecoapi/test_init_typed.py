"""Typed entities of the family house: lights, blinds, thermostats, buttons and more.

The demo program holds GTSAP1 families (lights of each dimtype, blinds, gates,
thermostats of each type, a button, a contact, a socket, a relay, a display) and
structs in our convention (a kids' room thermostat, blind and dimmer; an attic
tunable light and a roof window). Each test drives a typed entity through Home
Assistant and checks the PLC's variables over real HTTP.
"""

from typing import Any

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
from homeassistant.components.cover import ATTR_CURRENT_POSITION, ATTR_POSITION
from homeassistant.components.event import ATTR_EVENT_TYPE
from homeassistant.components.light import ATTR_SUPPORTED_COLOR_MODES
from homeassistant.const import (
    ATTR_DEVICE_CLASS,
    ATTR_SUPPORTED_FEATURES,
    ATTR_TEMPERATURE,
    ATTR_UNIT_OF_MEASUREMENT,
    STATE_UNAVAILABLE,
)
from homeassistant.core import Event, HomeAssistant, callback
from homeassistant.helpers import entity_registry as er
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry
from syrupy.assertion import SnapshotAssertion

from custom_components.tecoapi.compat import (
    AREA_IN_ENTITY_ID,
    ATTR_BRIGHTNESS,
    ATTR_COLOR_TEMP_KELVIN,
    ATTR_RGB_COLOR,
    CoverEntityFeature,
    HVACAction,
    HVACMode,
)
from custom_components.tecoapi.const import CONF_PLAIN_VARIABLES, PlainVariables
from tests.components.tecoapi.conftest import (
    entity_id_of,
    make_entry,
    poll,
    setup_entry,
    snapshot_entities,
)
from tests.components.tecoapi.flows.test_subentry import compose, composed_entity
from tests.conftest import SIM_PASSWORD, SIM_USERNAME
from tests.simulator import Program, Simulator, load_program

SERIAL = "SD 2080"


def typed(hass: HomeAssistant, domain: str, key: str) -> str:
    """The entity ID of a typed device of the demo."""
    return entity_id_of(hass, domain, f"{SERIAL}_{key}")


async def call(hass: HomeAssistant, domain: str, service: str, **data: Any) -> None:
    """Call an action and wait for it."""
    await hass.services.async_call(domain, service, data, blocking=True)


@pytest.mark.primary_only
@pytest.mark.parametrize("program_entry", ["demo"], indirect=True)
@pytest.mark.parametrize("domain", ["light", "cover", "climate", "event"])
async def test_typed_entities(
    hass: HomeAssistant,
    program_entry: MockConfigEntry,
    snapshot: SnapshotAssertion,
    domain: str,
) -> None:
    """Every typed entity of the demo: registry entry and state."""
    await snapshot_entities(hass, snapshot, program_entry, domain)


async def test_dimmable_light(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    """GTSAP1 dimtype 0: on/off and brightness; brightness writes the target level."""
    light = typed(hass, "light", "gtsap1:light:obyvak_strop")
    state = hass.states.get(light)
    assert state.state == "on"
    # Its GTSAP1 name, in its room's area without the room where IDs start with it.
    assert state.name == ("Strop" if AREA_IN_ENTITY_ID else "Obývák strop")
    assert state.attributes[ATTR_SUPPORTED_COLOR_MODES] == ["brightness"]
    assert state.attributes[ATTR_BRIGHTNESS] == 153  # 60 %

    await call(hass, "light", "turn_on", entity_id=light, brightness=51)
    assert simulator.get_value("OBYVAK_STROP_GTSAP1_LIGHT_tgtlevel") == 20.0
    assert simulator.get_value("OBYVAK_STROP_GTSAP1_LIGHT_onoff") is True

    await call(hass, "light", "turn_off", entity_id=light)
    assert simulator.get_value("OBYVAK_STROP_GTSAP1_LIGHT_onoff") is False
    assert hass.states.get(light).state == "off"


async def test_rgb_light(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    """GTSAP1 dimtype 1: the colour is written as R + G·256 + B·65536."""
    light = typed(hass, "light", "gtsap1:light:kuchyne_linka")
    assert hass.states.get(light).attributes[ATTR_SUPPORTED_COLOR_MODES] == ["rgb"]

    await call(hass, "light", "turn_on", entity_id=light, rgb_color=(255, 128, 1))

    assert (
        simulator.get_value("KUCHYNE_LINKA_GTSAP1_LIGHT_rgb") == 255 + 128 * 256 + 65536
    )
    assert simulator.get_value("KUCHYNE_LINKA_GTSAP1_LIGHT_onoff") is True
    assert hass.states.get(light).attributes[ATTR_RGB_COLOR] == (255, 128, 1)


async def test_tunable_light(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    """GTSAP1 dimtype 2: colour temperature in kelvin within the block's range."""
    light = typed(hass, "light", "gtsap1:light:loznice")
    state = hass.states.get(light)
    assert state.attributes[ATTR_SUPPORTED_COLOR_MODES] == ["color_temp"]
    low = simulator.get_value("LOZNICE_GTSAP1_LIGHT_minTempK")
    high = simulator.get_value("LOZNICE_GTSAP1_LIGHT_maxTempK")
    assert state.attributes["min_color_temp_kelvin"] == low
    assert state.attributes["max_color_temp_kelvin"] == high

    await call(hass, "light", "turn_on", entity_id=light, color_temp_kelvin=3000)

    assert simulator.get_value("LOZNICE_GTSAP1_LIGHT_colortemp") == 3000
    assert hass.states.get(light).attributes[ATTR_COLOR_TEMP_KELVIN] == 3000


async def test_on_off_light(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    """A light that is not dimmable: on and off only."""
    light = typed(hass, "light", "gtsap1:light:chodba")
    assert hass.states.get(light).attributes[ATTR_SUPPORTED_COLOR_MODES] == ["onoff"]

    await call(hass, "light", "turn_on", entity_id=light)

    assert simulator.get_value("CHODBA_GTSAP1_LIGHT_onoff") is True


async def test_struct_dimmer(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    """Our convention: a dimmer's brightness T_ApiObject is its state and level."""
    light = typed(hass, "light", "struct:light:detskypokoj.light")

    await call(hass, "light", "turn_on", entity_id=light, brightness=255)

    assert simulator.get_value("detskyPokoj.light.brightness.value") == 100
    assert simulator.get_value("detskyPokoj.light.onoff.value") is True
    assert hass.states.get(light).attributes[ATTR_BRIGHTNESS] == 255


@pytest.mark.parametrize(
    ("key", "dark", "level", "expected"),
    [
        # Nothing above zero known: full.
        ("gtsap1:light:kuchyne_linka", {}, "KUCHYNE_LINKA_GTSAP1_LIGHT_dimlevel", 100),
        (
            "gtsap1:light:obyvak_strop",
            {
                "OBYVAK_STROP_GTSAP1_LIGHT_tgtlevel": 0,
                "OBYVAK_STROP_GTSAP1_LIGHT_dimlevel": 0,
            },
            "OBYVAK_STROP_GTSAP1_LIGHT_tgtlevel",
            60,
        ),
        (
            "gtsap1:light:loznice",
            {"LOZNICE_GTSAP1_LIGHT_dimlevel": 0},
            "LOZNICE_GTSAP1_LIGHT_dimlevel",
            35,
        ),
        (
            "struct:light:detskypokoj.light",
            {},
            "detskyPokoj.light.brightness.value",
            100,
        ),
        (
            "struct:light:podkrovi.satnasvetlo",
            {"Podkrovi.satnaSvetlo.brightness.value": 0},
            "Podkrovi.satnaSvetlo.brightness.value",
            80,
        ),
    ],
    ids=["rgb", "dimmer", "tunable", "struct dimmer", "struct tunable"],
)
async def test_switched_on_a_dark_light_returns_to_its_last_level(
    hass: HomeAssistant,
    simulator: Simulator,
    demo_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
    *,
    key: str,
    dark: dict[str, Any],
    level: str,
    expected: int,
) -> None:
    """On from its icon (no brightness): the last level above zero, else full.

    Not on at 0 %: each light is switched off and dark (the PLC set its level to 0),
    then switched on without a brightness.
    """
    light = typed(hass, "light", key)
    await call(hass, "light", "turn_off", entity_id=light)
    for path, value in dark.items():
        simulator.set_value(path, value)
    await poll(hass, freezer)
    state = hass.states.get(light)
    assert state.state == "off"
    assert state.attributes[ATTR_BRIGHTNESS] is None

    await call(hass, "light", "turn_on", entity_id=light)

    assert simulator.get_value(level) == expected
    if level.endswith("_tgtlevel"):
        # Its level follows the target in the PLC: read again a second later.
        simulator.clear_requests()
        await poll(hass, freezer, 1)
        (read,) = simulator.requests
        assert set(read.query.split("&")) == {
            f"OBYVAK_STROP_GTSAP1_LIGHT_{prop}"
            for prop in ("onoff", "dimlevel", "tgtlevel")
        }
    state = hass.states.get(light)
    assert state.state == "on"
    assert state.attributes[ATTR_BRIGHTNESS] == round(expected * 255 / 100)


@pytest.mark.parametrize(
    "roles",
    [{"onoff": "lights[3]", "level": "blinds[3]"}, {"level": "blinds[3]"}],
    ids=["with onoff", "level alone"],
)
async def test_a_composed_dark_light_switched_on_goes_full(
    hass: HomeAssistant,
    simulator: Simulator,
    demo_entry: MockConfigEntry,
    roles: dict[str, str],
) -> None:
    """A composed light at level 0, nothing above zero known: full, not on at 0 %."""
    await compose(hass, demo_entry, "light", {"name": "Study lamp", **roles})
    light = composed_entity(hass, "light", demo_entry)
    assert simulator.get_value("blinds[3].value") == 0
    assert hass.states.get(light).state == "off"

    await call(hass, "light", "turn_on", entity_id=light)

    assert simulator.get_value("blinds[3].value") == 100
    state = hass.states.get(light)
    assert state.state == "on"
    assert state.attributes[ATTR_BRIGHTNESS] == 255


async def test_switched_on_a_bright_light_keeps_its_level(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    """A light off at a level above zero is switched on by ``onoff`` alone."""
    light = typed(hass, "light", "gtsap1:light:obyvak_strop")
    await call(hass, "light", "turn_off", entity_id=light)
    simulator.clear_requests()

    await call(hass, "light", "turn_on", entity_id=light)

    assert simulator.get_value("OBYVAK_STROP_GTSAP1_LIGHT_tgtlevel") == 60
    assert simulator.get_value("OBYVAK_STROP_GTSAP1_LIGHT_onoff") is True
    # One write, of onoff: the level stays.
    writes = [r for r in simulator.requests if r.service in {"SetObject", "PutObject"}]
    assert len(writes) == 1
    assert hass.states.get(light).attributes[ATTR_BRIGHTNESS] == 153


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


def record_events(hass: HomeAssistant, entity_id: str) -> list[str]:
    """The event types an event entity fires from now on, in order."""
    fired: list[str] = []

    @callback
    def record(event: Event[Any]) -> None:
        if event.data["entity_id"] == entity_id and event.data["new_state"] is not None:
            fired.append(event.data["new_state"].attributes[ATTR_EVENT_TYPE])

    hass.bus.async_listen("state_changed", record)
    return fired


CLICKS = "DVERE_TLACITKO_GTSAP1_BUTTON_CLICKCNT"
PRESSES = "DVERE_TLACITKO_GTSAP1_BUTTON_PRESSCNT"


async def test_button_events_one_per_increment(
    hass: HomeAssistant,
    simulator: Simulator,
    demo_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """Clicks and long presses: an event per increment.

    Nothing fires at start-up, after a counter reset, or for a counter that did
    not move; a wrap-around of the counter counts its increment.
    """
    button = typed(hass, "event", "gtsap1:button:dvere_tlacitko")
    assert hass.states.get(button).state == "unknown"
    fired = record_events(hass, button)

    simulator.set_value(CLICKS, simulator.get_value(CLICKS) + 1)
    await poll(hass, freezer)
    assert fired == ["click"]
    simulator.set_value(PRESSES, simulator.get_value(PRESSES) + 1)
    await poll(hass, freezer)
    assert fired == ["click", "long_press"]

    fired.clear()
    simulator.set_value(CLICKS, 65535)  # a jump: not clicks (a counter set)
    await poll(hass, freezer)
    simulator.set_value(CLICKS, 0)  # 65535 → 0: one increment
    await poll(hass, freezer)
    assert fired == ["click"]

    fired.clear()
    simulator.set_value(CLICKS, 40)
    simulator.set_value(PRESSES, 0)  # a reset
    await poll(hass, freezer)
    await poll(hass, freezer)
    assert fired == []


@pytest.mark.primary_only
async def test_button_increments_missed_between_polls_fire_each(
    hass: HomeAssistant,
    simulator: Simulator,
    demo_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """Three clicks and a long press between two polls: four events.

    (Home Assistant 2026.2 gives events of the same instant one timestamp, so
    with the test's frozen clock it shows them as one state.)
    """
    button = typed(hass, "event", "gtsap1:button:dvere_tlacitko")
    fired = record_events(hass, button)

    simulator.set_value(CLICKS, simulator.get_value(CLICKS) + 3)
    simulator.set_value(PRESSES, simulator.get_value(PRESSES) + 1)
    await poll(hass, freezer)

    assert sorted(fired) == ["click", "click", "click", "long_press"]


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
