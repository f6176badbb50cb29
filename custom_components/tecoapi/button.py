"""Buttons: points that are written and never read (an intercom's call)."""

from typing import override

from homeassistant.components.button import ButtonEntity
from homeassistant.const import Platform

from .entity import PlcPointEntity
from .follower import entity_platform
from .pyplc import ValueKind

PARALLEL_UPDATES = 1


class PlcButton(PlcPointEntity, ButtonEntity):
    """A write-only flag or integer: a press writes true (1) to it."""

    @override
    async def async_press(self) -> None:
        """Write true (a flag) or 1 (an integer) to the device."""
        value = True if self.point.kind is ValueKind.BOOL else 1
        await self.coordinator.async_write(self.key, value)


async_setup_entry = entity_platform(Platform.BUTTON, points=PlcButton)
