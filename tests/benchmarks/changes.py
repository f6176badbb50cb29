"""Changing PLC values between polls, as a running PLC program would."""

from collections.abc import Iterable, Sequence
from dataclasses import dataclass
import math
import random
from typing import Any, Final

from custom_components.tecoapi.pyplc import Point, ValueKind
from custom_components.tecoapi.pyplc.tecomat.points import value_path
from tests.simulator import Simulator

CHANGEABLE_KINDS: Final = frozenset(
    {ValueKind.BOOL, ValueKind.INTEGER, ValueKind.REAL, ValueKind.STRING}
)
_TEXTS: Final = ("Idle", "Running", "Check filter", "Away", "OK")


def changed_count(points: int, percent: float) -> int:
    """How many of `points` change for a percentage (at least one unless 0 %)."""
    if percent <= 0:
        return 0
    return min(points, max(1, round(points * percent / 100)))


def changes_in_poll(points: int, percent: float, index: int) -> int:
    """How many of `points` change before poll `index` so that `percent` hold on average.

    1 % of 50 points is half a value per poll: one value changes before every
    second poll. Rounding each poll up to one value would change 2 %.
    """
    rate = min(points, points * max(0.0, percent) / 100)
    return math.floor((index + 1) * rate + 1e-9) - math.floor(index * rate + 1e-9)


def candidates(point: Point, current: Any) -> list[Any]:
    """Values different from `current` that fit the point (its range, if it has one)."""
    values: list[Any]
    if point.kind is ValueKind.BOOL:
        values = [not current]
    elif point.kind is ValueKind.INTEGER:
        values = [current + 1, current - 1]
    elif point.kind is ValueKind.REAL:
        values = [round(current + 0.5, 1), round(current - 0.5, 1)]
    else:
        values = [text for text in _TEXTS if text != current]
    attributes = point.attributes
    if (
        attributes is not None
        and attributes.minimum is not None
        and attributes.maximum is not None
        and point.kind in (ValueKind.INTEGER, ValueKind.REAL)
    ):
        low, high = attributes.minimum, attributes.maximum
        values = [v for v in values if low <= v <= high]
    return [value for value in values if value != current]


class ValueChanger:
    """Changes the values of a share of points in a simulated PLC.

    Points are taken in a shuffled round robin, so consecutive polls change
    different points; `change` says which points it wrote and which changed.
    """

    def __init__(self, points: Iterable[Point], *, seed: int = 0) -> None:
        """Take the points whose values can be changed (bool, numbers, strings)."""
        self._points: Sequence[Point] = sorted(
            (point for point in points if point.kind in CHANGEABLE_KINDS),
            key=lambda point: point.key,
        )
        self._order = list(range(len(self._points)))
        random.Random(seed).shuffle(self._order)
        self._next = 0

    @property
    def changeable(self) -> int:
        """How many points this changer can change."""
        return len(self._points)

    def change(self, simulator: Simulator, count: int) -> "Change":
        """Give `count` points new values in the PLC (call on the simulator's loop).

        The PLC's program may move other values with them (its links: a light's
        level follows its target); those count as changed too.
        """
        before = {
            point.key: simulator.get_value(value_path(point)) for point in self._points
        }
        written: list[str] = []
        attempts = 0
        while len(written) < count and attempts < len(self._points):
            point = self._points[self._order[self._next]]
            self._next = (self._next + 1) % len(self._order)
            attempts += 1
            if point.key in written:
                continue
            if set_new_value(simulator, point):
                written.append(point.key)
        changed = frozenset(
            point.key
            for point in self._points
            if simulator.get_value(value_path(point)) != before[point.key]
        )
        return Change(tuple(written), changed)


@dataclass(frozen=True, slots=True)
class Change:
    """What one :meth:`ValueChanger.change` did in the PLC."""

    written: tuple[str, ...]
    """The points given new values, in order."""
    changed: frozenset[str]
    """Every point whose value differs afterwards: the written ones, and those the
    program's links moved with them."""


def set_new_value(simulator: Simulator, point: Point) -> bool:
    """Give one point a new value the PLC accepts; whether it found one."""
    current = simulator.get_value(value_path(point))
    for value in candidates(point, current):
        try:
            simulator.set_value(value_path(point), value)
        except ValueError:
            continue
        return True
    return False
