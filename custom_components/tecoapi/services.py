"""Actions: read and write any public variable of a PLC, by its path.

Only a source that reads and writes any path (``Capability.PATHS``) takes them;
an entry of another is told so.

``tecoapi.read_variable`` answers the variable's value as response data (any
JSON shape: a scalar, a struct as an object, an array as a list);
``tecoapi.write_variable`` writes a JSON value. Both name the PLC by its config
entry. A path that is a known point is written through the same validated write
path as its entity; any other path is left for the PLC to judge.
"""

import json
import re
from typing import Any, Final, cast

from homeassistant.config_entries import ConfigEntryState
from homeassistant.const import ATTR_CONFIG_ENTRY_ID
from homeassistant.core import (
    HomeAssistant,
    ServiceCall,
    ServiceResponse,
    SupportsResponse,
    callback,
)
from homeassistant.exceptions import ServiceValidationError
from homeassistant.helpers import config_validation as cv

from .compat import vol
from .const import DOMAIN
from .coordinator import PlcCoordinator
from .pyplc.core.descriptor import Capability

SERVICE_READ_VARIABLE: Final = "read_variable"
SERVICE_WRITE_VARIABLE: Final = "write_variable"
ATTR_PATH: Final = "path"
ATTR_VALUE: Final = "value"

# A variable path: a name, then members (.name) and indexes ([3]). Which names
# exist is the PLC's to say; the client encodes whatever a name holds.
VARIABLE_PATH: Final = re.compile(r"[^.\[\]]+(?:\.[^.\[\]]+|\[[0-9]+\])*")

READ_SCHEMA: Final = vol.Schema(
    {
        vol.Required(ATTR_CONFIG_ENTRY_ID): cv.string,
        vol.Required(ATTR_PATH): cv.string,
    }
)
WRITE_SCHEMA: Final = vol.Schema(
    {
        vol.Required(ATTR_CONFIG_ENTRY_ID): cv.string,
        vol.Required(ATTR_PATH): cv.string,
        vol.Required(ATTR_VALUE): cv.match_all,
    }
)


@callback
def async_setup_services(hass: HomeAssistant) -> None:
    """Register the integration's actions."""
    hass.services.async_register(
        DOMAIN,
        SERVICE_READ_VARIABLE,
        _async_read_variable,
        schema=READ_SCHEMA,
        supports_response=SupportsResponse.ONLY,
    )
    hass.services.async_register(
        DOMAIN,
        SERVICE_WRITE_VARIABLE,
        _async_write_variable,
        schema=WRITE_SCHEMA,
    )


async def _async_read_variable(call: ServiceCall) -> ServiceResponse:
    """Read a variable: ``{"path": ..., "value": ...}``."""
    coordinator = _coordinator(call)
    path = _path(call)
    value = await coordinator.writer.async_read_variable(path)
    return {"path": path, "value": value}


async def _async_write_variable(call: ServiceCall) -> None:
    """Write a JSON value to a variable."""
    coordinator = _coordinator(call)
    path = _path(call)
    await coordinator.writer.async_write_variable(
        path, _json_value(call.data[ATTR_VALUE])
    )


def _coordinator(call: ServiceCall) -> PlcCoordinator:
    """Return the coordinator of the loaded config entry the call names."""
    entry_id: str = call.data[ATTR_CONFIG_ENTRY_ID]
    entry = call.hass.config_entries.async_get_entry(entry_id)
    if entry is None or entry.domain != DOMAIN:
        raise ServiceValidationError(
            translation_domain=DOMAIN,
            translation_key="entry_not_found",
            translation_placeholders={"entry_id": entry_id},
        )
    if entry.state is not ConfigEntryState.LOADED:
        raise ServiceValidationError(
            translation_domain=DOMAIN,
            translation_key="entry_not_loaded",
            translation_placeholders={"name": entry.title},
        )
    coordinator = cast("PlcCoordinator", entry.runtime_data)
    if Capability.PATHS not in coordinator.descriptor.capabilities:
        raise ServiceValidationError(
            translation_domain=DOMAIN,
            translation_key="paths_not_supported",
            translation_placeholders={"name": entry.title},
        )
    return coordinator


def _path(call: ServiceCall) -> str:
    """Return the variable path of a call, refusing text that is no path."""
    path: str = call.data[ATTR_PATH].strip()
    if not VARIABLE_PATH.fullmatch(path):
        raise ServiceValidationError(
            translation_domain=DOMAIN,
            translation_key="invalid_path",
            translation_placeholders={"path": path},
        )
    return path


def _json_value(value: Any) -> Any:
    """Return the value to write: text is JSON, anything else is taken as it is.

    From YAML, ``value: 21.5`` or ``value: true`` arrive typed; a string must be
    written as JSON text, ``value: '"hello"'``.
    """
    if not isinstance(value, str):
        return value
    try:
        return json.loads(value)
    except ValueError as err:
        raise ServiceValidationError(
            translation_domain=DOMAIN,
            translation_key="invalid_json",
            translation_placeholders={"value": value},
        ) from err
