"""Displays: the value as a number, the unit text and the precision asked for."""

from typing import Any

import pytest

from custom_components.tecoapi.pyplc.core.appliances import MAX_PRECISION, Display
from custom_components.tecoapi.pyplc.core.devices import (
    READINGS,
    DeviceKind,
    Measurement,
    Readings,
    Role,
)
from custom_components.tecoapi.pyplc.core.models import ValueKind
from tests.pyplc.core.appliances.catalogue import INT, LENIENT, REAL, TEXT, make_device


def _display(
    *extra: Role,
    kind: ValueKind = REAL,
    readings: Readings = READINGS,
    measurement: Measurement | None = None,
) -> Display:
    roles = {Role.VALUE: ("value", kind)}
    if Role.UNIT in extra:
        roles[Role.UNIT] = ("unit", TEXT)
    if Role.PRECISION in extra:
        roles[Role.PRECISION] = ("precision", INT)
    device, points = make_device(
        DeviceKind.DISPLAY, roles, readings=readings, measurement=measurement
    )
    return Display(device, points)


@pytest.mark.parametrize(
    ("value", "number"),
    [
        (21.5, 21.5),
        (-3.25, -3.25),
        (0, 0.0),
        (21, 21.0),
        (True, None),
        (float("nan"), None),
        (float("inf"), None),
        ("21,5", None),
        (None, None),
    ],
)
def test_the_value_as_a_number(value: Any, number: float | None) -> None:
    state = _display().state({"value": value})
    assert state == number
    assert type(state) is type(number)


def test_an_unread_display_is_unknown() -> None:
    assert _display().state({}) is None


@pytest.mark.parametrize(
    ("text", "number"),
    [
        ("21,5", 21.5),
        (" 21.5 ", 21.5),
        ("-0,5", -0.5),
        ("7", 7.0),
        ("abc", None),
        ("", None),
        ("inf", None),
    ],
)
def test_a_text_value_with_lenient_readings(text: str, number: float | None) -> None:
    display = _display(kind=TEXT, readings=LENIENT)
    assert display.state({"value": text}) == number


@pytest.mark.parametrize(
    ("text", "unit"),
    [
        ("°C", "°C"),
        ("  kWh ", "kWh"),
        ("m³/h", "m³/h"),
        ("", None),
        ("   ", None),
        (5, None),
        (None, None),
    ],
)
def test_the_unit_text(text: Any, unit: str | None) -> None:
    assert _display(Role.UNIT).unit({"unit": text}) == unit


def test_no_unit_without_its_point_or_its_value() -> None:
    assert _display().unit({"unit": "°C"}) is None
    assert _display(Role.UNIT).unit({}) is None


def test_what_it_measures_is_the_devices() -> None:
    assert _display().measurement is None
    measured = _display(Role.UNIT, measurement=Measurement.HUMIDITY)
    assert measured.measurement is Measurement.HUMIDITY
    # The unit text is still read; which one is shown is the caller's choice.
    assert measured.unit({"unit": "%"}) == "%"


@pytest.mark.parametrize(
    ("value", "precision"),
    [
        (-1, None),
        (0, 0),
        (1, 1),
        (6, 6),
        (7, None),
        (2.0, 2),
        (2.5, None),
        (True, None),
        ("3", None),
        (None, None),
    ],
)
def test_the_precision_asked_for(value: Any, precision: int | None) -> None:
    shown = _display(Role.PRECISION).precision({"precision": value})
    assert shown == precision
    assert type(shown) is type(precision)


def test_a_text_precision_with_lenient_readings() -> None:
    display = _display(Role.PRECISION, readings=LENIENT)
    assert display.precision({"precision": " 3 "}) == 3
    assert display.precision({"precision": "2,5"}) is None
    assert display.precision({"precision": "9"}) is None
    assert display.precision({"precision": "6"}) == MAX_PRECISION


def test_no_precision_without_its_point_or_its_value() -> None:
    assert _display().precision({"precision": 2}) is None
    assert _display(Role.PRECISION).precision({}) is None
