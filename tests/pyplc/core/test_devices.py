"""The typed-device model: devices, readings, names, recognisers, button counters."""

from collections.abc import Mapping
from dataclasses import replace
from typing import Any, override

import pytest

from custom_components.tecoapi.pyplc import DataType, Point, ValueKind
from custom_components.tecoapi.pyplc.core.devices import (
    COMPOSED,
    READINGS,
    CoverClass,
    DeviceKind,
    LightMode,
    Measurement,
    Readings,
    Recognised,
    Recogniser,
    Role,
    SwitchClass,
    TypedDevice,
    counter_bits,
    counter_events,
    find_devices,
    is_gate_name,
    name_from_base,
)

# --- The model ------------------------------------------------------------------------


def test_devices_are_frozen_and_their_features_fit_their_kind() -> None:
    device = TypedDevice(
        key="composed:x",
        kind=DeviceKind.SWITCH,
        source=COMPOSED,
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
        "source": COMPOSED,
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


# --- Readings -------------------------------------------------------------------------


def _point(kind: ValueKind) -> Point:
    return Point(key="p", path="p", address="p", type=DataType(kind=kind))


@pytest.mark.parametrize(
    ("raw", "number", "integer", "flag"),
    [
        (21, 21.0, 21, None),
        (21.5, 21.5, None, None),
        (3.0, 3.0, 3, None),
        (1, 1.0, 1, True),
        (0.0, 0.0, 0, False),
        (True, None, None, True),
        (False, None, None, False),
        (float("nan"), None, None, None),
        (float("inf"), None, None, None),
        # Text is no number nor flag: a convention that keeps them in text
        # gives its devices readings of its own.
        ("21", None, None, None),
        ("21,5", None, None, None),
        ("1", None, None, None),
        ("on", None, None, None),
        (None, None, None, None),
    ],
)
def test_readings_read_what_a_kind_holds(
    raw: Any, number: float | None, integer: int | None, flag: bool | None
) -> None:
    assert READINGS.number(raw) == number
    assert READINGS.integer(raw) == integer
    assert READINGS.flag(raw) is flag


@pytest.mark.parametrize(
    ("kind", "value", "written"),
    [
        (ValueKind.BOOL, True, True),
        (ValueKind.BOOL, 0, False),
        (ValueKind.INTEGER, True, 1),
        (ValueKind.INTEGER, 49.6, 50),
        (ValueKind.REAL, 21, 21.0),
    ],
)
def test_readings_write_in_the_points_kind(
    kind: ValueKind, value: Any, written: Any
) -> None:
    result = READINGS.written(_point(kind), value)
    assert result == written
    assert type(result) is type(written)
    inverted = replace(_point(ValueKind.BOOL), invert=True)
    assert READINGS.written(inverted, True) is False


@pytest.mark.parametrize("kind", [ValueKind.STRING, ValueKind.DATE])
def test_readings_write_no_text_nor_dates(kind: ValueKind) -> None:
    with pytest.raises(ValueError, match="not a flag or a number"):
        READINGS.written(_point(kind), 1)


def test_a_device_reads_with_its_readings_but_compares_without() -> None:
    class Text(Readings):
        @override
        def number(self, value: Any) -> float | None:
            return float(value) if isinstance(value, str) else super().number(value)

    common: dict[str, Any] = {
        "key": "x:a",
        "kind": DeviceKind.DISPLAY,
        "source": "x",
        "base": "a",
        "name": "A",
        "roles": {Role.VALUE: "a"},
    }
    plain, texts = TypedDevice(**common), TypedDevice(readings=Text(), **common)
    assert plain.readings is READINGS
    assert (plain.readings.number("2"), texts.readings.number("2")) == (None, 2.0)
    assert plain == texts
    assert "readings" not in repr(texts)


# --- Recognisers ----------------------------------------------------------------------


def _flag(key: str) -> Point:
    return Point(key=key, path=key, address=key, type=DataType(kind=ValueKind.BOOL))


def _switches(name: str, suffix: str, seen: list[frozenset[str]]) -> Recogniser:
    """A convention: each point ending in ``suffix`` is a switch; ``seen`` the taken."""

    def find(
        points: Mapping[str, Point], values: Mapping[str, Any], taken: frozenset[str]
    ) -> Recognised:
        seen.append(taken)
        devices = tuple(
            TypedDevice(
                key=f"{name}:{key}",
                kind=DeviceKind.SWITCH,
                source=name,
                base=key,
                name=key,
                roles={Role.ONOFF: key},
            )
            for key in points
            if key.endswith(suffix) and key not in taken and values.get(key) is not None
        )
        skipped = {
            f"{name}:{key}": "no value"
            for key in points
            if key.endswith(suffix) and values.get(key) is None
        }
        return Recognised(devices=devices, skipped=skipped)

    return Recogniser(name=name, find=find)


def test_find_devices_runs_the_recognisers_in_order() -> None:
    """Each among the points those before it took; devices in the catalogue's order."""
    points = {key: _flag(key) for key in ("a_y", "b_x", "c_y", "d_y")}
    values = {"a_y": False, "b_x": True, "c_y": True}
    seen: list[frozenset[str]] = []
    first, second = _switches("one", "x", seen), _switches("two", "", seen)

    found = find_devices(points, values, (first, second))

    assert list(found.devices) == ["two:a_y", "one:b_x", "two:c_y"]
    assert seen == [frozenset(), frozenset({"b_x"})]
    assert found.consumed == {"a_y", "b_x", "c_y"}
    assert found.skipped == {"two:d_y": "no value"}
    assert found.devices["one:b_x"].source == "one"


def test_without_recognisers_nothing_is_a_device() -> None:
    points = {"b_x": _flag("b_x")}
    found = find_devices(points, {"b_x": True})
    assert (dict(found.devices), found.consumed, dict(found.skipped)) == ({}, set(), {})


def test_only_a_switch_has_a_switch_class() -> None:
    common: dict[str, Any] = {"key": "x:a", "source": "x", "base": "a", "name": "A"}
    outlet = TypedDevice(
        kind=DeviceKind.SWITCH,
        roles={Role.ONOFF: "a"},
        switch_class=SwitchClass.OUTLET,
        **common,
    )
    assert outlet.switch_class is SwitchClass.OUTLET
    assert not outlet.composed
    with pytest.raises(ValueError, match="has no switch_class"):
        TypedDevice(
            kind=DeviceKind.CONTACT,
            roles={Role.STATE: "a"},
            switch_class=SwitchClass.OUTLET,
            **common,
        )
