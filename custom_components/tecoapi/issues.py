"""Repair issues: what the user should know about a PLC and cannot fix from here."""

from homeassistant.config_entries import ConfigEntry
from homeassistant.core import HomeAssistant, callback
from homeassistant.helpers import issue_registry as ir

from .const import DOMAIN, ISSUE_COMPOSITION_BROKEN, ISSUE_PLC_NOT_RUNNING
from .pyplc import PlcMode
from .selection import Selection


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
    if mode is None or mode is PlcMode.RUN:
        ir.async_delete_issue(hass, DOMAIN, plc_not_running_issue_id(entry))
        return
    ir.async_create_issue(
        hass,
        DOMAIN,
        plc_not_running_issue_id(entry),
        is_fixable=False,
        is_persistent=False,
        severity=(
            ir.IssueSeverity.ERROR if mode is PlcMode.ERR else ir.IssueSeverity.WARNING
        ),
        translation_key=ISSUE_PLC_NOT_RUNNING,
        translation_placeholders={"name": entry.title, "mode": mode.value},
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
        ir.async_create_issue(
            hass,
            DOMAIN,
            issue_id,
            is_fixable=False,
            is_persistent=False,
            severity=ir.IssueSeverity.WARNING,
            translation_key=ISSUE_COMPOSITION_BROKEN,
            translation_placeholders={
                "name": subentry.title,
                "plc": entry.title,
                "role": error.role or "",
                "point": subentry.data["roles"].get(
                    error.role or "", error.point or ""
                ),
                "reason": str(error),
            },
        )


@callback
def async_clear_plc_issues(hass: HomeAssistant, entry: ConfigEntry) -> None:
    """Remove the entry's issues (the entry is unloaded or removed)."""
    ir.async_delete_issue(hass, DOMAIN, plc_not_running_issue_id(entry))
    for subentry_id in entry.subentries:
        ir.async_delete_issue(hass, DOMAIN, composition_issue_id(entry, subentry_id))
