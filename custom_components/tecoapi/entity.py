"""Base entities: one device per PLC, a unique ID per point, availability."""

from dataclasses import replace
from datetime import date, datetime
from typing import cast, override

from homeassistant.helpers.device_registry import (
    CONNECTION_NETWORK_MAC,
    DeviceInfo,
    format_mac,
)
from homeassistant.helpers.update_coordinator import CoordinatorEntity

from .const import DOMAIN, MANUFACTURER, PlainVariables
from .coordinator import TecoApiCoordinator
from .mapping import entity_name
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
        """Unavailable when polling fails, the point is missing or ``enable=false``."""
        meta = self.meta
        return (
            super().available
            and self.point.key not in self.coordinator.data.missing
            and (meta is None or meta.enable)
        )

    @override
    def _handle_coordinator_update(self) -> None:
        """Follow a changed title, then write the state."""
        if (meta := self.meta) is not None:
            self._attr_name = entity_name(replace(self.point, meta=meta))
        super()._handle_coordinator_update()
