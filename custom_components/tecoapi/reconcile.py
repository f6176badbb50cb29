"""Keep Home Assistant's entities in step with the PLC's catalogue of points.

A Mosaic download may add variables, remove them, or change their metadata. The
coordinator notices the new ``userProg.stamp``, discovers again, and reconciles
here, live, without reloading the entry:

- a new point gets an entity on its platform;
- a point that vanished loses its entity and its entity registry entry;
- a point whose platform changed (``readOnly`` flipped, or its kind changed) keeps
  its unique ID, ``<serial>_<path in lower case>``, on the new platform's domain:
  the old platform's registry entry is removed and a new entity is created, so no
  orphan remains (the entity ID changes with the domain);
- a point whose unit or kind changed on the same platform is re-created under the
  same registry entry, keeping its entity ID and the user's customisations, so that
  unit, device class and state class are registered anew;
- titles, ranges and the enable/visibility flags follow without re-creation (the
  entities read them from the coordinator's data).

The config entry's title names the program too; it follows the new program's name
unless the user renamed the entry.
"""

from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from typing import Self

from homeassistant.config_entries import ConfigEntry
from homeassistant.const import Platform
from homeassistant.core import HomeAssistant, callback
from homeassistant.helpers import entity_registry as er

from .config_flow import entry_title
from .const import STATUS_KEYS
from .mapping import UnitMapping, platform_for, unit_mapping
from .pytecoapi import PlcInfo, Point, ValueKind

type EntityShape = tuple[Platform, ValueKind, bool, UnitMapping | None]
"""What an entity fixes when it is created: platform, kind, metadata, unit."""


def entity_shape(point: Point) -> EntityShape:
    """Return what the entity of a point fixes when it is created."""
    return (platform_for(point), point.kind, point.is_api_object, unit_mapping(point))


@dataclass(frozen=True, slots=True)
class CatalogueChange:
    """How the selected points changed between two discoveries (keys)."""

    added: frozenset[str]
    removed: frozenset[str]
    moved: frozenset[str]
    """Points now shown on another platform."""
    reshaped: frozenset[str]
    """Points on the same platform whose kind or unit changed."""

    @classmethod
    def between(cls, old: Mapping[str, Point], new: Mapping[str, Point]) -> Self:
        """Compare the points before and after a program change."""
        kept = old.keys() & new.keys()
        moved = {
            key for key in kept if platform_for(old[key]) != platform_for(new[key])
        }
        reshaped = {
            key
            for key in kept - moved
            if entity_shape(old[key]) != entity_shape(new[key])
        }
        return cls(
            added=frozenset(new.keys() - old.keys()),
            removed=frozenset(old.keys() - new.keys()),
            moved=frozenset(moved),
            reshaped=frozenset(reshaped),
        )

    @property
    def to_create(self) -> frozenset[str]:
        """Points that need a new entity object."""
        return self.added | self.moved | self.reshaped

    def __bool__(self) -> bool:
        """Whether any entity has to change."""
        return bool(self.added or self.removed or self.moved or self.reshaped)


def _under(key: str, roots: Iterable[str]) -> bool:
    """Whether a point key lies in one of the (lower-case) roots."""
    return any(
        key == root or key.startswith((f"{root}.", f"{root}[")) for root in roots
    )


@callback
def async_remove_stale_entries(
    hass: HomeAssistant,
    entry_id: str,
    serial_number: str,
    points: Mapping[str, Point],
    skipped_roots: Iterable[str],
) -> list[str]:
    """Remove registry entries that no selected point backs on their platform.

    Covers points that vanished from the PLC or were filtered out by the options,
    and the old platform's entry of a point that moved. PLC status entities stay,
    and so do points under roots discovery skipped (the PLC could not read them
    this time; they may come back). Returns the removed entity IDs.
    """
    registry = er.async_get(hass)
    prefix = f"{serial_number}_"
    skipped = [root.lower() for root in skipped_roots]
    removed: list[str] = []
    for registry_entry in er.async_entries_for_config_entry(registry, entry_id):
        key = registry_entry.unique_id.removeprefix(prefix)
        if key in STATUS_KEYS:
            continue
        point = points.get(key)
        if point is None and _under(key, skipped):
            continue
        if point is None or platform_for(point) != registry_entry.domain:
            registry.async_remove(registry_entry.entity_id)
            removed.append(registry_entry.entity_id)
    return removed


@callback
def async_follow_program_title(
    hass: HomeAssistant, entry: ConfigEntry, previous: PlcInfo, info: PlcInfo
) -> None:
    """Retitle the entry after a new program, unless the user renamed it.

    The title is replaced only while it is the one the config flow gave for the
    previous program (``CP-2080 · FAMILY_HOUSE v1.3``).
    """
    title = entry_title(info)
    if entry.title == entry_title(previous) and entry.title != title:
        hass.config_entries.async_update_entry(entry, title=title)
