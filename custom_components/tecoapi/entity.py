"""Base entities: one device per PLC, a unique ID per point, availability.

Every entity hears of every update of the coordinator and writes its state only
when its own key changed or its availability did: a poll that changes one value
of a thousand costs one state write.
"""

from collections.abc import Callable, Coroutine, Mapping
from datetime import date, datetime
from typing import Any, cast, override

from homeassistant.const import Platform
from homeassistant.core import HomeAssistant, callback
from homeassistant.helpers import entity_registry as er
from homeassistant.helpers.device_registry import (
    CONNECTION_NETWORK_MAC,
    DeviceInfo,
    format_mac,
)
from homeassistant.helpers.entity import Entity
from homeassistant.helpers.entity_platform import (
    AddConfigEntryEntitiesCallback,
    async_get_current_platform,
)
from homeassistant.helpers.update_coordinator import CoordinatorEntity

from .const import DOMAIN, MANUFACTURER
from .coordinator import TecoApiConfigEntry, TecoApiCoordinator
from .data import TecoApiData
from .mapping import PointDescription, entity_name
from .pytecoapi import Point, PointMeta

type PointValue = bool | int | float | str | date | datetime | None
"""A point's value as the library types it (None: unknown)."""


class TecoApiEntity(CoordinatorEntity[TecoApiCoordinator]):
    """An entity of a Tecomat PLC that writes its state only when it has to."""

    _attr_has_entity_name = True

    def __init__(self, coordinator: TecoApiCoordinator, key: str) -> None:
        """Attach the entity to the PLC's device; ``key`` names what it shows."""
        super().__init__(coordinator, context=key)
        self.key = key
        info = coordinator.data.info
        self._attr_unique_id = f"{info.serial_number}_{key}"
        self._attr_device_info = DeviceInfo(
            identifiers={(DOMAIN, info.serial_number)},
            manufacturer=MANUFACTURER,
            model=info.type,
            name=f"Tecomat {info.type}" if info.type else "Tecomat PLC",
            serial_number=info.serial_number,
            sw_version=info.firmware,
            configuration_url=coordinator.source.configuration_url,
        )
        if info.mac:
            self._attr_device_info["connections"] = {
                (CONNECTION_NETWORK_MAC, format_mac(info.mac))
            }
        self._shown_data: TecoApiData | None = None
        self._shown_success = True

    @override
    async def async_added_to_hass(self) -> None:
        """Remember what the first state write shows."""
        await super().async_added_to_hass()
        self._shown_data = self.coordinator.data
        self._shown_success = self.coordinator.last_update_success

    @callback
    @override
    def _handle_coordinator_update(self) -> None:
        """Write the state only if this entity's data or availability changed.

        It runs for every entity on every update, so it is kept cheap: whatever
        changes what a point entity shows or its availability -- a value, its
        attributes, a missing point, the PLC's mode -- puts its key in
        ``data.changed``; a failed or recovered poll flips ``last_update_success``.
        """
        coordinator = self.coordinator
        data = coordinator.data
        success = coordinator.last_update_success
        if success is self._shown_success and (
            data is self._shown_data or self.key not in data.changed
        ):
            return
        self._shown_data, self._shown_success = data, success
        self._update_from_data(data)
        self.async_write_ha_state()

    def _update_from_data(self, data: TecoApiData) -> None:
        """Take what changed in the data before the state is written."""


class TecoApiPointEntity(TecoApiEntity):
    """An entity showing one point (variable) of the PLC, built from its description."""

    def __init__(
        self, coordinator: TecoApiCoordinator, description: PointDescription
    ) -> None:
        """Name the entity from ``attr.title`` (or the path)."""
        super().__init__(coordinator, description.key)
        self.description = description
        self.point: Point = coordinator.data.points[description.key]
        self._named_by = self.meta
        self._attr_name = entity_name(self.point, self._named_by)
        self._attr_entity_registry_enabled_default = description.enabled_default

    @property
    def meta(self) -> PointMeta | None:
        """The point's latest attributes (None for a plain variable)."""
        return self.coordinator.data.point_meta(self.key)

    @property
    def point_value(self) -> PointValue:
        """The point's latest value."""
        return cast("PointValue", self.coordinator.data.values.get(self.key))

    @property
    def point_is_on(self) -> bool | None:
        """The point's value as on/off (None: unknown)."""
        value = self.point_value
        return None if value is None else bool(value)

    @property
    @override
    def available(self) -> bool:
        """Whether the point can be shown.

        Not when polling fails, the PLC is not running, or the point is missing,
        gone from the program or ``enable=false``.
        """
        data = self.coordinator.data
        meta = self.meta
        return (
            super().available
            and data.running
            and self.key in data.points
            and self.key not in data.missing
            and (meta is None or meta.enable)
        )

    @override
    def _update_from_data(self, data: TecoApiData) -> None:
        """Follow a changed path spelling or title (new attributes, a new program)."""
        point = data.points.get(self.key, self.point)
        meta = data.point_meta(self.key)
        if point is not self.point or meta is not self._named_by:
            self.point, self._named_by = point, meta
            self._attr_name = entity_name(point, meta)


type PointEntityFactory = Callable[[TecoApiCoordinator, PointDescription], Entity]
type PlatformSetup = Callable[
    [HomeAssistant, TecoApiConfigEntry, AddConfigEntryEntitiesCallback],
    Coroutine[Any, Any, None],
]


def point_platform(platform: Platform, create: PointEntityFactory) -> PlatformSetup:
    """Return the ``async_setup_entry`` of a platform that shows points only."""

    async def async_setup_entry(
        hass: HomeAssistant,
        entry: TecoApiConfigEntry,
        async_add_entities: AddConfigEntryEntitiesCallback,
    ) -> None:
        """Create an entity per point of this platform, now and after a new program."""
        async_add_point_entities(entry, platform, create, async_add_entities)

    return async_setup_entry


@callback
def async_add_point_entities(
    entry: TecoApiConfigEntry,
    platform: Platform,
    create: PointEntityFactory,
    async_add_entities: AddConfigEntryEntitiesCallback,
) -> None:
    """Create the platform's point entities now, and follow the descriptions later.

    After a new program a point may be new on this platform (its entity is
    created), or its description may have changed (its entity is made again under
    the same registry entry). Entities of points that left the platform are
    removed through the entity registry by the coordinator.
    """
    follower = _DescriptionFollower(entry, platform, create, async_add_entities)
    follower.follow()
    entry.async_on_unload(entry.runtime_data.async_add_listener(follower.follow))


class _DescriptionFollower:
    """Keeps one platform's point entities in step with the coordinator's descriptions."""

    def __init__(
        self,
        entry: TecoApiConfigEntry,
        platform: Platform,
        create: PointEntityFactory,
        async_add_entities: AddConfigEntryEntitiesCallback,
    ) -> None:
        self._entry = entry
        self._coordinator = entry.runtime_data
        self._platform = platform
        self._entity_platform = async_get_current_platform()
        self._create = create
        self._add_entities = async_add_entities
        self._descriptions: Mapping[str, PointDescription] | None = None
        self._shown: dict[str, PointDescription] = {}

    @callback
    def follow(self) -> None:
        """Create or re-create entities when the descriptions changed."""
        descriptions = self._coordinator.data.descriptions
        if descriptions is self._descriptions:
            return
        self._descriptions = descriptions
        mine = {
            key: description
            for key, description in descriptions.items()
            if description.platform is self._platform
        }
        shown = self._shown
        added = [item for key, item in mine.items() if key not in shown]
        changed = [item for key, item in mine.items() if shown.get(key, item) != item]
        self._shown = mine
        if added:
            self._add(added)
        if changed:
            self._entry.async_create_task(
                self._coordinator.hass,
                self._async_recreate(changed),
                f"{self._coordinator.name} re-created entities",
            )

    def _add(self, descriptions: list[PointDescription]) -> None:
        coordinator = self._coordinator
        self._add_entities([self._create(coordinator, item) for item in descriptions])

    async def _async_recreate(self, descriptions: list[PointDescription]) -> None:
        """Remove the entities of changed descriptions, then create them anew."""
        registry = er.async_get(self._coordinator.hass)
        serial_number = self._coordinator.data.info.serial_number
        for description in descriptions:
            entity_id = registry.async_get_entity_id(
                self._platform, DOMAIN, f"{serial_number}_{description.key}"
            )
            if entity_id is not None and entity_id in self._entity_platform.entities:
                # The registry entry stays: the new entity takes it over.
                await self._entity_platform.async_remove_entity(entity_id)
        self._add(descriptions)
