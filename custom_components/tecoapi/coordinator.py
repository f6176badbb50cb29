"""The coordinator: discovers a PLC's points, polls them and writes to them."""

from collections import deque
from collections.abc import Callable, Iterable
from dataclasses import dataclass, replace
from datetime import datetime
from functools import partial
from typing import Any, override

from homeassistant.config_entries import ConfigEntry
from homeassistant.const import (
    CONF_HOST,
    CONF_PASSWORD,
    CONF_USERNAME,
    CONF_VERIFY_SSL,
    Platform,
)
from homeassistant.core import CALLBACK_TYPE, HomeAssistant, callback
from homeassistant.exceptions import (
    ConfigEntryAuthFailed,
    HomeAssistantError,
    ServiceValidationError,
)
from homeassistant.helpers.aiohttp_client import async_get_clientsession
from homeassistant.helpers.entity import Entity
from homeassistant.helpers.update_coordinator import DataUpdateCoordinator, UpdateFailed
from homeassistant.util import dt as dt_util

from .const import DOMAIN, LOGGER, RECENT_ERRORS, REQUEST_TIMEOUT
from .data import TecoApiData, discovered_data, polled_data
from .issues import async_follow_plc_mode
from .mapping import platform_for
from .options import TecoApiOptions
from .pytecoapi import (
    Catalogue,
    InvalidPathError,
    InvalidValueError,
    InvalidWriteError,
    OutOfRangeError,
    PlcAuthenticationError,
    PlcConnectionError,
    PlcError,
    PlcInfo,
    PlcMode,
    PlcResponseError,
    Point,
    PointMeta,
    ReadOnlyError,
    ReadPlan,
    TecoApiClient,
    ValueRejectedError,
    VariableNotFoundError,
)
from .pytecoapi.values import parse_value
from .reconcile import (
    CatalogueChange,
    async_follow_program_title,
    async_remove_stale_entries,
)

__all__ = ["TecoApiConfigEntry", "TecoApiCoordinator", "TecoApiData"]

type TecoApiConfigEntry = ConfigEntry[TecoApiCoordinator]
type PointAdder = Callable[[Iterable[Point]], None]
"""A platform's way to create entities for points after setup."""


@dataclass(frozen=True, slots=True, kw_only=True)
class RecentError:
    """A failure kept for the diagnostics download."""

    time: datetime
    operation: str
    """``discovery``, ``poll``, ``write`` or ``read``."""
    error: str
    """The client's exception class."""
    message: str


@dataclass(slots=True, kw_only=True)
class TecoApiStatistics:
    """What the coordinator did since the entry was set up (for diagnostics)."""

    polls: int = 0
    failed_polls: int = 0
    discoveries: int = 0
    program_changes: int = 0
    writes: int = 0
    failed_writes: int = 0
    last_poll_requests: int = 0


class TecoApiCoordinator(DataUpdateCoordinator[TecoApiData]):
    """Polls one PLC: discovery on the first refresh, then the read plan.

    Values are read every ``scan_interval``; T_ApiObject attributes and GetInfo
    (the PLC status and its program stamp) every ``attribute_interval``, and
    GetInfo also right after variables went missing, after a failed poll and on
    every poll while the PLC is not running. A new program stamp means a Mosaic
    download: the catalogue is discovered again and the entities reconciled live
    (see ``reconcile``). Only points that have an enabled entity are polled.

    Failures are logged once at info level when the PLC goes away (a warning for
    rejected credentials) and at debug level while it stays away; the coordinator
    logs its recovery at info level.
    """

    config_entry: TecoApiConfigEntry

    def __init__(self, hass: HomeAssistant, entry: TecoApiConfigEntry) -> None:
        """Create the client for the entry's PLC; nothing is requested yet."""
        self.options = TecoApiOptions.from_entry(entry)
        verify_ssl: bool = entry.data[CONF_VERIFY_SSL]
        self.client = TecoApiClient(
            async_get_clientsession(hass, verify_ssl=verify_ssl),
            entry.data[CONF_HOST],
            entry.data[CONF_USERNAME],
            entry.data[CONF_PASSWORD],
            verify_ssl=verify_ssl,
            timeout=REQUEST_TIMEOUT,
        )
        self.catalogue: Catalogue | None = None
        self.points: dict[str, Point] = {}
        self.point_entities: dict[str, Entity] = {}
        self.recent_errors: deque[RecentError] = deque(maxlen=RECENT_ERRORS)
        self.statistics = TecoApiStatistics()
        self._discovered: TecoApiData | None = None
        self._plans: dict[bool, ReadPlan] = {}
        self._attributes_due = dt_util.utcnow()
        self._info_due = False
        self._info_received = dt_util.utcnow()
        self._catalogue_change: CatalogueChange | None = None
        self._followed_mode: PlcMode | None = None
        self._point_adders: dict[Platform, PointAdder] = {}
        self._keyed_listeners: dict[str, dict[int, CALLBACK_TYPE]] = {}
        self._other_listeners: dict[int, CALLBACK_TYPE] = {}
        self._next_listener_id = 0
        self._notified_success = True
        super().__init__(
            hass,
            LOGGER,
            config_entry=entry,
            name=f"{DOMAIN} {entry.title}",
            update_interval=self.options.scan_interval,
        )

    @property
    def serial_number(self) -> str:
        """The PLC's serial number (the config entry's unique ID)."""
        return self.data.info.serial_number

    def point_meta(self, key: str) -> PointMeta | None:
        """Return the latest attributes of a point (None for a plain variable)."""
        if (meta := self.data.meta.get(key)) is not None:
            return meta
        point = self.points.get(key)
        return point.meta if point is not None else None

    # --- discovery and polling --------------------------------------------------

    @override
    async def _async_setup(self) -> None:
        """Discover the PLC: GetInfo, then its catalogue of points and values."""
        try:
            info = await self._async_get_info()
            catalogue = await self.client.discover()
        except PlcError as err:
            raise self._update_failed("discovery", err) from err
        self._use_catalogue(catalogue)
        self._discovered = discovered_data(
            info, catalogue, self.points, info_received=self._info_received
        )
        self._attributes_due = dt_util.utcnow() + self.options.attribute_interval

    def _use_catalogue(self, catalogue: Catalogue) -> None:
        """Take a discovered catalogue: select the points the options want."""
        self.catalogue = catalogue
        self.points = {
            key: point
            for key, point in catalogue.points.items()
            if self.options.selects(key, is_api_object=point.is_api_object)
        }
        self._plans = {}
        self.statistics.discoveries += 1

    @override
    async def _async_update_data(self) -> TecoApiData:
        """Read the polled points (and, when due, their attributes and GetInfo)."""
        if (discovered := self._discovered) is not None:
            # Discovery has just read every value: the first poll is free.
            self._discovered = None
            return discovered
        self.statistics.polls += 1
        requests_before = self.client.request_count
        try:
            return await self._async_poll(self.data)
        except PlcError as err:
            self.statistics.failed_polls += 1
            raise self._update_failed("poll", err) from err
        finally:
            self.statistics.last_poll_requests = (
                self.client.request_count - requests_before
            )

    async def _async_poll(self, previous: TecoApiData) -> TecoApiData:
        """One poll: GetInfo when due, then the values (while the program runs)."""
        now = dt_util.utcnow()
        with_attrs = now >= self._attributes_due
        info = previous.info
        if (
            with_attrs
            or self._info_due
            or not previous.running
            or not self.last_update_success
        ):
            info = await self._async_get_info()
            if _program_changed(previous.info, info):
                return await self._async_rediscover(previous, info)
        if info.mode is not PlcMode.RUN:
            # The entities are unavailable: the values of a stopped program are
            # not read (the attributes are read when it runs again).
            return polled_data(previous, info, None, info_received=self._info_received)
        plan = await self._async_plan(with_attrs)
        result = await self.client.read(plan, self.points)
        if with_attrs:
            self._attributes_due = now + self.options.attribute_interval
        if info is previous.info and result.missing - previous.missing:
            # Variables went missing: a new program may have been downloaded.
            info = await self._async_get_info()
            if _program_changed(previous.info, info):
                return await self._async_rediscover(previous, info)
        return polled_data(previous, info, result, info_received=self._info_received)

    async def _async_get_info(self) -> PlcInfo:
        """GetInfo: the PLC's mode, its program stamp and its clock."""
        info = await self.client.get_info()
        self._info_received = dt_util.utcnow()
        self._info_due = False
        return info

    async def _async_rediscover(
        self, previous: TecoApiData, info: PlcInfo
    ) -> TecoApiData:
        """Discover a new program's catalogue; the entities follow after the update."""
        LOGGER.info(
            "The PLC %s runs a new program (%s, stamp %s): reading its variables again",
            self.config_entry.title,
            info.program_name,
            info.program_stamp,
        )
        catalogue = await self.client.discover()
        async_follow_program_title(self.hass, self.config_entry, previous.info, info)
        old_points = self.points
        self._use_catalogue(catalogue)
        self.statistics.program_changes += 1
        self._catalogue_change = CatalogueChange.between(old_points, self.points)
        self._attributes_due = dt_util.utcnow() + self.options.attribute_interval
        return discovered_data(
            info, catalogue, self.points, previous, info_received=self._info_received
        )

    @property
    def polled_keys(self) -> frozenset[str]:
        """Keys of the points polled: those with an entity in Home Assistant."""
        return frozenset(self._keyed_listeners.keys() & self.points.keys())

    @property
    def read_plan(self) -> ReadPlan | None:
        """The plan of value polls (None before the first poll after discovery)."""
        return self._plans.get(False)

    @property
    def attribute_plan(self) -> ReadPlan | None:
        """The plan of polls with attributes (None before the first one)."""
        return self._plans.get(True)

    async def _async_plan(self, with_attrs: bool) -> ReadPlan:
        """Return the read plan for the points that have an entity listening.

        Planning is pure CPU work (about 0.1 s for 1000 points): it runs in the
        executor, and only when the polled points or the item limit changed.
        """
        polled = self.polled_keys
        plan = self._plans.get(with_attrs)
        if (
            plan is None
            or plan.point_keys != polled
            or plan.item_limit > self.client.item_limit
        ):
            points = [self.points[key] for key in polled]
            plan = self._plans[with_attrs] = await self.hass.async_add_executor_job(
                partial(self.client.plan, points, with_attrs=with_attrs)
            )
        return plan

    @override
    async def _async_refresh(
        self,
        log_failures: bool = True,
        raise_on_auth_failed: bool = False,
        scheduled: bool = False,
        raise_on_entry_error: bool = False,
    ) -> None:
        """Refresh; failures are logged here, at the levels the class describes."""
        await super()._async_refresh(
            log_failures=False,
            raise_on_auth_failed=raise_on_auth_failed,
            scheduled=scheduled,
            raise_on_entry_error=raise_on_entry_error,
        )

    @callback
    @override
    def _async_refresh_finished(self) -> None:
        """Follow the PLC's mode and a new program before the entities hear of it."""
        if not self.last_update_success:
            return
        if (mode := self.data.info.mode) is not self._followed_mode:
            self._followed_mode = mode
            async_follow_plc_mode(self.hass, self.config_entry, mode)
        if (change := self._catalogue_change) is not None:
            self._catalogue_change = None
            self._async_reconcile(change)

    def _update_failed(self, operation: str, err: PlcError) -> Exception:
        """Log a failed discovery or poll once, and return Home Assistant's error."""
        self._note_error(operation, err)
        error = _update_error(err)
        if operation == "discovery":
            # Setting up: Home Assistant logs the retry or the reauthentication.
            LOGGER.debug("Cannot set up the PLC %s: %s", self.config_entry.title, err)
        elif not self.last_update_success:
            LOGGER.debug(
                "The PLC %s is still unavailable: %s", self.config_entry.title, err
            )
        elif isinstance(error, ConfigEntryAuthFailed):
            LOGGER.warning(
                "The PLC %s rejected the stored credentials; sign in again",
                self.config_entry.title,
            )
        else:
            LOGGER.info("The PLC %s is unavailable: %s", self.config_entry.title, err)
        return error

    def _note_error(self, operation: str, err: PlcError) -> None:
        """Keep a failure for the diagnostics download."""
        self.recent_errors.append(
            RecentError(
                time=dt_util.utcnow(),
                operation=operation,
                error=type(err).__name__,
                message=str(err),
            )
        )

    # --- entities after setup -----------------------------------------------------

    @callback
    def async_add_point_platform(
        self, platform: Platform, add_points: PointAdder
    ) -> CALLBACK_TYPE:
        """Let a platform create entities for points that appear later."""
        self._point_adders[platform] = add_points

        @callback
        def remove() -> None:
            if self._point_adders.get(platform) is add_points:
                del self._point_adders[platform]

        return remove

    @callback
    def async_track_point_entity(self, key: str, entity: Entity) -> CALLBACK_TYPE:
        """Know the entity showing a point (to re-create it when the point changes)."""
        self.point_entities[key] = entity

        @callback
        def untrack() -> None:
            if self.point_entities.get(key) is entity:
                del self.point_entities[key]

        return untrack

    @callback
    def _async_reconcile(self, change: CatalogueChange) -> None:
        """Bring the entities in line with a new catalogue."""
        if not change:
            return
        catalogue = self.catalogue
        skipped = catalogue.skipped_roots if catalogue is not None else ()
        async_remove_stale_entries(
            self.hass,
            self.config_entry.entry_id,
            self.serial_number,
            self.points,
            skipped,
        )
        if change.to_create:
            self.config_entry.async_create_task(
                self.hass,
                self._async_create_entities(change),
                f"{self.name} entities for a new program",
            )

    async def _async_create_entities(self, change: CatalogueChange) -> None:
        """Create entities for new, moved and re-shaped points."""
        for key in sorted(change.reshaped):
            if (entity := self.point_entities.get(key)) is not None:
                # Keeps its registry entry: the new entity takes it over.
                await entity.async_remove()
        by_platform: dict[Platform, list[Point]] = {}
        for key in sorted(change.to_create):
            if (point := self.points.get(key)) is not None:
                by_platform.setdefault(platform_for(point), []).append(point)
        for platform, points in by_platform.items():
            if (add_points := self._point_adders.get(platform)) is not None:
                add_points(points)

    # --- writes and reads ---------------------------------------------------------

    def point_key(self, path: str) -> str | None:
        """Return the key of the point at a variable path, if it is one.

        A T_ApiObject is its own path or its ``.value`` member.
        """
        key = path.lower()
        if key in self.points:
            return key
        key = key.removesuffix(".value")
        point = self.points.get(key)
        return key if point is not None and point.is_api_object else None

    async def async_write(self, key: str, value: Any) -> None:
        """Write a value to a point: validate, send, show, re-read.

        This is the one write path of every entity (and of the write action for
        known points).

        Raises ``ServiceValidationError`` for a value the point does not accept
        and ``HomeAssistantError`` when the PLC could not be written; the entity
        then keeps showing the PLC's value.
        """
        point = self.points.get(key)
        if point is None:
            raise _validation_error("variable_not_found", {"path": key})
        point = replace(point, meta=self.point_meta(key))
        placeholders = {"path": point.path, "value": str(value)}
        self.statistics.writes += 1
        try:
            await self.client.write(point, value)
        except PlcError as err:
            raise self._write_failed(err, placeholders) from err
        shown = parse_value(point.kind, value)
        self._show_written(key, value if shown is None else shown)
        await self._async_confirm_write(point)

    async def _async_confirm_write(self, point: Point) -> None:
        """Read back the written point alone: one request, not a whole poll.

        The PLC program may have changed or clamped the value right away; what
        the PLC holds is what the entity shows. A failed read-back leaves the
        judgement to a full poll.
        """
        try:
            result = await self.client.read(
                self.client.plan([point], with_attrs=False), {point.key: point}
            )
        except PlcError as err:
            LOGGER.debug("Reading back %s after a write failed: %s", point.path, err)
            await self.async_request_refresh()
            return
        if result.missing:
            # The variable is gone: a new program may have been downloaded.
            self._info_due = True
            await self.async_request_refresh()
            return
        missing = self.data.missing - {point.key}
        self.async_set_updated_data(
            polled_data(self.data, self.data.info, replace(result, missing=missing))
        )

    async def async_write_variable(self, path: str, value: Any) -> None:
        """Write a JSON-shaped value to any public variable path.

        A known point is written through :meth:`async_write`, validated like
        its entity; any other path goes to the PLC as it is, which judges it.
        """
        if (key := self.point_key(path)) is not None:
            await self.async_write(key, value)
            return
        placeholders = {"path": path, "value": str(value)}
        self.statistics.writes += 1
        try:
            await self.client.write_path(path, value)
        except VariableNotFoundError as err:
            self._info_due = True
            raise _validation_error("variable_not_found", {"path": path}) from err
        except InvalidPathError as err:
            raise _validation_error("invalid_path", {"path": path}) from err
        except PlcError as err:
            raise self._write_failed(err, placeholders) from err
        await self.async_request_refresh()

    async def async_read_variable(self, path: str) -> Any:
        """Read any public variable path: its JSON-shaped value."""
        try:
            return await self.client.read_path(path)
        except VariableNotFoundError as err:
            raise _validation_error("variable_not_found", {"path": path}) from err
        except InvalidPathError as err:
            raise _validation_error("invalid_path", {"path": path}) from err
        except PlcAuthenticationError as err:
            self._note_error("read", err)
            self.config_entry.async_start_reauth(self.hass)
            raise _plc_error("auth_failed", {}) from err
        except PlcError as err:
            self._note_error("read", err)
            raise _plc_error("read_failed", {"path": path, "error": str(err)}) from err

    def _write_failed(
        self, err: PlcError, placeholders: dict[str, str]
    ) -> HomeAssistantError:
        """Return the error for a write that was refused or did not reach the PLC."""
        if isinstance(err, ReadOnlyError):
            return _validation_error("read_only", placeholders)
        if isinstance(err, OutOfRangeError):
            return _validation_error(
                "out_of_range",
                placeholders
                | {
                    "min_value": f"{err.min_value:g}",
                    "max_value": f"{err.max_value:g}",
                },
            )
        if isinstance(err, InvalidValueError | InvalidWriteError):
            return _validation_error(
                "invalid_value", placeholders | {"error": str(err)}
            )
        if isinstance(err, ValueRejectedError):
            return _validation_error(
                "value_rejected", placeholders | {"message": err.message}
            )
        self.statistics.failed_writes += 1
        self._note_error("write", err)
        if isinstance(err, PlcAuthenticationError):
            self.config_entry.async_start_reauth(self.hass)
            return _plc_error("auth_failed", {})
        if isinstance(err, VariableNotFoundError):
            # The variable went away: check the program on the next poll.
            self._info_due = True
        return _plc_error("write_failed", placeholders | {"error": str(err)})

    @callback
    def _show_written(self, key: str, value: Any) -> None:
        """Show a value the PLC acknowledged until the next poll confirms it."""
        self.data = replace(
            self.data,
            values={**self.data.values, key: value},
            changed=frozenset({key}),
        )
        for update_callback in list(self._keyed_listeners.get(key, {}).values()):
            update_callback()

    # --- listeners ----------------------------------------------------------------

    @callback
    @override
    def async_add_listener(
        self, update_callback: CALLBACK_TYPE, context: Any = None
    ) -> Callable[[], None]:
        """Listen for updates; a listener with a key as context hears only its key."""
        remove = super().async_add_listener(update_callback, context)
        self._next_listener_id += 1
        listener_id = self._next_listener_id
        if isinstance(context, str):
            listeners = self._keyed_listeners.setdefault(context, {})
        else:
            listeners = self._other_listeners
        listeners[listener_id] = update_callback

        @callback
        def remove_listener() -> None:
            remove()
            del listeners[listener_id]
            if not listeners and isinstance(context, str):
                del self._keyed_listeners[context]

        return remove_listener

    @callback
    @override
    def async_update_listeners(self) -> None:
        """Tell each entity about an update only if its own data changed.

        A change of availability (a poll failed, or succeeded after failures)
        concerns every entity.
        """
        if self.last_update_success != self._notified_success or self.data is None:
            self._notified_success = self.last_update_success
            super().async_update_listeners()
            return
        callbacks = list(self._other_listeners.values())
        for key in self.data.changed:
            callbacks.extend(self._keyed_listeners.get(key, {}).values())
        for update_callback in callbacks:
            try:
                update_callback()
            except Exception:
                # One entity failing must not keep the others from their update.
                self.logger.exception("Error updating a listener of %s", self.name)

    async def async_apply_options(self, options: TecoApiOptions) -> None:
        """Apply new polling intervals at once (other options need a reload)."""
        previous, self.options = self.options, options
        if options.attribute_interval != previous.attribute_interval:
            self._attributes_due = min(
                self._attributes_due, dt_util.utcnow() + options.attribute_interval
            )
        if options.scan_interval != previous.scan_interval:
            self.update_interval = options.scan_interval
            # Poll now: the next poll is then scheduled at the new interval.
            await self.async_request_refresh()


def _program_changed(previous: PlcInfo, info: PlcInfo) -> bool:
    """Whether GetInfo reports another user program than before."""
    return info.program_stamp is not None and info.program_stamp != (
        previous.program_stamp
    )


def _update_error(err: PlcError) -> Exception:
    """Return the Home Assistant error for a failed poll or discovery."""
    if isinstance(err, PlcAuthenticationError):
        return ConfigEntryAuthFailed(
            translation_domain=DOMAIN, translation_key="auth_failed"
        )
    if isinstance(err, PlcConnectionError):
        return UpdateFailed(
            translation_domain=DOMAIN,
            translation_key="cannot_connect",
            translation_placeholders={"error": str(err)},
        )
    if isinstance(err, PlcResponseError):
        return UpdateFailed(
            translation_domain=DOMAIN,
            translation_key="plc_error",
            translation_placeholders={"code": err.code, "message": err.message},
        )
    return UpdateFailed(
        translation_domain=DOMAIN,
        translation_key="unknown_error",
        translation_placeholders={"error": str(err)},
    )


def _validation_error(
    translation_key: str, placeholders: dict[str, str]
) -> ServiceValidationError:
    """Return a translated error for something the user asked wrongly."""
    return ServiceValidationError(
        translation_domain=DOMAIN,
        translation_key=translation_key,
        translation_placeholders=placeholders,
    )


def _plc_error(
    translation_key: str, placeholders: dict[str, str]
) -> HomeAssistantError:
    """Return a translated error for something that failed on the PLC's side."""
    return HomeAssistantError(
        translation_domain=DOMAIN,
        translation_key=translation_key,
        translation_placeholders=placeholders,
    )
