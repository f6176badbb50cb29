"""Buttons: the clicks and long presses a PLC counts, as events.

The PLC counts short clicks (``click_count``) and long presses
(``press_count``); each increment is one event. Increments missed between two
readings come together; a counter's first reading (start-up, a new program)
means nothing, and neither does a reset (see :func:`~..devices.counter_events`).
"""

from collections.abc import Mapping
from enum import StrEnum
from types import MappingProxyType
from typing import Any, Final

from ..devices import Role, TypedDevice, counter_events
from ..models import Point
from .base import Appliance


class ButtonEvent(StrEnum):
    """What a button did: a short click or a long press."""

    CLICK = "click"
    LONG_PRESS = "long_press"


COUNTER_EVENTS: Final[Mapping[Role, ButtonEvent]] = MappingProxyType(
    {Role.CLICK_COUNT: ButtonEvent.CLICK, Role.PRESS_COUNT: ButtonEvent.LONG_PRESS}
)
"""The event each counter counts, in the order events of one reading come."""


class Button(Appliance):
    """A button's counters, and the events between two readings of them.

    It keeps each counter's last reading (None: none yet, or unknown): the
    first reading, and a reading after an unknown one, means no event.
    """

    __slots__ = ("_counters", "events")

    def __init__(self, device: TypedDevice, points: Mapping[str, Point]) -> None:
        """Fix the events it has, by the counters it has; nothing read yet."""
        super().__init__(device, points)
        self._counters: dict[Role, int | None] = {
            role: None for role in COUNTER_EVENTS if role in device.roles
        }
        self.events: tuple[ButtonEvent, ...] = tuple(
            COUNTER_EVENTS[role] for role in self._counters
        )

    @property
    def counters(self) -> Mapping[Role, int | None]:
        """Each counter's last reading (None: none yet, or unknown)."""
        return MappingProxyType(self._counters)

    def state(self, values: Mapping[str, Any]) -> dict[Role, int | None]:
        """Read each counter (None: unknown, or not an integer)."""
        return {role: self.value(role).integer(values) for role in self._counters}

    def update(self, values: Mapping[str, Any]) -> list[ButtonEvent]:
        """Return the events since the last reading, and keep this one.

        One event per increment of each counter, clicks before long presses.
        """
        events: list[ButtonEvent] = []
        for role, current in self.state(values).items():
            events += [COUNTER_EVENTS[role]] * counter_events(
                self._counters[role], current
            )
            self._counters[role] = current
        return events
