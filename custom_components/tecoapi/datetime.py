"""Dates and times: writable DT points (UTC on the PLC)."""

from datetime import datetime
from typing import override

from homeassistant.components.datetime import DateTimeEntity
from homeassistant.const import Platform

from .entity import TecoApiPointEntity, entity_platform

PARALLEL_UPDATES = 1


class TecoApiDateTime(TecoApiPointEntity, DateTimeEntity):
    """A writable date and time."""

    @property
    @override
    def native_value(self) -> datetime | None:
        """The point's date and time (UTC)."""
        value = self.point_value
        return value if isinstance(value, datetime) else None

    @override
    async def async_set_value(self, value: datetime) -> None:
        """Write the date and time to the PLC (in UTC)."""
        await self.coordinator.async_write(self.key, value)


async_setup_entry = entity_platform(Platform.DATETIME, points=TecoApiDateTime)
