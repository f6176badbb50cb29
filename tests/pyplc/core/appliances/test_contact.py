"""Contacts: the ``state`` flag, inverted where the point says."""

from typing import Any

import pytest

from custom_components.tecoapi.pyplc.core.appliances import Contact
from custom_components.tecoapi.pyplc.core.devices import (
    READINGS,
    DeviceKind,
    Readings,
    Role,
)
from custom_components.tecoapi.pyplc.core.models import ValueKind
from tests.pyplc.core.appliances.catalogue import FLAG, LENIENT, TEXT, make_device


def _contact(
    kind: ValueKind = FLAG, *, invert: bool = False, readings: Readings = READINGS
) -> Contact:
    device, points = make_device(
        DeviceKind.CONTACT,
        {Role.STATE: ("state", kind)},
        readings=readings,
        invert=frozenset({"state"}) if invert else frozenset(),
    )
    return Contact(device, points)


@pytest.mark.parametrize(
    ("value", "plain", "inverted"),
    [
        (True, True, False),
        (False, False, True),
        (1, True, False),
        (0.0, False, True),
        (3, None, None),
        (float("nan"), None, None),
        ("1", None, None),
        (None, None, None),
    ],
)
def test_the_state_flag(value: Any, plain: bool | None, inverted: bool | None) -> None:
    assert _contact().state({"state": value}) is plain
    assert _contact(invert=True).state({"state": value}) is inverted


def test_an_unread_contact_is_unknown() -> None:
    assert _contact().state({}) is None


@pytest.mark.parametrize(
    ("text", "state"),
    [("true", True), (" 1 ", True), ("OFF", False), ("0", False), ("open", None)],
)
def test_a_text_contact_with_lenient_readings(text: str, state: bool | None) -> None:
    assert _contact(TEXT, readings=LENIENT).state({"state": text}) is state


def test_an_inverted_text_contact_reads_its_opposite() -> None:
    assert _contact(TEXT, invert=True, readings=LENIENT).state({"state": "on"}) is False


def test_a_contact_without_its_point_reads_the_value_as_it_is() -> None:
    contact = _contact(invert=True)
    contact.rebind({})
    assert contact.state({"state": True}) is True
    assert contact.motion == frozenset()
