"""The diagnostics download: complete enough to debug, nothing that identifies."""

from collections.abc import AsyncIterator
import json
from pathlib import Path
import tempfile
from typing import Final

from freezegun.api import FrozenDateTimeFactory
from homeassistant.components.diagnostics import REDACTED
from homeassistant.config_entries import ConfigEntry
from homeassistant.const import CONF_PASSWORD
from homeassistant.core import HomeAssistant
from homeassistant.setup import async_setup_component
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry
from pytest_homeassistant_custom_component.components.diagnostics import (
    get_diagnostics_for_config_entry,
)
from pytest_homeassistant_custom_component.typing import ClientSessionGenerator
from syrupy.assertion import SnapshotAssertion
from syrupy.filters import props
from syrupy.matchers import path_type

from custom_components.tecoapi.overrides import (
    async_load_overrides,
    async_save_overrides,
)
from custom_components.tecoapi.pyplc.core.models import PointOverride
from tests.components.tecoapi.conftest import FROZEN_TIME, poll
from tests.components.tecoapi.flows.test_config_tekon import add_gateway as add_tekon
from tests.components.tecoapi.fpi4c_gateway import add_gateway as add_fpi4c
from tests.components.tecoapi.mervis_house import (
    PASSWORD as MERVIS_PASSWORD,
    USER as MERVIS_USER,
    add_house,
)
from tests.components.tecoapi.overridden import change_point
from tests.conftest import SIM_PASSWORD, SIM_USERNAME
from tests.simulator import Simulator
from tests.simulator.fpi4c import FpI4cSimulator, demo_stations
from tests.simulator.mervis import MervisSimulator, house
from tests.simulator.tekon import TekonGateway


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


# --- each system in its own words --------------------------------------------------

PLANTED: Final = "planted-Pa55word"
"""A password an entry of a system without credentials holds all the same."""


def plant_a_password(hass: HomeAssistant, entry: ConfigEntry) -> None:
    """Store a password in the entry's data (no reload: not a connection key)."""
    hass.config_entries.async_update_entry(
        entry, data={**entry.data, CONF_PASSWORD: PLANTED}
    )


@pytest.fixture
def frozen(freezer: FrozenDateTimeFactory) -> None:
    """The clock set before the client's access token is made (it is then valid)."""
    freezer.move_to(FROZEN_TIME)


@pytest.fixture
async def uploads(
    hass: HomeAssistant, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Uploads go to the test's own folder (file_upload empties its own).

    The diagnostics' view is registered first: an upload's request freezes
    the web server's routes.
    """
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    assert await async_setup_component(hass, "diagnostics", {})


@pytest.fixture
async def fpi4c(socket_enabled: None) -> AsyncIterator[FpI4cSimulator]:
    async with FpI4cSimulator(demo_stations(), station=1) as simulator:
        yield simulator


@pytest.fixture
async def mervis(socket_enabled: None) -> AsyncIterator[MervisSimulator]:
    async with MervisSimulator(
        house(), username=MERVIS_USER, password=MERVIS_PASSWORD
    ) as simulator:
        yield simulator


@pytest.fixture
async def tekon(socket_enabled: None) -> AsyncIterator[TekonGateway]:
    async with TekonGateway() as simulator:
        yield simulator


@pytest.mark.usefixtures("frozen", "uploads")
async def test_a_gateway_s_diagnostics_speak_of_the_gateway_and_its_stations(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    fpi4c: FpI4cSimulator,
    freezer: FrozenDateTimeFactory,
    snapshot: SnapshotAssertion,
) -> None:
    """FP-I4C: where it is (no host), its map, each station's state; no program."""
    entry = await add_fpi4c(hass, hass_client, fpi4c)
    fpi4c.silent.add(2)
    await poll(hass, freezer)
    plant_a_password(hass, entry)

    diagnostics = await get_diagnostics_for_config_entry(hass, hass_client, entry)

    text = json.dumps(diagnostics)
    for secret in (PLANTED, "127.0.0.1", str(fpi4c.port)):
        assert secret not in text
    for tecomat in ("plain_variables", "api_objects", "program", "plccoms", "roots"):
        assert tecomat not in text
    # Where it is: its address alone (the form named no station).
    assert diagnostics["gateway"]["location"] == REDACTED
    assert diagnostics["source"]["stations"]["station_2"]["offline"] == (
        "err_code 28: No response from the PLC"
    )
    assert diagnostics == snapshot(matcher=path_type(FPI4C_PLANNED))


FPI4C_PLANNED: Final = {
    "entry.data.point_map": (str,),
    "read_plans.values.by_post": (list,),
    "read_plans.values.lower_bound": (int,),
    "read_plans.values.posts": (int,),
    "requests.posts": (int,),
    "requests.last_poll_requests": (int,),
}


@pytest.mark.usefixtures("frozen", "uploads")
async def test_a_controller_s_diagnostics_speak_of_its_project_and_boards(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    mervis: MervisSimulator,
    freezer: FrozenDateTimeFactory,
    snapshot: SnapshotAssertion,
) -> None:
    """Mervis: the controller, its .vlist's project and boards; no credentials."""
    entry = await add_house(hass, hass_client, mervis)
    port = mervis.port
    await mervis.stop()
    await poll(hass, freezer)
    await mervis.start(port=port)
    await poll(hass, freezer)

    diagnostics = await get_diagnostics_for_config_entry(hass, hass_client, entry)

    text = json.dumps(diagnostics)
    session = entry.runtime_data.source.client.session_credentials["p"]
    for secret in (MERVIS_PASSWORD, MERVIS_USER, session, "127.0.0.1", str(port)):
        assert secret not in text
    for tecomat in ("plain_variables", "api_objects", "program", "plccoms", "roots"):
        assert tecomat not in text
    assert diagnostics["source"]["project"]["boards"] == ["neuron_l203"]
    assert diagnostics == snapshot(matcher=path_type(MERVIS_PLANNED))


MERVIS_PLANNED: Final = {
    "entry.data.point_map": (str,),
    "read_plans.values.requests": (int,),
    "read_plans.values.lower_bound": (int,),
    "requests.on_the_wire": (int,),
    "requests.last_poll_requests": (int,),
}


@pytest.mark.usefixtures("frozen")
async def test_a_tekon_gateway_s_diagnostics_speak_of_its_address_space(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    tekon: TekonGateway,
    freezer: FrozenDateTimeFactory,
    snapshot: SnapshotAssertion,
) -> None:
    """Tekon: the gateway, its controllers and devices, the subscription."""
    entry: ConfigEntry = (await add_tekon(hass, tekon.url))["result"]
    await hass.async_block_till_done(wait_background_tasks=True)
    tekon.opc_available = False
    await poll(hass, freezer, 1)
    tekon.opc_available = True
    for _ in range(3):
        await poll(hass, freezer, 1)
    plant_a_password(hass, entry)

    diagnostics = await get_diagnostics_for_config_entry(hass, hass_client, entry)

    text = json.dumps(diagnostics, ensure_ascii=False)
    session_id = entry.runtime_data.source.client.session_id
    for secret in (PLANTED, session_id, "127.0.0.1", str(tekon.port)):
        assert secret not in text
    for tecomat in ("plain_variables", "api_objects", "program", "plccoms"):
        assert tecomat not in text
    assert diagnostics["source"]["subscription"]["session_id"] == REDACTED
    assert diagnostics == snapshot


async def test_diagnostics_show_what_the_user_changed_of_the_points(
    hass: HomeAssistant,
    simulator: Simulator,
    demo_entry: MockConfigEntry,
    hass_client: ClientSessionGenerator,
) -> None:
    """As stored, as applied (what a point takes), and those the PLC lacks now."""
    await change_point(hass, demo_entry, "doorbellcount", writable=True, unit="kWh")
    stored = await async_load_overrides(hass, demo_entry.entry_id)
    await async_save_overrides(
        hass,
        demo_entry.entry_id,
        {**stored, "gone": PointOverride(invert=True)},
    )
    await demo_entry.runtime_data.async_replace_overrides(
        await async_load_overrides(hass, demo_entry.entry_id)
    )

    diagnostics = await get_diagnostics_for_config_entry(hass, hass_client, demo_entry)

    assert diagnostics["overrides"] == {
        "points": {
            "doorbellcount": {"writable": True, "unit": "kWh"},
            "gone": {"invert": True},
        },
        "applied": {"doorbellcount": {"writable": True, "unit": "kWh"}},
        "not_in_catalogue": ["gone"],
    }
    assert SIM_PASSWORD not in json.dumps(diagnostics)
