"""The repair issues an entry's updates raise and clear (``issues.IssueFollower``).

A poll failing for the list of variables raises its issue, one that succeeds
clears it; a stopped program raises its own, running again clears it; a
composed device the program breaks has one; the points a device refuses with
a code of its own are listed, and the list follows any data shown.
"""

from dataclasses import replace
from typing import Final

from homeassistant.core import HomeAssistant
from homeassistant.helpers import issue_registry as ir
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.tecoapi.const import DOMAIN
from custom_components.tecoapi.data import PlcData, updated_data
from custom_components.tecoapi.issues import (
    IssueFollower,
    plc_not_running_issue_id,
    points_refused_issue_id,
    variable_list_issue_id,
)
from custom_components.tecoapi.options import PlcOptions
from custom_components.tecoapi.pyplc import PointQuality, Quality
from custom_components.tecoapi.pyplc.core import exceptions as plc
from custom_components.tecoapi.pyplc.core.models import PlcMode
from custom_components.tecoapi.selection import selector
from tests.components.tecoapi.catalogues import INFO, catalogue, point, snapshot

HOUSE: Final = catalogue(point("Outside", title="Outside"), point("Pump"))
REFUSED: Final = PointQuality(quality=Quality.BAD, reason="no such address", code="7")


def _data(**changes: object) -> PlcData:
    data = updated_data(None, snapshot(HOUSE), selector(PlcOptions(), [], []))
    return replace(data, **changes)  # type: ignore[arg-type]


def _issue(hass: HomeAssistant, issue_id: str) -> ir.IssueEntry | None:
    return ir.async_get(hass).async_get_issue(DOMAIN, issue_id)


async def test_the_list_of_variables_raises_its_issue_until_a_poll_succeeds(
    hass: HomeAssistant,
) -> None:
    entry = MockConfigEntry(domain=DOMAIN, title="P-1")
    follower = IssueFollower(hass, entry)

    follower.async_poll_failed(plc.PlcConnectionError("refused"))
    assert _issue(hass, variable_list_issue_id(entry)) is None
    follower.async_poll_failed(plc.VariableListTooLargeError("too many"))
    issue = _issue(hass, variable_list_issue_id(entry))
    assert issue is not None
    assert issue.translation_key == "variable_list_too_big"

    follower.async_poll_succeeded()
    assert _issue(hass, variable_list_issue_id(entry)) is None


async def test_a_stopped_program_raises_its_issue_and_running_clears_it(
    hass: HomeAssistant,
) -> None:
    entry = MockConfigEntry(domain=DOMAIN, title="P-1")
    follower = IssueFollower(hass, entry)
    running = _data()
    stopped = _data(info=replace(INFO, mode=PlcMode.STOPPED))

    await follower.async_polled(None, stopped)
    issue = _issue(hass, plc_not_running_issue_id(entry))
    assert issue is not None
    assert issue.severity is ir.IssueSeverity.WARNING
    assert issue.translation_placeholders == {"name": "P-1", "mode": "HALT"}

    await follower.async_polled(stopped, running)
    assert _issue(hass, plc_not_running_issue_id(entry)) is None


async def test_the_points_refused_follow_what_is_shown(hass: HomeAssistant) -> None:
    entry = MockConfigEntry(domain=DOMAIN, title="P-1")
    follower = IssueFollower(hass, entry)

    follower.async_shown(_data(quality={"pump": REFUSED}))

    issue = _issue(hass, points_refused_issue_id(entry))
    assert issue is not None
    assert "no such address" in (issue.translation_placeholders or {})["points"]
    # A bad value without the device's code is no refusal.
    follower.async_shown(
        _data(quality={"pump": PointQuality(quality=Quality.BAD, reason="timeout")})
    )
    assert _issue(hass, points_refused_issue_id(entry)) is None
