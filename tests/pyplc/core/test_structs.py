"""The core's struct convention, found in T_ApiObject programs after GTSAP1 families."""

from typing import Any

import pytest

from custom_components.tecoapi.pyplc.core.devices import (
    DEFAULT_MAX_KELVIN,
    DEFAULT_MIN_KELVIN,
    READINGS,
    ClimateSupport,
    CoverClass,
    LightMode,
    Role,
    kelvin_range,
    setpoint_range,
)
from tests.pyplc.tecomat.typed_programs import api, discover, only

# --- Our struct convention -----------------------------------------------------------


def thermostat_struct(**changes: Any) -> dict[str, Any]:
    members = {
        "temperature": api(21.2, readOnly=True, title="Kids room", units="°C"),
        "setpoint": api(21.0, minValue=16.0, maxValue=26.0, units="°C"),
        "heating": api(True, readOnly=True),
        "heatMode": api(True),
    }
    return members | changes


def test_struct_thermostat_with_its_attributes() -> None:
    tree = {"Rooms": {"kidsRoom": {"thermostat": thermostat_struct()}}}
    found, points = discover(tree)

    climate = only(found)
    prefix = "rooms.kidsroom.thermostat."
    assert climate.key == "struct:climate:rooms.kidsroom.thermostat"
    assert (climate.source, climate.base, climate.name) == (
        "struct",
        "Rooms.kidsRoom.thermostat",
        "Kids room thermostat",
    )
    # Its members hold what their kinds say: read as they are, text is no number.
    assert climate.readings is READINGS
    assert climate.roles == {
        Role.TEMPERATURE: f"{prefix}temperature",
        Role.SETPOINT: f"{prefix}setpoint",
        Role.HEATING: f"{prefix}heating",
        Role.HEAT_MODE: f"{prefix}heatmode",
    }
    assert climate.climate is ClimateSupport.HEATING
    # The setpoint's minValue/maxValue are the climate's range.
    assert setpoint_range(climate, points, {}) == (16.0, 26.0)
    assert points[f"{prefix}temperature"].attributes is not None


@pytest.mark.parametrize(
    ("changes", "support"),
    [
        ({"coolMode": api(False)}, ClimateSupport.BOTH),
        (
            {"heating": api(False, readOnly=True), "cooling": api(True)},
            ClimateSupport.BOTH,
        ),
    ],
)
def test_struct_thermostat_support_from_its_members(
    changes: dict[str, Any], support: ClimateSupport
) -> None:
    found, _ = discover({"t": thermostat_struct(**changes)})
    assert only(found).climate is support


def test_struct_thermostat_of_two_members_cools_or_heats() -> None:
    minimal = {"temperature": api(20.0, readOnly=True), "setpoint": api(21.0)}
    cooling = minimal | {"cooling": api(False, readOnly=True)}
    found, points = discover({"a": minimal, "b": cooling})

    heater, cooler = found.devices.values()
    assert heater.climate is ClimateSupport.HEATING
    assert cooler.climate is ClimateSupport.COOLING
    assert setpoint_range(heater, points, {}) is None  # no range given anywhere


def test_struct_members_match_ignoring_case() -> None:
    tree = {"study": {"TEMPERATURE": api(20.0, readOnly=True), "SetPoint": api(21.0)}}
    climate = only(discover(tree)[0])

    assert climate.key == "struct:climate:study"
    assert climate.roles[Role.SETPOINT] == "study.setpoint"
    assert climate.name == "Study"


def test_struct_blinds_with_and_without_a_target() -> None:
    tree = {
        "livingBlind": {
            "position": api(100, readOnly=True, minValue=0.0, maxValue=100.0),
            "target": api(100, minValue=0.0, maxValue=100.0),
            "moving": api(False, readOnly=True),
        },
        "Attic": {"roofWindow": {"position": api(0), "moving": api(False)}},
        "garageGate": {"position": api(0)},
    }
    found, _ = discover(tree)

    living, roof, gate = found.devices.values()
    assert living.key == "struct:cover:livingblind"
    assert living.name == "Living blind"
    assert living.roles == {
        Role.POSITION: "livingblind.position",
        Role.TARGET: "livingblind.target",
        Role.MOVING: "livingblind.moving",
    }
    assert living.cover_class is CoverClass.SHUTTER
    # Without a target the position is written to move it.
    assert roof.roles[Role.TARGET] == roof.roles[Role.POSITION]
    assert roof.name == "Roof window"
    assert gate.cover_class is CoverClass.GATE


def test_struct_blind_named_a_gate_by_its_title() -> None:
    tree = {"entrance": {"position": api(0, title="Vjezdová brána")}}
    assert only(discover(tree)[0]).cover_class is CoverClass.GATE


def test_struct_lights() -> None:
    tree = {
        "kidsLight": {"brightness": api(30, units="%"), "onoff": api(True)},
        "dimmer": {"brightness": api(0.0)},
        "wardrobe": {
            "brightness": api(80),
            "onoff": api(True),
            "colorTemp": api(4000, minValue=2700.0, maxValue=6500.0, units="K"),
        },
        "hall": {"brightness": api(80), "colorTemp": api(4000)},
    }
    found, points = discover(tree)

    kids, dimmer, wardrobe, hall = found.devices.values()
    assert kids.light_mode is LightMode.BRIGHTNESS
    assert kids.roles == {
        Role.LEVEL: "kidslight.brightness",
        Role.TARGET_LEVEL: "kidslight.brightness",
        Role.ONOFF: "kidslight.onoff",
    }
    # A single 0-100 value is state and brightness.
    assert set(dimmer.roles) == {Role.LEVEL, Role.TARGET_LEVEL}
    assert wardrobe.light_mode is LightMode.COLOR_TEMP
    assert kelvin_range(wardrobe, points, {}) == (2700, 6500)
    defaults = (DEFAULT_MIN_KELVIN, DEFAULT_MAX_KELVIN)
    assert kelvin_range(kids, points, {}) == defaults
    assert kelvin_range(hall, points, {}) == defaults  # a colour object without range


def test_a_room_struct_may_hold_one_device_of_each_kind() -> None:
    tree = {
        "living": {
            "temperature": api(21.0, readOnly=True),
            "setpoint": api(21.5),
            "position": api(50),
            "brightness": api(10),
            "humidity": api(40.0, readOnly=True),
        }
    }
    found, _ = discover(tree)

    assert list(found.devices) == [
        "struct:climate:living",
        "struct:cover:living",
        "struct:light:living",
    ]
    assert "living.humidity" not in found.consumed


@pytest.mark.parametrize(
    ("members", "reason"),
    [
        ({"temperature": api(20.0), "setpoint": api(21.0, readOnly=True)}, "read-only"),
        ({"temperature": api("warm"), "setpoint": api(21.0)}, "holds a string"),
        ({"position": api(0, readOnly=True)}, "read-only"),
        ({"brightness": api(True)}, "holds a bool"),
        ({"brightness": api(10, readOnly=True)}, "read-only"),
        ({"position": api(10), "target": api(10, readOnly=True)}, "read-only"),
    ],
)
def test_structs_that_do_not_fit_stay_raw(members: dict[str, Any], reason: str) -> None:
    found, _ = discover({"thing": members})

    assert found.devices == {}
    assert found.consumed == frozenset()
    [message] = found.skipped.values()
    assert reason in message


def test_structs_without_a_signature_are_not_devices() -> None:
    tree = {
        "pump": {"onoff": api(True), "speed": api(3)},  # onoff alone is no light
        "valve": {"target": api(10), "moving": api(False)},  # no position
        "boiler": {"temperature": api(60.0, readOnly=True)},  # no setpoint
        "setpoint": api(21.0),  # top-level members belong to no struct
        "temperature": api(20.0, readOnly=True),
        "rooms": [api(21.0), api(22.0)],  # array elements are no members
    }
    found, _ = discover(tree)

    assert found.devices == {}
    assert found.skipped == {}


def test_struct_devices_in_arrays_and_plain_members() -> None:
    tree = {
        "Main": {
            "blinds": [{"position": 0}, {"position": 100}],
            "hall": {"brightness": 50, "onoff": True},
        }
    }
    found, _ = discover(tree)

    assert list(found.devices) == [
        "struct:cover:main.blinds[0]",
        "struct:cover:main.blinds[1]",
        "struct:light:main.hall",
    ]
    assert found.devices["struct:cover:main.blinds[1]"].name == "Blinds 1"


def test_gtsap1_families_come_first_and_consume_their_points() -> None:
    tree = {
        "Main": {
            "LIVING": {
                "GTSAP1_THERMOSTAT_meastemp": 20.0,
                "temperature": api(20.0, readOnly=True),
                "setpoint": api(21.0),
            }
        }
    }
    found, _ = discover(tree)

    assert list(found.devices) == [
        "gtsap1:thermostat:main.living",
        "struct:climate:main.living",
    ]
    keys = [device.points for device in found.devices.values()]
    assert not keys[0] & keys[1]
    assert found.consumed == keys[0] | keys[1]
