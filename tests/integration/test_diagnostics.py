"""The diagnostics download: complete enough to debug, nothing that identifies."""

import json
from typing import Final

from freezegun.api import FrozenDateTimeFactory
from homeassistant.core import HomeAssistant
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry
from pytest_homeassistant_custom_component.components.diagnostics import (
    get_diagnostics_for_config_entry,
)
from pytest_homeassistant_custom_component.typing import ClientSessionGenerator
from syrupy.assertion import SnapshotAssertion
from syrupy.filters import props
from syrupy.matchers import path_type

from tests.conftest import SIM_PASSWORD, SIM_USERNAME
from tests.integration.conftest import poll
from tests.simulator import Simulator


@pytest.fixture
async def diagnostics(
    hass: HomeAssistant,
    simulator: Simulator,
    demo_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
    hass_client: ClientSessionGenerator,
) -> dict[str, object]:
    """Diagnostics after polls, one of them failed (HTTP 500), then a recovery.

    (The client's access token is made after the clock was set: it is valid.)
    """
    await poll(hass, freezer)
    simulator.faults.http_500 = True
    simulator.faults.remaining = 1
    await poll(hass, freezer)
    await poll(hass, freezer)
    result: dict[str, object] = await get_diagnostics_for_config_entry(
        hass, hass_client, demo_entry
    )
    return result


# What the read planner decides (the client library's business, pinned by its
# own tests): the snapshot keeps these fields' types, not their values.
PLANNED: Final = {
    "read_plans.values.requests": (int,),
    "read_plans.values.lower_bound": (int,),
    "requests.on_the_wire": (int,),
    "requests.last_poll_requests": (int,),
}


@pytest.mark.primary_only
async def test_diagnostics(
    diagnostics: dict[str, object], snapshot: SnapshotAssertion
) -> None:
    """PLC info, options, catalogue, plans, request counts, recent errors."""
    assert diagnostics == snapshot(exclude=props("targets"), matcher=path_type(PLANNED))


async def test_diagnostics_show_the_plan_it_polls(
    diagnostics: dict[str, object], demo_entry: MockConfigEntry
) -> None:
    """The value plan in the download is the one the coordinator executes."""
    plan = demo_entry.runtime_data.source.read_plan
    assert plan is not None
    plans = diagnostics["read_plans"]
    assert isinstance(plans, dict)
    assert plans["values"]["requests"] == len(plan.requests)
    assert plans["values"]["lower_bound"] == plan.lower_bound
    assert plans["values"]["targets"] == [
        {"target": request.target, "items": request.items} for request in plan.requests
    ]


async def test_diagnostics_redact_what_identifies(
    diagnostics: dict[str, object], simulator: Simulator
) -> None:
    """No credentials, host, MAC or serial number anywhere in the download."""
    text = json.dumps(diagnostics)
    for secret in (
        SIM_PASSWORD,
        SIM_USERNAME,
        simulator.url,
        simulator.host,
        str(simulator.port),
        simulator.serial_number,
        "00-0A-14-2C-80-17",
        "00:0a:14:2c:80:17",
    ):
        assert secret not in text
    errors = diagnostics["recent_errors"]
    assert isinstance(errors, list)
    assert [error["operation"] for error in errors] == ["poll"]
    assert errors[0]["message"].startswith("500.012")
    requests = diagnostics["requests"]
    assert isinstance(requests, dict)
    assert requests["failed_polls"] == 1
    assert requests["polls"] == 3


async def test_diagnostics_of_a_healthy_plc(
    hass: HomeAssistant,
    demo_entry: MockConfigEntry,
    hass_client: ClientSessionGenerator,
) -> None:
    """Before any failure and any poll: no exception, no errors, no plan yet."""
    result = await get_diagnostics_for_config_entry(hass, hass_client, demo_entry)

    assert result["last_exception"] is None
    assert result["recent_errors"] == []
    assert result["read_plans"] == {"values": None, "with_attributes": None}
    assert result["requests"]["discoveries"] == 1
