"""The Tecomat TecoApi integration: PLC variables as Home Assistant entities."""

from typing import TYPE_CHECKING, Final

from homeassistant.const import Platform
from homeassistant.core import HomeAssistant
from homeassistant.helpers import config_validation as cv
from homeassistant.helpers.typing import ConfigType

from .const import DOMAIN
from .coordinator import TecoApiConfigEntry, TecoApiCoordinator
from .issues import async_clear_plc_issues
from .options import TecoApiOptions
from .reconcile import async_remove_stale_entries
from .services import async_setup_services

CONFIG_SCHEMA: Final = cv.config_entry_only_config_schema(DOMAIN)
PLATFORMS: Final = [
    Platform.BINARY_SENSOR,
    Platform.NUMBER,
    Platform.SENSOR,
    Platform.SWITCH,
    Platform.TEXT,
]


async def async_setup(hass: HomeAssistant, config: ConfigType) -> bool:
    """Register the actions (they target a config entry, loaded or not)."""
    async_setup_services(hass)
    return True


async def async_setup_entry(hass: HomeAssistant, entry: TecoApiConfigEntry) -> bool:
    """Discover the PLC's points and create their entities."""
    coordinator = TecoApiCoordinator(hass, entry)
    await coordinator.async_config_entry_first_refresh()
    entry.runtime_data = coordinator
    catalogue = coordinator.catalogue
    if TYPE_CHECKING:
        assert catalogue is not None
    # Points the options now filter out, that the program no longer has, or
    # that moved to another platform leave no orphaned registry entry.
    async_remove_stale_entries(
        hass,
        entry.entry_id,
        coordinator.serial_number,
        coordinator.points,
        catalogue.skipped_roots,
    )
    await hass.config_entries.async_forward_entry_setups(entry, PLATFORMS)
    entry.async_on_unload(entry.add_update_listener(_async_entry_updated))
    return True


async def async_unload_entry(hass: HomeAssistant, entry: TecoApiConfigEntry) -> bool:
    """Remove the entry's entities; the coordinator stops with the entry."""
    if unloaded := await hass.config_entries.async_unload_platforms(entry, PLATFORMS):
        # Nobody watches the PLC's mode any more.
        async_clear_plc_issues(hass, entry)
    return unloaded


async def async_remove_entry(hass: HomeAssistant, entry: TecoApiConfigEntry) -> None:
    """Remove what the entry left behind: its repair issues."""
    async_clear_plc_issues(hass, entry)


async def _async_entry_updated(hass: HomeAssistant, entry: TecoApiConfigEntry) -> None:
    """Apply changed options: intervals at once, anything else by a reload."""
    coordinator = entry.runtime_data
    options = TecoApiOptions.from_entry(entry)
    if options.same_entities(coordinator.options):
        await coordinator.async_apply_options(options)
    else:
        hass.config_entries.async_schedule_reload(entry.entry_id)
