"""Covers: position and heading, moves by the target, arrival."""

from typing import TYPE_CHECKING, Any

import pytest

from custom_components.tecoapi.pyplc.core.appliances import (
    Cover,
    CoverState,
    percent,
)
from custom_components.tecoapi.pyplc.core.devices import (
    CoverClass,
    DeviceKind,
    Role,
)
from tests.pyplc.core.appliances.catalogue import (
    FLAG,
    INT,
    REAL,
    make_device,
)

if TYPE_CHECKING:
    from custom_components.tecoapi.pyplc import ValueKind


def _cover(*, target: bool = True, moving: bool = False) -> Cover:
    roles: dict[Role, tuple[str, ValueKind]] = {Role.POSITION: ("position", REAL)}
    if target:
        roles[Role.TARGET] = ("target", REAL)
    if moving:
        roles[Role.MOVING] = ("moving", FLAG)
    device, points = make_device(
        DeviceKind.COVER, roles, cover_class=CoverClass.SHUTTER
    )
    return Cover(device, points)


@pytest.mark.parametrize(
    ("values", "state"),
    [
        ({"position": 30.0, "target": 30.4}, CoverState(30, None, None, False, False)),
        ({"position": 30.0, "target": 31.0}, CoverState(30, 31, None, True, False)),
        ({"position": 30.0, "target": 29.0}, CoverState(30, 29, None, False, True)),
        ({"position": 0.0, "target": 100.0}, CoverState(0, 100, None, True, False)),
        ({"position": 100.0, "target": 0.0}, CoverState(100, 0, None, False, True)),
        ({"position": -3.0, "target": 150.0}, CoverState(0, 100, None, True, False)),
        ({"position": 30.0}, CoverState(30, None, None, False, False)),
        ({"target": 30.0}, CoverState(None, None, None, False, False)),
    ],
)
def test_a_covers_state(values: dict[str, Any], state: CoverState) -> None:
    assert _cover().state(values) == state


def test_closed_at_zero() -> None:
    cover = _cover()
    assert cover.state({"position": 0.4}).is_closed is True
    assert cover.state({"position": 0.6}).is_closed is False
    assert cover.state({}).is_closed is None


def test_a_cover_moves_by_its_target_and_stops_where_it_is() -> None:
    cover = _cover(moving=True)
    assert cover.can_stop
    assert cover.move_to(30) == {"target": 30.0}
    assert cover.open() == {"target": 100.0}
    assert cover.close() == {"target": 0.0}
    assert cover.stop({"position": 42.4, "target": 80.0}) == {"target": 42.0}
    assert cover.stop({"target": 80.0}) == {}
    assert cover.moves({"target": 30.0})
    assert not cover.moves({})
    assert cover.motion == {"position", "target", "moving"}
    assert cover.state({"moving": True}).moving is True


def test_a_cover_without_a_target_moves_by_its_position() -> None:
    cover = _cover(target=False)
    assert not cover.can_stop
    assert cover.move_to(30) == {"position": 30.0}
    # Stopped all the same, where it is: no target to differ.
    assert cover.stop({"position": 12.0}) == {"position": 12.0}
    assert not cover.moves({"position": 30.0})
    assert cover.motion == frozenset()
    assert cover.arrived({"position": 0.0})
    assert cover.state({"position": 10.0}) == CoverState(10, None, None, False, False)


def test_a_cover_arrives() -> None:
    cover = _cover(moving=True)
    assert not cover.arrived({"position": 10.0, "target": 30.0})
    assert cover.arrived({"position": 29.6, "target": 30.4})
    assert not cover.arrived({"position": 30.0, "target": 30.0, "moving": True})
    assert cover.arrived({"position": 30.0, "target": 30.0, "moving": False})
    assert cover.arrived({"position": None, "target": 30.0})
    assert cover.arrived({"position": 10.0})


def test_a_gate() -> None:
    device, points = make_device(
        DeviceKind.COVER, {Role.POSITION: ("p", INT)}, cover_class=CoverClass.GATE
    )
    gate = Cover(device, points)
    assert gate.gate
    assert gate.move_to(49.6) == {"p": 50}
    assert not _cover().gate


@pytest.mark.parametrize(
    ("value", "shown"), [(-1, 0), (0.4, 0), (99.5, 100), (101, 100)]
)
def test_percent(value: float, shown: int) -> None:
    assert percent(value) == shown
