"""Typed devices: GTSAP1 families, our struct convention, composition, button counters."""

from collections.abc import Mapping
from dataclasses import replace
from typing import Any

import pytest

from custom_components.tecoapi.pyplc import Point, ValueKind
from custom_components.tecoapi.pyplc.core.devices import (
    COMPOSITIONS,
    DEFAULT_MAX_KELVIN,
    DEFAULT_MIN_KELVIN,
    ClimateSupport,
    CompositionError,
    CompositionProblem,
    CoverClass,
    DeviceCatalogue,
    DeviceKind,
    DeviceSource,
    LightMode,
    Measurement,
    Role,
    TypedDevice,
    compose,
    counter_bits,
    counter_events,
    find_devices,
    fitting_points,
    is_gate_name,
    is_writable,
    kelvin_range,
    name_from_base,
    parse_bool,
    parse_int,
    parse_number,
    setpoint_range,
    value_for_point,
)
from custom_components.tecoapi.pyplc.tecomat.points import tecomat_point
from custom_components.tecoapi.pyplc.tecomat.tecoapi.catalogue import build_catalogue

ATTR = {
    "enable": True,
    "visibility": True,
    "readOnly": False,
    "title": "",
    "minValue": 0.0,
    "maxValue": 0.0,
    "units": "",
}


def api(value: Any, **attr: Any) -> dict[str, Any]:
    """A T_ApiObject as GetObject answers it (writable, no range unless told)."""
    return {"value": value, "attr": ATTR | attr}


def family(base: str, family_type: str, **properties: Any) -> dict[str, Any]:
    """The top-level variables of one GTSAP1 family."""
    return {
        f"{base}_GTSAP1_{family_type}_{prop}": value
        for prop, value in properties.items()
    }


def discover(tree: Mapping[str, Any]) -> tuple[DeviceCatalogue, dict[str, Point]]:
    """Devices of a GetObject tree, through the real catalogue walker."""
    catalogue = build_catalogue(list(tree), tree)
    return find_devices(catalogue.points, catalogue.values), dict(catalogue.points)


def only(found: DeviceCatalogue) -> TypedDevice:
    assert len(found.devices) == 1, found.skipped
    return next(iter(found.devices.values()))


# --- GTSAP1: lights ----------------------------------------------------------------


FULL_LIGHT = {
    "onoff": True,
    "type": True,
    "dimtype": 0,
    "dimlevel": 40.0,
    "tgtlevel": 60.0,
    "rgb": 255,
    "colortemp": 3000,
    "minTempK": 2200,
    "maxTempK": 5000,
    "name": "Obývák strop",
}


@pytest.mark.parametrize(
    ("changes", "mode", "target"),
    [
        ({"dimtype": 0}, LightMode.BRIGHTNESS, "tgtlevel"),
        ({"dimtype": 1}, LightMode.RGB, "dimlevel"),
        ({"dimtype": 2}, LightMode.COLOR_TEMP, "dimlevel"),
        ({"dimtype": 7}, LightMode.BRIGHTNESS, "tgtlevel"),
        ({"type": False}, LightMode.ONOFF, "tgtlevel"),
    ],
    ids=["dimtype0", "dimtype1-rgb", "dimtype2-colortemp", "unknown-dimtype", "onoff"],
)
def test_light_modes_follow_type_and_dimtype(
    changes: dict[str, Any], mode: LightMode, target: str
) -> None:
    found, _ = discover(family("LIVING_CEILING", "LIGHT", **FULL_LIGHT | changes))

    light = only(found)
    prefix = "living_ceiling_gtsap1_light_"
    assert light.key == "gtsap1:light:living_ceiling"
    assert (light.kind, light.source, light.base) == (
        DeviceKind.LIGHT,
        DeviceSource.GTSAP1,
        "LIVING_CEILING",
    )
    assert light.light_mode is mode
    assert light.name == "Obývák strop"
    assert light.roles == {
        Role.ONOFF: f"{prefix}onoff",
        Role.LEVEL: f"{prefix}dimlevel",
        Role.TARGET_LEVEL: f"{prefix}{target}",
        Role.RGB: f"{prefix}rgb",
        Role.COLOR_TEMP: f"{prefix}colortemp",
        Role.MIN_KELVIN: f"{prefix}mintempk",
        Role.MAX_KELVIN: f"{prefix}maxtempk",
        Role.NAME: f"{prefix}name",
    }
    # Every property is the device's, the configuration ones included.
    assert found.consumed == {prefix + prop.lower() for prop in FULL_LIGHT}
    assert light.points == found.consumed


@pytest.mark.parametrize(
    ("properties", "mode", "level", "target"),
    [
        # Without `type`, a level makes a light dimmable.
        (
            {"onoff": True, "dimlevel": 10.0},
            LightMode.BRIGHTNESS,
            "dimlevel",
            "dimlevel",
        ),
        ({"onoff": True}, LightMode.ONOFF, None, None),
        # Only a target level: it is read as the level too.
        (
            {"onoff": True, "tgtlevel": 5.0},
            LightMode.BRIGHTNESS,
            "tgtlevel",
            "tgtlevel",
        ),
        # A colour dimtype without its colour variable is brightness only.
        (
            {"onoff": True, "type": True, "dimtype": 1, "dimlevel": 1.0},
            LightMode.BRIGHTNESS,
            "dimlevel",
            "dimlevel",
        ),
        (
            {"onoff": True, "type": True, "dimtype": 2, "tgtlevel": 1.0},
            LightMode.BRIGHTNESS,
            "tgtlevel",
            "tgtlevel",
        ),
        # Dimmable by `type` but no level at all: on/off.
        ({"onoff": True, "type": True}, LightMode.ONOFF, None, None),
    ],
)
def test_light_mode_fallbacks(
    properties: dict[str, Any], mode: LightMode, level: str | None, target: str | None
) -> None:
    light = only(discover(family("HALL", "LIGHT", **properties))[0])

    assert light.light_mode is mode
    prefix = "hall_gtsap1_light_"
    assert light.point(Role.LEVEL) == (level and prefix + level)
    assert light.point(Role.TARGET_LEVEL) == (target and prefix + target)
    assert light.name == "Hall"


# --- GTSAP1: openers, thermostats, buttons, displays, contacts, switches ------------


@pytest.mark.parametrize(
    ("base", "name", "cover_class"),
    [
        ("LIVING_BLIND", "Obývák žaluzie", CoverClass.SHUTTER),
        ("ENTRANCE", "Vjezdová BRÁNA", CoverClass.GATE),
        ("GARAGE", "Garážová vrata", CoverClass.GATE),
        ("FRONT", "Front Gate", CoverClass.GATE),
        ("GARAZ_VRATA", None, CoverClass.GATE),  # no name: the base says it
        ("Brana_Vjezd", "  ", CoverClass.GATE),  # an empty name: the base
    ],
)
def test_openers_are_shutters_or_gates(
    base: str, name: str | None, cover_class: CoverClass
) -> None:
    properties: dict[str, Any] = {"current": 30, "target": 30, "moving": False}
    if name is not None:
        properties["name"] = name
    cover = only(discover(family(base, "OPENER", **properties))[0])

    prefix = f"{base.lower()}_gtsap1_opener_"
    assert cover.key == f"gtsap1:opener:{base.lower()}"
    assert cover.kind is DeviceKind.COVER
    assert cover.cover_class is cover_class
    assert cover.roles[Role.POSITION] == f"{prefix}current"
    assert cover.roles[Role.TARGET] == f"{prefix}target"
    assert cover.roles[Role.MOVING] == f"{prefix}moving"
    assert cover.name == (
        name.strip() if name and name.strip() else name_from_base(base)
    )


def test_opener_without_target_is_read_only() -> None:
    cover = only(discover(family("ROOF", "OPENER", current=0))[0])
    assert set(cover.roles) == {Role.POSITION}


FULL_THERMOSTAT = {
    "type": 3,
    "meastemp": 21.5,
    "setpoint": 22.0,
    "mintemp": 16.0,
    "maxtemp": 28.0,
    "heatmode": True,
    "coolmode": False,
    "heat": True,
    "cool": False,
    "name": "Obývák",
}


@pytest.mark.parametrize(
    ("type_code", "support"),
    [
        (1, ClimateSupport.COOLING),
        (2, ClimateSupport.HEATING),
        (3, ClimateSupport.BOTH),
    ],
)
def test_thermostat_type_is_heating_cooling_or_both(
    type_code: int, support: ClimateSupport
) -> None:
    found, points = discover(
        {
            "Main": family(
                "LIVING", "THERMOSTAT", **FULL_THERMOSTAT | {"type": type_code}
            )
        }
    )

    climate = only(found)
    prefix = "main.living_gtsap1_thermostat_"
    assert climate.key == "gtsap1:thermostat:main.living"
    assert climate.base == "Main.LIVING"
    assert climate.climate is support
    heating = {Role.HEAT_MODE: f"{prefix}heatmode", Role.HEATING: f"{prefix}heat"}
    cooling = {Role.COOL_MODE: f"{prefix}coolmode", Role.COOLING: f"{prefix}cool"}
    # The block has both modes' properties whatever its type: only those of what
    # it does are roles.
    assert climate.roles == {
        Role.TEMPERATURE: f"{prefix}meastemp",
        Role.SETPOINT: f"{prefix}setpoint",
        Role.MIN_TEMP: f"{prefix}mintemp",
        Role.MAX_TEMP: f"{prefix}maxtemp",
        **(heating if support is not ClimateSupport.COOLING else {}),
        **(cooling if support is not ClimateSupport.HEATING else {}),
        Role.NAME: f"{prefix}name",
    }
    assert found.consumed == {prefix + prop for prop in FULL_THERMOSTAT}
    catalogue = build_catalogue(
        ["Main"],
        {"Main": family("LIVING", "THERMOSTAT", **FULL_THERMOSTAT)},
    )
    assert setpoint_range(climate, points, catalogue.values) == (16.0, 28.0)


@pytest.mark.parametrize(
    ("properties", "support"),
    [
        ({}, ClimateSupport.HEATING),
        ({"heatmode": True}, ClimateSupport.HEATING),
        ({"cool": False}, ClimateSupport.COOLING),
        ({"coolmode": True, "heat": False}, ClimateSupport.BOTH),
        ({"type": 9, "coolmode": True}, ClimateSupport.COOLING),
    ],
)
def test_thermostat_without_a_known_type_follows_its_properties(
    properties: dict[str, Any], support: ClimateSupport
) -> None:
    found, _ = discover(family("STUDY", "THERMOSTAT", meastemp=20.0, **properties))
    assert only(found).climate is support


def test_button_counters() -> None:
    found, _ = discover(
        family("DOOR", "BUTTON", CLICKCNT=17, PRESSCNT=3, name="Tlačítko")
        | family("CLICK_ONLY", "BUTTON", CLICKCNT=0)
        | family("PRESS_ONLY", "BUTTON", presscnt=0)
    )

    door, click, press = found.devices.values()
    assert door.key == "gtsap1:button:door"
    assert door.kind is DeviceKind.BUTTON
    assert door.name == "Tlačítko"
    assert door.roles == {
        Role.CLICK_COUNT: "door_gtsap1_button_clickcnt",
        Role.PRESS_COUNT: "door_gtsap1_button_presscnt",
        Role.NAME: "door_gtsap1_button_name",
    }
    assert set(click.roles) == {Role.CLICK_COUNT}
    assert set(press.roles) == {Role.PRESS_COUNT}


@pytest.mark.parametrize(
    ("symbol", "measurement"),
    [
        (100, Measurement.TEMPERATURE),
        (101, Measurement.HUMIDITY),
        (104, Measurement.CO2),
        (105, Measurement.CO),
        (107, Measurement.ILLUMINANCE),
        (0, None),
        (None, None),
    ],
)
def test_display_measurement_from_its_symbol(
    symbol: int | None, measurement: Measurement | None
) -> None:
    properties: dict[str, Any] = {
        "value": 612.0,
        "type": 1,
        "unit": "ppm",
        "precision": 0,
        "name": "Obývák CO2",
    }
    if symbol is not None:
        properties["symbol"] = symbol
    found, _ = discover(family("LIVING", "DISPLAY", **properties))

    display = only(found)
    prefix = "living_gtsap1_display_"
    assert display.kind is DeviceKind.DISPLAY
    assert display.measurement is measurement
    assert display.roles == {
        Role.VALUE: f"{prefix}value",
        Role.UNIT: f"{prefix}unit",
        Role.PRECISION: f"{prefix}precision",
        Role.NAME: f"{prefix}name",
    }
    assert found.consumed == {prefix + prop for prop in properties}


def test_contacts_sockets_and_relays() -> None:
    found, _ = discover(
        family("DOOR", "CONTACT", state=False, name="Vstupní dveře")
        | family("TERRACE", "SOCKET", onoff=True)
        | family("PUMP", "RELAY", onoff=False, name="Čerpadlo")
    )

    contact, socket, relay = found.devices.values()
    assert (contact.key, contact.kind, contact.name) == (
        "gtsap1:contact:door",
        DeviceKind.CONTACT,
        "Vstupní dveře",
    )
    assert contact.roles[Role.STATE] == "door_gtsap1_contact_state"
    assert (socket.key, socket.kind, socket.name) == (
        "gtsap1:socket:terrace",
        DeviceKind.SWITCH,
        "Terrace",
    )
    assert (relay.key, relay.kind) == ("gtsap1:relay:pump", DeviceKind.SWITCH)
    assert relay.roles[Role.ONOFF] == "pump_gtsap1_relay_onoff"


def test_one_base_with_two_families_gives_two_devices() -> None:
    found, _ = discover(
        family("KITCHEN", "LIGHT", onoff=True) | family("KITCHEN", "SOCKET", onoff=True)
    )
    assert list(found.devices) == ["gtsap1:light:kitchen", "gtsap1:socket:kitchen"]


# --- GTSAP1: matching ----------------------------------------------------------------


def test_families_match_ignoring_case() -> None:
    tree = {
        "living_ceiling_gtsap1_light_ONOFF": True,
        "Living_Ceiling_Gtsap1_Light_DimLevel": 20.0,
        "LIVING_CEILING_GTSAP1_LIGHT_MINTEMPK": 2700,
    }
    light = only(discover(tree)[0])

    assert light.key == "gtsap1:light:living_ceiling"
    assert light.base == "living_ceiling"  # the first spelling in the catalogue
    assert light.roles[Role.LEVEL] == "living_ceiling_gtsap1_light_dimlevel"
    assert light.roles[Role.MIN_KELVIN] == "living_ceiling_gtsap1_light_mintempk"
    assert light.light_mode is LightMode.BRIGHTNESS


def test_families_inside_program_instances_structs_and_arrays() -> None:
    tree = {
        "Main": {
            **family("LIVING", "LIGHT", onoff=True),
            # A public block instance: its members are the family's names.
            "GATE": {"GTSAP1_OPENER_current": 0, "GTSAP1_OPENER_target": 0},
            "floors": [{"HALL_GTSAP1_CONTACT_state": False}],
        },
    }
    found, _ = discover(tree)

    assert list(found.devices) == [
        "gtsap1:light:main.living",
        "gtsap1:opener:main.gate",
        "gtsap1:contact:main.floors[0].hall",
    ]
    gate = found.devices["gtsap1:opener:main.gate"]
    assert gate.base == "Main.GATE"
    assert gate.cover_class is CoverClass.GATE
    assert gate.name == "Gate"
    assert gate.roles[Role.POSITION] == "main.gate.gtsap1_opener_current"
    assert found.devices["gtsap1:contact:main.floors[0].hall"].name == "Floors 0 hall"


@pytest.mark.parametrize(
    ("tree", "skipped"),
    [
        (family("A", "LIGHT", dimlevel=10.0, name="x"), "gtsap1:light:a"),
        (family("A", "OPENER", target=10, moving=False), "gtsap1:opener:a"),
        (family("A", "THERMOSTAT", setpoint=21.0, type=2), "gtsap1:thermostat:a"),
        (family("A", "BUTTON", name="x"), "gtsap1:button:a"),
        (family("A", "DISPLAY", symbol=100, unit="°C"), "gtsap1:display:a"),
        (family("A", "CONTACT", name="x"), "gtsap1:contact:a"),
        (family("A", "SOCKET", name="x"), "gtsap1:socket:a"),
        # The essential property holds something it cannot be.
        (family("A", "LIGHT", onoff="2020-01-01"), "gtsap1:light:a"),
        (family("A", "THERMOSTAT", meastemp="warm"), "gtsap1:thermostat:a"),
        (family("A", "BUTTON", CLICKCNT=1.5), "gtsap1:button:a"),
    ],
)
def test_incomplete_families_stay_raw(tree: dict[str, Any], skipped: str) -> None:
    found, _ = discover(tree)

    assert found.devices == {}
    assert found.consumed == frozenset()
    assert list(found.skipped) == [skipped]
    assert "has no usable" in found.skipped[skipped]


def test_unknown_families_properties_and_names_stay_raw() -> None:
    tree = {
        **family("A", "LIGHT", onoff=True, flicker=True),  # unknown property
        **family("B", "SHUTTER", run=True),  # unknown family
        "GTSAP1_LIGHT_onoff": True,  # no base
        "C_GTSAP1_LIGHT_onoff_old": True,  # not a property name
        "D_GTSAP1_LIGHT_onoff": [True, False],  # an array, not a variable
    }
    found, _ = discover(tree)

    assert list(found.devices) == ["gtsap1:light:a"]
    assert found.consumed == {"a_gtsap1_light_onoff"}


def test_values_as_text_with_a_decimal_comma() -> None:
    tree = family(
        "LIVING",
        "THERMOSTAT",
        meastemp="21,5",
        setpoint=" 22,0 ",
        type="3",
        heatmode="1",
        coolmode="FALSE",
        mintemp="16,0",
        maxtemp="28,5",
    ) | family("HALL", "LIGHT", onoff="1", type="1", dimtype="0", dimlevel="40,5")
    catalogue = build_catalogue(list(tree), tree)
    found = find_devices(catalogue.points, catalogue.values)

    climate = found.devices["gtsap1:thermostat:living"]
    assert climate.climate is ClimateSupport.BOTH
    assert set(climate.roles) == {
        Role.TEMPERATURE,
        Role.SETPOINT,
        Role.MIN_TEMP,
        Role.MAX_TEMP,
        Role.HEAT_MODE,
        Role.COOL_MODE,
    }
    assert setpoint_range(climate, catalogue.points, catalogue.values) == (16.0, 28.5)
    light = found.devices["gtsap1:light:hall"]
    assert light.light_mode is LightMode.BRIGHTNESS
    assert parse_number(catalogue.values[light.roles[Role.LEVEL]]) == 40.5


def test_a_property_of_a_kind_it_cannot_hold_stays_raw() -> None:
    tree = family("HALL", "LIGHT", onoff=True, dimlevel="bright", moving=True)
    found, _ = discover(tree)

    light = only(found)
    assert light.light_mode is LightMode.ONOFF
    assert found.consumed == {"hall_gtsap1_light_onoff"}


def test_a_property_spelled_twice_is_taken_once() -> None:
    tree = {
        "Main": {
            "LIVING_GTSAP1_LIGHT_onoff": True,
            "LIVING": {"GTSAP1_LIGHT_onoff": False, "GTSAP1_LIGHT_dimlevel": 5.0},
        }
    }
    found, _ = discover(tree)

    light = only(found)
    assert light.roles[Role.ONOFF] == "main.living_gtsap1_light_onoff"
    assert light.roles[Role.LEVEL] == "main.living.gtsap1_light_dimlevel"
    assert "main.living.gtsap1_light_onoff" not in found.consumed


@pytest.mark.parametrize(
    ("name", "expected"),
    [
        ("  Obývák   strop ", "Obývák strop"),
        ("", "Living ceiling"),
        ("42", "Living ceiling"),
        ("0,5", "Living ceiling"),
        (7, "Living ceiling"),  # a number, not a name
    ],
)
def test_names_come_from_the_name_variable_else_the_base(
    name: Any, expected: str
) -> None:
    found, _ = discover(family("LIVING_CEILING", "LIGHT", onoff=True, name=name))
    assert only(found).name == expected


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
        DeviceSource.STRUCT,
        "Rooms.kidsRoom.thermostat",
        "Kids room thermostat",
    )
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


# --- Composition ---------------------------------------------------------------------


COMPOSE_TREE = {
    "Heating": {
        "livingTemp": api(21.8, readOnly=True, title="Living room temperature"),
        "livingSetpoint": api(21.5, minValue=15.0, maxValue=28.0, units="°C"),
        "boilerOn": api(True),
        "burning": api(True, readOnly=True),
        "label": api("x"),
    },
    "blinds": [api(100, minValue=0.0, maxValue=100.0), api(0, readOnly=True)],
    "doorbellCount": 1287,
    "dimmer": 40.0,
}


@pytest.fixture
def points() -> Mapping[str, Point]:
    return build_catalogue(list(COMPOSE_TREE), COMPOSE_TREE).points


def test_compose_a_thermostat(points: Mapping[str, Point]) -> None:
    climate = compose(
        "climate",
        {
            "temperature": "Heating.livingTemp",  # a path in any case will do
            "setpoint": "heating.livingsetpoint",
            "heat_mode": "heating.boileron",
            "heating": "heating.burning",
        },
        points,
        ident="01JABCDEF",
        name="  Living   room ",
    )

    assert climate.key == "composed:01JABCDEF"
    assert (climate.kind, climate.source, climate.name) == (
        DeviceKind.CLIMATE,
        DeviceSource.COMPOSED,
        "Living room",
    )
    assert climate.base == "Heating.livingTemp"
    assert climate.roles == {
        Role.TEMPERATURE: "heating.livingtemp",
        Role.SETPOINT: "heating.livingsetpoint",
        Role.HEAT_MODE: "heating.boileron",
        Role.HEATING: "heating.burning",
    }
    assert climate.climate is ClimateSupport.HEATING
    assert setpoint_range(climate, points, {}) == (15.0, 28.0)


def test_compose_the_other_kinds(points: Mapping[str, Point]) -> None:
    cover = compose(
        DeviceKind.COVER, {"position": "blinds[0]"}, points, ident="c", name="Brána"
    )
    light = compose("light", {"level": "dimmer"}, points, ident="l")
    switch = compose("switch", {"onoff": "heating.boileron"}, points, ident="s")
    button = compose("button", {"click_count": "doorbellcount"}, points, ident="b")

    assert cover.cover_class is CoverClass.GATE
    assert cover.roles == {Role.POSITION: "blinds[0]", Role.TARGET: "blinds[0]"}
    assert light.light_mode is LightMode.BRIGHTNESS
    assert light.roles == {Role.LEVEL: "dimmer", Role.TARGET_LEVEL: "dimmer"}
    assert light.name == "Dimmer"
    assert switch.roles == {Role.ONOFF: "heating.boileron"}
    assert button.roles == {Role.CLICK_COUNT: "doorbellcount"}
    onoff = compose("light", {"onoff": "heating.boileron"}, points, ident="o")
    assert onoff.light_mode is LightMode.ONOFF


@pytest.mark.parametrize(
    ("kind", "roles", "problem", "role", "message"),
    [
        ("contact", {"state": "heating.burning"}, "not_composable", None, "cannot"),
        ("fridge", {}, "not_composable", None, "cannot"),
        (
            "climate",
            {"humidity": "heating.livingtemp"},
            "unknown_role",
            "humidity",
            "no role",
        ),
        ("cover", {"rgb": "dimmer"}, "unknown_role", "rgb", "no role"),
        (
            "climate",
            {"temperature": "heating.livingtemp"},
            "missing_role",
            "setpoint",
            "needs setpoint",
        ),
        (
            "cover",
            {"moving": "heating.burning"},
            "missing_role",
            "position",
            "needs position",
        ),
        ("light", {}, "missing_role", "level", "needs level or onoff"),
        ("button", {}, "missing_role", "click_count", "click_count or press_count"),
        (
            "light",
            {"onoff": "heating.boileron", "color_temp": "heating.livingsetpoint"},
            "missing_role",
            "level",
            "color_temp needs level",
        ),
        (
            "cover",
            {"position": "Rooms.gone"},
            "missing_point",
            "position",
            "no longer exists",
        ),
        (
            "cover",
            {"position": "heating.label"},
            "wrong_kind",
            "position",
            "holds a string",
        ),
        ("switch", {"onoff": "dimmer"}, "wrong_kind", "onoff", "holds a real"),
        (
            "button",
            {"press_count": "dimmer"},
            "wrong_kind",
            "press_count",
            "expected integer",
        ),
        (
            "climate",
            {"temperature": "heating.livingtemp", "setpoint": "heating.livingtemp"},
            "not_writable",
            "setpoint",
            "read-only",
        ),
        ("switch", {"onoff": "heating.burning"}, "not_writable", "onoff", "read-only"),
        # The position is written when no target is chosen: it is named.
        ("cover", {"position": "blinds[1]"}, "not_writable", "position", "read-only"),
        (
            "cover",
            {"position": "blinds[1]", "target": "blinds[1]"},
            "not_writable",
            "target",
            "read-only",
        ),
    ],
)
def test_composition_errors_name_the_role_and_the_problem(
    points: Mapping[str, Point],
    *,
    kind: str,
    roles: dict[str, str],
    problem: str,
    role: str | None,
    message: str,
) -> None:
    with pytest.raises(CompositionError, match=message) as caught:
        compose(kind, roles, points, ident="x")

    assert caught.value.problem == CompositionProblem(problem)
    assert caught.value.role == role
    assert caught.value.kind == kind


def test_a_composition_needs_an_ident(points: Mapping[str, Point]) -> None:
    with pytest.raises(ValueError, match="ident"):
        compose("switch", {"onoff": "heating.boileron"}, points, ident="")


def test_composition_describes_roles_and_fitting_points(
    points: Mapping[str, Point],
) -> None:
    climate = COMPOSITIONS[DeviceKind.CLIMATE]
    required = [spec.role for spec in climate.roles if spec.required]
    assert required == [Role.TEMPERATURE, Role.SETPOINT]
    assert climate.role(Role.SETPOINT).written  # type: ignore[union-attr]
    assert climate.role(Role.RGB) is None
    assert set(COMPOSITIONS) == {
        DeviceKind.LIGHT,
        DeviceKind.COVER,
        DeviceKind.CLIMATE,
        DeviceKind.BUTTON,
        DeviceKind.SWITCH,
    }

    def paths(kind: DeviceKind, role: Role) -> list[str]:
        return [point.path for point in fitting_points(kind, role, points)]

    # Temperatures only: a title or a unit says so (see below for the rest).
    assert paths(DeviceKind.CLIMATE, Role.TEMPERATURE) == [
        "Heating.livingTemp",
        "Heating.livingSetpoint",
    ]
    # Written roles offer no read-only T_ApiObject.
    assert paths(DeviceKind.CLIMATE, Role.SETPOINT) == ["Heating.livingSetpoint"]
    assert paths(DeviceKind.CLIMATE, Role.HEATING) == [
        "Heating.boilerOn",
        "Heating.burning",
    ]
    assert paths(DeviceKind.BUTTON, Role.CLICK_COUNT) == [
        "blinds[0]",
        "blinds[1]",
        "doorbellCount",
    ]
    with pytest.raises(ValueError, match="no role"):
        fitting_points(DeviceKind.SWITCH, Role.LEVEL, points)


FITTING_TREE = {
    "Rooms": {
        "livingTemp": api(21.8, readOnly=True, title="Living room", units="°C"),
        "livingHumidity": api(
            44.0, readOnly=True, title="Living room humidity", units="%"
        ),
        "outsideTemp": api(4.5, readOnly=True, title="Outside", units="degF"),
        "curveShift": api(0.0, title="Heating curve shift", units="K"),
        "power": api(1432.0, readOnly=True, title="House power", units="W"),
        "setpoint": api(21.0, title="Požadovaná teplota"),
        "blindPosition": api(100, readOnly=True, title="Blind position", units="%"),
        "wardrobeColour": api(4000, title="Wardrobe colour temperature"),
    },
    "OBYVAK_GTSAP1_THERMOSTAT_meastemp": 21.8,
    "LOZNICE_GTSAP1_LIGHT_colortemp": 2700,
    "LOZNICE_GTSAP1_LIGHT_dimlevel": 35.0,
    "doorbellCount": 1287,
}


@pytest.mark.parametrize(
    ("kind", "role", "expected"),
    [
        (
            DeviceKind.CLIMATE,
            Role.TEMPERATURE,
            [
                "Rooms.livingTemp",
                "Rooms.outsideTemp",
                "Rooms.setpoint",
                "OBYVAK_GTSAP1_THERMOSTAT_meastemp",
            ],
        ),
        (
            DeviceKind.COVER,
            Role.POSITION,
            [
                "Rooms.blindPosition",
                "LOZNICE_GTSAP1_LIGHT_dimlevel",
                "doorbellCount",
            ],
        ),
    ],
)
def test_fitting_points_say_nothing_else(
    kind: DeviceKind, role: Role, expected: list[str]
) -> None:
    """A role lists what its unit, title or path do not contradict.

    A thermostat's temperature: °C or °F, or a title or path saying temperature
    (not a humidity, a power, a blind's position or a light's colour
    temperature); a position: a share in % that is no humidity, or a number
    without a unit saying no temperature.
    """
    points = build_catalogue(list(FITTING_TREE), FITTING_TREE).points

    assert [point.path for point in fitting_points(kind, role, points)] == expected


def test_writability(points: Mapping[str, Point]) -> None:
    assert is_writable(points["heating.livingsetpoint"])
    assert not is_writable(points["heating.livingtemp"])
    assert is_writable(points["dimmer"])  # plain: not known to be read-only


def test_composition_survives_downloads_while_its_points_exist() -> None:
    before = build_catalogue(list(COMPOSE_TREE), COMPOSE_TREE).points
    roles = {"temperature": "heating.livingtemp", "setpoint": "heating.livingsetpoint"}
    first = compose("climate", roles, before, ident="sub1", name="Living")

    changed = {
        "Heating": {
            "livingSetpoint": api(21.5, minValue=15.0, maxValue=26.0),
            "livingTemp": api(22.0, readOnly=True),
            "newThing": api(1.0),
        }
    }
    after = build_catalogue(list(changed), changed).points
    second = compose("climate", roles, after, ident="sub1", name="Living")
    assert second.key == first.key
    assert second.roles == first.roles
    assert setpoint_range(second, after, {}) == (15.0, 26.0)

    del changed["Heating"]["livingTemp"]
    gone = build_catalogue(list(changed), changed).points
    with pytest.raises(CompositionError) as caught:
        compose("climate", roles, gone, ident="sub1", name="Living")
    assert caught.value.problem is CompositionProblem.MISSING_POINT
    assert (caught.value.role, caught.value.point) == (
        "temperature",
        "heating.livingtemp",
    )


# --- The model ------------------------------------------------------------------------


def test_devices_are_frozen_and_their_features_fit_their_kind() -> None:
    device = TypedDevice(
        key="composed:x",
        kind=DeviceKind.SWITCH,
        source=DeviceSource.COMPOSED,
        base="a",
        name="A",
        roles={"onoff": "a"},  # type: ignore[dict-item]
    )
    assert device.roles == {Role.ONOFF: "a"}
    assert device.points == {"a"}
    assert device.point(Role.ONOFF) == "a"
    assert device.point(Role.LEVEL) is None
    with pytest.raises(TypeError):
        device.roles[Role.ONOFF] = "b"  # type: ignore[index]

    common: dict[str, Any] = {
        "key": "k",
        "source": DeviceSource.COMPOSED,
        "base": "a",
        "name": "A",
        "roles": {},
    }
    with pytest.raises(ValueError, match="needs light_mode"):
        TypedDevice(kind=DeviceKind.LIGHT, **common)
    with pytest.raises(ValueError, match="has no cover_class"):
        TypedDevice(
            kind=DeviceKind.LIGHT,
            light_mode=LightMode.ONOFF,
            cover_class=CoverClass.GATE,
            **common,
        )
    with pytest.raises(ValueError, match="needs climate"):
        TypedDevice(kind=DeviceKind.CLIMATE, **common)
    with pytest.raises(ValueError, match="has no measurement"):
        TypedDevice(kind=DeviceKind.SWITCH, measurement=Measurement.CO2, **common)


def test_catalogue_of_kind() -> None:
    found, _ = discover(
        family("A", "LIGHT", onoff=True)
        | family("B", "SOCKET", onoff=True)
        | family("C", "LIGHT", onoff=True)
    )
    assert [d.key for d in found.of_kind(DeviceKind.LIGHT)] == [
        "gtsap1:light:a",
        "gtsap1:light:c",
    ]
    assert found.of_kind(DeviceKind.CLIMATE) == ()


# --- Values and names -----------------------------------------------------------------


@pytest.mark.parametrize(
    ("raw", "number"),
    [
        (21, 21.0),
        (21.5, 21.5),
        ("21,5", 21.5),
        (" -3.25 ", -3.25),
        ("1000", 1000.0),
        ("", None),
        ("warm", None),
        ("nan", None),
        (float("inf"), None),
        (True, None),
        (None, None),
        ([1], None),
    ],
)
def test_parse_number(raw: Any, number: float | None) -> None:
    assert parse_number(raw) == number


@pytest.mark.parametrize(
    ("raw", "integer"),
    [(3, 3), (3.0, 3), ("3", 3), ("3,0", 3), ("3,5", None), (False, None), ("x", None)],
)
def test_parse_int(raw: Any, integer: int | None) -> None:
    assert parse_int(raw) == integer


@pytest.mark.parametrize(
    ("raw", "flag"),
    [
        (True, True),
        (False, False),
        (1, True),
        (0, False),
        (1.0, True),
        (2, None),
        ("1", True),
        (" TRUE ", True),
        ("on", True),
        ("0", False),
        ("false", False),
        ("Off", False),
        ("yes", None),
        (None, None),
    ],
)
def test_parse_bool(raw: Any, flag: bool | None) -> None:
    assert parse_bool(raw) is flag


def _point(kind: ValueKind) -> Point:
    return tecomat_point("p", kind)


@pytest.mark.parametrize(
    ("kind", "value", "written"),
    [
        (ValueKind.BOOL, True, True),
        (ValueKind.BOOL, 0, False),
        (ValueKind.INTEGER, True, 1),
        (ValueKind.INTEGER, 49.6, 50),
        (ValueKind.REAL, 21, 21.0),
        (ValueKind.STRING, True, "1"),
        (ValueKind.STRING, False, "0"),
        (ValueKind.STRING, 22.0, "22"),
        (ValueKind.STRING, 21.5, "21.5"),
    ],
)
def test_value_for_point(kind: ValueKind, value: Any, written: Any) -> None:
    result = value_for_point(_point(kind), value)
    assert result == written
    assert type(result) is type(written)


def test_an_inverted_flag_is_written_as_its_opposite() -> None:
    """A composed device's role on an inverted point writes what its entity shows."""
    inverted = replace(_point(ValueKind.BOOL), invert=True)
    assert value_for_point(inverted, True) is False
    assert value_for_point(inverted, 0) is True


def test_value_for_point_refuses_dates() -> None:
    with pytest.raises(ValueError, match="not a flag or a number"):
        value_for_point(_point(ValueKind.DATE), 1)


@pytest.mark.parametrize(
    ("base", "name"),
    [
        ("LIVING_CEILING", "Living ceiling"),
        ("livingCeiling", "Living ceiling"),
        ("Main.KITCHEN_ISLAND", "Kitchen island"),
        ("Rooms.kidsRoom.blind", "Kids room blind"),
        ("Main.blinds[2]", "Blinds 2"),
        ("blinds[2]", "Blinds 2"),
        ("LIGHT2", "Light 2"),
    ],
)
def test_name_from_base(base: str, name: str) -> None:
    assert name_from_base(base) == name


@pytest.mark.parametrize(
    ("texts", "gate"),
    [
        (("Vjezdová brána",), True),
        (("BRANA",), True),
        (("Garážová vrata",), True),
        (("Front gate",), True),
        (("Obývák žaluzie", "LIVING"), False),
        (("Roleta", "GARAZ_VRATA"), True),
    ],
)
def test_gate_names(texts: tuple[str, ...], gate: bool) -> None:
    assert is_gate_name(*texts) is gate


def test_kelvin_range_from_gtsap1_values_else_defaults() -> None:
    tree = family(
        "A", "LIGHT", onoff=True, colortemp=3000, minTempK="2200", maxTempK=5000
    )
    tree |= family(
        "B", "LIGHT", onoff=True, colortemp=3000, minTempK=6000, maxTempK=5000
    )
    catalogue = build_catalogue(list(tree), tree)
    found = find_devices(catalogue.points, catalogue.values)

    a, b = found.devices.values()
    assert kelvin_range(a, catalogue.points, catalogue.values) == (2200, 5000)
    assert kelvin_range(b, catalogue.points, catalogue.values) == (2000, 6500)


# --- Button counters ------------------------------------------------------------------


@pytest.mark.parametrize(
    ("previous", "current", "events"),
    [
        (None, 17, 0),  # start-up: nothing to compare with
        (17, None, 0),  # the counter vanished
        (17, 17, 0),
        (17, 18, 1),
        (17, 21, 4),  # increments missed between polls
        (17, 17 + 32, 32),
        (17, 17 + 33, 0),  # no one clicks that fast: the program set it
        (65535, 0, 1),  # UINT wraps
        (65533, 2, 5),
        (4294967295, 0, 1),  # UDINT wraps
        (4294967290, 3, 9),
        (70000, 70003, 3),  # a UDINT above UINT's range
        (32767, -32768, 1),  # INT wraps
        (-1, 0, 1),
        (17, 0, 0),  # reset
        (500, 3, 0),  # reset to a small value
        (65535, 40000, 0),  # a drop that is not a wrap
        (100000, 2, 0),  # a UDINT reset
    ],
)
def test_counter_events(previous: int | None, current: int | None, events: int) -> None:
    assert counter_events(previous, current) == events


def test_counter_events_with_a_known_width_and_limit() -> None:
    assert counter_events(255, 0, bits=8) == 1
    assert counter_events(255, 0) == 0  # 8 bits are not guessed: a reset
    assert counter_events(0, 100, max_step=100) == 100
    assert counter_events(0, 100) == 0


def test_counter_bits() -> None:
    assert counter_bits(0, 65535) == 16
    assert counter_bits(-32768, 10) == 16
    assert counter_bits(65536) == 32
    assert counter_bits(-32769) == 32
