"""Fixtures for the Home Assistant integration tests."""

import asyncio
from collections import Counter
from collections.abc import AsyncIterator, Generator, Iterator
from datetime import timedelta
from pathlib import Path
import socket
import tempfile
from typing import Any
from unittest.mock import AsyncMock, PropertyMock, patch

from aiohttp import web
from freezegun.api import FrozenDateTimeFactory
from homeassistant.config_entries import SOURCE_USER, ConfigFlowResult
from homeassistant.const import CONF_HOST, CONF_PASSWORD, CONF_USERNAME, CONF_VERIFY_SSL
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
from homeassistant.helpers import entity_registry as er
from homeassistant.helpers.entity import Entity
import pytest
from pytest_homeassistant_custom_component.common import (
    MockConfigEntry,
    async_fire_time_changed,
)
from pytest_homeassistant_custom_component.syrupy import HomeAssistantSnapshotExtension
from syrupy.assertion import SnapshotAssertion

from custom_components.tecoapi.const import CONF_TRANSPORT, DOMAIN
from custom_components.tecoapi.point_maps import async_save_point_map
from custom_components.tecoapi.pyplc.core.descriptor import CONF_POINT_MAP
from tests.components.tecoapi.memory_house import IDENTITY
from tests.components.tecoapi.mervis_house import PASSWORD, USER
from tests.conftest import SIM_PASSWORD, SIM_USERNAME, Certificate
from tests.deprecations import DEPRECATED_USE
from tests.fake_source import (
    NAME,
    MemoryDevice,
    house_device,
    house_map,
    memory_registered,
)
from tests.simulator import Simulator
from tests.simulator.fpi4c import FpI4cSimulator, demo_stations
from tests.simulator.mervis import MervisSimulator, house as mervis_project


@pytest.fixture
def snapshot(snapshot: SnapshotAssertion) -> SnapshotAssertion:
    """Snapshots through Home Assistant's extension (stable registry IDs, states)."""
    return snapshot.use_extension(HomeAssistantSnapshotExtension)


@pytest.fixture(autouse=True)
def auto_enable_custom_integrations(enable_custom_integrations: None) -> None:
    """Let Home Assistant load custom_components.tecoapi in every test here."""


@pytest.fixture(autouse=True)
def no_deprecated_use(caplog: pytest.LogCaptureFixture) -> Iterator[None]:
    """Fail a test in which Home Assistant reports a deprecated use by the integration.

    A deprecation is a warning in the log today and a breakage a few releases later.
    Home Assistant reports each call site once per process, so the first test that
    reaches it fails.
    """
    yield
    assert [
        line
        for phase in ("setup", "call")
        for record in caplog.get_records(phase)
        if DEPRECATED_USE.search(line := f"[{record.name}] {record.getMessage()}")
    ] == []


def entry_data(sim: Simulator, **changes: Any) -> dict[str, Any]:
    """Config entry data for a simulator, as the config flow stores it."""
    return {
        CONF_HOST: sim.url,
        CONF_USERNAME: SIM_USERNAME,
        CONF_PASSWORD: SIM_PASSWORD,
        CONF_VERIFY_SSL: True,
        **changes,
    }


def make_entry(sim: Simulator, **options: Any) -> MockConfigEntry:
    """A config entry for a simulator, as the config flow creates it."""
    return MockConfigEntry(
        domain=DOMAIN,
        title=f"{sim.plc_type} · {sim.program.name}",
        unique_id=sim.serial_number,
        data=entry_data(sim),
        options=options,
    )


async def add_tecoapi(hass: HomeAssistant, host: str) -> ConfigFlowResult:
    """Add the simulated PLC at ``host`` from the UI, as a user does: TecoApi's form."""
    result = await hass.config_entries.flow.async_init(
        DOMAIN, context={"source": SOURCE_USER}
    )
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {"next_step_id": "tecoapi"}
    )
    return await hass.config_entries.flow.async_configure(
        result["flow_id"],
        {
            CONF_HOST: host,
            CONF_USERNAME: SIM_USERNAME,
            CONF_PASSWORD: SIM_PASSWORD,
            CONF_VERIFY_SSL: True,
        },
    )


async def setup_entry(hass: HomeAssistant, entry: MockConfigEntry) -> MockConfigEntry:
    """Add an entry to Home Assistant and set it up."""
    entry.add_to_hass(hass)
    await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    return entry


async def open_settings(hass: HomeAssistant, entry_id: str) -> dict[str, Any]:
    """Open an entry's options at its settings form: its menu's first choice."""
    result = await hass.config_entries.options.async_init(entry_id)
    assert result["type"] is FlowResultType.MENU, result
    assert result["menu_options"][0] == "settings"
    return dict(
        await hass.config_entries.options.async_configure(
            result["flow_id"], {"next_step_id": "settings"}
        )
    )


@pytest.fixture
def mock_setup_entry() -> Generator[AsyncMock]:
    """Keep config-flow tests to the flow: entries are created, not set up."""
    with patch(
        "custom_components.tecoapi.async_setup_entry", return_value=True
    ) as mock:
        yield mock


@pytest.fixture
def config_entry(simulator: Simulator) -> MockConfigEntry:
    """A config entry for the demo simulator (not yet added to Home Assistant)."""
    return make_entry(simulator)


@pytest.fixture
def manual_entry(manual_simulator: Simulator) -> MockConfigEntry:
    """A config entry for the manual's program (not yet added)."""
    return make_entry(manual_simulator)


@pytest.fixture
async def tls_simulator(
    hass: HomeAssistant, socket_enabled: None, certificate: Certificate
) -> AsyncIterator[Simulator]:
    """The demo simulator serving HTTPS with a self-signed certificate.

    A client that refuses the certificate hangs up mid-handshake; the simulated
    PLC's side of that (an error accepting the connection) is expected and kept
    out of the test loop's exception handler, which would fail the test.
    """
    loop = asyncio.get_running_loop()
    handler = loop.get_exception_handler()

    def ignore_refused_handshakes(
        loop: asyncio.AbstractEventLoop, context: dict[str, Any]
    ) -> None:
        if (
            context.get("message")
            == "Error on transport creation for incoming connection"
        ):
            return
        if handler is None:
            loop.default_exception_handler(context)
        else:
            handler(loop, context)

    loop.set_exception_handler(ignore_refused_handshakes)
    sim = Simulator("demo", username=SIM_USERNAME, password=SIM_PASSWORD)
    await sim.start(ssl_context=certificate.server_context())
    try:
        yield sim
    finally:
        await sim.stop()
        loop.set_exception_handler(handler)


@pytest.fixture
async def web_server(socket_enabled: None) -> AsyncIterator[str]:
    """A web server on 127.0.0.1 that is not a PLC; yields its host:port."""

    async def not_found(request: web.Request) -> web.Response:
        return web.Response(status=404, text="No such page")

    app = web.Application()
    app.router.add_get("/{tail:.*}", not_found)
    runner = web.AppRunner(app, access_log=None)
    await runner.setup()
    site = web.TCPSite(runner, "127.0.0.1", 0)
    await site.start()
    try:
        yield f"127.0.0.1:{runner.addresses[0][1]}"
    finally:
        await runner.cleanup()


@pytest.fixture
def closed_port(socket_enabled: None) -> str:
    """host:port on 127.0.0.1 where nothing listens."""
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    return f"127.0.0.1:{port}"


TIMEOUT = 0.5
"""The client timeout in tests of slow and hung PLCs (seconds).

Short, yet long enough for a request the PLC answers at once (a stale nonce costs
two round trips) on two busy cores, each running a pytest worker.
"""


@pytest.fixture
def short_timeout() -> Generator[None]:
    """Requests to the PLC time out after TIMEOUT seconds (real time, no freezer)."""
    with patch("custom_components.tecoapi.connection.REQUEST_TIMEOUT", TIMEOUT):
        yield


@pytest.fixture
async def plc(socket_enabled: None) -> AsyncIterator[Simulator]:
    """The demo PLC answering requests concurrently.

    A request sleeping out a latency spike then does not hold up the next one.
    """
    async with Simulator(
        "demo", username=SIM_USERNAME, password=SIM_PASSWORD, serialize=False
    ) as sim:
        yield sim


@pytest.fixture
def entity_registry_enabled_by_default() -> Generator[None]:
    """Create every entity enabled, including those disabled by default."""
    with patch(
        "homeassistant.helpers.entity.Entity.entity_registry_enabled_default",
        new_callable=PropertyMock,
        return_value=True,
    ):
        yield


class StateWrites(Counter[str]):
    """How often each entity wrote its state since the last reset."""

    @property
    def total(self) -> int:
        """All writes of all entities."""
        return sum(self.values())


@pytest.fixture
def state_writes() -> Generator[StateWrites]:
    """Count every entity state write (including writes that change nothing)."""
    writes = StateWrites()
    original = Entity.async_write_ha_state

    def counting_write(entity: Entity) -> None:
        writes[entity.entity_id] += 1
        original(entity)

    with patch.object(Entity, "async_write_ha_state", counting_write):
        yield writes


async def snapshot_entities(
    hass: HomeAssistant,
    snapshot: SnapshotAssertion,
    entry: MockConfigEntry,
    domain: str,
) -> None:
    """Pin registry entry and state of every entity of one platform of an entry."""
    registry = er.async_get(hass)
    entries = sorted(
        (
            entity
            for entity in er.async_entries_for_config_entry(registry, entry.entry_id)
            if entity.domain == domain
        ),
        key=lambda entity: entity.entity_id,
    )
    assert entries
    for entity in entries:
        assert entity == snapshot(name=f"{entity.entity_id}-entry")
        assert hass.states.get(entity.entity_id) == snapshot(
            name=f"{entity.entity_id}-state"
        )


def entity_id_of(hass: HomeAssistant, domain: str, unique_id: str) -> str:
    """The entity ID registered for a unique ID (IDs depend on devices and areas)."""
    entity_id = er.async_get(hass).async_get_entity_id(domain, DOMAIN, unique_id)
    assert entity_id is not None, unique_id
    return entity_id


FROZEN_TIME = "2026-03-14T10:00:00+00:00"


@pytest.fixture(params=["demo", "manual"])
async def program_entry(
    request: pytest.FixtureRequest,
    hass: HomeAssistant,
    socket_enabled: None,
    freezer: FrozenDateTimeFactory,
) -> AsyncIterator[MockConfigEntry]:
    """Each shipped program on its simulator, set up at a fixed time (snapshots)."""
    sim = Simulator(request.param, username=SIM_USERNAME, password=SIM_PASSWORD)
    await sim.start()
    try:
        freezer.move_to(FROZEN_TIME)
        yield await setup_entry(hass, make_entry(sim))
    finally:
        await sim.stop()


@pytest.fixture
async def demo_entry(
    hass: HomeAssistant,
    simulator: Simulator,
    config_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> MockConfigEntry:
    """The demo program set up at a fixed time."""
    freezer.move_to(FROZEN_TIME)
    return await setup_entry(hass, config_entry)


@pytest.fixture
async def manual_program_entry(
    hass: HomeAssistant,
    manual_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> MockConfigEntry:
    """The manual's program set up at a fixed time."""
    freezer.move_to(FROZEN_TIME)
    return await setup_entry(hass, manual_entry)


async def poll(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory, seconds: float = 5
) -> None:
    """Let time pass, and the polls it schedules finish."""
    freezer.tick(timedelta(seconds=seconds))
    async_fire_time_changed(hass)
    await hass.async_block_till_done(wait_background_tasks=True)


async def set_up_house(
    hass: HomeAssistant, parents: dict[str, str] | None = None
) -> MemoryDevice:
    """The memory house, set up as the config flow stores it (the source registered)."""
    device = house_device(IDENTITY)
    device.parents.update(parents or {})
    map_id = await async_save_point_map(hass, house_map())
    entry = MockConfigEntry(
        domain=DOMAIN,
        title="M1",
        unique_id=IDENTITY,
        data={"host": IDENTITY, CONF_TRANSPORT: NAME, CONF_POINT_MAP: map_id},
    )
    await setup_entry(hass, entry)
    return device


@pytest.fixture
async def house(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory
) -> AsyncIterator[MemoryDevice]:
    """The memory house (tests/components/tecoapi/memory_house.py drives it)."""
    freezer.move_to(FROZEN_TIME)
    with memory_registered():
        yield await set_up_house(hass)


@pytest.fixture
def memory(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Iterator[None]:
    """The memory source, offered while the test runs.

    Uploads go to the test's own temporary folder: ``file_upload`` empties its
    folder when it starts, and tests in other processes upload too.
    """
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    with memory_registered():
        yield


@pytest.fixture
async def gateway(socket_enabled: None) -> AsyncIterator[FpI4cSimulator]:
    """The simulated gateway, its demo stations, station 1 its own."""
    async with FpI4cSimulator(demo_stations(), station=1) as simulator:
        yield simulator


@pytest.fixture
def uploads(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Uploads go to the test's own folder (file_upload empties its folder at start)."""
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))


@pytest.fixture
async def mervis(socket_enabled: None, uploads: None) -> AsyncIterator[MervisSimulator]:
    """The simulated house, with credentials."""
    sim = MervisSimulator(mervis_project(), username=USER, password=PASSWORD)
    await sim.start()
    try:
        yield sim
    finally:
        await sim.stop()
