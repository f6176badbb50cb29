"""Names whose home moved between the Home Assistant releases this integration supports.

The floor is Home Assistant 2026.2, the primary target 2026.10, the newest release
2026.11 (a smoke run, scripts/smoke). Type checking
runs against the primary target; at run time each name comes from where the
running release keeps it (2026.10 moved several into the platforms' ``const``
modules and still re-exports them from the platforms).
"""

from typing import TYPE_CHECKING, Final, cast

from homeassistant.config_entries import ConfigEntries
from homeassistant.core import DOMAIN as HOMEASSISTANT_DOMAIN, HomeAssistant
from homeassistant.exceptions import ConfigEntryError
from homeassistant.helpers import device_registry as dr, entity_registry as er

if TYPE_CHECKING:
    from homeassistant.components.binary_sensor.const import BinarySensorDeviceClass
    from homeassistant.components.climate.const import (
        ClimateEntityFeature,
        HVACAction,
        HVACMode,
    )
    from homeassistant.components.cover.const import (
        CoverDeviceClass,
        CoverEntityFeature,
    )
    from homeassistant.components.light.const import (
        ATTR_BRIGHTNESS,
        ATTR_COLOR_TEMP_KELVIN,
        ATTR_RGB_COLOR,
        ColorMode,
    )
    from homeassistant.components.switch.const import SwitchDeviceClass
    import probatio as vol
else:
    # 2026.10 validates with probatio and aliases it as `voluptuous`; 2026.2 has
    # voluptuous itself. Both accept the same schemas.
    from homeassistant.components.binary_sensor import BinarySensorDeviceClass
    from homeassistant.components.climate import (
        ClimateEntityFeature,
        HVACAction,
        HVACMode,
    )
    from homeassistant.components.cover import CoverDeviceClass, CoverEntityFeature
    from homeassistant.components.light import (
        ATTR_BRIGHTNESS,
        ATTR_COLOR_TEMP_KELVIN,
        ATTR_RGB_COLOR,
        ColorMode,
    )
    from homeassistant.components.switch import SwitchDeviceClass
    import voluptuous as vol

PARTS_PER_MILLION: Final = "ppm"
"""The unit: ``UnitOfRatio.PARTS_PER_MILLION`` in 2026.10, which deprecates
``CONCENTRATION_PARTS_PER_MILLION``; 2026.2 has only the latter."""

# 2026.10 links a device to the one it sits under by the registry's device ID
# (`via_device`, the identifier, is deprecated there); 2026.2 knows only the
# identifier.
VIA_DEVICE_ID: Final = "via_device_id" in dr.DeviceInfo.__annotations__


AREA_IN_ENTITY_ID: Final = hasattr(er, "EntityNamePart")
"""Whether new entity IDs start with the device's area (2026.6 and later).

An ID is then made of the area, the device's name and the entity's; before, of
the device's name and the entity's only.
"""


ENTRY_RESULT_NONE: Final = hasattr(ConfigEntries, "async_unload_platforms_or_raise")
"""Whether a config entry's setup, unload and migration return None (2026.11 and later).

There a failure raises and a returned boolean is deprecated (False raises); before,
they return whether they succeeded (anything else is an error).
"""


def entry_result(done: bool) -> bool | None:
    """Return what a config entry's setup or unload returns when it is ``done`` (or not).

    2026.11 and later: None, and a failure raises the error Home Assistant's own
    ``async_unload_platforms_or_raise`` raises; before: ``done``.
    """
    if not ENTRY_RESULT_NONE:
        return done
    if not done:
        raise ConfigEntryError(
            translation_domain=HOMEASSISTANT_DOMAIN,
            translation_key="unload_platforms_failed",
        )
    return None


def entry_device(
    hass: HomeAssistant,
    entry_id: str,
    *,
    identifier: tuple[str, str] | None = None,
    connection: tuple[str, str] | None = None,
) -> dr.DeviceEntry | None:
    """Return a config entry's device with an identifier (or a connection).

    2026.10 keeps identifiers and connections unique per config entry only, and
    looks them up per entry; 2026.2 keeps them unique across entries.
    """
    registry = dr.async_get(hass)
    if hasattr(registry, "async_get_device_by_identifier"):
        if identifier is not None:
            return registry.async_get_device_by_identifier(identifier, entry_id)
        assert connection is not None
        return registry.async_get_device_by_connection(connection, entry_id)
    device = registry.async_get_device(  # 2026.2
        identifiers={identifier} if identifier is not None else None,
        connections={connection} if connection is not None else None,
    )
    return device if device is not None and entry_id in device.config_entries else None


def via_device(
    hass: HomeAssistant, entry_id: str, identifier: tuple[str, str]
) -> dr.DeviceInfo:
    """Return the device-info item linking a device to an entry's ``identifier``."""
    if not VIA_DEVICE_ID:
        return cast("dr.DeviceInfo", {"via_device": identifier})
    device = entry_device(hass, entry_id, identifier=identifier)
    return dr.DeviceInfo() if device is None else dr.DeviceInfo(via_device_id=device.id)


__all__ = [
    "AREA_IN_ENTITY_ID",
    "ATTR_BRIGHTNESS",
    "ATTR_COLOR_TEMP_KELVIN",
    "ATTR_RGB_COLOR",
    "ENTRY_RESULT_NONE",
    "PARTS_PER_MILLION",
    "BinarySensorDeviceClass",
    "ClimateEntityFeature",
    "ColorMode",
    "CoverDeviceClass",
    "CoverEntityFeature",
    "HVACAction",
    "HVACMode",
    "SwitchDeviceClass",
    "entry_device",
    "entry_result",
    "via_device",
    "vol",
]
