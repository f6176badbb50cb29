"""Appliances: typed state read through role transcoders, and one write batch per command."""

from collections.abc import Mapping
from dataclasses import replace
from typing import Any

import pytest

from custom_components.tecoapi.pyplc import DataType, Point, PointAttributes, ValueKind
from custom_components.tecoapi.pyplc.core.appliances import (
    Appliance,
    Cover,
    CoverState,
    Light,
    LightState,
    MissingPointError,
    RoleValue,
    Thermostat,
    ThermostatAction,
    ThermostatMode,
    brightness_level,
    level_brightness,
    percent,
    rgb_packed,
    rgb_split,
    thermostat_modes,
)
from custom_components.tecoapi.pyplc.core.devices import (
    READINGS,
    ClimateSupport,
    CoverClass,
    DeviceKind,
    LightMode,
    Readings,
    Role,
    TypedDevice,
)
from custom_components.tecoapi.pyplc.tecomat.gtsap1 import LenientReadings

LENIENT = LenientReadings()


def _point(
    key: str,
    kind: ValueKind,
    *,
    invert: bool = False,
    minimum: float | None = None,
    maximum: float | None = None,
) -> Point:
    attributes = (
        None
        if minimum is None and maximum is None
        else PointAttributes(minimum=minimum, maximum=maximum)
    )
    return Point(
        key=key,
        path=key.upper(),
        address=key,
        type=DataType(kind=kind),
        invert=invert,
        attributes=attributes,
    )


FLAG, INT, REAL, TEXT = (
    ValueKind.BOOL,
    ValueKind.INTEGER,
    ValueKind.REAL,
    ValueKind.STRING,
)


def _device(
    kind: DeviceKind,
    roles: Mapping[Role, tuple[str, ValueKind]],
    *,
    readings: Readings = READINGS,
    invert: frozenset[str] = frozenset(),
    **features: Any,
) -> tuple[TypedDevice, dict[str, Point]]:
    """A device of ``kind`` with a point per role (key, kind), and its catalogue."""
    device = TypedDevice(
        key=f"test:{kind}:x",
        kind=kind,
        source="test",
        base="x",
        name="X",
        roles={role: key for role, (key, _) in roles.items()},
        readings=readings,
        **features,
    )
    points = {
        key: _point(key, value_kind, invert=key in invert)
        for key, value_kind in roles.values()
    }
    return device, points


# --- Transcoders ----------------------------------------------------------------------


def test_a_role_value_reads_through_the_readings_and_inverts_flags() -> None:
    plain = RoleValue("a", _point("a", FLAG), READINGS)
    inverted = RoleValue("a", _point("a", FLAG, invert=True), READINGS)
    unknown = RoleValue("a", None, READINGS)
    assert plain.flag({"a": True}) is True
    assert inverted.flag({"a": True}) is False
    assert inverted.flag({"a": 0}) is True
    assert inverted.flag({}) is None
    assert unknown.flag({"a": 1}) is True  # no point: read as it is
    assert plain.number({"a": 2.5}) == 2.5
    assert plain.integer({"a": 7.0}) == 7
    assert plain.integer({"a": 7.5}) is None
    assert inverted.encode(True) is False
    assert plain.encode(True) is True
    with pytest.raises(MissingPointError, match="'a'") as err:
        unknown.encode(True)
    assert err.value.key == "a"


def test_lenient_readings_read_and_write_text() -> None:
    text = RoleValue("t", _point("t", TEXT), LENIENT)
    assert text.number({"t": " 21,5 "}) == 21.5
    assert text.flag({"t": "on"}) is True
    assert text.flag({"t": "maybe"}) is None
    assert text.encode(True) == "1"
    assert text.encode(21.5) == "21.5"
    assert RoleValue("t", _point("t", TEXT), READINGS).number({"t": "21"}) is None


def test_an_appliance_follows_a_new_catalogue() -> None:
    device, points = _device(DeviceKind.SWITCH, {Role.ONOFF: ("on", FLAG)})
    appliance = Appliance(device, points)
    assert appliance.flag(Role.ONOFF, {"on": True}) is True
    assert appliance.number(Role.LEVEL, {"on": True}) is None
    assert appliance.flag(Role.LEVEL, {}) is None
    appliance.rebind(points)  # the same points: the same transcoders
    before = appliance.value(Role.ONOFF)
    appliance.rebind(points)
    assert appliance.value(Role.ONOFF) is before
    appliance.rebind({"on": replace(points["on"], invert=True)})
    assert appliance.flag(Role.ONOFF, {"on": True}) is False
    assert appliance.write({}, Role.ONOFF, True) == {"on": False}
    # What moves by itself is a light's or a cover's: a plain appliance never.
    assert appliance.motion == frozenset()
    assert not appliance.moves({"on": False})
    assert appliance.arrived({})


# --- Lights ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("brightness", "level"),
    [(0, 1.0), (1, 1.0), (2, 1.0), (3, 1.0), (4, 2.0), (128, 50.0), (255, 100.0)],
)
def test_brightness_as_a_level_stays_on(brightness: int, level: float) -> None:
    assert brightness_level(brightness) == level


@pytest.mark.parametrize(
    ("level", "brightness"),
    [(-5.0, 0), (0.0, 0), (1.0, 3), (50.0, 128), (60.0, 153), (100.0, 255), (120, 255)],
)
def test_a_level_as_brightness_is_clamped(level: float, brightness: int) -> None:
    assert level_brightness(level) == brightness


def test_rgb_packing() -> None:
    assert rgb_packed(255, 128, 1) == 255 + 128 * 256 + 65536
    assert rgb_split(255 + 128 * 256 + 65536) == (255, 128, 1)
    assert rgb_split(0xFFFFFF) == (255, 255, 255)
    assert rgb_packed(0, 0, 0) == 0


def _dimmer(
    *, onoff: bool = True, target: bool = True, mode: LightMode = LightMode.BRIGHTNESS
) -> Light:
    roles: dict[Role, tuple[str, ValueKind]] = {Role.LEVEL: ("level", REAL)}
    if onoff:
        roles[Role.ONOFF] = ("onoff", FLAG)
    if target:
        roles[Role.TARGET_LEVEL] = ("target", REAL)
    if mode is LightMode.RGB:
        roles[Role.RGB] = ("rgb", INT)
    if mode is LightMode.COLOR_TEMP:
        roles[Role.COLOR_TEMP] = ("kelvin", INT)
    device, points = _device(DeviceKind.LIGHT, roles, light_mode=mode)
    return Light(device, points)


def test_a_dimmers_state() -> None:
    light = _dimmer()
    assert light.state({"onoff": True, "level": 60.0}) == LightState(
        is_on=True, level=60.0, brightness=153, rgb=None, kelvin=None
    )
    assert light.state({}) == LightState(None, None, None, None, None)
    # Without onoff: on while the level is above zero.
    bare = _dimmer(onoff=False, target=False)
    assert bare.state({"level": 0.0}).is_on is False
    assert bare.state({"level": 0.5}).is_on is True
    assert bare.state({}).is_on is None


def test_an_on_off_light_shows_no_brightness() -> None:
    device, points = _device(
        DeviceKind.LIGHT,
        {Role.ONOFF: ("onoff", FLAG), Role.LEVEL: ("level", REAL)},
        light_mode=LightMode.ONOFF,
    )
    light = Light(device, points)
    assert not light.dimmable
    assert light.state({"onoff": True, "level": 40}).brightness is None
    # Switched on, it is switched on: no level is written.
    assert light.turn_on({"level": 0}, brightness=100) == {"onoff": True}
    assert light.turn_off() == {"onoff": False}


def test_an_inverted_onoff_is_read_and_written_as_its_opposite() -> None:
    device, points = _device(
        DeviceKind.LIGHT,
        {Role.ONOFF: ("onoff", FLAG)},
        invert=frozenset({"onoff"}),
        light_mode=LightMode.ONOFF,
    )
    light = Light(device, points)
    assert light.state({"onoff": False}).is_on is True
    assert light.turn_on({}) == {"onoff": False}
    assert light.turn_off() == {"onoff": True}


def test_turn_on_is_one_ordered_batch() -> None:
    light = _dimmer(mode=LightMode.RGB)
    batch = light.turn_on({"level": 0.0}, brightness=51, rgb=(255, 128, 1))
    assert batch == {"rgb": 255 + 128 * 256 + 65536, "target": 20.0, "onoff": True}
    assert list(batch) == ["rgb", "target", "onoff"]
    assert light.moves(batch)
    assert light.motion == {"level", "target", "onoff"}


def test_turn_on_writes_in_each_points_kind() -> None:
    device, points = _device(
        DeviceKind.LIGHT,
        {
            Role.ONOFF: ("onoff", FLAG),
            Role.LEVEL: ("level", INT),
            Role.COLOR_TEMP: ("kelvin", INT),
        },
        light_mode=LightMode.COLOR_TEMP,
    )
    light = Light(device, points)
    batch = light.turn_on({"level": 0}, brightness=128, kelvin=3000.4)
    assert batch == {"kelvin": 3000, "level": 50, "onoff": True}
    assert all(type(value) is int for value in (batch["kelvin"], batch["level"]))
    # A colour it has no point for is not written.
    assert "rgb" not in light.turn_on({"level": 10}, rgb=(1, 2, 3))
    assert light.state({"kelvin": 2700.4}).kelvin == 2700
    assert light.state({"kelvin": "warm"}).kelvin is None
    assert light.state({"rgb": 5}).rgb is None  # no rgb role


def test_a_colour_temperature_range() -> None:
    device, points = _device(
        DeviceKind.LIGHT,
        {Role.LEVEL: ("level", REAL), Role.COLOR_TEMP: ("kelvin", INT)},
        light_mode=LightMode.COLOR_TEMP,
    )
    light = Light(device, points)
    assert light.kelvin_range(points, {}) == (2000, 6500)
    ranged = {"kelvin": _point("kelvin", INT, minimum=2700, maximum=5000)}
    assert light.kelvin_range(ranged, {}) == (2700, 5000)


def test_rgb_is_read_as_an_integer() -> None:
    light = _dimmer(mode=LightMode.RGB)
    assert light.state({"rgb": 0x010203}).rgb == (3, 2, 1)
    assert light.state({"rgb": 1.5}).rgb is None
    assert light.state({"rgb": 258.0}).rgb == (2, 1, 0)


def test_switched_on_dark_it_gets_its_last_level_back() -> None:
    light = _dimmer()
    # Nothing above zero known: full.
    assert light.last_level == 100.0
    assert light.turn_on({"level": 0.0}) == {"target": 100.0, "onoff": True}
    # The target (the level chosen) is remembered, not the level passed through.
    light.update({"target": 35.0, "level": 80.0})
    assert light.last_level == 35.0
    light.update({"target": 0.0})
    light.update({"target": None})
    assert light.last_level == 35.0
    light.update({"target": 250.0})
    assert light.last_level == 100.0
    light.update({"target": 35.0})
    assert light.turn_on({"level": 0.0}) == {"target": 35.0, "onoff": True}
    assert light.turn_on({}) == {"target": 35.0, "onoff": True}
    # Lit: onoff alone, the level stays.
    assert light.turn_on({"level": 10.0}) == {"onoff": True}


def test_a_light_without_onoff_switches_by_its_level() -> None:
    light = _dimmer(onoff=False, target=False)
    assert not light.follows_target
    assert light.turn_on({"level": 0}) == {"level": 100.0}
    assert light.turn_on({"level": 0}, brightness=255) == {"level": 100.0}
    assert light.turn_off() == {"level": 0.0}
    assert not light.moves({"level": 100.0})
    assert light.motion == frozenset()
    assert light.arrived({"level": 0})


def test_a_dimmer_arrives_at_its_target() -> None:
    light = _dimmer()
    assert not light.moves({"onoff": True})
    assert not light.arrived({"onoff": True, "level": 10.0, "target": 60.0})
    assert light.arrived({"onoff": True, "level": 59.6, "target": 60.4})
    assert light.arrived({"onoff": False, "level": 10.0, "target": 60.0})
    assert light.arrived({"onoff": True, "level": None, "target": 60.0})
    assert light.arrived({"onoff": True, "level": 10.0})


def test_a_text_light_with_lenient_readings() -> None:
    device, points = _device(
        DeviceKind.LIGHT,
        {
            Role.ONOFF: ("onoff", TEXT),
            Role.LEVEL: ("level", TEXT),
            Role.TARGET_LEVEL: ("target", TEXT),
        },
        readings=LENIENT,
        light_mode=LightMode.BRIGHTNESS,
    )
    light = Light(device, points)
    state = light.state({"onoff": " ON ", "level": "60,0"})
    assert (state.is_on, state.level, state.brightness) == (True, 60.0, 153)
    light.update({"target": "42,5"})
    assert light.turn_on({"level": "0"}) == {"target": "42.5", "onoff": "1"}
    assert light.turn_off() == {"onoff": "0"}


# --- Covers ---------------------------------------------------------------------------


def _cover(*, target: bool = True, moving: bool = False) -> Cover:
    roles: dict[Role, tuple[str, ValueKind]] = {Role.POSITION: ("position", REAL)}
    if target:
        roles[Role.TARGET] = ("target", REAL)
    if moving:
        roles[Role.MOVING] = ("moving", FLAG)
    device, points = _device(DeviceKind.COVER, roles, cover_class=CoverClass.SHUTTER)
    return Cover(device, points)


@pytest.mark.parametrize(
    ("values", "state"),
    [
        ({"position": 30.0, "target": 30.4}, CoverState(30, None, None, False, False)),
        ({"position": 30.0, "target": 31.0}, CoverState(30, 31, None, True, False)),
        ({"position": 30.0, "target": 29.0}, CoverState(30, 29, None, False, True)),
        ({"position": 0.0, "target": 100.0}, CoverState(0, 100, None, True, False)),
        ({"position": 100.0, "target": 0.0}, CoverState(100, 0, None, False, True)),
        ({"position": -3.0, "target": 150.0}, CoverState(0, 100, None, True, False)),
        ({"position": 30.0}, CoverState(30, None, None, False, False)),
        ({"target": 30.0}, CoverState(None, None, None, False, False)),
    ],
)
def test_a_covers_state(values: dict[str, Any], state: CoverState) -> None:
    assert _cover().state(values) == state


def test_closed_at_zero() -> None:
    cover = _cover()
    assert cover.state({"position": 0.4}).is_closed is True
    assert cover.state({"position": 0.6}).is_closed is False
    assert cover.state({}).is_closed is None


def test_a_cover_moves_by_its_target_and_stops_where_it_is() -> None:
    cover = _cover(moving=True)
    assert cover.can_stop
    assert cover.move_to(30) == {"target": 30.0}
    assert cover.open() == {"target": 100.0}
    assert cover.close() == {"target": 0.0}
    assert cover.stop({"position": 42.4, "target": 80.0}) == {"target": 42.0}
    assert cover.stop({"target": 80.0}) == {}
    assert cover.moves({"target": 30.0})
    assert not cover.moves({})
    assert cover.motion == {"position", "target", "moving"}
    assert cover.state({"moving": True}).moving is True


def test_a_cover_without_a_target_moves_by_its_position() -> None:
    cover = _cover(target=False)
    assert not cover.can_stop
    assert cover.move_to(30) == {"position": 30.0}
    # Stopped all the same, where it is: no target to differ.
    assert cover.stop({"position": 12.0}) == {"position": 12.0}
    assert not cover.moves({"position": 30.0})
    assert cover.motion == frozenset()
    assert cover.arrived({"position": 0.0})
    assert cover.state({"position": 10.0}) == CoverState(10, None, None, False, False)


def test_a_cover_arrives() -> None:
    cover = _cover(moving=True)
    assert not cover.arrived({"position": 10.0, "target": 30.0})
    assert cover.arrived({"position": 29.6, "target": 30.4})
    assert not cover.arrived({"position": 30.0, "target": 30.0, "moving": True})
    assert cover.arrived({"position": 30.0, "target": 30.0, "moving": False})
    assert cover.arrived({"position": None, "target": 30.0})
    assert cover.arrived({"position": 10.0})


def test_a_gate() -> None:
    device, points = _device(
        DeviceKind.COVER, {Role.POSITION: ("p", INT)}, cover_class=CoverClass.GATE
    )
    gate = Cover(device, points)
    assert gate.gate
    assert gate.move_to(49.6) == {"p": 50}
    assert not _cover().gate


@pytest.mark.parametrize(
    ("value", "shown"), [(-1, 0), (0.4, 0), (99.5, 100), (101, 100)]
)
def test_percent(value: float, shown: int) -> None:
    assert percent(value) == shown


# --- Thermostats ----------------------------------------------------------------------


def _thermostat(
    support: ClimateSupport,
    *extra: Role,
    readings: Readings = READINGS,
    kind: ValueKind = FLAG,
    invert: frozenset[str] = frozenset(),
) -> Thermostat:
    number = TEXT if kind is TEXT else REAL
    roles: dict[Role, tuple[str, ValueKind]] = {
        Role.TEMPERATURE: ("temp", number),
        Role.SETPOINT: ("set", number),
    }
    roles |= {role: (role.value, kind) for role in extra}
    device, points = _device(
        DeviceKind.CLIMATE, roles, readings=readings, invert=invert, climate=support
    )
    return Thermostat(device, points)


H, C = Role.HEAT_MODE, Role.COOL_MODE
HEAT, COOL, BOTH, OFF = (
    ThermostatMode.HEAT,
    ThermostatMode.COOL,
    ThermostatMode.HEAT_COOL,
    ThermostatMode.OFF,
)


@pytest.mark.parametrize(
    ("support", "flags", "modes"),
    [
        (ClimateSupport.HEATING, frozenset(), (HEAT,)),
        (ClimateSupport.COOLING, frozenset(), (COOL,)),
        (ClimateSupport.BOTH, frozenset(), (BOTH,)),
        (ClimateSupport.HEATING, frozenset({H}), (HEAT, OFF)),
        (ClimateSupport.COOLING, frozenset({C}), (COOL, OFF)),
        (ClimateSupport.BOTH, frozenset({H, C}), (HEAT, COOL, BOTH, OFF)),
    ],
)
def test_thermostat_modes(
    support: ClimateSupport, flags: frozenset[Role], modes: tuple[ThermostatMode, ...]
) -> None:
    assert thermostat_modes(support, flags) == modes
    assert _thermostat(support, *flags).modes == modes


def test_a_thermostat_without_flags_is_in_its_one_mode() -> None:
    thermostat = _thermostat(ClimateSupport.COOLING)
    state = thermostat.state({"temp": 24.5, "set": 23})
    assert (state.temperature, state.setpoint) == (24.5, 23.0)
    assert (state.mode, state.action) == (COOL, None)
    assert thermostat.set_mode(OFF) == {}
    assert thermostat.turn_on() == {}
    assert thermostat.set_setpoint(22) == {"set": 22.0}


@pytest.mark.parametrize(
    ("values", "mode"),
    [
        ({"heat_mode": True, "cool_mode": False}, HEAT),
        ({"heat_mode": False, "cool_mode": True}, COOL),
        ({"heat_mode": True, "cool_mode": True}, BOTH),
        ({"heat_mode": False, "cool_mode": False}, OFF),
        ({"heat_mode": None, "cool_mode": True}, COOL),
        ({}, OFF),
    ],
)
def test_the_mode_the_flags_say(values: dict[str, Any], mode: ThermostatMode) -> None:
    thermostat = _thermostat(ClimateSupport.BOTH, H, C)
    assert thermostat.mode(values) is mode
    assert thermostat.state(values).mode is mode


def test_a_mode_is_one_batch_of_every_flag() -> None:
    thermostat = _thermostat(ClimateSupport.BOTH, H, C)
    assert thermostat.set_mode(HEAT) == {"cool_mode": False, "heat_mode": True}
    assert list(thermostat.set_mode(HEAT)) == ["cool_mode", "heat_mode"]
    assert thermostat.set_mode(BOTH) == {"cool_mode": True, "heat_mode": True}
    assert thermostat.turn_on() == {"cool_mode": False, "heat_mode": True}
    assert thermostat.turn_off() == {"cool_mode": False, "heat_mode": False}


def test_inverted_mode_flags() -> None:
    thermostat = _thermostat(ClimateSupport.HEATING, H, invert=frozenset({"heat_mode"}))
    assert thermostat.mode({"heat_mode": False}) is HEAT
    assert thermostat.set_mode(HEAT) == {"heat_mode": False}
    assert thermostat.turn_off() == {"heat_mode": True}


@pytest.mark.parametrize(
    ("values", "action"),
    [
        ({"heat_mode": True, "heating": True}, ThermostatAction.HEATING),
        ({"heat_mode": True, "cooling": True}, ThermostatAction.COOLING),
        (
            {"heat_mode": True, "heating": True, "cooling": True},
            ThermostatAction.HEATING,
        ),
        ({"heat_mode": True, "heating": False}, ThermostatAction.IDLE),
        ({"heat_mode": False}, ThermostatAction.OFF),
        ({"heat_mode": False, "heating": True}, ThermostatAction.HEATING),
    ],
)
def test_the_action(values: dict[str, Any], action: ThermostatAction) -> None:
    thermostat = _thermostat(ClimateSupport.BOTH, H, Role.HEATING, Role.COOLING)
    assert thermostat.state(values).action is action


def test_an_action_from_one_flag() -> None:
    cooling = _thermostat(ClimateSupport.COOLING, Role.COOLING)
    assert cooling.state({"cooling": True}).action is ThermostatAction.COOLING
    assert cooling.state({"cooling": False}).action is ThermostatAction.IDLE


def test_a_text_thermostat_with_lenient_readings() -> None:
    thermostat = _thermostat(
        ClimateSupport.HEATING, H, Role.HEATING, readings=LENIENT, kind=TEXT
    )
    state = thermostat.state(
        {"temp": "21,5", "set": " 22 ", "heat_mode": "1", "heating": "off"}
    )
    assert state == thermostat.state(
        {"temp": 21.5, "set": 22.0, "heat_mode": True, "heating": False}
    )
    assert (state.mode, state.action) == (HEAT, ThermostatAction.IDLE)
    assert thermostat.set_setpoint(21.5) == {"set": "21.5"}
    assert thermostat.set_setpoint(22) == {"set": "22"}
    assert thermostat.turn_off() == {"heat_mode": "0"}


def test_the_setpoint_range_and_step() -> None:
    thermostat = _thermostat(ClimateSupport.HEATING)
    device = thermostat.device
    points = {"set": _point("set", REAL)}
    assert thermostat.setpoint_range(points, {}) == (7.0, 35.0, 0.5)
    points = {"set": _point("set", REAL, minimum=5.0, maximum=30.5)}
    assert thermostat.setpoint_range(points, {}) == (5.0, 30.5, 0.5)
    points = {"set": _point("set", REAL, minimum=5.2, maximum=30.0)}
    assert thermostat.setpoint_range(points, {}) == (5.2, 30.0, 0.1)
    assert device.kind is DeviceKind.CLIMATE


def test_a_command_to_a_point_not_in_the_catalogue_is_refused() -> None:
    thermostat = _thermostat(ClimateSupport.HEATING)
    thermostat.rebind({})
    with pytest.raises(MissingPointError):
        thermostat.set_setpoint(20)
