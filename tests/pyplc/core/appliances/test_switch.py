"""Switches: on/off read through the ``onoff`` transcoder, one write per command."""

from typing import Any

import pytest

from custom_components.tecoapi.pyplc.core.appliances import MissingPointError, Switch
from custom_components.tecoapi.pyplc.core.devices import (
    READINGS,
    DeviceKind,
    Readings,
    Role,
    SwitchClass,
)
from custom_components.tecoapi.pyplc.core.models import ValueKind
from tests.pyplc.core.appliances.catalogue import (
    FLAG,
    INT,
    LENIENT,
    TEXT,
    make_device,
    make_point,
)


def _switch(
    kind: ValueKind = FLAG,
    *,
    invert: bool = False,
    readings: Readings = READINGS,
    switch_class: SwitchClass | None = None,
) -> Switch:
    device, points = make_device(
        DeviceKind.SWITCH,
        {Role.ONOFF: ("on", kind)},
        readings=readings,
        invert=frozenset({"on"}) if invert else frozenset(),
        switch_class=switch_class,
    )
    return Switch(device, points)


@pytest.mark.parametrize(
    ("value", "is_on"),
    [
        (True, True),
        (False, False),
        (1, True),
        (0, False),
        (1.0, True),
        (2, None),
        (-1, None),
        ("1", None),
        ("on", None),
        (None, None),
    ],
)
def test_the_state_is_the_onoff_flag(value: Any, is_on: bool | None) -> None:
    assert _switch().state({"on": value}) is is_on


def test_an_unread_switch_is_unknown() -> None:
    assert _switch().state({}) is None
    assert _switch().state({"other": True}) is None


@pytest.mark.parametrize(
    ("value", "is_on"), [(True, False), (False, True), (1, False), (0, True), (2, None)]
)
def test_an_inverted_switch_reads_its_opposite(value: Any, is_on: bool | None) -> None:
    assert _switch(invert=True).state({"on": value}) is is_on


def test_turning_writes_one_flag() -> None:
    switch = _switch()
    assert switch.turn_on() == {"on": True}
    assert switch.turn_off() == {"on": False}
    assert switch.turn_on()["on"] is True
    assert switch.turn_off()["on"] is False
    inverted = _switch(invert=True)
    assert inverted.turn_on()["on"] is False
    assert inverted.turn_off()["on"] is True


def test_each_command_is_a_new_batch() -> None:
    switch = _switch()
    on = switch.turn_on()
    on["extra"] = 1
    assert switch.turn_on() == {"on": True}


def test_an_integer_onoff_is_written_as_an_integer() -> None:
    switch = _switch(INT)
    on, off = switch.turn_on()["on"], switch.turn_off()["on"]
    assert (on, type(on)) == (1, int)
    assert (off, type(off)) == (0, int)


def test_a_text_switch_with_lenient_readings() -> None:
    switch = _switch(TEXT, readings=LENIENT)
    assert switch.state({"on": " ON "}) is True
    assert switch.state({"on": "off"}) is False
    assert switch.state({"on": "0"}) is False
    assert switch.state({"on": "maybe"}) is None
    assert switch.turn_on() == {"on": "1"}
    assert switch.turn_off() == {"on": "0"}
    # The same text with the plain readings is no flag.
    assert _switch(TEXT).state({"on": "on"}) is None


@pytest.mark.parametrize(
    ("switch_class", "outlet"),
    [(SwitchClass.OUTLET, True), (SwitchClass.SWITCH, False), (None, False)],
)
def test_a_socket_is_an_outlet(switch_class: SwitchClass | None, outlet: bool) -> None:
    assert _switch(switch_class=switch_class).outlet is outlet


def test_a_switch_follows_its_catalogue_and_never_moves() -> None:
    switch = _switch()
    switch.rebind({"on": make_point("on", FLAG, invert=True)})
    assert switch.state({"on": True}) is False
    assert switch.turn_on() == {"on": False}
    assert switch.motion == frozenset()
    assert switch.moves(switch.turn_on()) is False
    assert switch.arrived({}) is True


def test_a_switch_whose_point_is_gone_is_refused() -> None:
    switch = _switch()
    switch.rebind({})
    assert switch.state({"on": True}) is True  # read as it is
    with pytest.raises(MissingPointError) as err:
        switch.turn_off()
    assert err.value.key == "on"
