"""Keep Home Assistant's registry and the entry's title in step with the device's points.

A new program (a Mosaic download to a Tecomat), a gateway telling other points
or the user's points edited may add points, remove them, or change their
metadata. The source discovers its catalogue again; the coordinator's new data
then carries new point descriptions, and (``async_follow_catalogue``):

- a point that vanished (or that the options no longer select) loses its entity
  and its entity registry entry (:func:`async_remove_stale_entries`);
- a point whose platform changed (``readOnly`` flipped, or its kind changed) keeps
  its unique ID, ``<serial>_<path in lower case>``, on the new platform's domain:
  the old platform's registry entry is removed here and the new platform creates
  the entity, so no orphan remains (the entity ID changes with the domain);
- each platform creates entities for new points, and makes the entity of a point
  whose description changed again under the same registry entry, keeping its
  entity ID and the user's customisations (``follower.entity_platform``);
- titles, ranges and the enable/visibility flags follow without re-creation (the
  entities read them from the coordinator's data);
- a group's device (a top-level struct, program instance or array) whose group is
  gone from the program or from the options leaves the registry once its
  entities have moved or gone (:func:`async_remove_stale_devices`).

The config entry's title names the program too; it follows the new program's name
unless the user renamed the entry.
"""

from collections.abc import Iterable
from dataclasses import replace
from typing import TYPE_CHECKING

from homeassistant.config_entries import ConfigEntry
from homeassistant.core import HomeAssistant, callback
from homeassistant.helpers import device_registry as dr, entity_registry as er

from .const import DOMAIN, STATUS_KEYS
from .mapping import DEVICE_PLATFORMS
from .pyplc import SourceInfo
from .pyplc.core.devices import COMPOSED

if TYPE_CHECKING:
    from .data import PlcData


def entry_title(info: SourceInfo) -> str:
    """Return the entry title: what it reaches, as its user tells two apart.

    The model and its program (``CP-2080 · DOC_TECOAPI v1.0``), where it is
    for a device without one (``FP-I4C · 192.168.1.5:2000, station 1``), or
    both for a device whose program may run on others too (``Mervis ·
    DemoDum · 192.168.1.20``: a location beside a program says so); then the
    way in, where the device may be reached another way too
    (``CP-2080 · DOC_TECOAPI v1.0 · PLCComS``).
    """
    parts = (info.model, info.program_name, info.location)
    title = " · ".join(part for part in parts if part) or info.identity
    return f"{title} · {info.way_in}" if info.way_in else title


def _titles_given(info: SourceInfo) -> set[str]:
    """Return the titles the config flow gave an entry of ``info``.

    Its title now, and the one before titles said the way in.
    """
    return {entry_title(info), entry_title(replace(info, way_in=None))}


def _composed(key: str) -> str | None:
    """Return the subentry ID of a composed device's key (None for any other key)."""
    source, _, ident = key.partition(":")
    return ident if source == COMPOSED else None


def _platform(data: "PlcData", key: str) -> str | None:
    """Return the platform a selected point or typed device of a key is shown on."""
    if (description := data.descriptions.get(key)) is not None:
        return description.platform
    if (device := data.devices.get(key)) is not None:
        return DEVICE_PLATFORMS[device.kind]
    return None


def _under(key: str, groups: Iterable[str]) -> bool:
    """Whether a point key lies in one of the (lower-case) top-level groups."""
    return any(
        key == group or key.startswith((f"{group}.", f"{group}[")) for group in groups
    )


@callback
def async_remove_stale_entries(
    hass: HomeAssistant, entry: ConfigEntry, data: "PlcData"
) -> None:
    """Remove registry entries that no selected point backs on their platform.

    Covers points that vanished from the PLC or were filtered out by the options,
    and the old platform's entry of a point that moved. PLC status entities stay,
    and so do points under the groups discovery skipped (the PLC could not read them
    this time; they may come back).
    """
    registry = er.async_get(hass)
    prefix = f"{data.info.identity}_"
    skipped = [group.lower() for group in data.catalogue.skipped_groups]
    for registry_entry in er.async_entries_for_config_entry(registry, entry.entry_id):
        key = registry_entry.unique_id.removeprefix(prefix)
        if key in STATUS_KEYS or _composed(key) in entry.subentries:
            # A composed device stays while its subentry does (unavailable while
            # its points are missing: a repair issue says so).
            continue
        platform = _platform(data, key)
        if platform is None and _under(key, skipped):
            continue
        if platform is None or platform != registry_entry.domain:
            registry.async_remove(registry_entry.entity_id)


@callback
def async_remove_stale_devices(
    hass: HomeAssistant, entry: ConfigEntry, data: "PlcData"
) -> None:
    """Remove the group devices, and typed devices' own, the selection no longer has.

    Called after the platforms placed their entities, so a group device left by
    an option change (everything on the PLC's device) is empty when it goes: Home
    Assistant removes a removed device's entities with it. The PLC's device and
    composed devices (removed with their subentries) stay, and so do the groups
    discovery skipped this time.
    """
    registry = dr.async_get(hass)
    identity = data.info.identity
    kept = {
        *data.selection.groups,
        *data.selection.places,
        *(group.lower() for group in data.catalogue.skipped_groups),
    }
    prefix = f"{identity}_"
    for device in dr.async_entries_for_config_entry(registry, entry.entry_id):
        if not device.identifiers or any(
            domain != DOMAIN or not ident.startswith(prefix)
            for domain, ident in device.identifiers
        ):
            continue  # the PLC's own device, or one not only a group of this PLC
        keys = {ident.removeprefix(prefix) for _, ident in device.identifiers}
        if keys.isdisjoint(kept) and not any(_composed(key) for key in keys):
            registry.async_remove_device(device.id)  # a group is ours alone


@callback
def async_follow_program_title(
    hass: HomeAssistant, entry: ConfigEntry, previous: SourceInfo, info: SourceInfo
) -> None:
    """Retitle the entry after a new program, unless the user renamed it.

    The title is replaced only while it is one the config flow gave for the
    previous program (``CP-2080 · FAMILY_HOUSE v1.3``). The same follows a
    device's new address in its title (a reconfigured Mervis controller), a
    map's project, and, at setup, a title given before a location was part of
    it (``previous`` without its location) or before titles said the way in
    (``CP-2080 · FAMILY_HOUSE v1.3 · PLCComS``).
    """
    title = entry_title(info)
    if entry.title in _titles_given(previous) and entry.title != title:
        hass.config_entries.async_update_entry(entry, title=title)


@callback
def async_follow_catalogue(
    hass: HomeAssistant, entry: ConfigEntry, previous: "PlcData", data: "PlcData"
) -> None:
    """Follow a new catalogue (a new program, the user's points changed).

    The entry's title follows its program; what the catalogue no longer backs
    leaves the registries. The platforms create the new entities when they
    hear of the data.
    """
    async_follow_program_title(hass, entry, previous.info, data.info)
    async_remove_stale_entries(hass, entry, data)
    async_remove_stale_devices(hass, entry, data)


def named_in_own_areas(hass: HomeAssistant, entry: ConfigEntry) -> dict[str, str]:
    """Return the names of the entry's entities a user put in an area of their own.

    By entity ID: those without a name the user gave, named by this integration
    (as version 0.2 named a thermostat *Obývák* on the device *Termostaty*).
    """
    return {
        item.entity_id: item.original_name
        for item in er.async_entries_for_config_entry(
            er.async_get(hass), entry.entry_id
        )
        if item.area_id is not None and item.name is None and item.original_name
    }


@callback
def async_keep_names_in_own_areas(hass: HomeAssistant, names: dict[str, str]) -> None:
    """Give the name they had to entities in an area of their own that lost it.

    An entity that became its device's main feature (a typed device's thermostat)
    has no name of its own; in an area of its own, Home Assistant would raise
    the repair ``entity_own_area_without_own_name``. Where the user set the area,
    the name it had is kept, as the user's.
    """
    registry = er.async_get(hass)
    for entity_id, name in names.items():
        item = registry.async_get(entity_id)
        if item is not None and item.name is None and not item.original_name:
            registry.async_update_entity(entity_id, name=name)
