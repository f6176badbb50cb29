"""The coordinator: discovers a PLC's points, polls them and writes to them."""

from collections.abc import Callable, Mapping
from dataclasses import dataclass, replace
from operator import attrgetter
from typing import Any, Final, override

from homeassistant.config_entries import ConfigEntry
from homeassistant.const import CONF_HOST, CONF_PASSWORD, CONF_USERNAME, CONF_VERIFY_SSL
from homeassistant.core import CALLBACK_TYPE, HomeAssistant, callback
from homeassistant.exceptions import (
    ConfigEntryAuthFailed,
    HomeAssistantError,
    ServiceValidationError,
)
from homeassistant.helpers.aiohttp_client import async_get_clientsession
from homeassistant.helpers.update_coordinator import DataUpdateCoordinator, UpdateFailed
from homeassistant.util import dt as dt_util

from .const import (
    DOMAIN,
    LOGGER,
    STATUS_CLOCK,
    STATUS_MODE,
    STATUS_PROGRAM_COMPILED,
    STATUS_PROGRAM_NAME,
    STATUS_RUNNING_PROBLEM,
)
from .options import TecoApiOptions
from .pytecoapi import (
    Catalogue,
    PlcInfo,
    Point,
    PointMeta,
    PollResult,
    ReadPlan,
    TecoApiAuthenticationError,
    TecoApiClient,
    TecoApiConnectionError,
    TecoApiError,
    TecoApiInvalidValueError,
    TecoApiOutOfRangeError,
    TecoApiReadOnlyError,
    TecoApiResponseError,
    TecoApiWriteError,
)
from .pytecoapi.exceptions import TecoApiValueRejectedError

type TecoApiConfigEntry = ConfigEntry[TecoApiCoordinator]

# Which GetInfo field each PLC status entity shows: a status entity is told about
# an update only when its field changed.
STATUS_FIELDS: Final[Mapping[str, Callable[[PlcInfo], object]]] = {
    STATUS_MODE: attrgetter("mode"),
    STATUS_RUNNING_PROBLEM: attrgetter("mode"),
    STATUS_PROGRAM_NAME: attrgetter("program_name"),
    STATUS_PROGRAM_COMPILED: attrgetter("program_compiled"),
    STATUS_CLOCK: attrgetter("time"),
}

_ABSENT: Final = object()


@dataclass(frozen=True, slots=True, kw_only=True)
class TecoApiData:
    """What the entities show: the PLC's info and its points' values and attributes.

    ``changed`` holds the keys (point keys and PLC status keys) whose value,
    attributes or availability changed in the update that produced this data;
    only their entities are told about it.
    """

    info: PlcInfo
    values: Mapping[str, Any]
    meta: Mapping[str, PointMeta]
    missing: frozenset[str]
    changed: frozenset[str]


class TecoApiCoordinator(DataUpdateCoordinator[TecoApiData]):
    """Polls one PLC: discovery on the first refresh, then the read plan.

    Values are read every ``scan_interval``; T_ApiObject attributes and GetInfo
    (the PLC status) every ``attribute_interval``. Only points that have an
    entity in Home Assistant (an enabled one) are polled.
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
        )
        self.catalogue: Catalogue | None = None
        self.points: dict[str, Point] = {}
        self._discovered: TecoApiData | None = None
        self._plans: dict[bool, ReadPlan] = {}
        self._attributes_due = dt_util.utcnow()
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
        return self.points[key].meta

    @override
    async def _async_setup(self) -> None:
        """Discover the PLC: GetInfo, then its catalogue of points and values."""
        try:
            info = await self.client.get_info()
            catalogue = await self.client.discover()
        except TecoApiError as err:
            raise _update_error(err) from err
        self.catalogue = catalogue
        self.points = {
            key: point
            for key, point in catalogue.points.items()
            if self.options.selects(key, is_api_object=point.is_api_object)
        }
        self._discovered = TecoApiData(
            info=info,
            values={key: catalogue.values.get(key) for key in self.points},
            meta={
                key: point.meta
                for key, point in self.points.items()
                if point.meta is not None
            },
            missing=frozenset(),
            changed=frozenset(),
        )
        self._attributes_due = dt_util.utcnow() + self.options.attribute_interval

    @override
    async def _async_update_data(self) -> TecoApiData:
        """Read the polled points (and, when due, their attributes and GetInfo)."""
        if (discovered := self._discovered) is not None:
            # Discovery has just read every value: the first poll is free.
            self._discovered = None
            return discovered
        previous = self.data
        now = dt_util.utcnow()
        with_attrs = now >= self._attributes_due
        try:
            info = await self.client.get_info() if with_attrs else previous.info
            result = await self.client.read(self._plan(with_attrs), self.points)
        except TecoApiError as err:
            raise _update_error(err) from err
        if with_attrs:
            self._attributes_due = now + self.options.attribute_interval
        # Compare with what the entities show now: a write may have landed meanwhile.
        return _merge(self.data, info, result)

    @property
    def polled_keys(self) -> frozenset[str]:
        """Keys of the points polled: those with an entity in Home Assistant."""
        return frozenset(self._keyed_listeners.keys() & self.points.keys())

    @property
    def read_plan(self) -> ReadPlan | None:
        """The plan of value polls (None before the first poll after discovery)."""
        return self._plans.get(False)

    def _plan(self, with_attrs: bool) -> ReadPlan:
        """Return the read plan for the points that have an entity listening."""
        polled = self.polled_keys
        plan = self._plans.get(with_attrs)
        if (
            plan is None
            or plan.point_keys != polled
            or plan.item_limit > self.client.item_limit
        ):
            plan = self._plans[with_attrs] = self.client.plan(
                (self.points[key] for key in polled), with_attrs=with_attrs
            )
        return plan

    async def async_write(self, key: str, value: Any) -> None:
        """Write a value to a point: validate, send, show, re-read.

        This is the one write path of every entity.

        Raises ``ServiceValidationError`` for a value the point does not accept
        and ``HomeAssistantError`` when the PLC could not be written.
        """
        point = replace(self.points[key], meta=self.point_meta(key))
        placeholders = {"path": point.path, "value": str(value)}
        try:
            await self.client.write(point, value)
        except TecoApiReadOnlyError as err:
            raise _validation_error("read_only", placeholders) from err
        except TecoApiOutOfRangeError as err:
            raise _validation_error(
                "out_of_range",
                placeholders
                | {
                    "min_value": f"{err.min_value:g}",
                    "max_value": f"{err.max_value:g}",
                },
            ) from err
        except (TecoApiInvalidValueError, TecoApiWriteError) as err:
            raise _validation_error(
                "invalid_value", placeholders | {"error": str(err)}
            ) from err
        except TecoApiValueRejectedError as err:
            raise _validation_error(
                "value_rejected", placeholders | {"message": err.message}
            ) from err
        except TecoApiAuthenticationError as err:
            self.config_entry.async_start_reauth(self.hass)
            raise HomeAssistantError(
                translation_domain=DOMAIN, translation_key="auth_failed"
            ) from err
        except TecoApiError as err:
            raise HomeAssistantError(
                translation_domain=DOMAIN,
                translation_key="write_failed",
                translation_placeholders=placeholders | {"error": str(err)},
            ) from err
        self._show_written(key, value)
        await self.async_request_refresh()

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


def _merge(previous: TecoApiData, info: PlcInfo, result: PollResult) -> TecoApiData:
    """Return the new data, noting which keys changed since the previous data."""
    values = dict(previous.values)
    changed = set(previous.missing ^ result.missing)
    for key, value in result.values.items():
        old = values.get(key, _ABSENT)
        if old != value or type(old) is not type(value):
            values[key] = value
            changed.add(key)
    meta = dict(previous.meta)
    for key, point_meta in result.meta.items():
        if meta.get(key) != point_meta:
            meta[key] = point_meta
            changed.add(key)
    if info != previous.info:
        changed.update(
            key
            for key, field in STATUS_FIELDS.items()
            if field(info) != field(previous.info)
        )
    return TecoApiData(
        info=info,
        values=values,
        meta=meta,
        missing=result.missing,
        changed=frozenset(changed),
    )


def _update_error(err: TecoApiError) -> Exception:
    """Return the Home Assistant error for a failed poll or discovery."""
    if isinstance(err, TecoApiAuthenticationError):
        return ConfigEntryAuthFailed(
            translation_domain=DOMAIN, translation_key="auth_failed"
        )
    if isinstance(err, TecoApiConnectionError):
        return UpdateFailed(
            translation_domain=DOMAIN,
            translation_key="cannot_connect",
            translation_placeholders={"error": str(err)},
        )
    if isinstance(err, TecoApiResponseError):
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
    """Return a translated error for a value the point does not accept."""
    return ServiceValidationError(
        translation_domain=DOMAIN,
        translation_key=translation_key,
        translation_placeholders=placeholders,
    )
