"""What the user changed of an entry's discovered points: a versioned store beside it.

A source that discovers its points (a PLC's program, a gateway's address
space) is told what the user changed of them (``pyplc.core.overrides``: a
variable made writable, a unit, a range, a contact inverted) by point key. They
are kept in a Home Assistant ``Store`` of their own beside the entry
(``tecoapi.overrides.<entry ID>``), not in its options: an entry keeps them
whatever its options become (a release before them rewrites the options it
knows and nothing else), they may be many (a building's channels), and the
entry's data and options stay as the previous release stored them, so no
migration is needed and that release loads the entry as it was. They go with
the entry.
"""

from collections.abc import Mapping
from typing import Any, Final

from homeassistant.core import HomeAssistant
from homeassistant.helpers.storage import Store

from .const import DOMAIN
from .pyplc.core.models import PointOverride
from .pyplc.core.overrides import overrides_from_json, overrides_json

STORAGE_VERSION: Final = 1
"""The version of the stored overrides (``{"points": {key: changes}}``)."""


def _store(hass: HomeAssistant, entry_id: str) -> Store[dict[str, Any]]:
    return Store(hass, STORAGE_VERSION, f"{DOMAIN}.overrides.{entry_id}")


async def async_load_overrides(
    hass: HomeAssistant, entry_id: str
) -> dict[str, PointOverride]:
    """Return an entry's overrides by point key (none stored: none)."""
    data = await _store(hass, entry_id).async_load()
    return {} if data is None else overrides_from_json(data.get("points", {}))


async def async_save_overrides(
    hass: HomeAssistant, entry_id: str, overrides: Mapping[str, PointOverride]
) -> None:
    """Store an entry's overrides in place of those stored (written at once)."""
    await _store(hass, entry_id).async_save({"points": overrides_json(overrides)})


async def async_remove_overrides(hass: HomeAssistant, entry_id: str) -> None:
    """Remove an entry's overrides (the entry is gone)."""
    await _store(hass, entry_id).async_remove()
