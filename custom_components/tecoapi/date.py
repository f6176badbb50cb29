"""Dates: writable DATE points."""

from datetime import date
from typing import override

from homeassistant.components.date import DateEntity
from homeassistant.const import Platform

from .entity import TecoApiPointEntity, entity_platform

PARALLEL_UPDATES = 1


class TecoApiDate(TecoApiPointEntity, DateEntity):
    """A writable DATE."""

    @property
    @override
    def native_value(self) -> date | None:
        """The point's date."""
        value = self.point_value
        return value if isinstance(value, date) else None

    @override
    async def async_set_value(self, value: date) -> None:
        """Write the date to the PLC."""
        await self.coordinator.async_write(self.key, value)


async_setup_entry = entity_platform(Platform.DATE, points=TecoApiDate)
