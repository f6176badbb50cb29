"""Base entities: one device per PLC, a unique ID per point, availability."""

from collections.abc import Callable, Iterable
from dataclasses import replace
from datetime import date, datetime
from typing import cast, override

from homeassistant.const import Platform
from homeassistant.core import callback
from homeassistant.helpers.device_registry import (
    CONNECTION_NETWORK_MAC,
    DeviceInfo,
    format_mac,
)
from homeassistant.helpers.entity import Entity
from homeassistant.helpers.entity_platform import AddConfigEntryEntitiesCallback
from homeassistant.helpers.update_coordinator import CoordinatorEntity

from .const import DOMAIN, MANUFACTURER, PlainVariables
from .coordinator import TecoApiConfigEntry, TecoApiCoordinator
from .mapping import entity_name, platform_for
from .pytecoapi import Point, PointMeta

type PointValue = bool | int | float | str | date | datetime | None
"""A point's value as the client types it (None: unknown)."""


class TecoApiEntity(CoordinatorEntity[TecoApiCoordinator]):
    """An entity of a Tecomat PLC, told about updates of its own key only."""

    _attr_has_entity_name = True

    def __init__(self, coordinator: TecoApiCoordinator, key: str) -> None:
        """Attach the entity to the PLC's device; ``key`` selects its updates."""
        super().__init__(coordinator, context=key)
        info = coordinator.data.info
        self._attr_unique_id = f"{info.serial_number}_{key}"
        self._attr_device_info = DeviceInfo(
            identifiers={(DOMAIN, info.serial_number)},
            manufacturer=MANUFACTURER,
            model=info.type,
            name=f"Tecomat {info.type}" if info.type else "Tecomat PLC",
            serial_number=info.serial_number,
            sw_version=info.firmware,
            configuration_url=coordinator.client.base_url,
        )
        if info.mac:
            self._attr_device_info["connections"] = {
                (CONNECTION_NETWORK_MAC, format_mac(info.mac))
            }


class TecoApiPointEntity(TecoApiEntity):
    """An entity showing one point (variable) of the PLC."""

    def __init__(self, coordinator: TecoApiCoordinator, point: Point) -> None:
        """Name the entity from ``attr.title`` (or the path)."""
        super().__init__(coordinator, point.key)
        self.point = point
        self._attr_name = entity_name(point)
        if point.meta is not None:
            self._attr_entity_registry_enabled_default = point.meta.visibility
        else:
            self._attr_entity_registry_enabled_default = (
                coordinator.options.plain_variables is PlainVariables.ENABLED
            )

    @property
    def meta(self) -> PointMeta | None:
        """The point's latest attributes (None for a plain variable)."""
        return self.coordinator.point_meta(self.point.key)

    @property
    def point_value(self) -> PointValue:
        """The point's latest value."""
        return cast("PointValue", self.coordinator.data.values.get(self.point.key))

    @property
    @override
    def available(self) -> bool:
        """Whether the point can be shown.

        Not when polling fails, the PLC is not running, or the point is missing,
        gone from the program or ``enable=false``.
        """
        meta = self.meta
        data = self.coordinator.data
        return (
            super().available
            and data.running
            and self.point.key in self.coordinator.points
            and self.point.key not in data.missing
            and (meta is None or meta.enable)
        )

    @override
    async def async_added_to_hass(self) -> None:
        """Listen for the point's updates; let the coordinator find the entity."""
        await super().async_added_to_hass()
        self.async_on_remove(
            self.coordinator.async_track_point_entity(self.point.key, self)
        )

    @override
    def _handle_coordinator_update(self) -> None:
        """Follow a changed path spelling or title, then write the state."""
        self.point = self.coordinator.points.get(self.point.key, self.point)
        if (meta := self.meta) is not None:
            self._attr_name = entity_name(replace(self.point, meta=meta))
        super()._handle_coordinator_update()


@callback
def async_add_point_entities(
    entry: TecoApiConfigEntry,
    platform: Platform,
    create: Callable[[TecoApiCoordinator, Point], Entity],
    async_add_entities: AddConfigEntryEntitiesCallback,
) -> None:
    """Create the platform's entities for the points now and for those added later.

    A new PLC program may bring points for this platform; the coordinator then
    calls back (see ``reconcile``).
    """
    coordinator = entry.runtime_data

    @callback
    def add_points(points: Iterable[Point]) -> None:
        async_add_entities(
            [
                create(coordinator, point)
                for point in points
                if platform_for(point) is platform
            ]
        )

    add_points(coordinator.points.values())
    entry.async_on_unload(coordinator.async_add_point_platform(platform, add_points))
