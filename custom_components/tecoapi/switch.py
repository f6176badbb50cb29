"""Switches: writable boolean points."""

from typing import Any, override

from homeassistant.components.switch import SwitchEntity
from homeassistant.const import Platform

from .entity import TecoApiPointEntity, point_platform

PARALLEL_UPDATES = 1


class TecoApiSwitch(TecoApiPointEntity, SwitchEntity):
    """A writable boolean point."""

    @property
    @override
    def is_on(self) -> bool | None:
        """The point's value."""
        return self.point_is_on

    @override
    async def async_turn_on(self, **kwargs: Any) -> None:
        """Write true to the PLC."""
        await self.coordinator.async_write(self.key, True)

    @override
    async def async_turn_off(self, **kwargs: Any) -> None:
        """Write false to the PLC."""
        await self.coordinator.async_write(self.key, False)


async_setup_entry = point_platform(Platform.SWITCH, TecoApiSwitch)
