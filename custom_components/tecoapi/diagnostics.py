"""Diagnostics download: what a maintainer needs, without what identifies the user.

Each system's download tells what that system has, in its words: the device
(under its descriptor's noun: ``plc``, ``gateway``, ``controller``) as far as
it tells of itself, the options its entries use, a summary of the catalogue,
what the user changed of the points it discovers (their overrides: as stored,
as applied, and those the device lacks now) and what its source tells of its protocol
(``pyplc``'s ``diagnostics()``: the read plans and request counts, a gateway's
stations, a controller's project, a subscription). The recent failures are everyone's. Nothing here names a
system: what a device tells follows its descriptor's capabilities.
Credentials (every descriptor's secret fields among them), the host (and the
host of a push server beside it), the MAC address, the serial number and a session's ID are
redacted, also where an error message or a gateway's location names a host.
"""

from collections import Counter
from datetime import datetime
from typing import Any, Final

from homeassistant.components.diagnostics import REDACTED, async_redact_data
from homeassistant.const import CONF_HOST, CONF_PASSWORD, CONF_USERNAME
from homeassistant.core import HomeAssistant
from yarl import URL

from .coordinator import PlcConfigEntry, PlcCoordinator
from .options import options_used
from .pyplc.core.descriptor import Capability
from .pyplc.core.overrides import override_json, overrides_json
from .pyplc.core.source import RecentError

TO_REDACT: Final = {
    # Also a push server's, in its settings (the options' ``push``).
    CONF_HOST,
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
CATALOGUED: Final = ("roots", "skipped_roots")
"""What a source that reads its points by top-level groups tells of them (under
the keys downloads have had since the first: ``Catalogue.groups`` counted and
``Catalogue.skipped_groups`` listed)."""


async def async_get_config_entry_diagnostics(
    hass: HomeAssistant, entry: PlcConfigEntry
) -> dict[str, Any]:
    """Return the diagnostics of an entry, in its system's words."""
    coordinator = entry.runtime_data
    descriptor = coordinator.descriptor
    scrub = _Scrubber(coordinator)
    source = coordinator.source.diagnostics()
    diagnostics: dict[str, Any] = {
        "entry": {
            # A gateway's title says where it is: its address is taken out.
            "title": scrub(entry.title),
            "unique_id": entry.unique_id,
            "data": dict(entry.data),
            "options": dict(entry.options),
        },
        "options": options_used(descriptor, coordinator.options),
        descriptor.noun.lower(): _device(coordinator, scrub),
        "catalogue": _catalogue(coordinator, source),
        **{key: source[key] for key in ("read_plans", "requests") if key in source},
        "last_update_success": coordinator.last_update_success,
        "last_exception": scrub(coordinator.last_exception),
        "recent_errors": [
            _error(error, scrub) for error in coordinator.source.recent_errors
        ],
    }
    if Capability.DISCOVERY in descriptor.capabilities:
        diagnostics["overrides"] = _overrides(coordinator)
    if protocol := {
        key: value for key, value in source.items() if key not in SUMMARISED
    }:
        # What else the source tells of its protocol (a gateway's session, its
        # stations): every text scrubbed of the host, as error messages are.
        diagnostics["source"] = _scrubbed(protocol, scrub)
    redacted = TO_REDACT | descriptor.secrets
    if (companion := descriptor.companion) is not None:
        # Its settings where the release before reads them, too (plccoms_host).
        redacted |= {
            legacy for legacy, key in companion.legacy_keys.items() if key in redacted
        }
    return async_redact_data(diagnostics, redacted)


def _device(coordinator: PlcCoordinator, scrub: "_Scrubber") -> dict[str, Any]:
    """Return what the device tells of itself, times as ISO text.

    What it tells of its hardware where it tells it; its run mode, program and
    clock where its descriptor says it has them (None: it told none this
    time); where it is reached, for a device known by its address (a gateway's
    address and station), the host taken out.
    """
    data = coordinator.data
    info = data.info
    descriptor = coordinator.descriptor
    told: dict[str, Any] = {
        key: value
        for key, value in {
            "family": info.family,
            "type": info.model,
            "serial_number": info.serial_number,
            "firmware": info.firmware,
            "mac": info.mac,
            "api_version": info.api_version,
            "location": scrub(info.location),
        }.items()
        if value is not None
    }
    if Capability.MODE in descriptor.capabilities:
        told["mode"] = info.mode
    if Capability.PROGRAM in descriptor.capabilities:
        told |= {
            "program_name": info.program_name,
            "program_compiled": info.program_compiled,
            "program_stamp": info.program_stamp,
        }
    if Capability.CLOCK in descriptor.status_entities:
        told |= {"time": info.time, "clock_offset": data.clock_offset}
    return {
        key: value.isoformat() if isinstance(value, datetime) else value
        for key, value in told.items()
    }


def _catalogue(coordinator: PlcCoordinator, source: dict[str, Any]) -> dict[str, Any]:
    """Count what discovery found and what became entities.

    How many top-level groups a source read its points by, where it
    does, and which it skipped; how many points
    tell more than their value (TecoApi's T_ApiObjects), where some may not.
    """
    data = coordinator.data
    points = data.points.values()
    descriptions = data.descriptions.values()
    catalogue: dict[str, Any] = {
        key: source[key] for key in CATALOGUED if key in source
    }
    catalogue |= {
        "points": source.get("points", len(data.catalogue.points)),
        "selected": len(data.points),
        "polled": len(coordinator.polled_keys),
        "by_kind": dict(sorted(Counter(point.kind.value for point in points).items())),
        "by_platform": dict(
            sorted(Counter(item.platform.value for item in descriptions).items())
        ),
        "missing": sorted(data.missing),
    }
    if Capability.PLAIN_VARIABLES in coordinator.descriptor.capabilities:
        catalogue["api_objects"] = sum(point.described for point in points)
    return catalogue


def _overrides(coordinator: PlcCoordinator) -> dict[str, Any]:
    """Return what the user changed of the points by key, and those the device lacks now.

    A change a point does not take (``pyplc.core.overrides``) is shown as
    stored, and left out of ``applied``.
    """
    points = coordinator.data.catalogue.points
    stored = coordinator.applier.overrides
    return {
        "points": overrides_json(stored),
        "applied": {
            key: override_json(override)
            for key in sorted(stored)
            if (point := points.get(key)) is not None
            and (override := point.override) is not None
        },
        "not_in_catalogue": sorted(key for key in stored if key not in points),
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

    def __init__(self, coordinator: PlcCoordinator) -> None:
        base_url = coordinator.source.configuration_url or ""
        host = str(coordinator.config_entry.data.get(CONF_HOST, ""))
        push = str(coordinator.options.push.get(CONF_HOST, ""))
        forms = {base_url, host, push}
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
