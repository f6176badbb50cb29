"""Repair issues: what the user should know about a PLC and cannot fix from here."""

from homeassistant.config_entries import ConfigEntry
from homeassistant.core import HomeAssistant, callback
from homeassistant.helpers import issue_registry as ir

from .const import DOMAIN, ISSUE_PLC_NOT_RUNNING
from .pytecoapi import PlcMode


def plc_not_running_issue_id(entry: ConfigEntry) -> str:
    """Return the ID of an entry's "PLC not running" issue."""
    return f"{ISSUE_PLC_NOT_RUNNING}_{entry.entry_id}"


@callback
def async_follow_plc_mode(
    hass: HomeAssistant, entry: ConfigEntry, mode: PlcMode
) -> None:
    """Raise the "PLC not running" issue in HALT or ERR; clear it in RUN.

    The issue cannot be fixed from Home Assistant: the program is started from
    Mosaic or the PLC's panel. ERR is an error, HALT (stopped on purpose, for
    example during commissioning) a warning.
    """
    if mode is PlcMode.RUN:
        async_clear_plc_issues(hass, entry)
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


@callback
def async_clear_plc_issues(hass: HomeAssistant, entry: ConfigEntry) -> None:
    """Remove the entry's issues (the PLC runs again, or the entry is unloaded)."""
    ir.async_delete_issue(hass, DOMAIN, plc_not_running_issue_id(entry))
