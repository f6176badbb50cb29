"""The Tecomat TecoApi integration: PLC variables as Home Assistant entities."""

from typing import TYPE_CHECKING, Final

from homeassistant.const import Platform
from homeassistant.core import HomeAssistant, callback
from homeassistant.helpers import config_validation as cv, entity_registry as er

from .const import DOMAIN
from .coordinator import TecoApiConfigEntry, TecoApiCoordinator
from .mapping import platform_for
from .options import TecoApiOptions

CONFIG_SCHEMA: Final = cv.config_entry_only_config_schema(DOMAIN)
PLATFORMS: Final = [
    Platform.BINARY_SENSOR,
    Platform.NUMBER,
    Platform.SENSOR,
    Platform.SWITCH,
    Platform.TEXT,
]


async def async_setup_entry(hass: HomeAssistant, entry: TecoApiConfigEntry) -> bool:
    """Discover the PLC's points and create their entities."""
    coordinator = TecoApiCoordinator(hass, entry)
    await coordinator.async_config_entry_first_refresh()
    entry.runtime_data = coordinator
    _async_remove_unwanted_entities(hass, coordinator)
    await hass.config_entries.async_forward_entry_setups(entry, PLATFORMS)
    entry.async_on_unload(entry.add_update_listener(_async_entry_updated))
    return True


async def async_unload_entry(hass: HomeAssistant, entry: TecoApiConfigEntry) -> bool:
    """Remove the entry's entities; the coordinator stops with the entry."""
    return await hass.config_entries.async_unload_platforms(entry, PLATFORMS)


async def _async_entry_updated(hass: HomeAssistant, entry: TecoApiConfigEntry) -> None:
    """Apply changed options: intervals at once, anything else by a reload."""
    coordinator = entry.runtime_data
    options = TecoApiOptions.from_entry(entry)
    if options.same_entities(coordinator.options):
        await coordinator.async_apply_options(options)
    else:
        hass.config_entries.async_schedule_reload(entry.entry_id)


@callback
def _async_remove_unwanted_entities(
    hass: HomeAssistant, coordinator: TecoApiCoordinator
) -> None:
    """Remove registry entries of points the options now filter out.

    Also removes an entry whose point moved to another platform (its
    ``readOnly`` flag changed), so the new entity does not leave an orphan.
    """
    catalogue = coordinator.catalogue
    if TYPE_CHECKING:
        assert catalogue is not None
    registry = er.async_get(hass)
    prefix = f"{coordinator.serial_number}_"
    for registry_entry in er.async_entries_for_config_entry(
        registry, coordinator.config_entry.entry_id
    ):
        key = registry_entry.unique_id.removeprefix(prefix)
        if key not in catalogue.points:
            continue
        point = coordinator.points.get(key)
        if point is None or platform_for(point) != registry_entry.domain:
            registry.async_remove(registry_entry.entity_id)
