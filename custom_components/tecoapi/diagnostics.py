"""Diagnostics download: what a maintainer needs, without what identifies the user.

PLC info and its clock's offset, options, a summary of the catalogue, the read
plans and request counts, the recent failures, and whatever else the source
tells of its protocol. Credentials, the host (and the PLCComS host), the MAC
address, the serial number and a session's ID are redacted, also where an error
message names a host.
"""

from collections import Counter
from datetime import datetime
from typing import Any, Final

from homeassistant.components.diagnostics import REDACTED, async_redact_data
from homeassistant.const import CONF_HOST, CONF_PASSWORD, CONF_USERNAME
from homeassistant.core import HomeAssistant
from yarl import URL

from .const import CONF_PLCCOMS_HOST
from .coordinator import TecoApiConfigEntry, TecoApiCoordinator
from .pyplc import SourceInfo
from .pyplc.core.source import RecentError

TO_REDACT: Final = {
    CONF_HOST,
    CONF_PLCCOMS_HOST,
    CONF_PASSWORD,
    CONF_USERNAME,
    "mac",
    "serial_number",
    "unique_id",
    "session_id",
}
SUMMARISED: Final = frozenset(
    {"roots", "skipped_roots", "points", "read_plans", "requests"}
)
"""What of a source's diagnostics the download shows in its own places."""


async def async_get_config_entry_diagnostics(
    hass: HomeAssistant, entry: TecoApiConfigEntry
) -> dict[str, Any]:
    """Return the diagnostics of a TecoApi entry."""
    coordinator = entry.runtime_data
    data = coordinator.data
    scrub = _Scrubber(coordinator)
    source = coordinator.source.diagnostics()
    diagnostics = {
        "entry": {
            # A gateway's title says where it is: its address is taken out.
            "title": scrub(entry.title),
            "unique_id": entry.unique_id,
            "data": dict(entry.data),
            "options": dict(entry.options),
        },
        "options": coordinator.options.as_dict(),
        "plc": {**_plc_info(data.info), "clock_offset": data.clock_offset},
        "catalogue": _catalogue(coordinator, source),
        "read_plans": source.get("read_plans"),
        "requests": source.get("requests"),
        "last_update_success": coordinator.last_update_success,
        "last_exception": scrub(coordinator.last_exception),
        "recent_errors": [
            _error(error, scrub) for error in coordinator.source.recent_errors
        ],
    }
    if protocol := {
        key: value for key, value in source.items() if key not in SUMMARISED
    }:
        # What else the source tells of its protocol (a gateway's session, its
        # last answers): every text scrubbed of the host, as error messages are.
        diagnostics["source"] = _scrubbed(protocol, scrub)
    return async_redact_data(diagnostics, TO_REDACT | coordinator.descriptor.secrets)


def _plc_info(info: SourceInfo) -> dict[str, Any]:
    """Return what the device tells of itself, times as ISO text."""
    fields = {
        "family": info.family,
        "type": info.model,
        "serial_number": info.serial_number,
        "firmware": info.firmware,
        "mac": info.mac,
        "mode": info.mode,
        "program_name": info.program_name,
        "program_compiled": info.program_compiled,
        "program_stamp": info.program_stamp,
        "time": info.time,
        "api_version": info.api_version,
    }
    return {
        key: value.isoformat() if isinstance(value, datetime) else value
        for key, value in fields.items()
    }


def _catalogue(
    coordinator: TecoApiCoordinator, source: dict[str, Any]
) -> dict[str, Any]:
    """Count what discovery found and what became entities."""
    data = coordinator.data
    points = data.points.values()
    descriptions = data.descriptions.values()
    return {
        "roots": source.get("roots", 0),
        "skipped_roots": source.get("skipped_roots", []),
        "points": source.get("points", len(data.catalogue.points)),
        "selected": len(data.points),
        "api_objects": sum(point.described for point in points),
        "polled": len(coordinator.polled_keys),
        "by_kind": dict(sorted(Counter(point.kind.value for point in points).items())),
        "by_platform": dict(
            sorted(Counter(item.platform.value for item in descriptions).items())
        ),
        "missing": sorted(data.missing),
    }


def _error(error: RecentError, scrub: "_Scrubber") -> dict[str, Any]:
    """Describe a recent failure, the host taken out of its message."""
    return {
        "time": error.time.isoformat(),
        "operation": error.operation,
        "error": error.error,
        "message": scrub(error.message),
    }


def _scrubbed(value: Any, scrub: "_Scrubber") -> Any:
    """Return a JSON-shaped value with every text in it scrubbed of the host."""
    if isinstance(value, str):
        return scrub(value)
    if isinstance(value, dict):
        return {key: _scrubbed(item, scrub) for key, item in value.items()}
    if isinstance(value, list | tuple):
        return [_scrubbed(item, scrub) for item in value]
    return value


class _Scrubber:
    """Takes the PLC's address out of text (error messages name it)."""

    def __init__(self, coordinator: TecoApiCoordinator) -> None:
        base_url = coordinator.source.configuration_url or ""
        host = str(coordinator.config_entry.data.get(CONF_HOST, ""))
        forms = {base_url, host, coordinator.options.plccoms_host}
        for address in (base_url, host):
            url = URL(address)
            if url.host:
                forms |= {url.host, f"{url.host}:{url.port}" if url.port else ""}
        self._forms = sorted((form for form in forms if form), key=len, reverse=True)

    def __call__(self, text: object) -> str | None:
        """Return ``text`` as a string with every spelling of the host redacted."""
        if text is None:
            return None
        message = str(text)
        for form in self._forms:
            message = message.replace(form, REDACTED)
        return message
