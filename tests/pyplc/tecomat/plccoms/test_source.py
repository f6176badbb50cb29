"""PlcComsSource: PLCComS alone as a PLC source, against the simulators on 127.0.0.1."""

from collections.abc import AsyncIterator, Awaitable, Callable
import contextlib
from datetime import UTC, date, datetime, timedelta
import struct
from typing import Any

import aiohttp
import pytest

from custom_components.tecoapi.pyplc import (
    InvalidValueError,
    NoPublicVariablesError,
    NotAPlcError,
    OutOfRangeError,
    PlcConnectionError,
    PlcMode,
    PlcUnreachableError,
    ReadOnlyError,
    Snapshot,
    ValueRejectedError,
    VariableNotFoundError,
)
from custom_components.tecoapi.pyplc.tecomat import TecoApiSession
from custom_components.tecoapi.pyplc.tecomat.plccoms.client import PlcComsClient
from custom_components.tecoapi.pyplc.tecomat.plccoms.events import (
    ConnectionChanged,
    PlcComsEvent,
    ProgramChanged,
)
from custom_components.tecoapi.pyplc.tecomat.plccoms.source import (
    UNFIT,
    PlcComsSource,
    plc_info_from_getinfo,
)
from tests.pyplc.conftest import START, Clock, Heard, make_client
from tests.simulator import Program, Simulator, load_program
from tests.simulator.plccoms import PlcComsOptions, PlcComsServer

pytestmark = pytest.mark.usefixtures("socket_enabled")

POLLED = frozenset({"outsidetemp", "heating.livingsetpoint", "lights[1]"})


class Plc:
    """A simulated PLC, its PLCComS server and a source of it."""

    def __init__(
        self, sim: Simulator, coms: PlcComsServer, source: PlcComsSource, clock: Clock
    ) -> None:
        self.sim = sim
        self.coms = coms
        self.source = source
        self.clock = clock

    @property
    def client(self) -> PlcComsClient:
        return self.source.client

    def commands_since(self, count: int) -> list[str]:
        return self.coms.commands[count:]


type StartPlc = Callable[..., Awaitable[Plc]]


@pytest.fixture
async def start() -> AsyncIterator[StartPlc]:
    """Start a demo PLC's PLCComS server (scanning when told) and a source of it."""
    async with contextlib.AsyncExitStack() as stack:

        async def starting(
            program: str | Program = "demo",
            server: PlcComsOptions | None = None,
            **options: Any,
        ) -> Plc:
            sim = Simulator(program, username="admin", password="s3cret-Pa55")
            coms = PlcComsServer(sim, options=server, scan_interval=None)
            await coms.start()
            stack.push_async_callback(coms.stop)
            # Long enough for an answer on two busy cores, each running a pytest
            # worker (0.5 s was not, once); a stalled server's tests wait it out.
            options.setdefault("timeout", 1.0)
            options.setdefault("reconnect_delay", 0.01)
            clock = Clock()
            source = PlcComsSource(
                PlcComsClient("127.0.0.1", coms.port, **options), clock=clock
            )
            stack.push_async_callback(source.close)
            return Plc(sim, coms, source, clock)

        yield starting


@pytest.fixture
async def plc(start: StartPlc) -> Plc:
    """The demo PLC, discovered and polling POLLED."""
    plc = await start()
    await plc.source.poll(())
    await plc.source.poll(POLLED)
    return plc


# --- identity and discovery -------------------------------------------------------------


async def test_identify_reads_getinfo_and_checks_list(start: StartPlc) -> None:
    plc = await start()

    info = await plc.source.identify()

    assert info.serial_number == "EPSNET 127.0.0.1:61682"
    assert info.model == "CP-2080"
    assert info.firmware == "Fx2 CP2080I v1.1"
    assert info.program_name == "FAMILY_HOUSE v1.3"
    assert info.program_stamp == plc.sim.stamp.upper()
    assert info.api_version == "PLCComS 6.1"
    # The same PLC may have a TecoApi entry: titles and names say the way in.
    assert info.way_in == "PLCComS"
    assert info.mode is PlcMode.RUNNING
    assert (info.mac, info.time, info.family) == (None, None, None)
    assert plc.source.configuration_url is None
    assert plc.coms.commands[:2] == ["LIST:", "GET:__PLC_RUN"]
    assert "GETINFO:" in plc.coms.commands


async def test_identify_of_a_program_without_variables(start: StartPlc) -> None:
    empty = load_program("demo").to_mapping()
    empty["variables"] = {}
    plc = await start(Program.from_mapping(empty))

    with pytest.raises(NoPublicVariablesError):
        await plc.source.identify()
    with pytest.raises(NoPublicVariablesError):
        await plc.source.poll(())


async def test_an_unreachable_server_is_a_connection_error(start: StartPlc) -> None:
    plc = await start()
    plc.coms.faults.refuse = True

    with pytest.raises(PlcConnectionError):
        await plc.source.identify()
    with pytest.raises(PlcConnectionError):
        await plc.source.poll(())
    assert plc.source.recent_errors[-1].operation == "discovery"

    plc.coms.faults.refuse = False
    snapshot = await plc.source.poll(())
    assert snapshot.catalogue.points


async def test_identify_reads_getinfo_of_the_old_form(start: StartPlc) -> None:
    plc = await start(server=PlcComsOptions(lower_case_info=True))

    info = await plc.source.identify()

    assert info.serial_number == "EPSNET 127.0.0.1:61682"
    assert info.program_name == "FAMILY_HOUSE v1.3"
    assert info.api_version == "PLCComS 6.1"


def test_getinfo_of_the_manual() -> None:
    info = plc_info_from_getinfo(
        {
            "VERSION": "Ver 6.1 Jun  1 2023 13:15:36",
            "VERSION_PLC": "",
            "IPADDR": " 192.168.1.5",
            "EPSPORT": "61682",
            "PUBFILE": "2/2 [FIXED_Foxtrot.pub,Dum.pub]",
            "NETWORK": "1/16 [127.0.0.1  2026-11-26 05:34:21]",
        },
        server="x:1",
        running=None,
        stamp=None,
    )

    assert (info.serial_number, info.program_name) == (
        "EPSNET 192.168.1.5:61682",
        "Dum",
    )
    assert (info.api_version, info.firmware) == ("PLCComS 6.1", None)
    only_fixed = {"VERSION": "6.2", "PUBFILE": "1/1 [FIXED_Foxtrot.pub]"}
    info = plc_info_from_getinfo(only_fixed, server="x:1", running=None, stamp=None)
    assert (info.program_name, info.api_version) == (None, "PLCComS 6.2")
    odd = plc_info_from_getinfo(
        {"version": "beta"}, server="x:1", running=None, stamp=None
    )
    assert odd.api_version == "PLCComS beta"


async def test_a_server_that_cannot_reach_its_plc(start: StartPlc) -> None:
    plc = await start()
    plc.coms.faults.plc_unreachable = True

    with pytest.raises(PlcUnreachableError, match="cannot reach its PLC"):
        await plc.source.identify()
    with pytest.raises(PlcUnreachableError):
        await plc.source.poll(())

    plc.coms.faults.plc_unreachable = False
    assert (await plc.source.poll(())).catalogue.points


async def test_a_plc_lost_behind_the_server_fails_polls_until_it_is_back(
    plc: Plc,
) -> None:
    plc.coms.faults.plc_unreachable = True
    with pytest.raises(PlcUnreachableError):
        await plc.source.poll(POLLED)
    # The client reconnects and is refused again: the reason stays.
    await plc.coms.wait_for_connections(3)
    with pytest.raises(PlcUnreachableError, match="cannot reach its PLC"):
        await plc.source.poll(POLLED)
    plc.sim.set_value("outsideTemp.value", -3.5)
    connected = Heard(plc.client.subscribe)

    plc.coms.faults.plc_unreachable = False
    await connected.wait_for(lambda e: isinstance(e, ConnectionChanged) and e.connected)

    # Everything was read again: what changed meanwhile is in the next poll.
    snapshot = await plc.source.poll(POLLED)
    assert snapshot.values["outsidetemp"] == -3.5


def test_identity_without_the_plc_address_is_the_server() -> None:
    info = plc_info_from_getinfo(
        {"version": "6.3", "pubfile": "C:\\plc\\house.pub"},
        server="10.0.0.5:5011",
        running=False,
        stamp=None,
    )

    assert info.serial_number == "PLCComS 10.0.0.5:5011"
    assert info.program_name == "house"
    assert info.model is None
    assert info.mode is PlcMode.STOPPED
    with pytest.raises(NotAPlcError):
        plc_info_from_getinfo({}, server="x:1", running=True, stamp=None)


async def test_first_poll_discovers_the_same_points_as_tecoapi(
    start: StartPlc, session: aiohttp.ClientSession
) -> None:
    """T_ApiObjects grouped again from their leaves: TecoApi's keys, kinds, metadata."""
    plc = await start()
    await plc.sim.start()
    try:
        tecoapi = await TecoApiSession(make_client(session, plc.sim)).poll(())
    finally:
        await plc.sim.stop()

    snapshot = await plc.source.poll(())

    points = snapshot.catalogue.points
    assert points.keys() == tecoapi.catalogue.points.keys()
    for key, point in points.items():
        expected = tecoapi.catalogue.points[key]
        assert (point.path, point.kind, point.attributes) == (
            expected.path,
            expected.kind,
            expected.attributes,
        ), key
    # A DT on the same clock as TecoApi's, to the millisecond (the manual's double).
    assert snapshot.values["lastrestart"] == tecoapi.values["lastrestart"]
    assert snapshot.values == tecoapi.values
    assert snapshot.attributes == tecoapi.attributes
    assert snapshot.catalogue.groups == tecoapi.catalogue.groups
    assert snapshot.info_read_at == START
    assert not snapshot.program_changed
    assert plc.source.statistics.discoveries == 1
    assert plc.coms.enabled()[0] == set()


# --- polls and pushes ---------------------------------------------------------------------


async def test_polls_enable_the_polled_points_and_read_only_the_new_ones(
    start: StartPlc,
) -> None:
    plc = await start()
    await plc.source.poll(())
    before = len(plc.coms.commands)

    first = await plc.source.poll(POLLED)
    enabled = plc.commands_since(before)
    before = len(plc.coms.commands)
    second = await plc.source.poll(POLLED)

    assert sorted(c for c in enabled if c.startswith("EN:")) == [
        "EN:Heating.livingSetpoint.value",
        "EN:lights[1].value",
        "EN:outsideTemp.value",
    ]
    assert sorted(c for c in enabled if c.startswith("GET:") and "__" not in c) == [
        "GET:Heating.livingSetpoint.value",
        "GET:lights[1].value",
        "GET:outsideTemp.value",
    ]
    assert first.values == {
        "outsidetemp": 4.5,
        "heating.livingsetpoint": 21.5,
        "lights[1]": True,
    }
    assert plc.commands_since(before) == ["GET:__PLC_RUN"]
    assert second.values == {}
    assert plc.source.statistics.last_poll_requests == 1
    assert plc.coms.enabled()[0] == {
        "outsidetemp.value",
        "heating.livingsetpoint.value",
        "lights[1].value",
    }


async def test_follow_enables_the_polled_points_between_polls(
    start: StartPlc,
) -> None:
    """Right after discovery: enabled, their values pushed, changes pushed."""
    plc = await start()
    await plc.source.follow(POLLED)  # before discovery: nothing to follow
    assert plc.coms.enabled() == []
    await plc.source.poll(())
    pushes = Heard[Snapshot](plc.source.subscribe)
    plc.sim.set_value("outsideTemp.value", -6.0)  # changed since discovery

    await plc.source.follow(POLLED)

    assert plc.coms.enabled()[0] >= {"outsidetemp.value", "lights[1].value"}
    caught_up = await pushes.wait_for(lambda s: "outsidetemp" in s.values)
    assert caught_up.values["outsidetemp"] == -6.0
    plc.sim.set_value("lights[1].value", False)
    await plc.coms.scan()
    changed = await pushes.wait_for(lambda s: s.values.get("lights[1]") is False)
    assert changed.values == {"lights[1]": False}
    # The next poll returns them too, and enables nothing again.
    before = len(plc.coms.commands)
    polled = await plc.source.poll(POLLED)
    assert polled.values == {
        "outsidetemp": -6.0,
        "heating.livingsetpoint": 21.5,
        "lights[1]": False,
    }
    assert plc.commands_since(before) == ["GET:__PLC_RUN"]


async def test_follow_leaves_a_failure_to_the_next_poll(plc: Plc) -> None:
    plc.coms.faults.stall = True
    before = plc.source.statistics.failed_polls

    await plc.source.follow(POLLED | {"rooms.livingtemp"})

    assert plc.source.statistics.failed_polls == before
    plc.coms.faults.stall = False


async def test_read_points_reads_what_is_not_pushed(plc: Plc) -> None:
    before = len(plc.coms.commands)

    assert await plc.source.read_points({"outsidetemp", "lights[1]"}) is None
    assert plc.commands_since(before) == []
    plc.sim.set_value("Heating.bedroomSetpoint.value", 19.0)
    read = await plc.source.read_points({"outsidetemp", "heating.bedroomsetpoint"})

    assert read is not None
    assert read.values == {"heating.bedroomsetpoint": 19.0}
    assert plc.commands_since(before) == ["GET:Heating.bedroomSetpoint.value"]


async def test_points_no_longer_polled_are_disabled(plc: Plc) -> None:
    await plc.source.poll({"outsidetemp"})

    assert plc.coms.enabled()[0] == {"outsidetemp.value"}
    assert "DI:lights[1].value" in plc.coms.commands


async def test_a_burst_of_changes_is_one_pushed_snapshot(plc: Plc) -> None:
    pushes = Heard[Snapshot](plc.source.subscribe)
    plc.sim.set_value("outsideTemp.value", -3.5)
    plc.sim.set_value("Heating.livingSetpoint.value", 22.0)
    plc.sim.set_value("lights[1].value", False)

    assert await plc.coms.scan() == 3
    pushed = await pushes.nth(1)

    assert pushed.values == {
        "outsidetemp": -3.5,
        "heating.livingsetpoint": 22.0,
        "lights[1]": False,
    }
    assert pushed.info.mode is PlcMode.RUNNING
    # The next poll returns what was pushed since the previous one, without a GET.
    before = len(plc.coms.commands)
    snapshot = await plc.source.poll(POLLED)
    assert snapshot.values == pushed.values
    assert snapshot.catalogue is pushed.catalogue
    assert plc.commands_since(before) == ["GET:__PLC_RUN"]
    assert len(pushes.items) == 1
    assert plc.source.diagnostics()["push"] == {"bursts": 1, "values": 3}


async def test_a_halt_is_pushed_at_once_and_run_again(plc: Plc) -> None:
    pushes = Heard[Snapshot](plc.source.subscribe)

    plc.sim.mode = "HALT"
    await plc.coms.scan()
    halted = await pushes.nth(1)
    plc.sim.mode = "RUN"
    await plc.coms.scan()
    running = await pushes.nth(2)

    assert halted.info.mode is PlcMode.STOPPED
    assert halted.values == {}
    assert running.info.mode is PlcMode.RUNNING
    assert (await plc.source.poll(POLLED)).info.mode is PlcMode.RUNNING


async def test_a_program_download_is_discovered_on_the_next_poll(plc: Plc) -> None:
    source = plc.sim.program.to_mapping()
    source["variables"]["garageDoor"] = {"type": "BOOL", "value": True}
    plc.sim.load_program(Program.from_mapping(source))
    connected = plc.client.health.reconnects
    events = Heard[PlcComsEvent](plc.client.subscribe)

    await plc.coms.scan()  # __PLC_RUN 0
    await plc.coms.scan()  # __PLC_RUN 1: the client reads LIST: again
    await events.wait_for(lambda event: isinstance(event, ProgramChanged))
    snapshot = await plc.source.poll(POLLED)

    assert snapshot.program_changed
    assert snapshot.values["garagedoor"] is True
    assert snapshot.values.keys() == snapshot.catalogue.points.keys()
    assert snapshot.info.program_stamp == plc.sim.stamp.upper()
    assert plc.source.statistics.program_changes == 1
    assert plc.client.health.reconnects == connected
    # The polled points are pushed again.
    assert {"outsidetemp.value", "lights[1].value"} <= plc.coms.enabled()[0]


async def test_getinfo_and_attributes_are_read_again_on_the_metadata_cadence(
    plc: Plc,
) -> None:
    plc.sim.set_value("outsideTemp.attr.title", "Outdoor temperature")
    before = len(plc.coms.commands)

    plc.clock.tick(30)
    early = await plc.source.poll(POLLED)
    plc.clock.tick(30)
    due = await plc.source.poll(POLLED)

    assert early.attributes == {}
    assert early.info_read_at is None
    assert due.info_read_at == plc.clock.now
    assert due.attributes.keys() == POLLED
    assert due.attributes["outsidetemp"].name == "Outdoor temperature"
    assert "GETINFO:" in plc.commands_since(before)


async def test_a_shorter_metadata_interval_applies_from_now(plc: Plc) -> None:
    plc.source.metadata_interval = timedelta(seconds=10)

    plc.clock.tick(5)
    assert (await plc.source.poll(POLLED)).attributes == {}

    plc.clock.tick(5)
    due = await plc.source.poll(POLLED)
    assert due.info_read_at == plc.clock.now
    assert due.attributes.keys() == POLLED
    assert plc.source.metadata_interval == timedelta(seconds=10)


# --- a server that stops answering, or restarts ------------------------------------------


async def test_a_stalled_server_fails_the_poll(plc: Plc) -> None:
    plc.coms.faults.stall = True

    with pytest.raises(PlcConnectionError):
        await plc.source.poll(POLLED)

    assert plc.source.statistics.failed_polls == 1
    assert plc.source.recent_errors[-1].error == "PlcConnectionError"
    plc.coms.faults.stall = False


async def test_after_a_restart_the_values_changed_meanwhile_arrive(plc: Plc) -> None:
    pushes = Heard[Snapshot](plc.source.subscribe)
    events = Heard[PlcComsEvent](plc.client.subscribe)
    plc.coms.faults.refuse = True  # a server that is not ready yet
    await plc.coms.restart()
    await events.wait_for(
        lambda event: isinstance(event, ConnectionChanged) and not event.connected
    )
    plc.sim.set_value("outsideTemp.value", 12.5)  # never pushed: nobody listens

    with pytest.raises(PlcConnectionError):
        await plc.source.poll(POLLED)
    plc.coms.faults.refuse = False
    reread = await pushes.nth(1)
    snapshot = await plc.source.poll(POLLED)

    assert reread.values["outsidetemp"] == 12.5
    assert snapshot.values["outsidetemp"] == 12.5
    assert plc.client.health.reconnects == 1


# --- writes and reads ---------------------------------------------------------------------


async def test_write_sets_pushes_and_reads_back(plc: Plc) -> None:
    pushes = Heard[Snapshot](plc.source.subscribe)

    confirmed = await plc.source.write("heating.livingsetpoint", 23)

    assert plc.sim.get_value("Heating.livingSetpoint.value") == 23.0
    assert "SET:Heating.livingSetpoint.value,23" in plc.coms.commands
    assert (await pushes.nth(1)).values == {"heating.livingsetpoint": 23.0}
    assert confirmed is not None
    assert confirmed.values == {"heating.livingsetpoint": 23.0}
    assert plc.source.statistics.writes == 1


@pytest.mark.parametrize(
    ("key", "value", "error"),
    [
        ("heating.livingsetpoint", 40.0, OutOfRangeError),
        ("outsidetemp", 1.0, ReadOnlyError),
        ("lights[1]", "on", InvalidValueError),
        ("nosuchpoint", 1, VariableNotFoundError),
    ],
)
async def test_write_validates_like_tecoapi(
    plc: Plc, key: str, value: Any, error: type[Exception]
) -> None:
    before = len(plc.coms.commands)

    with pytest.raises(error):
        await plc.source.write(key, value)

    assert not any(c.startswith("SET:") for c in plc.commands_since(before))


async def test_a_value_the_server_refuses(plc: Plc) -> None:
    with pytest.raises(ValueRejectedError):
        await plc.source.write("displaymessage", "x" * 200)

    assert plc.source.statistics.failed_writes == 0


async def test_a_batch_is_one_exchange_of_set_lines_and_one_of_gets(plc: Plc) -> None:
    pushes = Heard[Snapshot](plc.source.subscribe)
    before = len(plc.coms.commands)
    batch = {"heating.livingsetpoint": 23.0, "lights[1]": False}

    confirmed = await plc.source.write_many(batch)

    assert plc.commands_since(before) == [
        "SET:Heating.livingSetpoint.value,23",
        "SET:lights[1].value,0",
        "GET:__PLC_RUN",
        "GET:Heating.livingSetpoint.value",
        "GET:lights[1].value",
    ]
    assert plc.sim.get_value("Heating.livingSetpoint.value") == 23.0
    assert plc.sim.get_value("lights[1].value") is False
    assert (await pushes.nth(1)).values == batch
    assert confirmed is not None
    assert confirmed.values == batch
    assert plc.source.statistics.writes == 2


async def test_a_value_the_server_refuses_in_a_batch_is_named(plc: Plc) -> None:
    before = len(plc.coms.commands)

    with pytest.raises(ValueRejectedError) as raised:
        await plc.source.write_many({"lights[1]": False, "displaymessage": "x" * 200})

    assert raised.value.path == "displayMessage.value"
    assert raised.value.value == "x" * 200
    sets = [c for c in plc.commands_since(before) if c.startswith("SET:")]
    assert len(sets) == 2


async def test_a_batch_is_checked_by_the_latest_attributes_first(plc: Plc) -> None:
    plc.sim.set_value("Heating.livingSetpoint.attr.readOnly", True)
    plc.clock.tick(60)
    await plc.source.poll(POLLED)
    before = len(plc.coms.commands)

    with pytest.raises(ReadOnlyError):
        await plc.source.write_many({"lights[1]": False, "heating.livingsetpoint": 22})
    with pytest.raises(ReadOnlyError):
        await plc.source.write("heating.livingsetpoint", 22)

    assert not any(c.startswith("SET:") for c in plc.commands_since(before))


async def test_write_of_dates_and_times(plc: Plc) -> None:
    await plc.source.write_variable("commissioned", "2020-02-29")
    await plc.source.write("heating.nightsetback", "23:15:00.000")

    assert plc.sim.get_value("commissioned") == "2020-02-29"
    assert plc.sim.get_value("Heating.nightSetback.value") == "23:15:00.000"
    assert await plc.source.read_variable("commissioned") == "2020-02-29"


async def test_write_variable_by_either_path_and_of_other_variables(plc: Plc) -> None:
    await plc.source.write_variable("Heating.livingSetpoint.value", 20.5)
    assert await plc.source.write_variable("outsideTemp.attr.title", "Out") is None

    assert plc.sim.get_value("Heating.livingSetpoint.value") == 20.5
    assert plc.sim.get_value("outsideTemp.attr.title") == "Out"
    with pytest.raises(InvalidValueError) as caught:
        await plc.source.write_variable("Rooms", {"livingTemp": {"value": 1.0}})
    assert caught.value.text().key == "write_elementary"


async def test_read_variable(plc: Plc) -> None:
    assert await plc.source.read_variable("lastRestart") == "2026-03-01T06:12:45.120Z"
    assert await plc.source.read_variable("outsideTemp.attr.units") == "°C"
    with pytest.raises(VariableNotFoundError):
        await plc.source.read_variable("Rooms")


async def test_a_failed_write_and_read_are_kept_for_diagnostics(plc: Plc) -> None:
    plc.coms.faults.stall = True

    with pytest.raises(PlcConnectionError):
        await plc.source.write("lights[1]", False)
    with pytest.raises(PlcConnectionError):
        await plc.source.read_variable("lights[1].value")

    assert [e.operation for e in plc.source.recent_errors] == ["write", "read"]
    assert plc.source.statistics.failed_writes == 1
    plc.coms.faults.stall = False


# --- diagnostics and closing ---------------------------------------------------------------


async def test_diagnostics_name_no_host(plc: Plc) -> None:
    diagnostics = plc.source.diagnostics()

    assert diagnostics["transport"] == "plccoms"
    assert diagnostics["server"] == {
        "version": "Ver 6.1 Jun  1 2023 13:15:36",
        "version_plc": "Fx2 CP2080I v1.1",
    }
    assert diagnostics["points"] == 143
    assert diagnostics["enabled"] == 3
    assert diagnostics["connection"]["connected"] is True
    assert "127.0.0.1" not in repr(diagnostics)


async def test_close_closes_the_connection(plc: Plc) -> None:
    await plc.source.close()

    await plc.coms.wait_for_open_connections(0)
    assert not plc.client.connected


async def test_a_date_pushed_reads_as_tecoapi_reads_it(plc: Plc) -> None:
    await plc.source.poll(POLLED | {"commissioned", "heating.nextservice"})
    pushes = Heard[Snapshot](plc.source.subscribe)
    plc.sim.set_value("commissioned", "2021-06-01")

    await plc.coms.scan()

    assert (await pushes.nth(1)).values == {"commissioned": date(2021, 6, 1)}


async def test_a_variable_gone_before_list_is_read_again_is_missing(
    start: StartPlc,
) -> None:
    """A download the client has not seen yet: one vanished name, the rest read."""
    plc = await start()
    await plc.client.connect()
    source = plc.sim.program.to_mapping()
    del source["variables"]["alarmArmed"]
    plc.sim.load_program(Program.from_mapping(source))

    snapshot = await plc.source.poll(())

    assert snapshot.missing == {"alarmarmed"}
    assert "alarmarmed" not in snapshot.values
    assert snapshot.values["outsidetemp"] == 4.5


async def test_a_point_the_server_will_not_enable_is_missing(plc: Plc) -> None:
    source = plc.sim.program.to_mapping()
    del source["variables"]["alarmArmed"]
    plc.sim.load_program(Program.from_mapping(source))

    snapshot = await plc.source.poll(POLLED | {"alarmarmed"})

    assert "alarmarmed" in snapshot.missing
    assert "alarmarmed" not in snapshot.values


async def test_a_stall_while_enabling_fails_the_poll(plc: Plc) -> None:
    plc.coms.faults.stall = True

    with pytest.raises(PlcConnectionError):
        await plc.source.poll({"alarmarmed"})
    plc.coms.faults.stall = False


async def test_write_variable_before_discovery_needs_a_connection(
    start: StartPlc,
) -> None:
    plc = await start()

    with pytest.raises(PlcConnectionError):
        await plc.source.write_variable("alarmArmed", True)
    assert plc.source.diagnostics()["points"] == 0


async def test_a_value_its_type_cannot_hold_is_bad_for_that_point_alone(
    plc: Plc,
) -> None:
    # The double of 1.6e12 s: the year 52,671, never shown as a date.
    year_50000 = str(int.from_bytes(struct.pack("<d", 1.6e12), "little"))
    plc.coms.faults.raw_values["lastRestart"] = year_50000

    snapshot = await plc.source.poll({*POLLED, "lastrestart"})

    assert snapshot.values["lastrestart"] is None
    assert snapshot.quality["lastrestart"] == UNFIT
    assert snapshot.missing == {"lastrestart"}
    assert "outsidetemp" not in snapshot.quality
    pushed = Heard(plc.source.subscribe)
    del plc.coms.faults.raw_values["lastRestart"]
    plc.sim.set_value("lastRestart", "2026-03-02T07:00:00.000Z")
    await plc.coms.scan()

    fixed = await pushed.wait_for(lambda s: "lastrestart" in s.values)
    assert fixed.values["lastrestart"] == datetime(2026, 3, 2, 7, tzinfo=UTC)
    assert "lastrestart" not in fixed.quality
