"""Outages and every simulator fault: availability, log levels, reauth, clean unload.

These tests run in real time (no frozen clock): client timeouts must fire. The
client timeout is made small, and polls are started by hand rather than by the
5 s timer. The simulated PLC answers concurrently here (``serialize=False``), so
that a request still sleeping out a latency spike does not hold up the next one
once the spike is over.
"""

import asyncio
from collections.abc import Callable
from dataclasses import dataclass
import logging
from typing import Final

from homeassistant.config_entries import SOURCE_REAUTH, ConfigEntryState
from homeassistant.const import STATE_UNAVAILABLE
from homeassistant.core import HomeAssistant
from homeassistant.util.async_ import get_scheduled_timer_handles
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.tecoapi.const import DOMAIN
from custom_components.tecoapi.coordinator import PlcCoordinator
from tests.components.tecoapi.conftest import (
    TIMEOUT,
    entry_data,
    make_entry,
    setup_entry,
)
from tests.conftest import SIM_PASSWORD
from tests.simulator import Simulator

OUTSIDE = "sensor.tecomat_cp_2080_outside_temperature"
MODE = "sensor.tecomat_cp_2080_mode"
INTEGRATION_LOGGER = "custom_components.tecoapi"


@pytest.fixture
async def entry(
    hass: HomeAssistant, plc: Simulator, short_timeout: None
) -> MockConfigEntry:
    """The demo PLC set up (first refresh done)."""
    return await setup_entry(hass, make_entry(plc))


def integration_records(
    caplog: pytest.LogCaptureFixture, level: int = logging.INFO
) -> list[tuple[int, str]]:
    """(level, message) the integration logged at ``level`` or above."""
    return [
        (record.levelno, record.getMessage())
        for record in caplog.records
        if record.name.startswith(INTEGRATION_LOGGER) and record.levelno >= level
    ]


def reauth_flows(hass: HomeAssistant) -> list[str]:
    """Sources of the integration's flows in progress."""
    return [
        flow["context"]["source"]
        for flow in hass.config_entries.flow.async_progress_by_handler(DOMAIN)
        if flow["context"]["source"] == SOURCE_REAUTH
    ]


async def refresh(hass: HomeAssistant, coordinator: PlcCoordinator) -> None:
    """One poll, and the state writes it causes."""
    await coordinator.async_refresh()
    await hass.async_block_till_done()


def coordinator_timers(hass: HomeAssistant, coordinator: PlcCoordinator) -> list[str]:
    """Timers scheduled for the coordinator (its refresh, its debouncer)."""
    owners = (coordinator, coordinator._debounced_refresh)
    found = []
    for handle in get_scheduled_timer_handles(hass.loop):
        if handle.cancelled():
            continue
        callback = handle._callback
        if getattr(callback, "__self__", None) in owners:
            found.append(repr(handle))
    return found


async def unload_cleanly(
    hass: HomeAssistant, entry: MockConfigEntry, tasks_before: set[asyncio.Task[object]]
) -> None:
    """Unload the entry; nothing of it may keep running."""
    coordinator = entry.runtime_data
    assert await hass.config_entries.async_unload(entry.entry_id)
    await hass.async_block_till_done()
    assert entry.state is ConfigEntryState.NOT_LOADED
    assert coordinator_timers(hass, coordinator) == []
    current = asyncio.current_task()
    assert {
        task
        for task in asyncio.all_tasks() - tasks_before
        if task is not current and _runs_home_assistant_code(task)
    } == set()


def _runs_home_assistant_code(task: asyncio.Task[object]) -> bool:
    """Whether a task runs Home Assistant's or the integration's code.

    The other tasks a test sees belong to the simulated PLC (its web server,
    its hung requests waiting for release).
    """
    code = getattr(task.get_coro(), "cr_code", None)
    filename = code.co_filename if code is not None else ""
    return "homeassistant" in filename or "custom_components" in filename


@dataclass(frozen=True, slots=True)
class Fault:
    """A simulator fault and what the integration must make of it."""

    name: str
    switch_on: Callable[[Simulator], None]
    available: bool
    """Whether the entities stay available."""
    logged: int | None
    """The level of the one line the integration logs (None: nothing above debug)."""
    reauth: bool = False


def _latency(sim: Simulator) -> None:
    sim.faults.latency = TIMEOUT * 3


def _drop(sim: Simulator) -> None:
    # aiohttp silently retries a dropped GET once: keep dropping.
    sim.faults.drop_connection = True


def _http_500(sim: Simulator) -> None:
    sim.faults.http_500 = True


def _truncated(sim: Simulator) -> None:
    sim.faults.truncated_json = True


def _malformed(sim: Simulator) -> None:
    sim.faults.malformed_json = True


def _hang(sim: Simulator) -> None:
    sim.faults.hang = True


def _stale_nonce(sim: Simulator) -> None:
    sim.nonce_max_uses = 1


def _revoked(sim: Simulator) -> None:
    sim.password = "other"


FAULTS: Final = [
    Fault("latency beyond the timeout", _latency, False, logging.INFO),
    Fault("dropped connection", _drop, False, logging.INFO),
    Fault("HTTP 500", _http_500, False, logging.INFO),
    Fault("truncated JSON", _truncated, False, logging.INFO),
    Fault("malformed JSON", _malformed, False, logging.INFO),
    Fault("hung response", _hang, False, logging.INFO),
    Fault("stale nonce", _stale_nonce, True, None),
    Fault("credentials revoked", _revoked, False, logging.WARNING, reauth=True),
]


@pytest.mark.parametrize("fault", FAULTS, ids=[fault.name for fault in FAULTS])
async def test_fault(
    hass: HomeAssistant,
    plc: Simulator,
    short_timeout: None,
    caplog: pytest.LogCaptureFixture,
    fault: Fault,
) -> None:
    """The first failed poll: availability, one log line at its level, reauth or not.

    Polls that keep failing log nothing more above debug; once the fault is gone
    the next poll brings the values back with one info line; unloading leaves no
    task or timer of the entry behind.
    """
    tasks_before = asyncio.all_tasks()
    entry = await setup_entry(hass, make_entry(plc))
    coordinator = entry.runtime_data
    caplog.set_level(logging.DEBUG)
    caplog.clear()

    fault.switch_on(plc)
    await refresh(hass, coordinator)

    expected = STATE_UNAVAILABLE if not fault.available else "4.5"
    assert hass.states.get(OUTSIDE).state == expected
    assert (hass.states.get(MODE).state == STATE_UNAVAILABLE) is not fault.available
    records = integration_records(caplog)
    assert [level for level, _message in records] == (
        [fault.logged] if fault.logged is not None else []
    )
    if fault.logged == logging.INFO:
        assert records[0][1].startswith(f"The PLC {entry.title} is unavailable: ")
    await hass.async_block_till_done()
    assert reauth_flows(hass) == ([SOURCE_REAUTH] if fault.reauth else [])
    if fault.name == "stale nonce":
        # Every request after the first met a used-up nonce and was answered again.
        assert any(request.status == 401 for request in plc.requests[1:])
    if fault.name == "hung response":
        assert plc.hung_requests >= 1

    if not fault.reauth:
        await refresh(hass, coordinator)
        assert integration_records(caplog) == records

    plc.faults.clear()
    plc.password = SIM_PASSWORD
    plc.set_value("outsideTemp.value", 6.5)
    if not fault.reauth:
        await refresh(hass, coordinator)
        assert hass.states.get(OUTSIDE).state == "6.5"
        assert hass.states.get(MODE).state == "run"
        recovered = integration_records(caplog)[len(records) :]
        if fault.available:
            assert recovered == []
        else:
            assert recovered == [
                (logging.INFO, f"The PLC {entry.title} is available again")
            ]
    assert integration_records(caplog, logging.ERROR) == []

    await unload_cleanly(hass, entry, tasks_before)


async def test_unreachable_at_start_retries_without_errors(
    hass: HomeAssistant,
    plc: Simulator,
    closed_port: str,
    caplog: pytest.LogCaptureFixture,
) -> None:
    """No PLC at start: setup is retried, and nothing is logged above info."""
    caplog.set_level(logging.DEBUG)
    entry = MockConfigEntry(
        domain=DOMAIN,
        title="CP-2080 · FAMILY_HOUSE v1.3",
        unique_id=plc.serial_number,
        data=entry_data(plc, host=f"http://{closed_port}"),
    )

    await setup_entry(hass, entry)

    assert entry.state is ConfigEntryState.SETUP_RETRY
    assert [
        record.getMessage()
        for record in caplog.records
        if record.levelno >= logging.WARNING
        and record.name.startswith(
            (
                INTEGRATION_LOGGER,
                "homeassistant.config_entries",
                "homeassistant.helpers",
            )
        )
    ] == []
    # Home Assistant says it will retry (info on 2026.10, debug on 2026.2).
    assert any(
        "not ready yet" in record.getMessage() and record.levelno <= logging.INFO
        for record in caplog.records
    )


async def test_hung_poll_is_cancelled_by_unload(
    hass: HomeAssistant,
    plc: Simulator,
    caplog: pytest.LogCaptureFixture,
) -> None:
    """Unloading while a poll waits for a hung answer: the poll is cancelled cleanly."""
    tasks_before = asyncio.all_tasks()
    entry = await setup_entry(hass, make_entry(plc))
    coordinator = entry.runtime_data
    plc.faults.hang = True

    poll = entry.async_create_background_task(
        hass, coordinator.async_refresh(), "a poll that hangs"
    )
    await plc.wait_for_hung_requests(1)
    await unload_cleanly(hass, entry, tasks_before)

    assert poll.cancelled()
    assert integration_records(caplog, logging.WARNING) == []


async def test_entities_unavailable_until_the_plc_returns(
    hass: HomeAssistant,
    plc: Simulator,
    entry: MockConfigEntry,
    caplog: pytest.LogCaptureFixture,
) -> None:
    """Gone for several polls: one info line when it goes, one when it returns."""
    coordinator = entry.runtime_data
    caplog.set_level(logging.DEBUG)
    caplog.clear()
    port = plc.port
    await plc.stop()

    for _ in range(3):
        await refresh(hass, coordinator)
        assert hass.states.get(OUTSIDE).state == STATE_UNAVAILABLE

    plc.set_value("outsideTemp.value", -3.0)
    await plc.start(port=port)
    await refresh(hass, coordinator)

    assert hass.states.get(OUTSIDE).state == "-3.0"
    records = integration_records(caplog)
    assert [level for level, _message in records] == [logging.INFO, logging.INFO]
    assert records[0][1].startswith(f"The PLC {entry.title} is unavailable: ")
    assert records[1] == (logging.INFO, f"The PLC {entry.title} is available again")
    # Home Assistant's own "data recovered" says it no more than at debug.
    assert not [
        record
        for record in caplog.records
        if "recovered" in record.getMessage() and record.levelno > logging.DEBUG
    ]
    assert [
        message
        for level, message in integration_records(caplog, logging.DEBUG)
        if "still unavailable" in message
    ] != []
