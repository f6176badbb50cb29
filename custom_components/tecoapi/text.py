"""Texts: writable string points."""

from typing import Final, override

from homeassistant.components.text import TextEntity
from homeassistant.const import Platform

from .entity import TecoApiPointEntity, entity_platform

PARALLEL_UPDATES = 1

# A PLC STRING holds at most 255 characters. The PLC takes ASCII only: text with
# other characters is refused by the write path with a translated error (a
# pattern here would give the user a raw regular expression instead).
MAX_LENGTH: Final = 255


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


async_setup_entry = entity_platform(Platform.TEXT, points=TecoApiText)
