"""TecoApiSession: what is read on which poll, one snapshot per poll, writes."""

from collections.abc import Callable
from datetime import timedelta
from typing import Any

import aiohttp
import pytest

from custom_components.tecoapi.pyplc import (
    NoPublicVariablesError,
    OutOfRangeError,
    PlcConnectionError,
    PlcMode,
    ReadOnlyError,
    Snapshot,
    VariableNotFoundError,
)
from custom_components.tecoapi.pyplc.tecomat import TecoApiSession
from tests.pyplc.conftest import START, Clock, StartSimulator, make_client
from tests.simulator import Program, Simulator, load_program

INTERVAL = timedelta(seconds=60)


@pytest.fixture
def clock() -> Clock:
    return Clock()


@pytest.fixture
def demo_session(
    session: aiohttp.ClientSession, simulator: Simulator, clock: Clock
) -> TecoApiSession:
    """A session of the demo simulator, planning on the event loop (no executor)."""
    return TecoApiSession(
        make_client(session, simulator),
        metadata_interval=INTERVAL,
        clock=clock,
        run_blocking=_at_once,
    )


async def _at_once(job: Callable[[], Any]) -> Any:
    return job()


def services(simulator: Simulator) -> list[str]:
    return [request.service for request in simulator.requests if request.authorized]


POLLED = frozenset({"outsidetemp", "rooms.livingtemp", "heating.livingsetpoint"})


async def test_first_poll_discovers_every_point(
    demo_session: TecoApiSession, simulator: Simulator
) -> None:
    snapshot = await demo_session.poll(POLLED)

    assert services(simulator)[:2] == ["GetInfo", "GetList"]
    assert snapshot.info.serial_number == "SD 2080"
    assert snapshot.info_read_at == START
    assert not snapshot.program_changed
    assert snapshot.values.keys() == snapshot.catalogue.points.keys()
    assert snapshot.values["outsidetemp"] == 4.5
    assert snapshot.attributes["outsidetemp"].name == "Outside temperature"
    assert snapshot.missing == frozenset()
    assert demo_session.statistics.discoveries == 1
    assert demo_session.statistics.polls == 0


async def test_polls_read_the_polled_values_and_metadata_on_cadence(
    demo_session: TecoApiSession, simulator: Simulator, clock: Clock
) -> None:
    first = await demo_session.poll(POLLED)
    simulator.clear_requests()
    simulator.set_value("outsideTemp.value", -1.5)

    clock.tick(5)
    snapshot = await demo_session.poll(POLLED)

    assert services(simulator) == ["GetObject"]
    assert snapshot.values == {
        "outsidetemp": -1.5,
        "rooms.livingtemp": 21.8,
        "heating.livingsetpoint": 21.5,
    }
    assert snapshot.attributes == {}
    assert snapshot.info_read_at is None
    assert snapshot.catalogue is first.catalogue
    assert demo_session.read_plan is not None
    assert demo_session.read_plan.point_keys == POLLED

    simulator.clear_requests()
    clock.tick(60)
    snapshot = await demo_session.poll(POLLED)

    assert services(simulator)[0] == "GetInfo"
    assert snapshot.info_read_at == clock.now
    assert snapshot.attributes.keys() == POLLED
    assert demo_session.attribute_plan is not None
    assert demo_session.statistics.polls == 2


async def test_a_shorter_metadata_interval_applies_from_now(
    demo_session: TecoApiSession, simulator: Simulator, clock: Clock
) -> None:
    await demo_session.poll(POLLED)
    demo_session.metadata_interval = timedelta(seconds=10)

    clock.tick(5)
    assert (await demo_session.poll(POLLED)).attributes == {}

    clock.tick(5)
    assert (await demo_session.poll(POLLED)).attributes.keys() == POLLED
    assert demo_session.metadata_interval == timedelta(seconds=10)


async def test_after_a_failed_poll_getinfo_is_read_again(
    demo_session: TecoApiSession, simulator: Simulator, clock: Clock
) -> None:
    await demo_session.poll(POLLED)
    simulator.faults.drop_connection = True
    with pytest.raises(PlcConnectionError):
        await demo_session.poll(POLLED)
    simulator.faults.clear()
    simulator.clear_requests()

    clock.tick(5)
    snapshot = await demo_session.poll(POLLED)

    assert services(simulator) == ["GetInfo", "GetObject"]
    assert snapshot.info_read_at == clock.now
    assert demo_session.statistics.failed_polls == 1
    assert [error.operation for error in demo_session.recent_errors] == ["poll"]
    assert demo_session.recent_errors[0].error == "PlcConnectionError"


async def test_a_stopped_program_is_watched_but_not_read(
    demo_session: TecoApiSession, simulator: Simulator, clock: Clock
) -> None:
    await demo_session.poll(POLLED)
    simulator.mode = "HALT"
    clock.tick(60)
    halted = await demo_session.poll(POLLED)
    simulator.clear_requests()

    clock.tick(5)
    snapshot = await demo_session.poll(POLLED)

    assert halted.info.mode is PlcMode.STOPPED
    assert services(simulator) == ["GetInfo"]
    assert snapshot.values == {}
    assert snapshot.info.mode is PlcMode.STOPPED


async def test_a_quiet_poll_reads_getinfo_so_a_halt_shows_on_the_next_poll(
    demo_session: TecoApiSession, simulator: Simulator, clock: Clock
) -> None:
    """Nothing changed since the previous poll: GetInfo after the values (issue 13)."""
    await demo_session.poll(POLLED)
    simulator.mode = "HALT"
    simulator.clear_requests()

    clock.tick(5)
    snapshot = await demo_session.poll(POLLED)

    assert services(simulator) == ["GetObject", "GetInfo"]
    assert snapshot.info.mode is PlcMode.STOPPED
    assert snapshot.info_read_at == clock.now
    assert demo_session.statistics.last_poll_requests == 2


async def test_a_poll_that_saw_a_change_reads_no_getinfo(
    demo_session: TecoApiSession, simulator: Simulator, clock: Clock
) -> None:
    """A changed value proves the program ran: the mode check costs nothing then."""
    await demo_session.poll(POLLED)
    simulator.set_value("outsideTemp.value", 9.5)
    simulator.mode = "HALT"  # after the change: seen by the next (quiet) poll
    simulator.clear_requests()

    clock.tick(5)
    changed = await demo_session.poll(POLLED)
    clock.tick(5)
    quiet = await demo_session.poll(POLLED)

    assert services(simulator) == ["GetObject", "GetObject", "GetInfo"]
    assert changed.info.mode is PlcMode.RUNNING
    assert quiet.info.mode is PlcMode.STOPPED


async def test_without_the_quiet_check_getinfo_follows_the_cadence(
    session: aiohttp.ClientSession, simulator: Simulator, clock: Clock
) -> None:
    plc = TecoApiSession(
        make_client(session, simulator),
        metadata_interval=INTERVAL,
        clock=clock,
        run_blocking=_at_once,
        check_quiet_polls=False,
    )
    await plc.poll(POLLED)
    simulator.mode = "HALT"
    simulator.clear_requests()

    clock.tick(5)
    assert (await plc.poll(POLLED)).info.mode is PlcMode.RUNNING
    clock.tick(55)
    assert (await plc.poll(POLLED)).info.mode is PlcMode.STOPPED
    assert services(simulator).count("GetInfo") == 1


async def test_variables_gone_missing_check_the_program_at_once(
    demo_session: TecoApiSession, simulator: Simulator, clock: Clock
) -> None:
    first = await demo_session.poll(POLLED)
    source = simulator.program.to_mapping()
    del source["variables"]["outsideTemp"]
    simulator.load_program(Program.from_mapping(source))
    simulator.clear_requests()

    clock.tick(5)
    snapshot = await demo_session.poll(POLLED)

    sequence = services(simulator)
    # The value poll first, then GetInfo (a new stamp), then discovery.
    assert sequence[0] == "GetObject"
    assert sequence.count("GetInfo") == 1
    assert sequence.index("GetInfo") < sequence.index("GetList")
    assert snapshot.program_changed
    assert snapshot.catalogue is not first.catalogue
    assert "outsidetemp" not in snapshot.catalogue.points
    assert snapshot.values.keys() == snapshot.catalogue.points.keys()
    assert demo_session.statistics.program_changes == 1
    assert demo_session.statistics.discoveries == 2


async def test_a_missing_variable_of_the_same_program_is_reported_missing(
    demo_session: TecoApiSession, simulator: Simulator, clock: Clock
) -> None:
    await demo_session.poll(POLLED)
    simulator.faults.rejected_by_object = {"outsideTemp"}
    simulator.clear_requests()

    clock.tick(5)
    snapshot = await demo_session.poll(POLLED)

    assert "GetInfo" in services(simulator)
    assert not snapshot.program_changed
    assert snapshot.missing == {"outsidetemp"}
    assert snapshot.values.keys() == POLLED - {"outsidetemp"}


async def test_write_pushes_the_acknowledged_value_then_reads_it_back(
    demo_session: TecoApiSession, simulator: Simulator
) -> None:
    await demo_session.poll(POLLED)
    pushed: list[Snapshot] = []
    unsubscribe = demo_session.subscribe(pushed.append)
    simulator.clear_requests()

    confirmed = await demo_session.write("heating.livingsetpoint", 22.5)

    assert [snapshot.values for snapshot in pushed] == [
        {"heating.livingsetpoint": 22.5}
    ]
    assert services(simulator) == ["SetObject", "GetObject"]
    assert confirmed is not None
    assert confirmed.values == {"heating.livingsetpoint": 22.5}
    assert simulator.get_value("Heating.livingSetpoint.value") == 22.5
    assert demo_session.statistics.writes == 1

    unsubscribe()
    await demo_session.write("heating.livingsetpoint", 21.0)
    assert len(pushed) == 1


async def test_write_validates_against_the_latest_attributes(
    demo_session: TecoApiSession, simulator: Simulator, clock: Clock
) -> None:
    await demo_session.poll(POLLED)
    simulator.set_value("Heating.livingSetpoint.attr.readOnly", True)
    clock.tick(60)
    await demo_session.poll(POLLED)
    simulator.clear_requests()

    with pytest.raises(ReadOnlyError):
        await demo_session.write("heating.livingsetpoint", 22.0)

    assert simulator.requests == []
    assert demo_session.statistics.failed_writes == 0


async def test_write_to_a_vanished_variable_makes_getinfo_due(
    demo_session: TecoApiSession, simulator: Simulator, clock: Clock
) -> None:
    await demo_session.poll(POLLED)
    simulator.faults.rejected_by_object = {"Heating"}

    with pytest.raises(VariableNotFoundError):
        await demo_session.write("heating.livingsetpoint", 22.0)
    simulator.faults.clear()
    simulator.clear_requests()
    clock.tick(5)
    await demo_session.poll(POLLED)

    assert services(simulator)[0] == "GetInfo"
    assert demo_session.statistics.failed_writes == 1
    assert [error.operation for error in demo_session.recent_errors] == ["write"]


async def test_a_failed_read_back_leaves_it_to_the_next_poll(
    demo_session: TecoApiSession, simulator: Simulator
) -> None:
    """The write was acknowledged; the read-back after it fails: None, no error."""
    await demo_session.poll(POLLED)

    def break_the_next_request(snapshot: Snapshot) -> None:
        simulator.faults.remaining = 1
        simulator.faults.http_500 = True

    demo_session.subscribe(break_the_next_request)

    assert await demo_session.write("heating.livingsetpoint", 22.0) is None
    assert simulator.get_value("Heating.livingSetpoint.value") == 22.0
    assert [request.status for request in simulator.requests[-2:]] == [200, 500]


async def test_a_read_back_missing_the_point_makes_getinfo_due(
    demo_session: TecoApiSession, simulator: Simulator, clock: Clock
) -> None:
    await demo_session.poll(POLLED)

    def hide_it(snapshot: Snapshot) -> None:
        simulator.faults.rejected_by_object = {"Heating"}

    demo_session.subscribe(hide_it)
    assert await demo_session.write("heating.livingsetpoint", 22.0) is None
    simulator.faults.clear()
    simulator.clear_requests()
    clock.tick(5)
    await demo_session.poll(POLLED)

    assert services(simulator)[0] == "GetInfo"


BLIND = frozenset(
    f"stineni.obyvak_zaluzie_gtsap1_opener_{prop}"
    for prop in ("current", "target", "moving")
)


async def test_read_points_reads_them_alone_and_leaves_the_schedule(
    demo_session: TecoApiSession, simulator: Simulator, clock: Clock
) -> None:
    """One GetObject for a blind's points between polls; the poll's cadence stays."""
    assert await demo_session.read_points(BLIND) is None  # nothing discovered yet
    await demo_session.poll(POLLED)
    simulator.set_value("Stineni.OBYVAK_ZALUZIE_GTSAP1_OPENER_current", 70)
    simulator.clear_requests()

    clock.tick(1)
    snapshot = await demo_session.read_points(BLIND)
    clock.tick(1)
    again = await demo_session.read_points(BLIND | {"no.such.point"})

    assert services(simulator) == ["GetObject", "GetObject"]
    assert snapshot is not None
    assert again is not None
    assert snapshot.values == {
        "stineni.obyvak_zaluzie_gtsap1_opener_current": 70,
        "stineni.obyvak_zaluzie_gtsap1_opener_target": 100,
        "stineni.obyvak_zaluzie_gtsap1_opener_moving": False,
    }
    assert snapshot.attributes == {}
    assert snapshot.info_read_at is None
    assert again.values == snapshot.values
    assert demo_session.statistics.polls == 0
    assert await demo_session.read_points({"no.such.point"}) is None
    # The metadata cadence is the discovery's: attributes a minute after it.
    simulator.clear_requests()
    clock.tick(58)
    polled = await demo_session.poll(POLLED)
    assert polled.attributes.keys() == POLLED


async def test_read_points_missing_one_leaves_it_to_the_next_poll(
    demo_session: TecoApiSession, simulator: Simulator, clock: Clock
) -> None:
    await demo_session.poll(POLLED)
    simulator.faults.rejected_by_object = {"Stineni"}

    assert await demo_session.read_points(BLIND) is None
    simulator.faults.clear()
    simulator.clear_requests()
    clock.tick(5)
    await demo_session.poll(POLLED)

    assert services(simulator)[0] == "GetInfo"


async def test_a_failed_read_of_points_is_kept_for_diagnostics(
    demo_session: TecoApiSession, simulator: Simulator
) -> None:
    await demo_session.poll(POLLED)
    simulator.faults.drop_connection = True

    with pytest.raises(PlcConnectionError):
        await demo_session.read_points(BLIND)

    assert [error.operation for error in demo_session.recent_errors] == ["read"]


async def test_write_variable_validates_a_point_by_either_of_its_paths(
    demo_session: TecoApiSession, simulator: Simulator
) -> None:
    await demo_session.poll(POLLED)

    with pytest.raises(OutOfRangeError):
        await demo_session.write_variable("Heating.livingSetpoint.value", 99.0)
    confirmed = await demo_session.write_variable("Heating.LivingSetpoint", 20.5)

    assert confirmed is not None
    assert confirmed.values == {"heating.livingsetpoint": 20.5}
    assert simulator.requests[-2].query == "Heating.livingSetpoint.value=20.5"


async def test_write_variable_sends_other_paths_as_they_are(
    demo_session: TecoApiSession, simulator: Simulator
) -> None:
    await demo_session.poll(POLLED)

    assert await demo_session.write_variable("outsideTemp.attr.title", "Out") is None
    assert simulator.get_value("outsideTemp.attr.title") == "Out"
    with pytest.raises(VariableNotFoundError):
        await demo_session.write_variable("noSuchVariable", 1)
    assert await demo_session.read_variable("outsideTemp.attr.title") == "Out"
    with pytest.raises(VariableNotFoundError):
        await demo_session.read_variable("noSuchVariable")
    assert list(demo_session.recent_errors) == [
        error for error in demo_session.recent_errors if error.operation == "write"
    ]


async def test_a_write_to_an_unknown_point_is_refused(
    demo_session: TecoApiSession, simulator: Simulator
) -> None:
    await demo_session.poll(POLLED)
    simulator.clear_requests()

    with pytest.raises(VariableNotFoundError) as raised:
        await demo_session.write("nosuchpoint", 1)

    assert raised.value.path == "nosuchpoint"
    assert simulator.requests == []


async def test_identify_checks_that_the_program_publishes_variables(
    session: aiohttp.ClientSession, start_simulator: StartSimulator
) -> None:
    source = load_program("manual").to_mapping()
    sim = await start_simulator(Program.from_mapping(source))
    tecoapi = TecoApiSession(make_client(session, sim))
    assert (await tecoapi.identify()).serial_number == sim.serial_number

    source["variables"] = {}
    sim.load_program(Program.from_mapping(source))
    with pytest.raises(NoPublicVariablesError):
        await tecoapi.identify()


async def test_diagnostics_describe_plans_and_requests(
    demo_session: TecoApiSession, clock: Clock
) -> None:
    before = demo_session.diagnostics()
    await demo_session.poll(POLLED)
    clock.tick(5)
    await demo_session.poll(POLLED)

    after = demo_session.diagnostics()

    assert before["read_plans"] == {"values": None, "with_attributes": None}
    assert before["points"] == 0
    assert after["read_plans"]["values"]["points"] == len(POLLED)
    assert after["requests"]["polls"] == 1
    assert after["requests"]["authentication"] == "digest"
    assert after["skipped_roots"] == []
    assert demo_session.configuration_url == demo_session.client.base_url
