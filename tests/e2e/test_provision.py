"""scripts/develop's setup of a real Home Assistant, over its REST and WebSocket APIs."""

from collections.abc import AsyncIterator
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
    MERVIS_DEMO_POINTS,
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
# A line Home Assistant logs at ERROR or above, or a traceback.
LOGGED_ERROR: Final = re.compile(r"^\S+ \S+ (ERROR|CRITICAL) |^Traceback ")


def logged_errors(log: Path) -> list[str]:
    """The lines of a Home Assistant log that report an error, from any component."""
    return [
        line
        for line in log.read_text("utf-8").splitlines()
        if LOGGED_ERROR.search(line)
    ]


def dashboard_entities(node: Any) -> set[str]:
    """Every `entity:` a dashboard names, at any depth."""
    if isinstance(node, dict):
        own = {node["entity"]} if isinstance(node.get("entity"), str) else set()
        return own.union(*(dashboard_entities(value) for value in node.values()))
    if isinstance(node, list):
        return set().union(*(dashboard_entities(item) for item in node))
    return set()


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
        if not issue["ignored"] and issue["domain"] != DOMAIN
    ]
    assert shown == []
    # The other onboarding steps and the HTTP settings were settled beforehand.
    assert first == [
        "created the owner account 'owner'",
        f"made /{DASHBOARD_URL_PATH} the dashboard Home Assistant opens on",
        f"added the PLC {titles[0]!r}",
        f"added the gateway 'FP-I4C · {gateway_host}'",
        f"added the gateway {TEKON_TITLE!r}",
        f"added the Mervis controller 'Mervis · {HOUSE_NAME}'",
        (
            f"changed {len(MERVIS_DEMO_POINTS)} of its points (setpoints and relays "
            "writable, units)"
        ),
    ]
    assert again == []
    assert titles[1:] == [
        f"FP-I4C · {gateway_host}",
        TEKON_TITLE,
        f"Mervis · {HOUSE_NAME}",
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
    finally:
        stopped = await process.stop()

    assert stopped == 0, "Home Assistant did not stop cleanly after the restart"
    assert after_restart == []
    assert "http" not in yaml.safe_load(
        (config_dir / "configuration.yaml").read_text("utf-8")
    )
    assert logged_errors(home_assistant_log) == []
