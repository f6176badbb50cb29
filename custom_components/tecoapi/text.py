"""Texts: writable string points."""

from typing import Final, override

from homeassistant.components.text import TextEntity
from homeassistant.const import Platform
from homeassistant.core import HomeAssistant
from homeassistant.helpers.entity_platform import AddConfigEntryEntitiesCallback

from .coordinator import TecoApiConfigEntry
from .entity import TecoApiPointEntity, async_add_point_entities

PARALLEL_UPDATES = 1

# A PLC STRING holds at most 255 characters. The PLC takes ASCII only: text with
# other characters is refused by the write path with a translated error (a
# pattern here would give the user a raw regular expression instead).
MAX_LENGTH: Final = 255


async def async_setup_entry(
    hass: HomeAssistant,
    entry: TecoApiConfigEntry,
    async_add_entities: AddConfigEntryEntitiesCallback,
) -> None:
    """Create a text per writable string point."""
    async_add_point_entities(entry, Platform.TEXT, TecoApiText, async_add_entities)


class TecoApiText(TecoApiPointEntity, TextEntity):
    """A writable string (ASCII, up to 255 characters)."""

    _attr_native_max = MAX_LENGTH

    @property
    @override
    def native_value(self) -> str | None:
        """The point's value."""
        value = self.point_value
        return value if isinstance(value, str) else None

    @override
    async def async_set_value(self, value: str) -> None:
        """Write the text to the PLC."""
        await self.coordinator.async_write(self.key, value)
