"""PLC Bridge: the points of PLCs and their gateways as Home Assistant entities."""

from dataclasses import replace
from functools import partial
from typing import Any, Final

from homeassistant.const import Platform
from homeassistant.core import HomeAssistant, callback
from homeassistant.exceptions import ConfigEntryError
from homeassistant.helpers import config_validation as cv, device_registry as dr
from homeassistant.helpers.typing import ConfigType

from .applier import create_entry_source
from .compat import entry_result
from .connection import descriptor_of
from .const import DOMAIN, ENTRY_MINOR_VERSION, ENTRY_VERSION
from .coordinator import PlcConfigEntry, PlcCoordinator
from .device_info import (
    async_create_declared_devices,
    async_place_entities,
    plc_device_info,
    plc_device_name,
)
from .issues import async_clear_plc_issues
from .options import PlcOptions, reconciled_options
from .overrides import async_load_overrides, async_remove_overrides
from .point_maps import async_load_point_map, async_remove_point_map
from .pyplc.core.descriptor import CONF_POINT_MAP, SourceDescriptor
from .reconcile import (
    async_follow_program_title,
    async_keep_names_in_own_areas,
    async_remove_stale_devices,
    async_remove_stale_entries,
    named_in_own_areas,
)
from .selection import compositions_of
from .services import async_setup_services
from .source_cache import EntryCache

CONFIG_SCHEMA: Final = cv.config_entry_only_config_schema(DOMAIN)
PLATFORMS: Final = [
    Platform.BINARY_SENSOR,
    Platform.BUTTON,
    Platform.CLIMATE,
    Platform.COVER,
    Platform.DATE,
    Platform.DATETIME,
    Platform.EVENT,
    Platform.LIGHT,
    Platform.NUMBER,
    Platform.SENSOR,
    Platform.SWITCH,
    Platform.TEXT,
    Platform.TIME,
]


async def async_setup(hass: HomeAssistant, config: ConfigType) -> bool:
    """Register the actions (they target a config entry, loaded or not).

    A value the user typed wrongly is refused with a translated
    ``ServiceValidationError``: the frontend shows it to the user; how Home
    Assistant logs it is Home Assistant's to decide.
    """
    async_setup_services(hass)
    return True


async def async_migrate_entry(hass: HomeAssistant, entry: PlcConfigEntry) -> bool:
    """Bring an entry of an earlier version to this one's; its IDs never change.

    1.1 to 1.2: a push server's settings are kept in one mapping too (``push``),
    and stay where 1.1 reads them (``options.reconciled_options``): the release
    before reads them still. An entry of a later major version is a newer
    release's: it is left alone (it does not load); one of a later minor
    version loads as it is.
    """
    if entry.version > ENTRY_VERSION:
        return False
    if entry.minor_version < ENTRY_MINOR_VERSION:
        hass.config_entries.async_update_entry(
            entry,
            options=reconciled_options(_descriptor(entry), entry.options),
            minor_version=ENTRY_MINOR_VERSION,
        )
    return True


def _descriptor(entry: PlcConfigEntry) -> SourceDescriptor | None:
    """Return the descriptor of an entry's source; None for a newer release's source."""
    try:
        return descriptor_of(entry.data)
    except KeyError:
        return None


@callback
def _async_reconcile_options(hass: HomeAssistant, entry: PlcConfigEntry) -> None:
    """Read back what an older release changed in the options after a downgrade.

    The release before this one (0.3) reads and writes a push server's settings
    at the top level of the options only: switched on, off or moved there, they
    are taken into ``push`` again, so that push is as the user left it
    (``options.reconciled_options``). An entry of a later minor version is a
    newer release's, kept in step by it: it loads as it is.
    """
    if entry.minor_version > ENTRY_MINOR_VERSION:
        return
    options = reconciled_options(_descriptor(entry), entry.options)
    if options != entry.options:
        hass.config_entries.async_update_entry(entry, options=options)


async def async_setup_entry(hass: HomeAssistant, entry: PlcConfigEntry) -> bool | None:
    """Discover the PLC's points and create their entities.

    A failure raises; the result is what the running release expects of a setup
    that succeeded (compat.entry_result).
    """
    try:
        descriptor_of(entry.data)
    except KeyError as err:
        # An entry of a source this version does not have (a newer one's).
        raise ConfigEntryError(
            translation_domain=DOMAIN,
            translation_key="source_unknown",
            translation_placeholders={"source": str(err)},
        ) from err
    _async_reconcile_options(hass, entry)
    options = PlcOptions.from_entry(entry)
    point_map = None
    map_id = entry.data.get(CONF_POINT_MAP)
    if (
        map_id is not None
        and (point_map := await async_load_point_map(hass, map_id)) is None
    ):
        raise ConfigEntryError(
            translation_domain=DOMAIN, translation_key="point_map_lost"
        )
    overrides = await async_load_overrides(hass, entry.entry_id)
    source = create_entry_source(hass, entry, options, point_map, overrides)
    coordinator = PlcCoordinator(
        hass, entry, source, point_map=point_map, overrides=overrides
    )
    await coordinator.async_config_entry_first_refresh()
    # A title the config flow gave before a location was part of titles (two
    # Mervis controllers of one project were both "Mervis · DemoDum"), or before
    # titles said the way in, says it now, unless renamed.
    info = coordinator.data.info
    async_follow_program_title(hass, entry, replace(info, location=None), info)
    coordinator.device_name = plc_device_name(coordinator)
    entry.runtime_data = coordinator
    # The PLC's device first: the groups' devices sit under it.
    dr.async_get(hass).async_get_or_create(
        config_entry_id=entry.entry_id, **plc_device_info(coordinator)
    )
    # The devices the source declares below it, each after its parent.
    async_create_declared_devices(coordinator)
    # Points the options now filter out, that the program no longer has, or
    # that moved to another platform leave no orphaned registry entry.
    async_remove_stale_entries(hass, entry, coordinator.data)
    named = named_in_own_areas(hass, entry)
    await hass.config_entries.async_forward_entry_setups(entry, PLATFORMS)
    async_keep_names_in_own_areas(hass, named)
    # The entities listen: the points they show are known. A push source pushes
    # them from now on, not from the first poll an interval later.
    coordinator.async_start_following()
    # Group devices the options or the program no longer have, now empty.
    async_remove_stale_devices(hass, entry, coordinator.data)
    connection = {
        key: entry.data.get(key) for key in descriptor_of(entry.data).connection_keys
    }
    entry.async_on_unload(
        entry.add_update_listener(partial(_async_entry_updated, connection=connection))
    )
    return entry_result(True)


async def async_unload_entry(hass: HomeAssistant, entry: PlcConfigEntry) -> bool | None:
    """Remove the entry's entities; the coordinator stops with the entry.

    A platform that does not unload fails it as the running release expects
    (compat.entry_result).
    """
    if unloaded := await hass.config_entries.async_unload_platforms(entry, PLATFORMS):
        # Nobody watches the PLC's mode any more.
        async_clear_plc_issues(hass, entry)
    return entry_result(unloaded)


async def async_remove_entry(hass: HomeAssistant, entry: PlcConfigEntry) -> None:
    """Remove what the entry left behind: its repair issues, point map, overrides, cache."""
    async_clear_plc_issues(hass, entry)
    if (map_id := entry.data.get(CONF_POINT_MAP)) is not None:
        await async_remove_point_map(hass, map_id)
    await async_remove_overrides(hass, entry.entry_id)
    await EntryCache(hass, entry.entry_id).remove()


async def _async_entry_updated(
    hass: HomeAssistant,
    entry: PlcConfigEntry,
    *,
    connection: dict[str, Any],
) -> None:
    """Follow a changed entry: in place, but for a new connection.

    The config flow's reauthentication and reconfiguration only update the
    entry and leave the reload to this listener (``connection`` is what the
    running coordinator was built from). Options and composed devices
    (subentries added, changed or removed) apply in place: only the entities
    they add, remove or move change (``applier.OptionsApplier``); push switched on
    or off swaps the coordinator's source. A new title needs nothing.
    """
    if any(entry.data.get(key) != value for key, value in connection.items()):
        hass.config_entries.async_schedule_reload(entry.entry_id)
        return
    coordinator = entry.runtime_data
    if await coordinator.applier.async_apply_options(
        PlcOptions.from_entry(entry), compositions_of(entry.subentries)
    ):
        # Entities whose device the new options change move to it; group
        # devices left empty go.
        async_place_entities(coordinator)
        async_remove_stale_devices(hass, entry, coordinator.data)
