"""Lights: typed state, the last level, one ordered batch per command."""

from typing import TYPE_CHECKING

import pytest

from custom_components.tecoapi.pyplc.core.appliances import (
    Light,
    LightState,
    brightness_level,
    level_brightness,
    rgb_packed,
    rgb_split,
)
from custom_components.tecoapi.pyplc.core.devices import (
    DeviceKind,
    LightMode,
    Role,
)
from tests.pyplc.core.appliances.catalogue import (
    FLAG,
    INT,
    LENIENT,
    REAL,
    TEXT,
    make_device,
    make_point,
)

if TYPE_CHECKING:
    from custom_components.tecoapi.pyplc import ValueKind


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
    device, points = make_device(DeviceKind.LIGHT, roles, light_mode=mode)
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
    device, points = make_device(
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
    device, points = make_device(
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
    device, points = make_device(
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
    device, points = make_device(
        DeviceKind.LIGHT,
        {Role.LEVEL: ("level", REAL), Role.COLOR_TEMP: ("kelvin", INT)},
        light_mode=LightMode.COLOR_TEMP,
    )
    light = Light(device, points)
    assert light.kelvin_range(points, {}) == (2000, 6500)
    ranged = {"kelvin": make_point("kelvin", INT, minimum=2700, maximum=5000)}
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
    device, points = make_device(
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
