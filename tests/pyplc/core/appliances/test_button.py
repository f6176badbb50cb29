"""Buttons: the counters' readings, and the events between two of them."""

from typing import Any

import pytest

from custom_components.tecoapi.pyplc.core.appliances import (
    COUNTER_EVENTS,
    Button,
    ButtonEvent,
)
from custom_components.tecoapi.pyplc.core.devices import (
    MAX_COUNTER_STEP,
    READINGS,
    DeviceKind,
    Readings,
    Role,
)
from tests.pyplc.core.appliances.catalogue import INT, LENIENT, TEXT, make_device

CLICK, LONG = ButtonEvent.CLICK, ButtonEvent.LONG_PRESS


def _button(
    *counters: Role, readings: Readings = READINGS, text: bool = False
) -> Button:
    keys = {Role.CLICK_COUNT: "clicks", Role.PRESS_COUNT: "presses"}
    device, points = make_device(
        DeviceKind.BUTTON,
        {role: (keys[role], TEXT if text else INT) for role in counters},
        readings=readings,
    )
    return Button(device, points)


def _both() -> Button:
    return _button(Role.PRESS_COUNT, Role.CLICK_COUNT)


def test_the_events_it_has_follow_its_counters() -> None:
    assert _both().events == (CLICK, LONG)
    assert _button(Role.PRESS_COUNT).events == (LONG,)
    assert _button(Role.CLICK_COUNT).events == (CLICK,)
    assert _button().events == ()
    assert [event.value for event in _both().events] == ["click", "long_press"]
    assert dict(COUNTER_EVENTS) == {
        Role.CLICK_COUNT: ButtonEvent.CLICK,
        Role.PRESS_COUNT: ButtonEvent.LONG_PRESS,
    }


def test_the_first_reading_means_no_event() -> None:
    button = _both()
    assert dict(button.counters) == {Role.CLICK_COUNT: None, Role.PRESS_COUNT: None}
    assert button.update({"clicks": 5, "presses": 9}) == []
    assert dict(button.counters) == {Role.CLICK_COUNT: 5, Role.PRESS_COUNT: 9}


def test_each_increment_is_one_event_clicks_first() -> None:
    button = _both()
    button.update({"clicks": 5, "presses": 9})
    assert button.update({"clicks": 7, "presses": 10}) == [CLICK, CLICK, LONG]
    assert button.update({"clicks": 7, "presses": 10}) == []
    assert button.update({"clicks": 7, "presses": 11}) == [LONG]
    assert dict(button.counters) == {Role.CLICK_COUNT: 7, Role.PRESS_COUNT: 11}


def test_the_state_reads_each_counter() -> None:
    button = _both()
    assert button.state({"clicks": 3.0, "presses": 2.5}) == {
        Role.CLICK_COUNT: 3,
        Role.PRESS_COUNT: None,
    }
    assert button.state({}) == {Role.CLICK_COUNT: None, Role.PRESS_COUNT: None}
    # Reading is not updating: the last reading stays.
    assert dict(button.counters) == {Role.CLICK_COUNT: None, Role.PRESS_COUNT: None}


@pytest.mark.parametrize(
    ("previous", "current", "events"),
    [
        (65535, 0, 1),  # a 16-bit wrap
        (65534, 1, 3),
        (2**32 - 1, 0, 1),  # a 32-bit wrap
        (-1, 0, 1),  # INT
        (10, 10 + MAX_COUNTER_STEP, MAX_COUNTER_STEP),
        (10, 11 + MAX_COUNTER_STEP, 0),  # too many: a counter set
        (10, 0, 0),  # a reset
        (10, 9, 0),
    ],
)
def test_wraps_resets_and_the_largest_step(
    previous: int, current: int, events: int
) -> None:
    button = _button(Role.CLICK_COUNT)
    button.update({"clicks": previous})
    assert button.update({"clicks": current}) == [CLICK] * events
    assert button.counters[Role.CLICK_COUNT] == current


@pytest.mark.parametrize("unknown", [None, "x", 1.5, True])
def test_an_unknown_reading_breaks_the_count(unknown: Any) -> None:
    button = _button(Role.CLICK_COUNT)
    button.update({"clicks": 1})
    assert button.update({"clicks": unknown}) == []
    assert button.counters[Role.CLICK_COUNT] is None
    # What came while it was unknown is not known: no event for it.
    assert button.update({"clicks": 4}) == []
    assert button.update({"clicks": 5}) == [CLICK]


def test_a_counter_gone_from_the_values_breaks_the_count() -> None:
    button = _button(Role.CLICK_COUNT)
    button.update({"clicks": 1})
    assert button.update({}) == []
    assert button.update({"clicks": 2}) == []


def test_text_counters_with_lenient_readings() -> None:
    button = _button(Role.CLICK_COUNT, readings=LENIENT, text=True)
    button.update({"clicks": " 4 "})
    assert button.update({"clicks": "6"}) == [CLICK, CLICK]
    assert button.update({"clicks": "six"}) == []
    plain = _button(Role.CLICK_COUNT, text=True)
    plain.update({"clicks": "4"})
    assert plain.update({"clicks": "6"}) == []


def test_the_counters_shown_are_read_only() -> None:
    button = _button(Role.CLICK_COUNT)
    with pytest.raises(TypeError):
        button.counters[Role.CLICK_COUNT] = 3  # type: ignore[index]
