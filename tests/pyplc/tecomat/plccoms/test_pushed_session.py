"""PushedTecoApiSession: TecoApi for identity and writes, PLCComS for the values.

Against both simulators of one PLC on 127.0.0.1: TecoApi requests are counted in
the simulator's records, PLCComS change detection runs when a test awaits
`coms.scan()`, and nothing sleeps: tests await the pushes and events they expect.
"""

import asyncio
from collections.abc import AsyncIterator, Callable
import contextlib
from typing import Any

import aiohttp
import pytest

from custom_components.tecoapi.pyplc import PlcMode, Snapshot
from custom_components.tecoapi.pyplc.tecomat.plccoms.client import PlcComsClient
from custom_components.tecoapi.pyplc.tecomat.plccoms.events import (
    ConnectionChanged,
    PlcComsEvent,
)
from custom_components.tecoapi.pyplc.tecomat.plccoms.pushed_session import (
    CONNECT_RETRY,
    PushedTecoApiSession,
)
from tests.pyplc.conftest import Clock, Heard, make_client
from tests.simulator import Program, Simulator
from tests.simulator.plccoms import PlcComsServer

pytestmark = pytest.mark.usefixtures("socket_enabled")

POLLED = frozenset({"outsidetemp", "heating.livingsetpoint", "lights[1]"})


def connected(state: bool) -> Callable[[PlcComsEvent], bool]:
    return lambda event: (
        isinstance(event, ConnectionChanged) and event.connected is state
    )


class Plc:
    """One simulated PLC with TecoApi and PLCComS, and a pushed session of it."""

    def __init__(
        self,
        sim: Simulator,
        coms: PlcComsServer,
        session: PushedTecoApiSession,
        clock: Clock,
    ) -> None:
        self.sim = sim
        self.coms = coms
        self.session = session
        self.clock = clock
        self.events = Heard[PlcComsEvent](session.coms.subscribe)
        self.pushes = Heard[Snapshot](session.subscribe)

    def services(self) -> list[str]:
        return [r.service for r in self.sim.requests if r.authorized]

    async def poll(self, seconds: float = 5) -> Snapshot:
        self.clock.tick(seconds)
        return await self.session.poll(POLLED)

    async def pushed(self, condition: Callable[[Snapshot], bool]) -> Snapshot:
        return await self.pushes.wait_for(condition)


async def _at_once(job: Callable[[], Any]) -> Any:
    return job()


@contextlib.asynccontextmanager
async def started(
    session: aiohttp.ClientSession, simulator: Simulator, **server: Any
) -> AsyncIterator[Plc]:
    """The demo PLC discovered, PLCComS connected, the polled points pushed."""
    async with PlcComsServer(simulator, scan_interval=None, **server) as coms:
        clock = Clock()
        pushed = PushedTecoApiSession(
            make_client(session, simulator),
            PlcComsClient("127.0.0.1", coms.port, timeout=0.5, reconnect_delay=0.01),
            clock=clock,
            run_blocking=_at_once,
        )
        plc = Plc(simulator, coms, pushed, clock)
        try:
            await pushed.poll(())  # discovery; PLCComS connects in the background
            await plc.events.wait_for(connected(True))
            await plc.poll()  # enables the polled points, reads TecoApi once more
            yield plc
        finally:
            await pushed.close()


@pytest.fixture
async def plc(
    session: aiohttp.ClientSession, simulator: Simulator
) -> AsyncIterator[Plc]:
    """The demo PLC discovered, PLCComS connected, the polled points pushed."""
    async with started(session, simulator) as plc:
        yield plc


@pytest.fixture
async def discovered(
    session: aiohttp.ClientSession, simulator: Simulator
) -> AsyncIterator[Plc]:
    """The demo PLC discovered, PLCComS connecting in the background, no poll yet."""
    async with PlcComsServer(simulator, scan_interval=None) as coms:
        clock = Clock()
        pushed = PushedTecoApiSession(
            make_client(session, simulator),
            PlcComsClient("127.0.0.1", coms.port, timeout=0.5, reconnect_delay=0.01),
            clock=clock,
            run_blocking=_at_once,
        )
        plc = Plc(simulator, coms, pushed, clock)
        try:
            await pushed.poll(())
            yield plc
        finally:
            await pushed.close()


# --- following the polled points before the first poll ----------------------------------


async def test_follow_enables_the_polled_points_without_a_poll(
    discovered: Plc,
) -> None:
    """Right after discovery: changes are pushed at once, and TecoApi is not read."""
    plc = discovered
    plc.sim.set_value("outsideTemp.value", -2.0)  # changed since discovery
    plc.sim.clear_requests()

    await plc.session.follow(POLLED)

    assert plc.sim.requests == []
    assert plc.coms.enabled()[0] >= {"outsidetemp.value", "lights[1].value"}
    caught_up = await plc.pushed(lambda s: "outsidetemp" in s.values)
    assert caught_up.values["outsidetemp"] == -2.0
    plc.sim.set_value("lights[1].value", False)
    await plc.coms.scan()
    pushed = await plc.pushed(lambda s: s.values.get("lights[1]") is False)
    assert pushed.values == {"lights[1]": False}
    assert plc.session.statistics.polls == 0
    # The first poll still reads TecoApi once before trusting pushes; then none.
    await plc.poll()
    plc.sim.clear_requests()
    await plc.poll()
    assert plc.sim.requests == []


async def test_follow_without_plccoms_leaves_it_to_the_polls(
    session: aiohttp.ClientSession, simulator: Simulator
) -> None:
    coms = PlcComsServer(simulator, scan_interval=None)
    await coms.start()
    port = coms.port
    await coms.stop()  # nothing listens there
    pushed = PushedTecoApiSession(
        make_client(session, simulator),
        PlcComsClient("127.0.0.1", port, timeout=0.5, reconnect_delay=0.01),
        clock=Clock(),
        run_blocking=_at_once,
    )
    try:
        await pushed.follow(POLLED)  # before discovery: nothing to follow
        await pushed.poll(())
        simulator.clear_requests()

        await pushed.follow(POLLED)

        assert simulator.requests == []
        assert pushed.diagnostics()["push"]["enabled"] == 0
    finally:
        await pushed.close()


async def test_read_points_reads_only_what_plccoms_does_not_push(plc: Plc) -> None:
    """A pushed point needs no read; another is read through TecoApi."""
    plc.sim.clear_requests()

    assert await plc.session.read_points({"outsidetemp", "lights[1]"}) is None
    assert plc.sim.requests == []

    plc.sim.set_value("Heating.bedroomSetpoint.value", 19.5)
    read = await plc.session.read_points({"outsidetemp", "heating.bedroomsetpoint"})

    assert read is not None
    assert read.values == {"heating.bedroomsetpoint": 19.5}
    assert plc.services() == ["GetObject"]


# --- push instead of polling -----------------------------------------------------------


async def test_no_tecoapi_value_poll_while_plccoms_is_healthy(plc: Plc) -> None:
    plc.sim.clear_requests()

    snapshots = [await plc.poll() for _ in range(10)]  # 50 s: no reconciliation yet

    assert plc.sim.requests == []
    assert all(snapshot.values == {} for snapshot in snapshots)
    assert plc.session.statistics.last_poll_requests == 0
    assert plc.session.diagnostics()["push"]["polls_without_tecoapi"] == 10
    assert plc.coms.enabled()[0] >= {"outsidetemp.value", "lights[1].value"}


async def test_changes_arrive_by_diff_as_one_snapshot_per_burst(plc: Plc) -> None:
    plc.sim.clear_requests()
    plc.sim.set_value("outsideTemp.value", -7.5)
    plc.sim.set_value("lights[1].value", False)

    await plc.coms.scan()
    pushed = await plc.pushed(lambda s: bool(s.values))
    polled = await plc.poll()

    assert pushed.values == {"outsidetemp": -7.5, "lights[1]": False}
    assert len(plc.pushes.items) == 1
    assert polled.values == pushed.values
    assert polled.catalogue is pushed.catalogue
    assert plc.sim.requests == []


async def test_attributes_come_over_plccoms_and_tecoapi_every_five_minutes(
    plc: Plc,
) -> None:
    plc.sim.set_value("outsideTemp.attr.title", "Outdoor temperature")
    plc.sim.clear_requests()
    before = len(plc.coms.commands)

    early = await plc.poll(30)
    attributes = await plc.poll(30)  # the metadata cadence: over PLCComS

    assert early.attributes == {}
    assert attributes.attributes.keys() == POLLED
    assert attributes.attributes["outsidetemp"].name == "Outdoor temperature"
    assert "GET:outsideTemp.attr.title" in plc.coms.commands[before:]
    assert plc.sim.requests == []

    # 50 polls at 5 s in all: then the reconciliation reads TecoApi, once.
    for _ in range(47):
        await plc.poll()
    assert plc.sim.requests == []
    reconciled = await plc.poll()
    assert plc.services() == ["GetInfo", "GetObject"]
    assert reconciled.values.keys() == POLLED
    assert reconciled.info_read_at == plc.clock.now
    plc.sim.clear_requests()
    await plc.poll()
    assert plc.sim.requests == []
    assert plc.session.diagnostics()["push"]["reconciliations"] == 2


async def test_a_value_pushed_during_a_tecoapi_read_wins(plc: Plc) -> None:
    """The DIFF is newer than what the slow reconciliation read."""
    plc.sim.faults.hang = True
    polling = asyncio.ensure_future(plc.poll(300))
    await plc.sim.wait_for_hung_requests(1)
    plc.sim.set_value("outsideTemp.value", 30.5)
    await plc.coms.scan()
    await plc.pushed(lambda s: s.values.get("outsidetemp") == 30.5)
    # The PLC moves on once more; its DIFF comes with the next scan.
    plc.sim.set_value("outsideTemp.value", 31.0)
    plc.sim.faults.hang = False

    reconciled = await polling

    assert reconciled.values["outsidetemp"] == 30.5
    await plc.coms.scan()
    await plc.pushed(lambda s: s.values.get("outsidetemp") == 31.0)


# --- falling back to TecoApi, and back to push -----------------------------------------


async def test_a_dropped_plccoms_falls_back_to_tecoapi_without_gaps(plc: Plc) -> None:
    plc.coms.faults.refuse = True
    await plc.coms.restart()
    await plc.events.wait_for(connected(False))
    plc.sim.set_value("outsideTemp.value", 1.5)  # never pushed: PLCComS is down
    plc.sim.clear_requests()

    fallback = await plc.poll()

    assert plc.services() == ["GetObject"]
    assert fallback.values["outsidetemp"] == 1.5
    assert fallback.values.keys() == POLLED

    # PLCComS is back: the first poll enables, then reads everything from TecoApi.
    plc.coms.faults.refuse = False
    await plc.events.wait_for(connected(True), count=2)
    plc.sim.set_value("outsideTemp.value", 2.5)
    plc.sim.clear_requests()
    resync = await plc.poll()
    assert "GetObject" in plc.services()
    assert resync.values["outsidetemp"] == 2.5

    plc.sim.clear_requests()
    await plc.poll()
    assert plc.sim.requests == []
    assert plc.session.diagnostics()["push"]["fallback_polls"] == 1


async def test_a_stalled_plccoms_falls_back_within_the_client_timeout(
    plc: Plc,
) -> None:
    plc.coms.faults.stall = True
    plc.sim.set_value("Heating.livingSetpoint.value", 24.0)
    plc.sim.clear_requests()

    fallback = await plc.poll()

    assert plc.services() == ["GetObject"]
    assert fallback.values["heating.livingsetpoint"] == 24.0
    assert plc.session.coms.health.stalls == 1

    plc.coms.faults.stall = False
    await plc.events.wait_for(connected(True), count=2)
    await plc.poll()  # enables again and reads TecoApi once
    plc.sim.clear_requests()
    await plc.poll()
    assert plc.sim.requests == []


async def test_an_unreachable_plccoms_means_tecoapi_polling(
    session: aiohttp.ClientSession, simulator: Simulator
) -> None:
    clock = Clock()
    coms = PlcComsServer(simulator, scan_interval=None)
    await coms.start()
    port = coms.port
    await coms.stop()  # nothing listens there for now
    pushed = PushedTecoApiSession(
        make_client(session, simulator),
        PlcComsClient("127.0.0.1", port, timeout=0.5, reconnect_delay=0.01),
        clock=clock,
        run_blocking=_at_once,
    )
    events = Heard[PlcComsEvent](pushed.coms.subscribe)
    try:
        await pushed.poll(())
        simulator.clear_requests()
        clock.tick(5)
        await pushed.poll(POLLED)
        clock.tick(5)
        snapshot = await pushed.poll(POLLED)

        assert [r.service for r in simulator.requests].count("GetObject") == 2
        assert snapshot.values.keys() == POLLED
        assert pushed.diagnostics()["push"]["connected"] is False
        assert pushed.diagnostics()["push"]["fallback_polls"] == 2

        # The server is there now: it is tried again after a while.
        await coms.start(port=port)
        clock.tick(CONNECT_RETRY.total_seconds())
        await pushed.poll(POLLED)
        await events.wait_for(connected(True))
        clock.tick(5)
        await pushed.poll(POLLED)  # enables, reads TecoApi once more
        simulator.clear_requests()
        clock.tick(5)
        await pushed.poll(POLLED)
        assert simulator.requests == []
    finally:
        await pushed.close()
        await coms.stop()


# --- writes ------------------------------------------------------------------------------


async def test_values_written_through_tecoapi_arrive_by_diff(plc: Plc) -> None:
    plc.sim.clear_requests()

    confirmed = await plc.session.write("heating.livingsetpoint", 22.5)
    acknowledged = await plc.pushed(lambda s: bool(s.values))
    await plc.coms.scan()
    held = await plc.pushed(lambda s: s is not acknowledged and bool(s.values))

    assert confirmed is None  # what the PLC holds comes by DIFF
    assert plc.services() == ["SetObject"]
    assert acknowledged.values == {"heating.livingsetpoint": 22.5}
    assert held.values == {"heating.livingsetpoint": 22.5}
    assert plc.sim.get_value("Heating.livingSetpoint.value") == 22.5


async def test_a_write_to_a_point_not_pushed_reads_back_through_tecoapi(
    plc: Plc,
) -> None:
    plc.sim.clear_requests()

    confirmed = await plc.session.write("heating.bedroomsetpoint", 20.0)

    assert confirmed is not None
    assert confirmed.values == {"heating.bedroomsetpoint": 20.0}
    assert plc.services() == ["SetObject", "GetObject"]


# --- the PLC's mode and program ---------------------------------------------------------


@pytest.mark.parametrize("mode", ["HALT", "ERR"])
async def test_a_stopped_plc_is_pushed_at_once(plc: Plc, mode: str) -> None:
    plc.sim.clear_requests()
    plc.sim.mode = mode

    await plc.coms.scan()
    stopped = await plc.pushed(lambda s: s.info.mode is not PlcMode.RUNNING)

    assert stopped.info.mode is PlcMode(mode)
    assert stopped.values == {}
    assert plc.services() == ["GetInfo"]

    plc.sim.mode = "RUN"
    await plc.coms.scan()
    running = await plc.pushed(
        lambda s: s is not stopped and s.info.mode is PlcMode.RUNNING
    )
    assert running.info.mode is PlcMode.RUNNING


async def test_a_program_download_is_discovered_on_the_next_poll(plc: Plc) -> None:
    source = plc.sim.program.to_mapping()
    source["variables"]["garageDoor"] = {"type": "BOOL", "value": True}
    plc.sim.load_program(Program.from_mapping(source))

    await plc.coms.scan()  # __PLC_RUN 0
    await plc.coms.scan()  # __PLC_RUN 1
    await plc.events.wait_for(lambda e: type(e).__name__ == "ProgramChanged")
    changed = await plc.poll()

    assert changed.program_changed
    assert changed.values["garagedoor"] is True
    assert plc.session.statistics.program_changes == 1
    # The new program's points are pushed again after one more TecoApi read.
    await plc.poll()
    plc.sim.clear_requests()
    plc.sim.set_value("outsideTemp.value", 3.0)
    await plc.coms.scan()
    pushed = await plc.pushed(lambda s: s.values.get("outsidetemp") == 3.0)
    assert pushed.catalogue is changed.catalogue
    assert plc.sim.requests == []


async def test_a_point_plccoms_does_not_list_is_read_from_tecoapi(
    session: aiohttp.ClientSession, simulator: Simulator
) -> None:
    """The server's public file lacks it: each poll reads it from TecoApi."""
    async with started(session, simulator, unpublished={"lights[1].value"}) as plc:
        assert "lights[1].value" not in plc.coms.enabled()[0]
        plc.sim.clear_requests()
        plc.sim.set_value("lights[1].value", False)
        snapshot = await plc.poll()
        assert plc.services() == ["GetObject"]
        assert snapshot.values == {"lights[1]": False}
        plc.sim.set_value("outsideTemp.value", 4.0)
        await plc.coms.scan()
        pushed = await plc.pushed(lambda s: s.values.get("outsidetemp") == 4.0)
        assert "lights[1]" not in pushed.values
        assert plc.session.diagnostics()["push"]["unpushable"] == 1


async def test_close_closes_plccoms(plc: Plc) -> None:
    await plc.session.close()

    await plc.coms.wait_for_open_connections(0)
    with contextlib.suppress(Exception):
        await plc.session.close()


async def test_a_stop_is_pushed_from_plccoms_when_getinfo_fails(plc: Plc) -> None:
    plc.sim.faults.http_500 = True
    plc.sim.mode = "HALT"

    await plc.coms.scan()
    stopped = await plc.pushed(lambda s: s.info.mode is not PlcMode.RUNNING)

    assert stopped.info.mode is PlcMode.STOPPED
    plc.sim.faults.http_500 = False
    plc.sim.clear_requests()
    polled = await plc.poll()
    assert plc.services() == ["GetInfo"]
    assert polled.info.mode is PlcMode.STOPPED


async def test_unknown_polled_keys_are_ignored(plc: Plc) -> None:
    plc.sim.clear_requests()
    plc.clock.tick(5)

    snapshot = await plc.session.poll(POLLED | {"nosuchpoint"})

    assert snapshot.values == {}
    assert plc.sim.requests == []
