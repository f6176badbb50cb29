"""Covers: blinds, shutters and gates with a position, 0 % closed to 100 % open."""

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from ..devices import CoverClass, Role, TypedDevice
from ..models import Point
from .base import FULL, Appliance, Batch


def percent(value: float) -> int:
    """Return a position or target as the whole percent shown (0-100)."""
    return round(min(max(value, 0.0), FULL))


@dataclass(frozen=True, slots=True)
class CoverState:
    """Where a cover is (0 closed to 100 open) and where it is on its way to.

    ``target`` is the target it is heading for (None: it is where its target
    says, or it has none); ``moving`` the ``moving`` flag (None: none, unknown).
    """

    position: int | None
    target: int | None
    moving: bool | None
    opening: bool
    closing: bool

    @property
    def is_closed(self) -> bool | None:
        """Closed at position 0 (None: unknown)."""
        return None if self.position is None else self.position == 0


class Cover(Appliance):
    """A blind, shutter or gate with a position, 0 % closed to 100 % open.

    It moves by writing its target (its position, when it has no target of its
    own) and stops when its current position is written as the target. It is
    opening or closing while its target differs from its position: at once
    after a move is asked for, before the PLC has set it moving.
    """

    __slots__ = ("can_stop", "gate", "target")

    def __init__(self, device: TypedDevice, points: Mapping[str, Point]) -> None:
        """Fix the role moved, and whether it has a target apart from its position."""
        super().__init__(device, points)
        roles = device.roles
        self.gate = device.cover_class is CoverClass.GATE
        self.target = Role.TARGET if Role.TARGET in roles else Role.POSITION
        self.can_stop = (
            roles.get(Role.TARGET, roles[Role.POSITION]) != (roles[Role.POSITION])
        )

    def state(self, values: Mapping[str, Any]) -> CoverState:
        """Read where it is and where it is heading from the values."""
        number = self.number(Role.POSITION, values)
        position = None if number is None else percent(number)
        target = self.number(Role.TARGET, values) if self.can_stop else None
        heading = (
            None
            if target is None or position is None or percent(target) == position
            else percent(target)
        )
        return CoverState(
            position=position,
            target=heading,
            moving=self.flag(Role.MOVING, values),
            opening=heading is not None and heading > (position or 0),
            closing=heading is not None and heading < (position or 0),
        )

    def move_to(self, position: float) -> Batch:
        """Go to a position (%)."""
        return self.write({}, self.target, position)

    def open(self) -> Batch:
        """Go to 100 %."""
        return self.move_to(FULL)

    def close(self) -> Batch:
        """Go to 0 %."""
        return self.move_to(0)

    def stop(self, values: Mapping[str, Any]) -> Batch:
        """Stop where it is: its current position becomes the target (unknown: nothing)."""
        position = self.state(values).position
        return {} if position is None else self.move_to(position)

    @property
    def motion(self) -> frozenset[str]:
        """Its position, target and ``moving``, for a cover moved by a target."""
        if not self.can_stop:
            return frozenset()
        return self._keys(Role.POSITION, Role.TARGET, Role.MOVING)

    def moves(self, batch: Mapping[str, Any]) -> bool:
        """Whether the batch sets the target of a cover moved by one."""
        return self.can_stop and self.value(self.target).key in batch

    def arrived(self, values: Mapping[str, Any]) -> bool:
        """Whether it is where its target says and ``moving`` (if any) says still.

        Unknown values count as there: nothing is left to follow.
        """
        position = self.number(Role.POSITION, values)
        target = self.number(Role.TARGET, values)
        if not self.can_stop or position is None or target is None:
            return True
        moving = self.flag(Role.MOVING, values)
        return percent(position) == percent(target) and moving is not True
