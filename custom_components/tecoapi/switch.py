"""Switches: writable boolean points."""

from typing import Any, override

from homeassistant.components.switch import SwitchEntity
from homeassistant.const import Platform
from homeassistant.core import HomeAssistant
from homeassistant.helpers.entity_platform import AddConfigEntryEntitiesCallback

from .coordinator import TecoApiConfigEntry
from .entity import TecoApiPointEntity, async_add_point_entities

PARALLEL_UPDATES = 1


async def async_setup_entry(
    hass: HomeAssistant,
    entry: TecoApiConfigEntry,
    async_add_entities: AddConfigEntryEntitiesCallback,
) -> None:
    """Create a switch per writable boolean point."""
    async_add_point_entities(entry, Platform.SWITCH, TecoApiSwitch, async_add_entities)


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
