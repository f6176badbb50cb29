"""Appliances' base: role transcoders, and an appliance bound to a catalogue."""

from dataclasses import replace

import pytest

from custom_components.tecoapi.pyplc.core.appliances import (
    Appliance,
    MissingPointError,
    RoleValue,
)
from custom_components.tecoapi.pyplc.core.devices import (
    READINGS,
    DeviceKind,
    Role,
)
from tests.pyplc.core.appliances.catalogue import (
    FLAG,
    LENIENT,
    TEXT,
    make_device,
    make_point,
)


def test_a_role_value_reads_through_the_readings_and_inverts_flags() -> None:
    plain = RoleValue("a", make_point("a", FLAG), READINGS)
    inverted = RoleValue("a", make_point("a", FLAG, invert=True), READINGS)
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
    text = RoleValue("t", make_point("t", TEXT), LENIENT)
    assert text.number({"t": " 21,5 "}) == 21.5
    assert text.flag({"t": "on"}) is True
    assert text.flag({"t": "maybe"}) is None
    assert text.encode(True) == "1"
    assert text.encode(21.5) == "21.5"
    assert RoleValue("t", make_point("t", TEXT), READINGS).number({"t": "21"}) is None


def test_an_appliance_follows_a_new_catalogue() -> None:
    device, points = make_device(DeviceKind.SWITCH, {Role.ONOFF: ("on", FLAG)})
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
