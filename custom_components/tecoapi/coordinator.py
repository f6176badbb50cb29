"""The coordinator: polls a PLC source and tells the entities what changed.

It depends on the transport-neutral seam only (``pyplc.core.source``, the neutral
models and exceptions): the source decides what to read when, the coordinator
turns its snapshots into what the entities show (``data``), follows the PLC's
mode and program, and is the one write path of every entity. What a user set
moving is read between the polls by its ``motion`` (``motion.MotionFollower``).
"""

import asyncio
from collections.abc import Mapping
from dataclasses import replace
import logging
from typing import Any, Final

from homeassistant.config_entries import ConfigEntry
from homeassistant.core import HomeAssistant, callback

from .connection import create_source, descriptor_of
from .const import DOMAIN, LOGGER
from .data import PlcData, updated_data
from .helpers import plc_action, update_error, validation_error
from .issues import (
    async_follow_compositions,
    async_follow_plc_mode,
    async_follow_refused_points,
    async_follow_variable_list,
    async_load_issue_texts,
    refused_points,
)
from .listeners import KeyedCoordinator
from .motion import MotionFollower
from .options import PlcOptions
from .pyplc import PlcAuthenticationError, PlcError, Point, PointQuality
from .pyplc.core.descriptor import Capability, SourceOptions
from .pyplc.core.models import PointOverride
from .pyplc.core.pointmap import PointMap
from .pyplc.core.source import PlcSource, Snapshot
from .reconcile import (
    async_follow_program_title,
    async_remove_stale_devices,
    async_remove_stale_entries,
)
from .selection import Composition, compositions_of, selector

type PlcConfigEntry = ConfigEntry[PlcCoordinator]


def create_entry_source(
    hass: HomeAssistant,
    entry: PlcConfigEntry,
    options: PlcOptions,
    point_map: PointMap | None,
    overrides: Mapping[str, PointOverride] | None = None,
) -> PlcSource:
    """Return the source an entry reaches its device through, as its options say.

    Made at setup, and again when the coordinator swaps it (push switched on,
    off or to another server; the user's points edited, or what the user
    changed of the points discovered: ``overrides``).
    """
    return create_source(
        hass,
        entry.data,
        SourceOptions(
            metadata_interval=options.attribute_interval,
            companion=options.push_server,
            point_map=point_map,
            identity=entry.unique_id,
            overrides=overrides or {},
        ),
        entry.entry_id,
    )


RECOVERED: Final = "Fetching %s data recovered"
"""The line the data update coordinator logs when a poll succeeds after a failure."""


class _OutageFilter(logging.Filter):
    """Keep the data update coordinator's own outage lines at debug level.

    The coordinator logs an outage itself, once, at info level (a warning for
    rejected credentials), and the return once, in the words of the device's
    system (the gateway …, the controller …), as Home Assistant's quality scale
    asks; the base class would log the same failure again as an error and the
    return as its own "data recovered". Unexpected exceptions, logged with
    their traceback, stay errors.
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
        self, hass: HomeAssistant, entry: PlcConfigEntry, source: PlcSource
    ) -> None:
        """Poll ``source`` for the entry; nothing is requested yet."""
        self.source = source
        self.descriptor = descriptor_of(entry.data)
        """What the entry's source declares (its capabilities)."""
        self.point_map: PointMap | None = None
        """The user's points, for a source that takes a map (set at setup)."""
        self.overrides: Mapping[str, PointOverride] = {}
        """What the user changed of the points discovered, by key (set at setup)."""
        self.options = PlcOptions.from_entry(entry)
        self.compositions = compositions_of(entry.subentries)
        self.device_name = ""
        """The PLC device's name (set once the PLC is known, see ``device_info``)."""
        self.group_device_names: dict[str, str] = {}
        """Each group device's name, by group key, chosen once (see ``device_info``)."""
        self._select = selector(
            self.options, self.compositions, self.descriptor.recognisers
        )
        # Polls, reads of what moves and following the polled points take turns:
        # each shows what it read in the order it read it.
        self._reading = asyncio.Lock()
        # The points the device refuses with a code of its own (its repair issue;
        # None: not followed yet, so the first data clears a stale one).
        self._refused: dict[str, PointQuality] | None = None
        # Whether a poll failed for the list of public variables (its repair issue;
        # None: not followed yet, so the first data clears a stale one).
        self._variable_list_failed: bool | None = None
        super().__init__(
            hass,
            POLL_LOGGER,
            config_entry=entry,
            name=f"{DOMAIN} {entry.title}",
            update_interval=self.options.scan_interval,
        )
        self.motion = MotionFollower(
            hass,
            entry,
            name=self.name,
            reading=self._reading,
            source=lambda: self.source,
            show=self._async_show_between_polls,
            shown=lambda: self.data,
        )
        """What a user set moving, read every second until it arrives."""
        # The source may be swapped (push switched on or off): hear the current one.
        self._unsubscribe_pushed = source.subscribe(self._async_show_between_polls)
        entry.async_on_unload(self._stop_hearing_source)

    async def _async_update_data(self) -> PlcData:
        """Read what the source says is due, and follow the PLC's mode and program."""
        polled = self.polled_keys if self.data is not None else frozenset()
        source = self.source
        try:
            async with self._reading:
                snapshot = await source.poll(polled)
        except PlcError as err:
            if self.source is not source:
                # Swapped and closed while it was read: the new one answers.
                return await self._async_update_data()
            self._log_failure(err)
            if async_follow_variable_list(self.hass, self.config_entry, err):
                self._variable_list_failed = True
            raise update_error(err) from err
        if self._variable_list_failed is not False:
            async_follow_variable_list(self.hass, self.config_entry, None)
            self._variable_list_failed = False
        previous = self.data
        if previous is not None and not self.last_update_success:
            LOGGER.info("The %s is available again", self._named)
        data = self._updated(snapshot)
        if previous is None or data.info.mode is not previous.info.mode:
            async_follow_plc_mode(self.hass, self.config_entry, data.info.mode)
        if previous is None or data.selection is not previous.selection:
            await async_load_issue_texts(self.hass)
            async_follow_compositions(self.hass, self.config_entry, data.selection)
        if previous is not None and snapshot.program_changed:
            self._follow_program(previous, data)
        return data

    def _updated(self, snapshot: Snapshot) -> PlcData:
        """Return the data after a snapshot (a new catalogue is selected from anew).

        The repair issue listing the points the device refuses follows it
        (raised, changed or cleared when the list changes).
        """
        data = updated_data(self.data, snapshot, self._select)
        refused = refused_points(data, self._refused or {})
        if refused != self._refused:
            self._refused = refused
            async_follow_refused_points(self.hass, self.config_entry, data, refused)
        return data

    def _follow_program(self, previous: PlcData, data: PlcData) -> None:
        """Follow a new program: retitle the entry, drop what it no longer has.

        The platforms create the new program's entities when they hear of the data.
        """
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
        async_follow_program_title(
            self.hass, self.config_entry, previous.info, data.info
        )
        async_remove_stale_entries(self.hass, self.config_entry, data)
        async_remove_stale_devices(self.hass, self.config_entry, data)

    @property
    def _named(self) -> str:
        """The device as log lines name it, in its system's words: ``gateway FP-I4C · …``."""
        return f"{self.descriptor.noun} {self.config_entry.title}"

    def _log_failure(self, err: PlcError) -> None:
        """Log a failed poll once when the device goes away, at debug while it stays away.

        Its return is logged once too (:meth:`_async_update_data`).
        """
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

    def _stop_hearing_source(self) -> None:
        """Hear no more snapshots of the current source (the entry unloads)."""
        self._unsubscribe_pushed()

    @callback
    def _async_show_between_polls(self, snapshot: Snapshot) -> None:
        """Show a pushed snapshot (or a read of what moves) at once.

        The next poll stays where it is.
        """
        data: PlcData | None = self.data
        if data is not None and snapshot.catalogue is data.catalogue:
            self.data = self._updated(snapshot)
            self.async_update_listeners()

    @callback
    def async_start_following(self) -> None:
        """Have the source follow the polled points now, not from the next poll.

        Called once the platforms' entities listen (the polled points are known)
        and whenever the source is swapped (push switched on in the options):
        with push, their changes are pushed from then on instead of from the
        next scheduled poll, up to an interval later. No poll is read for it;
        it runs in the background, so a PLCComS still connecting holds up
        neither the setup nor the options.
        """
        self.config_entry.async_create_background_task(
            self.hass, self._async_follow_polled(), f"{DOMAIN} follow the polled points"
        )

    async def _async_follow_polled(self) -> None:
        async with self._reading:
            await self.source.follow(self.polled_keys)

    # --- writes and reads ---------------------------------------------------------

    def point(self, key: str) -> Point:
        """Return the catalogue's point of a key; a translated error if there is none."""
        if (point := self.data.catalogue.points.get(key)) is None:
            raise validation_error("variable_not_found", {"path": key})
        return point

    async def async_write(self, key: str, value: Any) -> None:
        """Write a value to a point: the one write path of every entity.

        The source validates and sends it; the entity shows the acknowledged value
        at once and then what the PLC holds. Raises a translated error when the
        value is refused or the PLC could not be written; the entity then keeps
        showing the PLC's value.
        """
        point = self.point(key)
        with plc_action(
            self.hass,
            self.config_entry,
            operation="write",
            path=point.path,
            value=value,
        ):
            confirmed = await self.source.write(key, value)
        await self._async_show(confirmed)

    async def async_write_many(self, values: Mapping[str, Any]) -> None:
        """Write several points' values as one batch: one command of a device.

        Every value is checked before anything is sent, so a refused one leaves
        the PLC and Home Assistant as they were; the translated error names the
        point refused.
        """
        if not values:
            return
        points = {key: self.point(key) for key in values}
        try:
            confirmed = await self.source.write_many(values)
        except PlcError as err:
            key = _refused(points, getattr(err, "path", None))
            with plc_action(
                self.hass,
                self.config_entry,
                operation="write",
                path=points[key].path,
                value=values[key],
            ):
                raise
        await self._async_show(confirmed)

    async def async_write_variable(self, path: str, value: Any) -> None:
        """Write a JSON-shaped value to any public variable path (the action)."""
        with plc_action(
            self.hass,
            self.config_entry,
            operation="write_variable",
            path=path,
            value=value,
        ):
            confirmed = await self.source.write_variable(path, value)
        await self._async_show(confirmed)

    async def async_read_variable(self, path: str) -> Any:
        """Read any public variable path: its JSON-shaped value (the action)."""
        with plc_action(
            self.hass, self.config_entry, operation="read_variable", path=path
        ):
            return await self.source.read_variable(path)

    async def _async_show(self, confirmed: Snapshot | None) -> None:
        """Show what a write's read-back found, or poll when it found nothing."""
        if confirmed is None or confirmed.catalogue is not self.data.catalogue:
            await self.async_request_refresh()
        else:
            self.async_set_updated_data(self._updated(confirmed))

    async def async_apply_options(
        self, options: PlcOptions, compositions: list[Composition]
    ) -> bool:
        """Apply new options and composed devices in place, without a reload.

        Only what changes changes: new polling intervals apply at once; push
        switched on, off or to another server swaps the source (the old one is
        closed); another choice of entities (filters, plain variables, devices)
        or composed devices selects anew from the catalogue known, and the
        platforms add and remove just the entities concerned. The other
        entities keep showing their values. Returns whether it selected anew
        (the caller then moves entities whose device changed).
        """
        previous, self.options = self.options, options
        reselect = (
            not options.same_entities(previous) or compositions != self.compositions
        )
        if reselect:
            self.compositions = compositions
            self._select = selector(options, compositions, self.descriptor.recognisers)
        if options.push_server != previous.push_server:
            await self._async_swap_source(options)
        else:
            self.source.metadata_interval = options.attribute_interval
        if reselect:
            self._async_reselect()
            # The values of points new to the selection, at once.
            await self.async_refresh()
        if options.scan_interval != previous.scan_interval:
            self.update_interval = options.scan_interval
            # Poll now: the next poll is then scheduled at the new interval.
            await self.async_request_refresh()
        return reselect

    async def async_replace_point_map(self, point_map: PointMap) -> None:
        """Take the user's new or edited points in place, without a reload.

        A new source reads the new map; the catalogue it discovers is selected
        from as a new program's is: points kept keep their entities (their keys
        are the map's IDs), new ones get entities, and those gone leave the
        registry. The other entities keep showing their values meanwhile.
        """
        previous = self.data
        self.point_map = point_map
        await self._async_swap_source(self.options)
        if self._async_followed_new_points(previous):
            LOGGER.info(
                "The points of %s changed: %d points now",
                self.config_entry.title,
                len(point_map.points),
            )
            # The map may name another project (a Mervis installation's).
            async_follow_program_title(
                self.hass, self.config_entry, previous.info, self.data.info
            )

    async def async_replace_overrides(
        self, overrides: Mapping[str, PointOverride]
    ) -> None:
        """Take what the user changed of the points discovered, in place.

        A new source discovers the points again with the changes applied, and
        the catalogue is selected from as a new program's is: a point shown on
        another platform now (made writable, or shown only) has its entity
        there, under the same unique ID, and its old registry entry goes; one
        whose description changed (a unit) is made again under its registry
        entry. The other entities keep showing their values meanwhile.
        """
        previous = self.data
        self.overrides = dict(overrides)
        await self._async_swap_source(self.options)
        if self._async_followed_new_points(previous):
            LOGGER.info(
                "The points of %s changed: %d of them as the user asked",
                self.config_entry.title,
                len(overrides),
            )

    @callback
    def _async_followed_new_points(self, previous: PlcData) -> bool:
        """Drop what a new catalogue no longer backs; whether there is one."""
        data: PlcData = self.data
        if data is previous:
            return False
        async_remove_stale_entries(self.hass, self.config_entry, data)
        async_remove_stale_devices(self.hass, self.config_entry, data)
        return True

    async def _async_swap_source(self, options: PlcOptions) -> None:
        """Reach the PLC through a new source (push on, off or moved); close the old.

        Its first poll discovers the program again; the entities keep showing
        the values they have until it answers.
        """
        old = self.source
        self.source = create_entry_source(
            self.hass, self.config_entry, options, self.point_map, self.overrides
        )
        self._unsubscribe_pushed()
        self._unsubscribe_pushed = self.source.subscribe(self._async_show_between_polls)
        await old.close()
        await self.async_refresh()
        # The entities listen already: the new source follows their points now.
        self.async_start_following()

    @callback
    def _async_reselect(self) -> None:
        """Select from the known catalogue again, as the new options say.

        Registry entries the selection no longer backs go first (their entities
        with them); the platforms then create the new entities.
        """
        data: PlcData = self.data
        selection = self._select(data.catalogue)
        points = data.catalogue.points
        self.data = replace(
            data,
            selection=selection,
            values={key: data.values.get(key) for key in selection.watched},
            attributes={
                key: attributes
                for key in selection.watched
                if (attributes := data.attributes.get(key)) is not None
                or (
                    key in points and (attributes := points[key].attributes) is not None
                )
            },
            changed=frozenset(),
        )
        async_follow_compositions(self.hass, self.config_entry, selection)
        async_remove_stale_entries(self.hass, self.config_entry, self.data)
        self.async_update_listeners()

    async def async_shutdown(self) -> None:
        """Stop polling and following what moves, and release the source."""
        self.motion.async_stop()
        await super().async_shutdown()
        await self.source.close()


def _refused(points: Mapping[str, Point], refused: str | None) -> str:
    """Return the key of the batch's point an error names, else the batch's first.

    A source names a point by its path, its key or its address, or by a path
    within it (the member that holds its value), in any case.
    """
    name = (refused or "").lower()
    for key, point in points.items():
        if name in {key.lower(), point.path.lower(), point.address.lower()}:
            return key
    within = [
        key
        for key, point in points.items()
        if name.startswith(f"{point.path.lower()}.")
    ]
    return max(
        within, key=lambda key: len(points[key].path), default=next(iter(points))
    )
