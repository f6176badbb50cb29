"""Repair issues: what the user should know about a PLC and cannot fix from here."""

from collections.abc import Mapping
from typing import Final

from homeassistant.config_entries import ConfigEntry
from homeassistant.core import HomeAssistant, callback
from homeassistant.helpers import issue_registry as ir

from .const import (
    DOMAIN,
    ISSUE_COMPOSITION_BROKEN,
    ISSUE_PLC_NOT_RUNNING,
    ISSUE_POINTS_REFUSED,
    ISSUE_VARIABLE_LIST,
)
from .data import PlcData
from .helpers import variable_list_failure
from .mapping import point_label
from .pyplc import PlcError, PlcMode, PointQuality, Quality
from .selection import Selection


@callback
def _async_raise(
    hass: HomeAssistant,
    issue_id: str,
    translation_key: str,
    placeholders: dict[str, str],
    severity: ir.IssueSeverity = ir.IssueSeverity.WARNING,
) -> None:
    """Raise (or update) an issue the user fixes outside Home Assistant.

    It is not kept over a restart: whatever raised it raises it again.
    """
    ir.async_create_issue(
        hass,
        DOMAIN,
        issue_id,
        is_fixable=False,
        is_persistent=False,
        severity=severity,
        translation_key=translation_key,
        translation_placeholders=placeholders,
    )


def plc_not_running_issue_id(entry: ConfigEntry) -> str:
    """Return the ID of an entry's "PLC not running" issue."""
    return f"{ISSUE_PLC_NOT_RUNNING}_{entry.entry_id}"


@callback
def async_follow_plc_mode(
    hass: HomeAssistant, entry: ConfigEntry, mode: PlcMode | None
) -> None:
    """Raise the "PLC not running" issue in HALT or ERR; clear it in RUN (or no mode).

    The issue cannot be fixed from Home Assistant: the program is started from
    Mosaic or the PLC's panel. ERR is an error, HALT (stopped on purpose, for
    example during commissioning) a warning.
    """
    if mode is None or mode is PlcMode.RUNNING:
        ir.async_delete_issue(hass, DOMAIN, plc_not_running_issue_id(entry))
        return
    _async_raise(
        hass,
        plc_not_running_issue_id(entry),
        ISSUE_PLC_NOT_RUNNING,
        {"name": entry.title, "mode": mode.value},
        ir.IssueSeverity.ERROR if mode is PlcMode.FAULT else ir.IssueSeverity.WARNING,
    )


def composition_issue_id(entry: ConfigEntry, subentry_id: str) -> str:
    """Return the ID of the issue of a composed device that does not fit the program."""
    return f"{ISSUE_COMPOSITION_BROKEN}_{entry.entry_id}_{subentry_id}"


@callback
def async_follow_compositions(
    hass: HomeAssistant, entry: ConfigEntry, selection: Selection
) -> None:
    """Raise an issue for each composed device its program breaks; clear the others.

    A point the device was composed of vanished (a program download) or no
    longer fits its role: the device's entity is unavailable, and the issue
    names the role and the variable and says how to choose another one.
    """
    for subentry_id, subentry in entry.subentries.items():
        issue_id = composition_issue_id(entry, subentry_id)
        if (error := selection.broken.get(subentry_id)) is None:
            ir.async_delete_issue(hass, DOMAIN, issue_id)
            continue
        _async_raise(
            hass,
            issue_id,
            ISSUE_COMPOSITION_BROKEN,
            {
                "name": subentry.title,
                "plc": entry.title,
                "role": error.role or "",
                "point": subentry.data["roles"].get(
                    error.role or "", error.point or ""
                ),
                "reason": str(error),
            },
        )


REFUSED_LISTED: Final = 20
"""Refused points an issue lists at most (the diagnostics download lists them all)."""


def points_refused_issue_id(entry: ConfigEntry) -> str:
    """Return the ID of an entry's "refuses some points" issue."""
    return f"{ISSUE_POINTS_REFUSED}_{entry.entry_id}"


def refused_points(
    data: PlcData, before: Mapping[str, PointQuality]
) -> dict[str, PointQuality]:
    """Return the shown points the device refuses with a code of its own, by key.

    ``before`` is what this returned last time: a point refused then whose
    device exchanges no data now keeps its place (nothing tells whether it
    reads again before its device is back). A point the catalogue no longer
    has (a new map) leaves.
    """
    watched = data.selection.watched
    refused = {
        key: quality
        for key, quality in data.quality.items()
        if key in watched and quality.quality is Quality.BAD and quality.code
    }
    for key, quality in before.items():
        if (
            key not in refused
            and key in watched
            and (point := data.catalogue.points.get(key)) is not None
            and not data.device_available(point.device)
        ):
            refused[key] = quality
    return refused


@callback
def async_follow_refused_points(
    hass: HomeAssistant,
    entry: ConfigEntry,
    data: PlcData,
    refused: Mapping[str, PointQuality],
) -> None:
    """Raise the issue listing the points the device refuses; clear it when none is.

    Each point is listed with its name, its key, its address and the device's
    code and message (an address the PLC lacks: a typo in the user's map); the
    first :data:`REFUSED_LISTED` by key, then how many more there are.
    Their entities are unavailable, and Home Assistant shows no attributes on
    an unavailable entity: this is where the user sees the code.
    """
    issue_id = points_refused_issue_id(entry)
    if not refused:
        ir.async_delete_issue(hass, DOMAIN, issue_id)
        return
    points = data.catalogue.points
    keys = sorted(refused)
    lines = [
        f"- {point_label(points[key])}, {points[key].address}: {refused[key].reason}"
        for key in keys[:REFUSED_LISTED]
    ]
    if len(keys) > REFUSED_LISTED:
        lines.append(f"- … (+{len(keys) - REFUSED_LISTED})")
    _async_raise(
        hass,
        issue_id,
        ISSUE_POINTS_REFUSED,
        {"name": entry.title, "points": "\n".join(lines)},
    )


def variable_list_issue_id(entry: ConfigEntry) -> str:
    """Return the ID of an entry's "cannot serve its list of variables" issue."""
    return f"{ISSUE_VARIABLE_LIST}_{entry.entry_id}"


@callback
def async_follow_variable_list(
    hass: HomeAssistant, entry: ConfigEntry, err: PlcError | None
) -> bool:
    """Raise the issue of a device that cannot serve its list of public variables.

    ``err`` is the failure of a poll, None after one that succeeded. The list
    is too big, or the device cannot read it: no variable can be read until
    the program is changed, which only the user can do, outside Home
    Assistant. A poll that succeeds clears the issue; any other failure (the
    device unreachable) leaves it as it is, since it tells nothing of the list.
    Returns whether ``err`` raised the issue.
    """
    issue_id = variable_list_issue_id(entry)
    if err is None:
        ir.async_delete_issue(hass, DOMAIN, issue_id)
        return False
    if (key := variable_list_failure(err)) is None:
        return False
    _async_raise(
        hass,
        issue_id,
        key,
        {"name": entry.title, "error": str(err)},
        ir.IssueSeverity.ERROR,
    )
    return True


@callback
def async_clear_plc_issues(hass: HomeAssistant, entry: ConfigEntry) -> None:
    """Remove the entry's issues (the entry is unloaded or removed)."""
    ir.async_delete_issue(hass, DOMAIN, plc_not_running_issue_id(entry))
    ir.async_delete_issue(hass, DOMAIN, points_refused_issue_id(entry))
    ir.async_delete_issue(hass, DOMAIN, variable_list_issue_id(entry))
    for subentry_id in entry.subentries:
        ir.async_delete_issue(hass, DOMAIN, composition_issue_id(entry, subentry_id))
