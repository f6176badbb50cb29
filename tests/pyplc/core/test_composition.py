"""Typed devices the user composes: the rules per kind, fitting points, errors."""

from collections.abc import Mapping

import pytest

from custom_components.tecoapi.pyplc import Point
from custom_components.tecoapi.pyplc.core.composition import (
    COMPOSITIONS,
    CompositionError,
    CompositionProblem,
    compose,
    fitting_points,
    is_writable,
)
from custom_components.tecoapi.pyplc.core.devices import (
    COMPOSED,
    ClimateSupport,
    CoverClass,
    DeviceKind,
    LightMode,
    Role,
    setpoint_range,
)
from custom_components.tecoapi.pyplc.tecomat.tecoapi.catalogue import build_catalogue
from tests.pyplc.tecomat.typed_programs import api

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
        COMPOSED,
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
