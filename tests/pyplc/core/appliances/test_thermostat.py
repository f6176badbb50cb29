"""Thermostats: modes from their flags, action, setpoint range."""

from typing import Any

import pytest

from custom_components.tecoapi.pyplc import ValueKind
from custom_components.tecoapi.pyplc.core.appliances import (
    MissingPointError,
    Thermostat,
    ThermostatAction,
    ThermostatMode,
    thermostat_modes,
)
from custom_components.tecoapi.pyplc.core.devices import (
    READINGS,
    ClimateSupport,
    DeviceKind,
    Readings,
    Role,
)
from tests.pyplc.core.appliances.catalogue import (
    FLAG,
    LENIENT,
    REAL,
    TEXT,
    make_device,
    make_point,
)


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
    device, points = make_device(
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
    points = {"set": make_point("set", REAL)}
    assert thermostat.setpoint_range(points, {}) == (7.0, 35.0, 0.5)
    points = {"set": make_point("set", REAL, minimum=5.0, maximum=30.5)}
    assert thermostat.setpoint_range(points, {}) == (5.0, 30.5, 0.5)
    points = {"set": make_point("set", REAL, minimum=5.2, maximum=30.0)}
    assert thermostat.setpoint_range(points, {}) == (5.2, 30.0, 0.1)
    assert device.kind is DeviceKind.CLIMATE


def test_a_command_to_a_point_not_in_the_catalogue_is_refused() -> None:
    thermostat = _thermostat(ClimateSupport.HEATING)
    thermostat.rebind({})
    with pytest.raises(MissingPointError):
        thermostat.set_setpoint(20)
