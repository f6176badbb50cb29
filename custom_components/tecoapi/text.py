"""Texts: writable string points."""

from typing import Final

from homeassistant.components.text import TextEntity
from homeassistant.const import Platform

from .entity import TecoApiValueEntity, entity_platform

PARALLEL_UPDATES = 1

# A PLC STRING holds at most 255 characters. The PLC takes ASCII only: text with
# other characters is refused by the write path with a translated error (a
# pattern here would give the user a raw regular expression instead).
MAX_LENGTH: Final = 255


class TecoApiText(TecoApiValueEntity[str], TextEntity):
    """A writable string (ASCII, up to 255 characters)."""

    _attr_native_max = MAX_LENGTH
    _value_type = str


async_setup_entry = entity_platform(Platform.TEXT, points=TecoApiText)
