"""scripts/develop's setup of a real Home Assistant, over its REST and WebSocket APIs."""

from collections.abc import AsyncIterator
from datetime import UTC, datetime, timedelta
from pathlib import Path
import re
from typing import Any, Final

import aiohttp
import pytest
import yaml

from tests.conftest import SIM_PASSWORD, SIM_USERNAME
from tests.e2e.configuration import (
    DASHBOARD_URL_PATH,
    DEMO_DASHBOARD,
    http_settings,
    write_configuration,
)
from tests.e2e.conftest import bounded, real_home_assistant
from tests.e2e.home_assistant import HomeAssistantProcess
from tests.e2e.provision import (
    DOMAIN,
    TEKON_TITLE,
    GatewayAccess,
    HomeAssistantApi,
    MervisAccess,
    PlcAccess,
    provision,
)
from tests.simulator import Simulator
from tests.simulator.fpi4c import EXAMPLE_CSV, FpI4cSimulator, demo_stations
from tests.simulator.mervis import HOUSE_NAME, MervisSimulator
from tests.simulator.tekon import TekonGateway

HOUSE_VLIST: Final = Path(__file__).parents[1] / "simulator" / "mervis" / "house.vlist"

pytestmark = real_home_assistant

LISTEN: Final = ("127.0.0.1",)
# The line a map changed in place logs (coordinator.py).
POINTS_CHANGED: Final = re.compile(r"The points of .* changed")
# A line Home Assistant logs at ERROR or above, or a traceback.
LOGGED_ERROR: Final = re.compile(r"^\S+ \S+ (ERROR|CRITICAL) |^Traceback ")


def logged_errors(log: Path) -> list[str]:
    """The lines of a Home Assistant log that report an error, from any component."""
    return logged_lines(log, LOGGED_ERROR)


def logged_lines(log: Path, pattern: re.Pattern[str]) -> list[str]:
    """The lines of a Home Assistant log that `pattern` finds."""
    return [
        line for line in log.read_text("utf-8").splitlines() if pattern.search(line)
    ]


def dashboard_entities(node: Any) -> set[str]:
    """Every `entity:` a dashboard names, at any depth."""
    if isinstance(node, dict):
        own = {node["entity"]} if isinstance(node.get("entity"), str) else set()
        return own.union(*(dashboard_entities(value) for value in node.values()))
    if isinstance(node, list):
        return set().union(*(dashboard_entities(item) for item in node))
    return set()


async def recorded_units(api: HomeAssistantApi, domain: str) -> dict[str, set[str]]:
    """The units each sensor of `domain` with a state class was recorded with, ever.

    A sensor recorded without its unit and then with it is one whose long-term
    statistics the recorder cannot convert (a warning, and a Repairs issue).
    """
    registry = await api.websocket_command({"type": "config/entity_registry/list"})
    sensors = sorted(
        item["entity_id"]
        for item in registry
        if item["platform"] == domain and item["entity_id"].startswith("sensor.")
    )
    states = await api.request("GET", "/api/states")
    measured = {
        state["entity_id"]
        for state in states
        if state["entity_id"] in sensors and "state_class" in state["attributes"]
    }
    # Every state since an hour ago (since the first start), as the frontend asks.
    history = await api.websocket_command(
        {
            "type": "history/history_during_period",
            "start_time": (datetime.now(UTC) - timedelta(hours=1)).isoformat(),
            "entity_ids": sorted(measured),
            "significant_changes_only": False,
            "minimal_response": False,
            "no_attributes": False,
        }
    )
    return {
        entity_id: {
            str(row["a"].get("unit_of_measurement")) for row in rows if "a" in row
        }
        for entity_id, rows in history.items()
    }


@pytest.fixture
async def gateway() -> AsyncIterator[FpI4cSimulator]:
    """The demo's FP-I4C gateway (a heating plant and a garage door)."""
    async with FpI4cSimulator(demo_stations(), station=1) as simulator:
        yield simulator


@pytest.fixture
async def mervis(socket_enabled: None) -> AsyncIterator[MervisSimulator]:
    """The simulated Mervis cottage scripts/develop adds beside the PLC."""
    async with MervisSimulator(username=SIM_USERNAME, password=SIM_PASSWORD) as sim:
        yield sim


@pytest.fixture
async def tekon() -> AsyncIterator[TekonGateway]:
    """A simulated Tekon gateway (a small building)."""
    async with TekonGateway() as simulator:
        yield simulator


@pytest.fixture
async def session() -> AsyncIterator[aiohttp.ClientSession]:
    """An HTTP client for Home Assistant."""
    async with aiohttp.ClientSession() as client:
        yield client


async def start(
    config_dir: Path, port: int, log: Path, session: aiohttp.ClientSession
) -> HomeAssistantProcess:
    """Write the demo's configuration (passwordless local sign-in) and start on it."""
    write_configuration(
        config_dir, port=port, listen=LISTEN, trusted_local_login=True, demo=True
    )
    process = HomeAssistantProcess(config_dir, port, log)
    await process.start(session)
    return process


@bounded
async def test_provision_then_restart(
    *,
    simulator: Simulator,
    gateway: FpI4cSimulator,
    tekon: TekonGateway,
    mervis: MervisSimulator,
    unused_tcp_port: int,
    home_assistant_log: Path,
    session: aiohttp.ClientSession,
) -> None:
    """The first start adds the PLC, both gateways and the Mervis controller; then nothing.

    Both start cleanly offline: nothing logged at ERROR by any component (tts and
    camera find ffmpeg and libturbojpeg; nothing is set up that needs the internet),
    and no repair shown but this integration's.
    """
    config_dir = home_assistant_log.parent / "config"
    plc = PlcAccess(host=simulator.host, username=SIM_USERNAME, password=SIM_PASSWORD)
    settings = http_settings(unused_tcp_port, LISTEN)
    cottage = MervisAccess(
        host=mervis.host,
        username=SIM_USERNAME,
        password=SIM_PASSWORD,
        vlist=HOUSE_VLIST,
        content=HOUSE_VLIST.read_bytes(),
    )
    gateway_host = gateway.url.removeprefix("http://")
    fpi4c = GatewayAccess(host=gateway_host, point_map=EXAMPLE_CSV)

    process = await start(config_dir, unused_tcp_port, home_assistant_log, session)
    try:
        first = await provision(
            session,
            process.url,
            plc,
            settings,
            DASHBOARD_URL_PATH,
            gateway=fpi4c,
            tekon=tekon.url,
            mervis=cottage,
        )
        again = await provision(
            session,
            process.url,
            plc,
            settings,
            DASHBOARD_URL_PATH,
            gateway=fpi4c,
            tekon=tekon.url,
            mervis=cottage,
        )

        api = HomeAssistantApi(session, process.url)
        await api.sign_in(await api.trusted_network_code())
        titles = await api.entry_titles(DOMAIN)
        http = await api.websocket_command({"type": "http/config"})
        core = await api.websocket_command(
            {"type": "frontend/get_system_data", "key": "core"}
        )
        states = {
            state["entity_id"]: state["state"]
            for state in await api.request("GET", "/api/states")
        }
        repairs = await api.websocket_command({"type": "repairs/list_issues"})
    finally:
        stopped = await process.stop()

    assert stopped == 0, "Home Assistant did not stop cleanly"
    assert logged_errors(home_assistant_log) == []
    shown = [
        (issue["domain"], issue["issue_id"])
        for issue in repairs["issues"]
        if not issue["ignored"]
    ]
    assert shown == []
    # Nothing changed a map after the entries were added.
    assert logged_lines(home_assistant_log, POINTS_CHANGED) == []
    # The other onboarding steps and the HTTP settings were settled beforehand.
    assert first == [
        "created the owner account 'owner'",
        f"made /{DASHBOARD_URL_PATH} the dashboard Home Assistant opens on",
        f"added the PLC {titles[0]!r}",
        f"added the gateway 'FP-I4C · {gateway_host}'",
        f"added the gateway {TEKON_TITLE!r}",
        (
            f"added the Mervis controller 'Mervis · {HOUSE_NAME} · {mervis.host}' "
            "(its map with units, setpoints and relays writable)"
        ),
    ]
    assert again == []
    assert titles[1:] == [
        f"FP-I4C · {gateway_host}",
        TEKON_TITLE,
        f"Mervis · {HOUSE_NAME} · {mervis.host}",
    ]
    assert http["pending"] is None
    assert {key: http["stable"][key] for key in settings} == settings
    assert core["value"]["default_panel"] == DASHBOARD_URL_PATH
    # The dashboard shows what the integration made of the demo program and of
    # the gateway's map.
    wanted = dashboard_entities(yaml.safe_load(DEMO_DASHBOARD.read_text("utf-8")))
    assert wanted
    missing = {
        entity: states.get(entity)
        for entity in wanted
        if states.get(entity) in {None, "unavailable"}
    }
    assert missing == {}

    # A second start keeps the settings in Home Assistant's storage and has no
    # onboarding left to do.

    process = await start(config_dir, unused_tcp_port, home_assistant_log, session)
    try:
        after_restart = await provision(
            session,
            process.url,
            plc,
            settings,
            DASHBOARD_URL_PATH,
            gateway=fpi4c,
            tekon=tekon.url,
            mervis=cottage,
        )
        # What the first start recorded is all written now (it stopped).
        api = HomeAssistantApi(session, process.url)
        await api.sign_in(await api.trusted_network_code())
        units = await recorded_units(api, DOMAIN)
    finally:
        stopped = await process.stop()

    assert stopped == 0, "Home Assistant did not stop cleanly after the restart"
    assert after_restart == []
    # Every sensor was created with the unit it has (the Mervis map arrived
    # complete): long-term statistics never see a unit they cannot convert, so
    # the recorder has nothing to warn of and Repairs nothing to show later.
    assert units
    assert {entity_id: seen for entity_id, seen in units.items() if len(seen) > 1} == {}
    assert "http" not in yaml.safe_load(
        (config_dir / "configuration.yaml").read_text("utf-8")
    )
    assert logged_errors(home_assistant_log) == []
