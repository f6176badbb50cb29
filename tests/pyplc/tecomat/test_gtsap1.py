"""GTSAP1 block families: what each family becomes, matching, lenient readings."""

from dataclasses import replace
from typing import Any

import pytest

from custom_components.tecoapi.pyplc import Point, ValueKind
from custom_components.tecoapi.pyplc.core.devices import (
    ClimateSupport,
    CoverClass,
    DeviceKind,
    LightMode,
    Measurement,
    Role,
    SwitchClass,
    find_devices,
    kelvin_range,
    name_from_base,
    setpoint_range,
)
from custom_components.tecoapi.pyplc.tecomat.conventions import RECOGNISERS
from custom_components.tecoapi.pyplc.tecomat.gtsap1 import LENIENT
from custom_components.tecoapi.pyplc.tecomat.points import tecomat_point
from custom_components.tecoapi.pyplc.tecomat.tecoapi.catalogue import build_catalogue
from tests.pyplc.tecomat.typed_programs import discover, family, only

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
        "gtsap1",
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
    # A socket is an outlet; a relay says nothing more.
    assert (socket.switch_class, relay.switch_class) == (SwitchClass.OUTLET, None)


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
    found = find_devices(catalogue.points, catalogue.values, RECOGNISERS)

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
    # A family's devices read their values as leniently as they were found.
    assert light.readings is climate.readings is LENIENT
    assert light.readings.number(catalogue.values[light.roles[Role.LEVEL]]) == 40.5


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


# --- Lenient readings -------------------------------------------------------------


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
def test_lenient_numbers(raw: Any, number: float | None) -> None:
    assert LENIENT.number(raw) == number


@pytest.mark.parametrize(
    ("raw", "integer"),
    [(3, 3), (3.0, 3), ("3", 3), ("3,0", 3), ("3,5", None), (False, None), ("x", None)],
)
def test_lenient_integers(raw: Any, integer: int | None) -> None:
    assert LENIENT.integer(raw) == integer


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
def test_lenient_flags(raw: Any, flag: bool | None) -> None:
    assert LENIENT.flag(raw) is flag


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
def test_lenient_writes(kind: ValueKind, value: Any, written: Any) -> None:
    result = LENIENT.written(_point(kind), value)
    assert result == written
    assert type(result) is type(written)


def test_an_inverted_flag_is_written_as_its_opposite() -> None:
    """A composed device's role on an inverted point writes what its entity shows."""
    inverted = replace(_point(ValueKind.BOOL), invert=True)
    assert LENIENT.written(inverted, True) is False
    assert LENIENT.written(inverted, 0) is True


def test_lenient_writes_refuse_dates() -> None:
    with pytest.raises(ValueError, match="not a flag or a number"):
        LENIENT.written(_point(ValueKind.DATE), 1)


def test_kelvin_range_from_gtsap1_values_else_defaults() -> None:
    tree = family(
        "A", "LIGHT", onoff=True, colortemp=3000, minTempK="2200", maxTempK=5000
    )
    tree |= family(
        "B", "LIGHT", onoff=True, colortemp=3000, minTempK=6000, maxTempK=5000
    )
    catalogue = build_catalogue(list(tree), tree)
    found = find_devices(catalogue.points, catalogue.values, RECOGNISERS)

    a, b = found.devices.values()
    assert kelvin_range(a, catalogue.points, catalogue.values) == (2200, 5000)
    assert kelvin_range(b, catalogue.points, catalogue.values) == (2000, 6500)
