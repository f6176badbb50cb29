"""Writes are never lost silently: every failure on the wire reaches the caller.

A write the PLC did not acknowledge raises a ``HomeAssistantError`` (not a
validation error: the user asked nothing wrong) and the entity keeps showing
what the PLC holds. Real time, a short client timeout, a PLC answering
concurrently (see ``test_coordinator_faults``).
"""

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Final

from homeassistant.components.number import (
    ATTR_VALUE,
    DOMAIN as NUMBER_DOMAIN,
    SERVICE_SET_VALUE,
)
from homeassistant.components.text import DOMAIN as TEXT_DOMAIN
from homeassistant.config_entries import SOURCE_REAUTH
from homeassistant.const import ATTR_ENTITY_ID
from homeassistant.core import HomeAssistant
from homeassistant.exceptions import HomeAssistantError, ServiceValidationError
import pytest

from custom_components.tecoapi.const import DOMAIN
from custom_components.tecoapi.helpers import plc_action
from tests.components.tecoapi.conftest import make_entry, setup_entry
from tests.simulator import Simulator

SETPOINT = "number.heating_living_room_setpoint"
MESSAGE = "text.tecomat_cp_2080_hall_display_message"


@dataclass(frozen=True, slots=True)
class Target:
    """An entity to write, the PLC variable behind it, a new value."""

    entity_id: str
    domain: str
    variable: str
    value: Any
    form: str
    """The service the write uses on the wire."""


SETPOINT_WRITE: Final = Target(
    SETPOINT, NUMBER_DOMAIN, "Heating.livingSetpoint.value", 22.5, "SetObject"
)
MESSAGE_WRITE: Final = Target(
    MESSAGE, TEXT_DOMAIN, "displayMessage.value", 'Dinner at 7 & "wine"', "SetObject"
)


@dataclass(frozen=True, slots=True)
class WireFailure:
    """A way for a write to fail on the wire."""

    name: str
    switch_on: Callable[[Simulator], None]
    translation_key: str = "write_failed"
    times_out: bool = False
    """Whether the write fails by waiting out the client's timeout (a short one then)."""


def _drop(sim: Simulator) -> None:
    sim.faults.drop_connection = True  # aiohttp retries a dropped request once


def _http_500(sim: Simulator) -> None:
    sim.faults.http_500 = True


def _slow(sim: Simulator) -> None:
    # Far beyond the client timeout: the write is still waiting when the test
    # ends, and the simulator drops it unanswered when it stops.
    sim.faults.latency = 60.0


def _hang(sim: Simulator) -> None:
    sim.faults.hang = True


def _revoked(sim: Simulator) -> None:
    sim.password = "changed-on-the-plc"


def _vanished(sim: Simulator) -> None:
    sim.faults.rejected_by_object = {"Heating", "displayMessage"}


FAILURES: Final = [
    WireFailure("dropped connection", _drop),
    WireFailure("HTTP 500", _http_500),
    WireFailure("latency beyond the timeout", _slow, times_out=True),
    WireFailure("hung response", _hang, times_out=True),
    WireFailure("credentials revoked", _revoked, "auth_failed"),
    WireFailure("variable gone (400.005)", _vanished),
]


async def write(hass: HomeAssistant, target: Target, value: Any) -> None:
    """Set the entity's value through its platform's action."""
    await hass.services.async_call(
        target.domain,
        SERVICE_SET_VALUE,
        {ATTR_ENTITY_ID: target.entity_id, ATTR_VALUE: value},
        blocking=True,
    )


@pytest.mark.parametrize(
    "target", [SETPOINT_WRITE, MESSAGE_WRITE], ids=["number", "text"]
)
@pytest.mark.parametrize("failure", FAILURES, ids=[f.name for f in FAILURES])
async def test_failed_write_raises_and_keeps_the_plc_value(
    hass: HomeAssistant,
    plc: Simulator,
    target: Target,
    failure: WireFailure,
    request: pytest.FixtureRequest,
) -> None:
    """Each wire failure: a HomeAssistantError, the PLC and the entity unchanged.

    Only the failures that wait out the client's timeout shorten it: under a
    short timeout, a setup on two busy cores could time out before the write.
    """
    if failure.times_out:
        request.getfixturevalue("short_timeout")
    entry = await setup_entry(hass, make_entry(plc))
    coordinator = entry.runtime_data
    held = plc.get_value(target.variable)
    shown = hass.states.get(target.entity_id).state
    failure.switch_on(plc)
    plc.clear_requests()

    with pytest.raises(HomeAssistantError) as raised:
        await write(hass, target, target.value)

    assert not isinstance(raised.value, ServiceValidationError)
    assert raised.value.translation_domain == DOMAIN
    assert raised.value.translation_key == failure.translation_key
    assert plc.requests[0].service == target.form
    assert plc.get_value(target.variable) == held
    assert hass.states.get(target.entity_id).state == shown
    assert coordinator.source.statistics.failed_writes == 1
    assert coordinator.source.recent_errors[-1].operation == "write"
    await hass.async_block_till_done()
    reauth = [
        flow["context"]["source"]
        for flow in hass.config_entries.flow.async_progress_by_handler(DOMAIN)
    ]
    assert reauth == (
        [SOURCE_REAUTH] if failure.translation_key == "auth_failed" else []
    )


@pytest.mark.parametrize("fault", ["truncated_json", "malformed_json"])
@pytest.mark.parametrize(
    "target", [SETPOINT_WRITE, MESSAGE_WRITE], ids=["number", "text"]
)
async def test_mangled_bodies_do_not_fail_a_write(
    hass: HomeAssistant, plc: Simulator, target: Target, fault: str
) -> None:
    """A write's answer has no body to mangle: the write succeeds, nothing invented."""
    await setup_entry(hass, make_entry(plc))
    setattr(plc.faults, fault, True)
    plc.faults.remaining = 1

    await write(hass, target, target.value)

    assert plc.get_value(target.variable) == target.value
    assert hass.states.get(target.entity_id).state == str(target.value)


async def test_a_point_the_source_does_not_have_is_not_found_by_its_key(
    hass: HomeAssistant, plc: Simulator
) -> None:
    """The library's one check that a point exists is the translated not-found error.

    Refused before anything is sent, whatever the caller checked before: the
    error names the key, as the write path's own check does.
    """
    entry = await setup_entry(hass, make_entry(plc))
    plc.clear_requests()

    with (
        pytest.raises(ServiceValidationError) as raised,
        plc_action(hass, entry, operation="write", path="Heating.gone", value=1),
    ):
        await entry.runtime_data.source.write("heating.gone", 1)

    assert raised.value.translation_domain == DOMAIN
    assert raised.value.translation_key == "variable_not_found"
    assert raised.value.translation_placeholders == {"path": "heating.gone"}
    assert plc.requests == []
    assert entry.runtime_data.source.statistics.writes == 0
