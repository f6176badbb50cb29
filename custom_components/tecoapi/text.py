"""Texts: writable string points."""

from typing import Final

from homeassistant.components.text import TextEntity
from homeassistant.const import Platform

from .coordinator import PlcCoordinator
from .entity import PlcValueEntity
from .follower import entity_platform
from .mapping import PointDescription

PARALLEL_UPDATES = 1

# Text of a type that says no length (a Tecomat STRING holds 255 characters and
# says so). Characters the device's encoding lacks are refused by the write path
# with a translated error (a pattern here would give the user a raw regular
# expression instead).
MAX_LENGTH: Final = 255


class PlcText(PlcValueEntity[str], TextEntity):
    """A writable string, as long as its data type allows."""

    _value_type = str

    def __init__(
        self, coordinator: PlcCoordinator, description: PointDescription
    ) -> None:
        """Take the longest text the point's type holds."""
        super().__init__(coordinator, description)
        self._attr_native_max = self.point.type.length or MAX_LENGTH


async_setup_entry = entity_platform(Platform.TEXT, points=PlcText)
