"""What a source keeps beside its entry between runs: a versioned store each.

A source may keep what it learned of its device (a gateway's address space, a
thousand times larger than a poll) so that a restart asks the device only
whether it changed. Each entry has one ``Store`` (``tecoapi.source_cache.<entry
ID>``), given to its source as the ``cache`` of its
:class:`~.pyplc.core.descriptor.SourceContext`; it goes with the entry.
"""

from typing import Any, Final

from homeassistant.core import HomeAssistant
from homeassistant.helpers.storage import Store

from .const import DOMAIN

STORAGE_VERSION: Final = 1


class EntryCache:
    """The store of one entry's source (a :class:`~.pyplc.core.descriptor.SourceCache`)."""

    def __init__(self, hass: HomeAssistant, entry_id: str) -> None:
        """Name the entry's store; nothing is read yet."""
        self._store: Store[Any] = Store(
            hass, STORAGE_VERSION, f"{DOMAIN}.source_cache.{entry_id}"
        )

    async def load(self) -> Any:
        """Return what the source saved last (None: nothing)."""
        return await self._store.async_load()

    async def save(self, data: Any) -> None:
        """Keep what the source gives (written at once, not held in memory after)."""
        await self._store.async_save(data)

    async def remove(self) -> None:
        """Remove the store (the entry is gone)."""
        await self._store.async_remove()
