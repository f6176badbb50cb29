"""What a user set moving (a blind on its way, a light going to its level), followed there.

A device's points are read every second until it arrives; the steady poll keeps
its interval. The reads take turns with the coordinator's polls (one lock), and
each shows what it read the way a pushed snapshot is shown: at once, the next
poll staying where it is.
"""

import asyncio
from collections.abc import Callable, Collection
from dataclasses import dataclass
from datetime import datetime
from typing import Any, Final

from homeassistant.config_entries import ConfigEntry
from homeassistant.core import CALLBACK_TYPE, HomeAssistant, callback
from homeassistant.helpers.event import async_call_later

from .const import LOGGER
from .data import PlcData
from .pyplc import PlcError
from .pyplc.core.source import PlcSource, Snapshot

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

    It belongs to a coordinator, and reaches its source and its data through
    the functions it is given: ``source`` is its source now (one swapped in
    when push is switched on or off is read from then on), ``show`` shows a
    snapshot read, ``shown`` is the data shown. ``reading`` is the lock the
    coordinator's polls hold.
    """

    def __init__(
        self,
        hass: HomeAssistant,
        entry: ConfigEntry[Any],
        *,
        name: str,
        reading: asyncio.Lock,
        source: Callable[[], PlcSource],
        show: Callable[[Snapshot], None],
        shown: Callable[[], PlcData],
    ) -> None:
        """Follow nothing yet; ``name`` names the background task of a read."""
        self._hass = hass
        self._entry = entry
        self._name = name
        self._reading = reading
        self._source = source
        self._show = show
        self._shown = shown
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
        if arrived(self._shown()):
            self._motions.pop(key, None)
            return
        self._motions[key] = _Motion(frozenset(points), arrived, MOTION_READS)
        if self._motion_timer is None and self._motion_read is None:
            self._schedule_motion_read()

    @callback
    def _schedule_motion_read(self) -> None:
        self._motion_timer = async_call_later(
            self._hass, MOTION_INTERVAL, self._async_motion_due
        )

    @callback
    def _async_motion_due(self, _now: datetime) -> None:
        self._motion_timer = None
        self._motion_read = self._entry.async_create_background_task(
            self._hass, self._async_read_motions(), f"{self._name} motion"
        )

    async def _async_read_motions(self) -> None:
        """Read what moves, show it, and read again in a second while it moves."""
        points = frozenset[str]().union(*(m.points for m in self._motions.values()))
        try:
            async with self._reading:
                snapshot = await self._source().read_points(points)
        except PlcError as err:
            # The polls tell what became of the PLC.
            LOGGER.debug("Reading %s while they move failed: %s", sorted(points), err)
            self._motions.clear()
        else:
            if snapshot is not None:
                self._show(snapshot)
        data = self._shown()
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
