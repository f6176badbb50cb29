"""Repair issues: what the user should know about a PLC and cannot fix from here.

Each issue has its functions, which raise or clear it; :class:`IssueFollower`
follows them all as an entry's polls and updates find its device.
"""

from collections.abc import Mapping
from types import MappingProxyType
from typing import Final

from homeassistant.config_entries import ConfigEntry, ConfigSubentry
from homeassistant.core import HomeAssistant, callback
from homeassistant.helpers import issue_registry as ir, translation

from .connection import descriptor_of
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
from .messages import error_detail, quality_text
from .pyplc import PlcError, PlcMode, PointQuality, Quality
from .pyplc.core.composition import CompositionError, CompositionProblem
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
    """Raise the "not running" issue while the program is stopped or in fault.

    It is cleared while it runs (or the device has no mode). The issue cannot
    be fixed from Home Assistant: the program is started on the device (a
    Tecomat's from Mosaic or its panel). A fault is an error, a stop (on
    purpose, for example during commissioning) a warning.
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


COMPOSITION_TEXTS: Final[Mapping[CompositionProblem, str]] = MappingProxyType(
    {
        CompositionProblem.MISSING_POINT: "composition_missing_point",
        CompositionProblem.WRONG_KIND: "composition_wrong_kind",
        CompositionProblem.NOT_WRITABLE: "composition_not_writable",
        CompositionProblem.MISSING_ROLE: "composition_missing_role",
    }
)
"""The issue's text for each way a program breaks a composed device.

Any other problem (a kind or a role this version does not have) gets the
generic :data:`ISSUE_COMPOSITION_BROKEN`, which names neither.
"""

_SUBENTRY_TEXTS: Final = "config_subentries"


async def async_load_issue_texts(hass: HomeAssistant) -> None:
    """Load the integration's texts the issues fill in, in Home Assistant's language.

    A composed device's issue names the role and the button of its form as the
    form does (see :func:`async_follow_compositions`); Home Assistant keeps
    them cached once loaded.
    """
    await translation.async_get_translations(
        hass, hass.config.language, _SUBENTRY_TEXTS, {DOMAIN}
    )


def _subentry_text(hass: HomeAssistant, subentry_type: str, *path: str) -> str | None:
    """Return a text of a subentry type's form in Home Assistant's language.

    Home Assistant's cache of a language holds the English text of what that
    language lacks; a language not loaded yet (just changed) gives English.
    """
    key = ".".join(("component", DOMAIN, _SUBENTRY_TEXTS, subentry_type, *path))
    for language in (hass.config.language, "en"):
        texts = translation.async_get_cached_translations(
            hass, language, _SUBENTRY_TEXTS, DOMAIN
        )
        if text := texts.get(key):
            return text
    return None


def _composition_placeholders(
    hass: HomeAssistant,
    entry: ConfigEntry,
    subentry: ConfigSubentry,
    error: CompositionError,
) -> dict[str, str]:
    """Return what a composed device's issue fills in, each in the reader's words.

    The role is named by its field's label and the button by its own label, as
    the device's form shows them in Home Assistant's language; the variable
    and the names are the program's and the user's own.
    """
    role = str(error.role or "")
    kind = subentry.subentry_type
    return {
        "name": subentry.title,
        "plc": entry.title,
        "point": subentry.data["roles"].get(role, error.point or ""),
        "role": _subentry_text(hass, kind, "step", "reconfigure", "data", role) or role,
        "change": _subentry_text(hass, kind, "initiate_flow", "reconfigure") or "",
    }


@callback
def async_follow_compositions(
    hass: HomeAssistant, entry: ConfigEntry, selection: Selection
) -> None:
    """Raise an issue for each composed device its program breaks; clear the others.

    A point the device was composed of vanished (a program download) or no
    longer fits its role: the device's entity is unavailable, and the issue
    names the role and the variable and says how to choose another one, in a
    text of its own for each problem (:data:`COMPOSITION_TEXTS`). The texts it
    fills in come from :func:`async_load_issue_texts`.
    """
    for subentry_id, subentry in entry.subentries.items():
        issue_id = composition_issue_id(entry, subentry_id)
        if (error := selection.broken.get(subentry_id)) is None:
            ir.async_delete_issue(hass, DOMAIN, issue_id)
            continue
        _async_raise(
            hass,
            issue_id,
            COMPOSITION_TEXTS.get(error.problem, ISSUE_COMPOSITION_BROKEN),
            _composition_placeholders(hass, entry, subentry, error),
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

    Each point is listed with its name, its key, its address and why: the
    device's code and message (an address the PLC lacks: a typo in the user's
    map), or the source's reason in Home Assistant's language; the first
    :data:`REFUSED_LISTED` by key, then how many more there are. Their
    entities are unavailable, and Home Assistant shows no attributes on an
    unavailable entity: this is where the user sees the code. The issue's text
    is the source's (its ``Words``): a map's points are a controller's
    variables, a gateway's registers, each fixed in its own file.
    """
    issue_id = points_refused_issue_id(entry)
    if not refused:
        ir.async_delete_issue(hass, DOMAIN, issue_id)
        return
    points = data.catalogue.points
    keys = sorted(refused)
    lines = [
        f"- {point_label(points[key])}, {points[key].address}: "
        f"{quality_text(hass, refused[key])}"
        for key in keys[:REFUSED_LISTED]
    ]
    if len(keys) > REFUSED_LISTED:
        lines.append(f"- … (+{len(keys) - REFUSED_LISTED})")
    _async_raise(
        hass,
        issue_id,
        descriptor_of(entry.data).words.points_refused,
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
        {"name": entry.title, "error": error_detail(hass, err)},
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


class IssueFollower:
    """Raises and clears one entry's repair issues as its device is found.

    A poll tells whether the device serves its list of variables, its mode and
    whether the program breaks a composed device; every update (a poll, a
    push, a write's read-back) which points the device refuses. An issue
    stale from an earlier run is cleared by the first data.
    """

    def __init__(self, hass: HomeAssistant, entry: ConfigEntry) -> None:
        """Follow ``entry``'s issues; none is known yet."""
        self._hass = hass
        self._entry = entry
        # The points refused, as their issue lists them (None: not followed yet).
        self._refused: dict[str, PointQuality] | None = None
        # Whether the list of variables failed (None: not followed yet).
        self._variable_list_failed: bool | None = None

    @callback
    def async_poll_failed(self, err: PlcError) -> None:
        """Follow a failed poll: a list of variables the device cannot serve."""
        if async_follow_variable_list(self._hass, self._entry, err):
            self._variable_list_failed = True

    @callback
    def async_poll_succeeded(self) -> None:
        """Follow a poll that succeeded: the list of variables is served."""
        if self._variable_list_failed is not False:
            async_follow_variable_list(self._hass, self._entry, None)
            self._variable_list_failed = False

    async def async_polled(self, previous: PlcData | None, data: PlcData) -> None:
        """Follow a poll's data: the device's mode, the composed devices it breaks."""
        if previous is None or data.info.mode is not previous.info.mode:
            async_follow_plc_mode(self._hass, self._entry, data.info.mode)
        if previous is None or data.selection is not previous.selection:
            await async_load_issue_texts(self._hass)
            async_follow_compositions(self._hass, self._entry, data.selection)

    @callback
    def async_shown(self, data: PlcData) -> None:
        """Follow any data shown: the points the device refuses, when they change."""
        refused = refused_points(data, self._refused or {})
        if refused != self._refused:
            self._refused = refused
            async_follow_refused_points(self._hass, self._entry, data, refused)
