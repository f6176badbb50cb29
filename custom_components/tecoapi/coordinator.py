"""The coordinator: polls a PLC source and hands the entities what it found.

It depends on the transport-neutral seam only: the source decides what to read
when, the coordinator turns its snapshots, polled or pushed, into ``data``. Its
helpers do the rest: the write path (``writer``), the options applied in place
(``applier``), the repair issues (``issues``) and what moves (``motion``).
"""

import asyncio
from collections.abc import Mapping
import logging
from typing import Any, Final

from homeassistant.config_entries import ConfigEntry
from homeassistant.core import HomeAssistant, callback

from .applier import OptionsApplier
from .connection import descriptor_of
from .const import DOMAIN, LOGGER
from .data import PlcData, updated_data
from .helpers import update_error
from .issues import IssueFollower
from .listeners import KeyedCoordinator
from .motion import MotionFollower
from .options import PlcOptions
from .pyplc import PlcAuthenticationError, PlcError
from .pyplc.core.descriptor import Capability
from .pyplc.core.models import PointOverride
from .pyplc.core.pointmap import PointMap
from .pyplc.core.source import PlcSource, Snapshot
from .reconcile import async_follow_catalogue
from .writer import PlcWriter

type PlcConfigEntry = ConfigEntry[PlcCoordinator]

RECOVERED: Final = "Fetching %s data recovered"
"""The line the data update coordinator logs when a poll succeeds after a failure."""


class _OutageFilter(logging.Filter):
    """Keep the data update coordinator's own outage lines at debug level.

    The coordinator logs an outage and the return once, in the words of the
    device's system (the gateway …), as Home Assistant's quality scale asks;
    the base class would log them again. Unexpected exceptions stay errors.
    """

    def filter(self, record: logging.LogRecord) -> bool:
        if (record.levelno == logging.ERROR and record.exc_info is None) or (
            record.levelno == logging.INFO and record.msg == RECOVERED
        ):
            record.levelno, record.levelname = logging.DEBUG, "DEBUG"
        return True


POLL_LOGGER = LOGGER.getChild("poll")
POLL_LOGGER.addFilter(_OutageFilter())


class PlcCoordinator(KeyedCoordinator):
    """Polls one PLC every ``scan_interval`` through its source.

    Only points that have an entity listening (enabled in the registry) are
    polled (``polled_keys``). Entities read their values from ``data`` and write
    their state only when their key is in ``data.changed`` or their availability
    changed; an entity is told of an update only then (``listeners``).
    """

    config_entry: PlcConfigEntry

    def __init__(
        self,
        hass: HomeAssistant,
        entry: PlcConfigEntry,
        source: PlcSource,
        *,
        point_map: PointMap | None = None,
        overrides: Mapping[str, PointOverride] | None = None,
    ) -> None:
        """Poll ``source`` for the entry; nothing is requested yet."""
        self.source = source
        self.descriptor = descriptor_of(entry.data)
        """What the entry's source declares (its capabilities)."""
        self.applier = OptionsApplier(
            self, entry, point_map=point_map, overrides=overrides
        )
        """What the entry asks for (options, points), applied in place."""
        self.writer = PlcWriter(self)
        """The one write path of every entity and action."""
        self.issues = IssueFollower(hass, entry)
        """The entry's repair issues, raised and cleared as updates find the device."""
        self.device_name = ""
        """The PLC device's name (set once the PLC is known, see ``device_info``)."""
        self.group_device_names: dict[str, str] = {}
        """Each group device's name, by group key, chosen once (see ``device_info``)."""
        self.reading = asyncio.Lock()
        """Polls, reads of what moves and following take turns (shown in order)."""
        super().__init__(
            hass,
            POLL_LOGGER,
            config_entry=entry,
            name=f"{DOMAIN} {entry.title}",
            update_interval=self.options.scan_interval,
        )
        self.motion = MotionFollower(self)
        """What a user set moving, read every second until it arrives."""
        # The source may be swapped (push switched on or off): hear the current one.
        self._unsubscribe_pushed = source.subscribe(self.async_show)

    @property
    def options(self) -> PlcOptions:
        """The entry's options in force."""
        return self.applier.options

    @property
    def point_map(self) -> PointMap | None:
        """The user's points, for a source that takes a map."""
        return self.applier.point_map

    async def _async_update_data(self) -> PlcData:
        """Read what the source says is due, and follow the PLC's mode and program."""
        polled = self.polled_keys if self.data is not None else frozenset()
        source = self.source
        try:
            async with self.reading:
                snapshot = await source.poll(polled)
        except PlcError as err:
            if self.source is not source:
                # Swapped and closed while it was read: the new one answers.
                return await self._async_update_data()
            self._log_failure(err)
            self.issues.async_poll_failed(err)
            raise update_error(err) from err
        self.issues.async_poll_succeeded()
        previous = self.data
        if previous is not None and not self.last_update_success:
            LOGGER.info("The %s is available again", self._named)
        data = self.updated(snapshot)
        await self.issues.async_polled(previous, data)
        if previous is not None and snapshot.program_changed:
            self._log_new_catalogue(previous, data)
            async_follow_catalogue(self.hass, self.config_entry, previous, data)
        return data

    def updated(self, snapshot: Snapshot) -> PlcData:
        """Return the data after a snapshot (a new catalogue is selected from anew)."""
        data = updated_data(self.data, snapshot, self.applier.select)
        self.issues.async_shown(data)
        return data

    @property
    def _named(self) -> str:
        """The device as log lines name it, in its system's words: ``gateway FP-I4C · …``."""
        return f"{self.descriptor.noun} {self.config_entry.title}"

    def _log_new_catalogue(self, previous: PlcData, data: PlcData) -> None:
        """Log a new program (or, for a device without one, other points told)."""
        if Capability.PROGRAM in self.descriptor.capabilities:
            LOGGER.info(
                "The %s runs a new program (%s, stamp %s): its variables were read again",
                self._named,
                data.info.program_name,
                data.info.program_stamp,
            )
        else:
            LOGGER.info(
                "The %s tells other points now (%d, %d before): they were read again",
                self._named,
                len(data.catalogue.points),
                len(previous.catalogue.points),
            )

    def _log_failure(self, err: PlcError) -> None:
        """Log a failed poll once when the device goes away, at debug while away."""
        named = self._named
        shown: PlcData | None = self.data
        if shown is None:
            # Setting up: Home Assistant logs the retry or the reauthentication.
            LOGGER.debug("Cannot set up the %s: %s", named, err)
        elif not self.last_update_success:
            LOGGER.debug("The %s is still unavailable: %s", named, err)
        elif isinstance(err, PlcAuthenticationError):
            LOGGER.warning(
                "The %s rejected the stored credentials; sign in again", named
            )
        else:
            LOGGER.info("The %s is unavailable: %s", named, err)

    @callback
    def async_show(self, snapshot: Snapshot) -> None:
        """Show a snapshot read between polls (pushed, or of what moves) at once.

        The next poll stays where it is.
        """
        data: PlcData | None = self.data
        if data is not None and snapshot.catalogue is data.catalogue:
            self.data = self.updated(snapshot)
            self.async_update_listeners()

    @callback
    def async_start_following(self) -> None:
        """Have the source follow the polled points now, not from the next poll.

        Called once the entities listen and whenever the source is swapped: with
        push, their changes are pushed from then on. It runs in the background,
        so a push server still connecting holds up neither setup nor options.
        """
        self.config_entry.async_create_background_task(
            self.hass, self._async_follow_polled(), f"{DOMAIN} follow the polled points"
        )

    async def _async_follow_polled(self) -> None:
        async with self.reading:
            await self.source.follow(self.polled_keys)

    async def async_use_source(self, source: PlcSource) -> None:
        """Reach the PLC through a new source; close the old (``applier``).

        Its first poll discovers the program again; the entities keep their values.
        """
        old, self.source = self.source, source
        self._unsubscribe_pushed()
        self._unsubscribe_pushed = source.subscribe(self.async_show)
        await old.close()
        await self.async_refresh()
        # The entities listen already: the new source follows their points now.
        self.async_start_following()

    async def async_write(self, key: str, value: Any) -> None:
        """Write a value to a point (``writer.PlcWriter.async_write``)."""
        await self.writer.async_write(key, value)

    async def async_write_many(self, values: Mapping[str, Any]) -> None:
        """Write one command's batch (``writer.PlcWriter.async_write_many``)."""
        await self.writer.async_write_many(values)

    async def async_replace_overrides(
        self, overrides: Mapping[str, PointOverride]
    ) -> None:
        """Take the user's overrides in place (``applier.OptionsApplier``)."""
        await self.applier.async_replace_overrides(overrides)

    async def async_shutdown(self) -> None:
        """Stop polling and following what moves, and release the source unheard."""
        self.motion.async_stop()
        self._unsubscribe_pushed()
        await super().async_shutdown()
        await self.source.close()
