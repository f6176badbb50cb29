"""What a user set moving (a blind on its way, a light going to its level), followed there.

A device's points are read every second until it arrives; the steady poll keeps
its interval. The reads take turns with the coordinator's polls (one lock), and
each shows what it read the way a pushed snapshot is shown: at once, the next
poll staying where it is.
"""

from collections.abc import Callable, Collection
from dataclasses import dataclass
from datetime import datetime
from typing import TYPE_CHECKING, Final

from homeassistant.core import CALLBACK_TYPE, callback
from homeassistant.helpers.event import async_call_later

from .const import LOGGER
from .data import PlcData
from .pyplc import PlcError

if TYPE_CHECKING:
    import asyncio

    from .coordinator import PlcCoordinator

MOTION_INTERVAL: Final = 1.0
"""Seconds between two reads of what a user set moving (a blind on its way)."""
MOTION_READS: Final = 120
"""Reads of one motion at most (two minutes): one that never arrives is left to the polls."""

type Arrival = Callable[[PlcData], bool]
"""Whether a device got where it was sent, by the data shown."""


@dataclass(slots=True)
class _Motion:
    """A device a user set moving: the points to read, and when it is there."""

    points: frozenset[str]
    arrived: Arrival
    reads_left: int


class MotionFollower:
    """Reads the points of what a user set moving every second until it arrives.

    It belongs to a coordinator, and reads through its source now (one
    swapped in when push is switched on or off is read from then on), taking
    turns with its polls (``reading``), and shows what it read as a snapshot
    pushed between polls is shown (``async_show``).
    """

    def __init__(self, coordinator: "PlcCoordinator") -> None:
        """Follow nothing yet."""
        self._coordinator = coordinator
        self._motions: dict[str, _Motion] = {}
        self._motion_timer: CALLBACK_TYPE | None = None
        self._motion_read: asyncio.Task[None] | None = None

    @callback
    def async_follow(self, key: str, points: Collection[str], arrived: Arrival) -> None:
        """Read a device's points every second until it arrives (a blind on its way).

        ``key`` names the device (following it again starts over), ``points`` are
        read, ``arrived`` says from the data shown whether it is there. The steady
        poll keeps its interval: only these points are read, at most
        ``MOTION_READS`` times, never two reads at once nor beside a poll; what a
        source pushes is not read at all. A device already there is not followed.
        """
        if arrived(self._coordinator.data):
            self._motions.pop(key, None)
            return
        self._motions[key] = _Motion(frozenset(points), arrived, MOTION_READS)
        if self._motion_timer is None and self._motion_read is None:
            self._schedule_motion_read()

    @callback
    def _schedule_motion_read(self) -> None:
        self._motion_timer = async_call_later(
            self._coordinator.hass, MOTION_INTERVAL, self._async_motion_due
        )

    @callback
    def _async_motion_due(self, _now: datetime) -> None:
        self._motion_timer = None
        coordinator = self._coordinator
        self._motion_read = coordinator.config_entry.async_create_background_task(
            coordinator.hass, self._async_read_motions(), f"{coordinator.name} motion"
        )

    async def _async_read_motions(self) -> None:
        """Read what moves, show it, and read again in a second while it moves."""
        coordinator = self._coordinator
        points = frozenset[str]().union(*(m.points for m in self._motions.values()))
        try:
            async with coordinator.reading:
                snapshot = await coordinator.source.read_points(points)
        except PlcError as err:
            # The polls tell what became of the PLC.
            LOGGER.debug("Reading %s while they move failed: %s", sorted(points), err)
            self._motions.clear()
        else:
            if snapshot is not None:
                coordinator.async_show(snapshot)
        data = coordinator.data
        for key, motion in list(self._motions.items()):
            motion.reads_left -= 1
            if motion.reads_left <= 0 or motion.arrived(data):
                del self._motions[key]
        self._motion_read = None
        if self._motions:
            self._schedule_motion_read()

    @callback
    def async_stop(self) -> None:
        """Follow nothing more (the entry unloads)."""
        self._motions.clear()
        if self._motion_timer is not None:
            self._motion_timer()
            self._motion_timer = None
