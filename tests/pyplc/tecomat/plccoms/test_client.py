"""The PLCComS client against the PLCComS simulator (and a scripted server) on 127.0.0.1."""

import asyncio
from collections.abc import AsyncIterator, Awaitable, Callable
import contextlib
from datetime import UTC, date, datetime, timedelta
import socket
import struct
from typing import Any

import aiohttp
import pytest

from custom_components.tecoapi.pyplc.core.exceptions import (
    InvalidPathError,
    InvalidValueError,
    PlcConnectionError,
    PlcResponseError,
    PlcUnreachableError,
    ResponseTooLargeError,
    ValueRejectedError,
    VariableNotFoundError,
)
from custom_components.tecoapi.pyplc.core.models import ValueKind
from custom_components.tecoapi.pyplc.tecomat.plccoms.client import PlcComsClient
from custom_components.tecoapi.pyplc.tecomat.plccoms.errors import VariableDisabledError
from custom_components.tecoapi.pyplc.tecomat.plccoms.events import (
    ConnectionChanged,
    PlcComsEvent,
    ProgramChanged,
    RunStateChanged,
    ValueChanged,
)
from custom_components.tecoapi.pyplc.tecomat.plccoms.variables import (
    PlcComsVariable,
    build_catalogue,
)
from tests.pyplc.conftest import WAIT, Heard, make_client
from tests.simulator import Program, Simulator
from tests.simulator.plccoms import PlcComsOptions, PlcComsServer

pytestmark = pytest.mark.usefixtures("socket_enabled")


class Events(Heard[PlcComsEvent]):
    """Everything a client delivered to a subscriber, awaitable by condition."""

    def __init__(self, client: PlcComsClient) -> None:
        super().__init__(client.subscribe)

    async def connection(self, connected: bool) -> ConnectionChanged:
        event = await self.wait_for(
            lambda e: isinstance(e, ConnectionChanged) and e.connected is connected
        )
        assert isinstance(event, ConnectionChanged)
        return event

    async def value(self, name: str, *, start: int = 0) -> ValueChanged:
        event = await self.wait_for(
            lambda e: isinstance(e, ValueChanged) and e.name == name, start=start
        )
        assert isinstance(event, ValueChanged)
        return event

    def of[T](self, kind: type[T]) -> list[T]:
        return [event for event in self.items if isinstance(event, kind)]


type Start = Callable[..., Awaitable[tuple[Simulator, PlcComsServer, PlcComsClient]]]


@pytest.fixture
async def start() -> AsyncIterator[Start]:
    """Start a TecoApi simulator, its PLCComS server and a connected client."""
    async with contextlib.AsyncExitStack() as stack:

        async def starting(
            program: str | Program = "manual",
            *,
            options: PlcComsOptions | None = None,
            **client_options: Any,
        ) -> tuple[Simulator, PlcComsServer, PlcComsClient]:
            sim = Simulator(program, username="admin", password="s3cret-Pa55")
            await sim.start()
            stack.push_async_callback(sim.stop)
            coms = PlcComsServer(sim, options=options, scan_interval=None)
            await coms.start()
            stack.push_async_callback(coms.stop)
            client_options.setdefault("timeout", 2.0)
            client_options.setdefault("reconnect_delay", 0.01)
            client = PlcComsClient("127.0.0.1", coms.port, **client_options)
            await client.connect()
            stack.push_async_callback(client.close)
            return sim, coms, client

        yield starting


def free_port() -> int:
    """A port nothing listens on (bound, then released)."""
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return int(probe.getsockname()[1])


# --- connecting, LIST:, the catalogue ---------------------------------------------------


async def test_connect_reads_list_and_the_run_state(start: Start) -> None:
    _, coms, client = await start()

    assert client.connected
    assert client.plc_running is True
    # The fixed __PLC_RUN is pushed without EN: (the changelog, 1.5).
    assert coms.commands == ["LIST:", "GET:__PLC_RUN"]
    assert client.variables["plcdata.varreal"] == PlcComsVariable(
        "plcData.varReal", "REAL"
    )
    catalogue = client.catalogue
    assert catalogue is not None
    point = catalogue.points["main.myobject3.attr.title"]
    assert (point.path, point.kind, point.attributes) == (
        "Main.myObject3.attr.title",
        ValueKind.STRING,
        None,
    )
    assert catalogue.points["arr2[1][3]"].kind is ValueKind.REAL
    assert catalogue.points["plcdata.vardt"].kind is ValueKind.DATETIME
    assert "__plc_run" not in catalogue.points
    assert catalogue.groups == (
        "plcName",
        "plcType",
        "plcDesc",
        "plcData",
        "myObject",
        "arr1",
        "arr2",
        "arr3",
        "Main",
    )
    assert len(catalogue.points) == len(coms.variables) - 2
    health = client.health
    assert (health.connected, health.plc_running, health.lines_sent) == (True, True, 2)
    assert health.lines_received == len(coms.variables) + 2  # LIST, its end, GET
    assert health.idle is not None
    assert health.last_line_at is not None


async def test_connect_to_nothing_raises_a_connection_error() -> None:
    client = PlcComsClient("127.0.0.1", free_port(), timeout=2.0)

    with pytest.raises(PlcConnectionError, match="Cannot reach PLCComS"):
        await client.connect()

    assert not client.connected
    assert client.health.last_error is not None
    with pytest.raises(PlcConnectionError):
        await client.get(["plcType"])
    await client.close()


async def test_async_with_connects_and_closes(start: Start) -> None:
    _, coms, _ = await start()

    async with PlcComsClient("127.0.0.1", coms.port, timeout=2.0) as client:
        assert client.connected
        events = Events(client)
        with pytest.raises(RuntimeError):
            await client.connect()

    assert not client.connected
    assert events.of(ConnectionChanged) == [
        ConnectionChanged(False, "closed by the client")
    ]
    await coms.wait_for_open_connections(1)  # only the fixture's client is left
    with pytest.raises(PlcConnectionError, match="Not connected"):
        await client.list_variables()
    await client.close()  # idempotent


async def test_list_variables_again(start: Start) -> None:
    _, coms, client = await start()

    variables = await client.list_variables()

    assert variables[0] == PlcComsVariable("__PLC_RUN", "BOOL")
    assert variables[0].enabled  # the fixed variables always are
    assert coms.commands.count("LIST:") == 2


async def test_list_beyond_its_bound_is_refused(start: Start) -> None:
    _, coms, _ = await start()
    client = PlcComsClient("127.0.0.1", coms.port, timeout=2.0, max_variables=10)

    with pytest.raises(ResponseTooLargeError):
        await client.connect()

    assert not client.connected
    await coms.wait_for_open_connections(1)


# --- GET: -------------------------------------------------------------------------------


async def test_get_types_every_value(start: Start) -> None:
    _, _, client = await start()
    await client.set("plcName", "Dobrý den")  # Windows-1250 on the wire

    values = await client.get(
        [
            "plcData.varBool1",
            "plcData.varSint",
            "plcData.varUdint",
            "PLCDATA.VARREAL",
            "plcData.varLreal",
            "plcName",
            "plcData.varTime",
            "plcData.varDate",
            "plcData.varDT",
            "Main.myObject1.attr.units",
            "__PLC_RUN",
        ]
    )

    assert values == {
        "plcData.varBool1": True,
        "plcData.varSint": -11,
        "plcData.varUdint": 33333333,
        "PLCDATA.VARREAL": 1000.0,
        "plcData.varLreal": 1000000.0,
        "plcName": "Dobrý den",
        "plcData.varTime": timedelta(hours=1, minutes=2, seconds=3, milliseconds=450),
        "plcData.varDate": date(2015, 6, 17),
        "plcData.varDT": datetime(2018, 5, 11, 11, 22, 33, 456000, tzinfo=UTC),
        "Main.myObject1.attr.units": "°C",
        "__PLC_RUN": True,
    }
    assert await client.get([]) == {}


async def test_get_matches_answers_out_of_order_by_name(start: Start) -> None:
    _, coms, client = await start()
    coms.faults.out_of_order = True
    names = [f"arr3[0][1][{index}]" for index in range(4)] + ["plcType", "plcType"]

    values = await client.get(names)

    assert values == {
        "arr3[0][1][0]": 10,
        "arr3[0][1][1]": 11,
        "arr3[0][1][2]": 12,
        "arr3[0][1][3]": 13,
        "plcType": 2005,
    }
    # Asked once each, answered in reverse.
    assert coms.commands[-5:] == [f"GET:{name}" for name in names[:5]]


@pytest.mark.parametrize(
    ("options", "wire"),
    [
        (PlcComsOptions(decimal_comma=True, decimals=3), "1,300"),
        (PlcComsOptions(scientific=True), "1.300000e+00"),
        (PlcComsOptions(scientific=True, decimal_comma=True), "1,300000e+00"),
        (PlcComsOptions(crlf=False, decimals=0), "1"),
    ],
)
async def test_get_reads_every_number_format(
    start: Start, options: PlcComsOptions, wire: str
) -> None:
    _, _, client = await start(options=options)
    events = Events(client)
    await client.enable(["arr2[1][3]"])

    values = await client.get(["arr2[1][3]", "plcData.varReal", "plcData.varSint"])

    expected = 1.0 if options.decimals == 0 else 1.3
    assert values == {
        "arr2[1][3]": expected,
        "plcData.varReal": 1000.0,
        "plcData.varSint": -11,
    }
    await client.set("arr2[1][3]", 2.5)
    changed = await events.value("arr2[1][3]")
    assert changed.value == (2.0 if options.decimals == 0 else 2.5)
    assert wire  # the form the server used, shown in the test id


async def test_get_survives_lines_split_across_writes(start: Start) -> None:
    _, coms, client = await start()
    coms.faults.split_writes = True
    writes = coms.writes

    values = await client.get(["plcName", "plcData.varReal"])

    assert values == {"plcName": "myFoxtrot", "plcData.varReal": 1000.0}
    assert coms.writes - writes == 4  # two lines, each in two writes


async def test_get_of_a_name_list_does_not_hold_sends_nothing(start: Start) -> None:
    _, _, client = await start()
    sent = client.health.lines_sent

    with pytest.raises(VariableNotFoundError) as caught:
        await client.get(["plcType", "noSuchThing"])

    assert caught.value.path == "noSuchThing"
    assert client.health.lines_sent == sent


async def test_get_of_a_name_the_server_no_longer_has(start: Start) -> None:
    sim, _, client = await start()
    sim.load_program("demo")  # the client's LIST: is now stale

    with pytest.raises(VariableNotFoundError) as caught:
        await client.get(["plcName", "plcType"])

    assert caught.value.path in {"plcName", "plcType"}
    assert client.connected
    assert client.health.server_errors == 2


@pytest.mark.parametrize("name", ["", " ", "a,b", "a b", "line\nbreak", "GET:x", "Ж"])
async def test_names_one_line_cannot_carry_are_refused(start: Start, name: str) -> None:
    _, _, client = await start()

    with pytest.raises(InvalidPathError):
        await client.get([name])


# --- SET: -----------------------------------------------------------------------------


async def test_set_writes_every_kind(start: Start) -> None:
    sim, coms, client = await start()

    await client.set("plcType", 42)
    await client.set("plcData.varReal", 21.5)
    await client.set("plcData.varLreal", 1e-7)
    await client.set("plcData.varBool0", True)
    await client.set("plcName", "Žluťoučký")
    await client.set("plcData.varTime", "00:00:01.500")
    await client.set("plcData.varDate", date(2020, 2, 29))
    await client.set("plcData.varDT", datetime(2021, 1, 2, 3, 4, 5, tzinfo=UTC))

    assert sim.get_value("plcType") == 42
    assert sim.get_value("plcData.varReal") == 21.5
    assert sim.get_value("plcData.varLreal") == 1e-7
    assert sim.get_value("plcData.varBool0") is True
    assert sim.get_value("plcName") == "Žluťoučký"
    assert sim.get_value("plcData.varTime") == "00:00:01.500"
    assert sim.get_value("plcData.varDate") == "2020-02-29"
    assert sim.get_value("plcData.varDT") == "2021-01-02T03:04:05.000Z"
    assert "SET:plcData.varLreal,0.0000001" in coms.commands
    assert 'SET:plcName,"Žluťoučký"' in coms.commands
    # Each SET: is followed by the GET:__PLC_RUN that confirms it was processed.
    assert coms.commands.count("GET:__PLC_RUN") == 1 + 8


async def test_set_refused_by_the_server(start: Start) -> None:
    sim, _, client = await start()

    with pytest.raises(ValueRejectedError) as caught:
        await client.set("plcName", "far too long for ten")

    assert (caught.value.path, caught.value.value) == (
        "plcName",
        "far too long for ten",
    )
    assert caught.value.code == "35"  # Wrong parameter value (the manual)
    assert sim.get_value("plcName") == "myFoxtrot"
    assert client.connected


async def test_set_of_a_variable_the_server_no_longer_has(start: Start) -> None:
    sim, _, client = await start()
    sim.load_program("demo")

    with pytest.raises(VariableNotFoundError) as caught:
        await client.set("plcType", 1)

    assert caught.value.path == "plcType"


@pytest.mark.parametrize(
    ("name", "value"),
    [
        ("plcData.varReal", "21.5"),
        ("plcData.varReal", float("nan")),
        ("plcData.varBool0", 2),
        ("plcType", 1.5),
        ("plcName", 'say "hi"'),
        ("plcName", "Ж"),
        ("plcData.varDate", datetime(2020, 1, 1, tzinfo=UTC)),
        ("plcData.varDT", date(2020, 1, 1)),
        ("plcData.varTime", "soon"),
    ],
)
async def test_set_refuses_what_the_kind_cannot_take_before_sending(
    start: Start, name: str, value: Any
) -> None:
    _, _, client = await start()
    sent = client.health.lines_sent

    with pytest.raises(InvalidValueError):
        await client.set(name, value)

    assert client.health.lines_sent == sent


async def test_set_of_an_unknown_name_sends_nothing(start: Start) -> None:
    _, _, client = await start()

    with pytest.raises(VariableNotFoundError):
        await client.set("noSuchThing", 1)


# --- EN:, DI:, DIFF: ---------------------------------------------------------------------


async def test_enabled_changes_arrive_as_diff(start: Start) -> None:
    sim, coms, client = await start()
    events = Events(client)

    await client.enable(["plcData.varReal", "plcType"], delta=0.5)
    sim.set_value("plcData.varReal", 1000.25)
    assert await coms.scan() == 0  # below the delta
    sim.set_value("plcData.varReal", 1000.75)
    sim.set_value("plcType", 7)
    assert await coms.scan() == 2

    real = await events.value("plcData.varReal")
    integer = await events.value("plcType")
    assert (real.key, real.value, real.raw, real.pushed) == (
        "plcdata.varreal",
        1000.75,
        "1000.75",
        True,
    )
    assert integer.value == 7
    assert "EN:plcData.varReal 0.5" in coms.commands
    assert client.enabled == {"plcData.varReal", "plcType"}


async def test_disable_stops_the_pushes(start: Start) -> None:
    sim, coms, client = await start()
    await client.enable(["plcType", "plcName"])

    await client.disable(["plcType"])

    assert client.enabled == {"plcName"}
    sim.set_value("plcType", 9)
    assert await coms.scan() == 0
    await client.disable([])
    await client.enable([])


async def test_enable_with_a_mask_and_a_bad_delta(start: Start) -> None:
    sim, coms, client = await start()
    events = Events(client)

    await client.enable(["Main.myObject*.value"])
    sim.set_value("Main.myObject2.value", 30.0)
    assert await coms.scan() == 1
    assert (await events.value("Main.myObject2.value")).value == 30.0

    for delta in (-1, float("inf"), True):
        with pytest.raises(InvalidValueError):
            await client.enable(["plcType"], delta=delta)


async def test_enable_of_names_the_server_refuses(start: Start) -> None:
    sim, _, client = await start()
    sim.load_program("demo")

    with pytest.raises(VariableNotFoundError) as caught:
        await client.enable(["plcName", "__PLC_RUN"])

    assert caught.value.path == "plcName"
    assert client.enabled == {"__PLC_RUN"}
    with pytest.raises(VariableNotFoundError) as caught:
        await client.disable(["plcType"])
    assert caught.value.path == "plcType"
    with pytest.raises(VariableNotFoundError):
        await client.enable(["noSuchThing"])


async def test_a_set_is_pushed_back_as_diff(start: Start) -> None:
    _, _, client = await start()
    events = Events(client)

    await client.set("plcType", 12)

    assert (await events.value("plcType")).value == 12


async def test_get_info(start: Start) -> None:
    _, _, client = await start()

    info = await client.get_info()
    assert info["VERSION"] == "Ver 6.1 Jun  1 2023 13:15:36"
    assert set(info) == {
        "VERSION",
        "VERSION_EPSNET",
        "VERSION_INI",
        "VERSION_PLC",
        "IPADDR",
        "EPSADDR",
        "EPSPORT",
        "PUBFILE",
        "NETWORK",
    }
    # The key asked for in any case; the answer is its one line (changelog 5.8).
    assert await client.get_info("version_plc") == {"VERSION_PLC": "sim CP-W32I v1.1"}
    assert await client.get(["plcType"]) == {"plcType": 2005}
    with pytest.raises(PlcResponseError, match="Unknown GETINFO name"):
        await client.get_info("colour")


async def test_get_info_of_the_old_form(start: Start) -> None:
    _, _, client = await start(options=PlcComsOptions(lower_case_info=True))

    assert (await client.get_info())["version"] == "6.1"
    assert await client.get_info("VERSION_PLC") == {"version_plc": "sim CP-W32I v1.1"}
    # The terminator of the one-key answer is read and ignored.
    assert await client.get(["plcType"]) == {"plcType": 2005}


# --- both protocols on one PLC ------------------------------------------------------------


async def test_a_tecoapi_write_arrives_as_diff_and_a_plccoms_set_is_read_by_tecoapi(
    start: Start, session: aiohttp.ClientSession
) -> None:
    sim, coms, client = await start("demo")
    tecoapi = make_client(session, sim)
    events = Events(client)
    await client.enable(["outsideTemp.value", "Rooms.windowOpen.value"])

    await tecoapi.write_path("outsideTemp.value", -3.5)
    await tecoapi.write_path("Rooms.windowOpen.value", True)
    assert await coms.scan() == 2

    assert (await events.value("outsideTemp.value")).value == -3.5
    assert (await events.value("Rooms.windowOpen.value")).value is True
    await client.set("displayMessage.value", "Vítejte doma")
    await client.set("Heating.livingSetpoint.value", 22.5)
    assert await tecoapi.read_path("Heating.livingSetpoint.value") == 22.5
    assert await tecoapi.read_path("displayMessage.value") == "Vítejte doma"


# --- __PLC_RUN and program downloads -------------------------------------------------------


async def test_halt_and_run_are_pushed(start: Start) -> None:
    sim, coms, client = await start()
    events = Events(client)

    sim.mode = "HALT"
    await coms.scan()
    assert await events.wait_for(lambda e: isinstance(e, RunStateChanged)) == (
        RunStateChanged(False)
    )
    assert client.plc_running is False
    sim.mode = "RUN"
    await coms.scan()
    await events.wait_for(lambda e: e == RunStateChanged(True))
    assert client.plc_running is True


async def test_a_program_download_reads_list_again_and_enables_again(
    start: Start,
) -> None:
    sim, coms, client = await start()
    events = Events(client)
    await client.enable(["plcType"], delta=2)
    source = sim.program.to_mapping()
    source["variables"]["extraCounter"] = {"type": "UINT", "value": 5}
    source["variables"]["plcType"] = {"type": "UINT", "value": 3000}

    sim.load_program(Program.from_mapping(source))
    await coms.scan()  # __PLC_RUN 0
    await coms.scan()  # __PLC_RUN 1

    changed = await events.wait_for(lambda e: isinstance(e, ProgramChanged))
    assert isinstance(changed, ProgramChanged)
    assert "extracounter" in changed.catalogue.points
    assert [e.running for e in events.of(RunStateChanged)] == [False, True]
    # plcType survived the download: enabled again with its delta and read again
    # (the server also pushed its new initial value: it stayed enabled there).
    reread = await events.wait_for(
        lambda e: isinstance(e, ValueChanged) and e.name == "plcType" and not e.pushed
    )
    assert isinstance(reread, ValueChanged)
    assert reread.value == 3000
    assert coms.commands.count("LIST:") == 2
    assert coms.commands.count("EN:plcType 2") == 2
    assert coms.enabled() == [{"plctype"}]
    assert "extracounter" in client.variables
    assert client.connected


async def test_halt_and_run_without_a_download_changes_no_program(start: Start) -> None:
    sim, coms, client = await start()
    events = Events(client)
    await client.enable(["plcType"])

    sim.mode = "HALT"
    await coms.scan()
    sim.mode = "RUN"
    await coms.scan()

    assert (await events.value("plcType")).pushed is False
    assert events.of(ProgramChanged) == []


# --- restarts, stalls, backoff ----------------------------------------------------------------


async def test_a_restarted_server_is_reconnected_and_enabled_again(
    start: Start,
) -> None:
    sim, coms, client = await start()
    await client.enable(["plcType"])
    events = Events(client)

    await coms.restart()

    lost = await events.connection(False)
    assert lost.reason == "closed by the server"
    await events.connection(True)
    assert client.health.reconnects == 1
    assert coms.connections_accepted == 2
    assert coms.commands.count("LIST:") == 2
    assert coms.commands.count("EN:plcType") == 2
    assert coms.enabled() == [{"plctype"}]
    assert (await events.value("plcType")).pushed is False
    sim.set_value("plcType", 77)
    assert await coms.scan() == 1
    assert (await events.value("plcType", start=len(events.items))).value == 77
    assert events.of(ProgramChanged) == []


async def test_a_program_changed_while_disconnected_is_reported(start: Start) -> None:
    sim, coms, client = await start()
    events = Events(client)

    await coms.restart()
    sim.load_program("demo")

    changed = await events.wait_for(lambda e: isinstance(e, ProgramChanged))
    assert isinstance(changed, ProgramChanged)
    assert "outsidetemp.value" in changed.catalogue.points
    await events.connection(True)


async def test_reconnect_backs_off_exponentially(start: Start) -> None:
    delays: list[float] = []

    async def sleep(delay: float) -> None:
        """The client's wait between attempts (its ``sleep``): noted, not waited."""
        delays.append(delay)
        if len(delays) == 4:
            coms.faults.refuse = False
        await asyncio.sleep(0)

    _, coms, client = await start(
        reconnect_delay=0.01, reconnect_max_delay=0.03, sleep=sleep
    )
    events = Events(client)
    coms.faults.refuse = True
    await coms.restart()

    await events.connection(True)
    assert delays == [0.01, 0.02, 0.03, 0.03]
    health = client.health
    assert (health.reconnect_attempts, health.reconnects) == (4, 1)
    assert coms.connections_accepted == 1 + 4


async def test_a_silent_connection_is_found_by_the_keepalive(start: Start) -> None:
    _, coms, client = await start(
        keepalive_interval=0.05, keepalive_timeout=0.1, timeout=1.0
    )
    events = Events(client)
    # Heal the server the moment the client gives up on it: one stall, one reconnect.
    client.subscribe(
        lambda e: (
            setattr(coms.faults, "stall", False)
            if isinstance(e, ConnectionChanged) and not e.connected
            else None
        )
    )

    coms.faults.stall = True

    lost = await events.connection(False)
    assert lost.reason == "no answer within 0.1 s"
    await events.connection(True)
    health = client.health
    assert (health.stalls, health.reconnects) == (1, 1)
    assert health.keepalives >= 1


async def test_the_keepalive_asks_only_when_the_server_is_quiet(start: Start) -> None:
    _, coms, client = await start(keepalive_interval=0.05)
    setup = len(coms.commands)

    await coms.wait_for_commands(setup + 1)

    assert coms.commands[setup] == "GET:__PLC_RUN"
    await coms.wait_for_commands(setup + 2)
    assert client.health.keepalives >= 2
    assert client.health.stalls == 0
    assert client.connected


async def test_a_command_without_answer_drops_the_connection(start: Start) -> None:
    _, coms, client = await start(timeout=0.3)
    events = Events(client)
    coms.faults.stall = True

    with pytest.raises(PlcConnectionError, match=r"did not answer within 0\.3 s"):
        await client.get(["plcType"])

    assert not client.connected
    assert client.health.stalls == 1
    coms.faults.stall = False
    await events.connection(True)
    assert await client.get(["plcType"]) == {"plcType": 2005}


async def test_an_over_long_line_is_discarded_and_counted(start: Start) -> None:
    sim, coms, client = await start(max_line_length=64)
    events = Events(client)
    await client.enable(["plcDesc", "plcType"])

    sim.set_value("plcDesc", "x" * 70)
    sim.set_value("plcType", 1)
    assert await coms.scan() == 2

    assert (await events.value("plcType")).value == 1
    assert client.health.discarded_lines == 1
    assert [e.name for e in events.of(ValueChanged)] == ["plcType"]
    assert client.connected


# --- subscribers -------------------------------------------------------------------------------


async def test_a_failing_subscriber_does_not_stop_the_others(start: Start) -> None:
    _, _, client = await start()

    def broken(event: PlcComsEvent) -> None:
        raise RuntimeError("broken subscriber")

    client.subscribe(broken)
    events = Events(client)
    silenced = Events(client)
    silenced.unsubscribe()
    silenced.unsubscribe()  # twice is harmless

    await client.set("plcType", 3)

    assert (await events.value("plcType")).value == 3
    assert silenced.items == []


def test_build_catalogue_skips_unknown_types_and_repeats() -> None:
    catalogue = build_catalogue(
        [
            PlcComsVariable("__PF_CRC", "DWORD"),
            PlcComsVariable("T_ZONES_SET[0].TOPIT_TC", "BOOL", "*"),
            PlcComsVariable("t_zones_set[0].topit_tc", "INT"),
            PlcComsVariable("Blob", "ARRAY OF BYTE"),
            PlcComsVariable("Text", "STRING[32]", "~"),
        ]
    )

    assert list(catalogue.points) == ["t_zones_set[0].topit_tc", "text"]
    assert catalogue.points["t_zones_set[0].topit_tc"].kind is ValueKind.BOOL
    assert catalogue.groups == ("T_ZONES_SET", "Text")
    assert catalogue.skipped_groups == ("Blob",)
    assert PlcComsVariable("Text", "STRING[32]", "~").hidden
    assert catalogue.values == {}


# --- a scripted server: what the simulator never sends ------------------------------------


class ScriptedServer:
    """A PLCComS stand-in answering each command line as the test scripted it.

    `replies[line]` is a list of byte strings, one used (and removed) per time the
    line arrives; without one, `LIST:` lists `listing`, `GET:name` answers from
    `values`, and anything else answers nothing.
    """

    def __init__(self) -> None:
        self.listing = [b"LIST:__PLC_RUN,BOOL", b"LIST:temp,REAL", b"LIST:name,STRING"]
        self.values = {"__PLC_RUN": b"1", "temp": b"21,5", "name": b'"x"'}
        self.replies: dict[str, list[bytes]] = {}
        self.received: list[str] = []
        self.connections = 0
        self.writers: list[asyncio.StreamWriter] = []
        self.arrived = asyncio.Event()
        self.listener: asyncio.Server | None = None

    async def start(self) -> int:
        self.listener = await asyncio.start_server(self.serve, "127.0.0.1", 0)
        return int(self.listener.sockets[0].getsockname()[1])

    async def stop(self) -> None:
        assert self.listener is not None
        self.listener.close()
        self.drop()
        await self.listener.wait_closed()

    def drop(self) -> None:
        for writer in self.writers:
            writer.transport.abort()
        self.writers.clear()

    async def push(self, data: bytes) -> None:
        writer = self.writers[-1]
        writer.write(data)
        await writer.drain()

    async def wait_for(self, line: str, count: int = 1) -> None:
        async with asyncio.timeout(WAIT):
            while self.received.count(line) < count:
                await self.arrived.wait()

    def answer(self, line: str) -> bytes:
        if self.replies.get(line):
            return self.replies[line].pop(0)
        if line == "LIST:":
            return b"".join(entry + b"\n" for entry in [*self.listing, b"LIST:"])
        command, _, name = line.partition(":")
        if command == "GET" and name in self.values:
            return b"GET:" + name.encode() + b"," + self.values[name] + b"\n"
        return b""

    async def serve(
        self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter
    ) -> None:
        self.connections += 1
        self.writers.append(writer)
        with contextlib.suppress(ConnectionError):
            while line := await reader.readline():
                text = line.decode("cp1250").rstrip("\r\n")
                self.received.append(text)
                arrived, self.arrived = self.arrived, asyncio.Event()
                arrived.set()
                if answer := self.answer(text):
                    writer.write(answer)
                    await writer.drain()


class WireReader:
    """The stream a client reads a connection from, counting the bytes it read."""

    def __init__(self, reader: asyncio.StreamReader, wire: "Wire") -> None:
        self.reader = reader
        self.wire = wire
        self.received = 0

    async def read(self, n: int = -1) -> bytes:
        """Read as the client asked; raise the wire's bug on the bytes it names."""
        data = await self.reader.read(n)
        self.received += len(data)
        if self.wire.bug is not None and self.wire.bug in data:
            self.wire.bug = None
            raise RuntimeError("bug")
        return data


class Wire:
    """The connections a client opened through its ``open_connection`` seam.

    Each reader counts what the client read; ``bug`` makes the next read that
    holds those bytes fail as a bug in the client's reading would (once).
    """

    def __init__(self) -> None:
        self.readers: list[WireReader] = []
        self.writers: list[asyncio.StreamWriter] = []
        self.bug: bytes | None = None

    async def open(
        self, host: str, port: int
    ) -> tuple[WireReader, asyncio.StreamWriter]:
        reader, writer = await asyncio.open_connection(host, port)
        self.readers.append(WireReader(reader, self))
        self.writers.append(writer)
        return self.readers[-1], writer


@pytest.fixture
def wire() -> Wire:
    return Wire()


@pytest.fixture
async def scripted(wire: Wire) -> AsyncIterator[tuple[ScriptedServer, PlcComsClient]]:
    server = ScriptedServer()
    port = await server.start()
    client = PlcComsClient(
        "127.0.0.1",
        port,
        timeout=1.0,
        reconnect_delay=0.01,
        keepalive_interval=60,
        open_connection=wire.open,
    )
    await client.connect()
    yield server, client
    await client.close()
    await server.stop()


async def until(condition: Callable[[], bool]) -> None:
    """Let the loop run until `condition` holds (for states no event announces).

    Only for the bytes the client read and the commands it has pending, which
    have no event: the loop yields to the client's tasks and fails after WAIT
    seconds.
    """
    async with asyncio.timeout(WAIT):
        while not condition():  # noqa: ASYNC110 - no event exists to await
            await asyncio.sleep(0)


async def test_noise_between_answers_is_counted_and_ignored(
    scripted: tuple[ScriptedServer, PlcComsClient],
) -> None:
    server, client = scripted
    events = Events(client)

    await server.push(
        b"WARNING:12 too many DIFF messages\r\n"
        b"WARNING:252 Changed active variables in public file: '[1/3]'\r\n"
        b"EN:temp,7\r\n"  # an older server's answer to EN: -- not a value
        b"DI:temp,7\r\n"
        b"garbage without a colon\r\n"
        b"DIFF:broken\r\n"
        b"\r\n"
        b"LIST:stray,BOOL\r\n"
        b"GET:temp,1\r\n"
        b"ERROR:9 nobody asked\r\n"
        b"HELLO:there\r\n"
        b'DIFF:notListed,"text"\r\n'
        b"DIFF:__PLC_RUN,maybe\r\n"
        b"DIFF:temp,2,5\r\n"
    )

    assert (await events.value("temp")).value == 2.5
    assert [(e.name, e.value) for e in events.of(ValueChanged)] == [
        ("notListed", "text"),
        ("temp", 2.5),
    ]
    health = client.health
    assert (health.malformed_lines, health.server_errors) == (3, 1)
    assert client.plc_running is True
    assert client.connected


async def test_answers_that_belong_to_no_command_in_flight(
    scripted: tuple[ScriptedServer, PlcComsClient],
) -> None:
    server, client = scripted
    server.replies["LIST:"] = [
        (
            b"GET:temp,1\nGETINFO:x,y\nLIST:temp*~,REAL\nLIST:broken\nLIST:*~,BOOL\n"
            b"LIST:blob,ARRAY\nLIST:\n"
        )
    ]
    server.replies["GET:temp"] = [
        b"LIST:zzz,BOOL\nGETINFO:a,b\nGET:other,1\nGET:temp,3\n"
    ]
    server.replies["GETINFO:"] = [b"LIST:zzz,BOOL\nGETINFO:version,6.1\nGETINFO:\n"]
    server.replies["SET:temp,4"] = [b"GET:temp,4\n"]

    variables = await client.list_variables()
    values = await client.get(["temp"])
    info = await client.get_info()
    await client.set("temp", 4)

    # An entry without a type (the manual's own example) is listed, of no kind.
    assert [(v.name, v.flags, v.kind) for v in variables] == [
        ("temp", "*~", ValueKind.REAL),
        ("broken", "", None),
        ("blob", "", None),
    ]
    assert values == {"temp": 3.0}
    assert info == {"version": "6.1"}
    assert client.health.malformed_lines == 1  # a name of flags alone


async def test_an_error_in_a_get_batch(
    scripted: tuple[ScriptedServer, PlcComsClient],
) -> None:
    server, client = scripted
    server.replies["GET:temp"] = [
        b"ERROR:41 PLC does not communicate\n",
        b"ERROR:2 Variable 'temp' does not exist\n",
    ]

    with pytest.raises(PlcResponseError, match="PLC does not communicate") as caught:
        await client.get(["temp", "name"])
    assert type(caught.value) is PlcResponseError
    assert caught.value.code == "41"
    with pytest.raises(VariableNotFoundError) as missing:
        await client.get(["name", "temp"])
    assert missing.value.path == "temp"
    assert client.connected


async def test_errors_of_list_getinfo_and_disable(
    scripted: tuple[ScriptedServer, PlcComsClient],
) -> None:
    server, client = scripted
    server.replies["LIST:"] = [b"ERROR:5 public file unreadable\n"]
    server.replies["GETINFO:"] = [
        b"".join(b"GETINFO:k%d,v\n" % n for n in range(300)) + b"GETINFO:\n",
        b"ERROR:1 busy\n",
    ]
    server.replies["DI:temp"] = [b"ERROR:7 busy\n"]

    with pytest.raises(PlcResponseError, match="public file unreadable"):
        await client.list_variables()
    with pytest.raises(ResponseTooLargeError):
        await client.get_info()
    with pytest.raises(PlcResponseError, match="busy"):
        await client.get_info()
    with pytest.raises(PlcResponseError, match="busy") as caught:
        await client.disable(["temp"])
    assert type(caught.value) is PlcResponseError


async def test_a_line_split_across_tcp_segments(
    scripted: tuple[ScriptedServer, PlcComsClient], wire: Wire
) -> None:
    server, client = scripted
    events = Events(client)
    reader = wire.readers[-1]
    before = reader.received

    # Each segment is read (and framed) before the next is sent.
    await server.push(b"DIFF:temp,1")
    await until(lambda: reader.received == before + len(b"DIFF:temp,1"))
    assert events.items == []
    await server.push(b"2,25\r")
    await until(lambda: reader.received == before + len(b"DIFF:temp,12,25\r"))
    assert events.items == []
    await server.push(b'\nDIFF:name,"\xe8\xe1p"\n')

    assert (await events.value("name")).value == "čáp"
    assert [e.value for e in events.of(ValueChanged)] == [12.25, "čáp"]


async def test_enable_again_after_a_reconnect_when_the_server_refuses(
    scripted: tuple[ScriptedServer, PlcComsClient],
) -> None:
    server, client = scripted
    events = Events(client)
    await client.enable(["temp", "T*"], delta=1.5)
    server.replies["EN:temp 1.5"] = [b"ERROR:2 Variable 'temp' not found\n"]

    server.drop()

    await events.connection(False)
    await events.connection(True)
    assert server.received.count("EN:T* 1.5") == 2
    assert server.received.count("GET:temp") == 1  # read again; the mask is not
    assert client.enabled == {"temp", "T*"}


async def test_setting_up_again_after_the_plc_restarts_can_fail(
    scripted: tuple[ScriptedServer, PlcComsClient],
) -> None:
    server, client = scripted
    events = Events(client)
    server.replies["LIST:"] = [b"ERROR:5 public file unreadable\n"]

    await server.push(b"DIFF:__PLC_RUN,0\nDIFF:__PLC_RUN,1\n")

    lost = await events.connection(False)
    assert lost.reason.startswith("setting up again failed")
    await events.connection(True)
    assert server.connections == 2
    assert [e.running for e in events.of(RunStateChanged)] == [False, True]


async def test_a_bug_while_reading_drops_the_connection(
    scripted: tuple[ScriptedServer, PlcComsClient], wire: Wire
) -> None:
    server, client = scripted
    events = Events(client)
    wire.bug = b"DIFF:temp,1"

    await server.push(b"DIFF:temp,1\n")

    assert (await events.connection(False)).reason == "internal error"
    await events.connection(True)
    assert len(wire.readers) == 2
    assert events.of(ValueChanged) == []  # the read that failed is not delivered


async def test_a_failed_send_drops_the_connection(
    scripted: tuple[ScriptedServer, PlcComsClient], wire: Wire
) -> None:
    _, client = scripted
    events = Events(client)

    def refuse(data: object) -> None:
        raise ConnectionResetError

    wire.writers[-1].write = refuse  # type: ignore[method-assign]

    with pytest.raises(PlcConnectionError, match="Cannot send"):
        await client.get(["temp"])
    assert not client.connected
    lost = await events.connection(False)
    assert lost.reason == "sending failed: ConnectionResetError"
    await events.connection(True)
    assert len(wire.writers) == 2


async def test_commands_waiting_their_turn_fail_when_the_connection_drops(
    scripted: tuple[ScriptedServer, PlcComsClient],
) -> None:
    server, client = scripted
    server.values.pop("name")  # GET:name is never answered
    first = asyncio.ensure_future(client.get(["name"]))
    await server.wait_for("GET:name")
    second = asyncio.ensure_future(client.get(["temp"]))
    await until(lambda: client.commands_pending == 2)  # the second waits its turn

    server.drop()

    for task in (first, second):
        with pytest.raises(PlcConnectionError):
            await task
    assert client.commands_pending == 0


def test_timeouts_must_be_positive() -> None:
    with pytest.raises(ValueError, match="positive"):
        PlcComsClient("127.0.0.1", timeout=0)
    with pytest.raises(ValueError, match="positive"):
        PlcComsClient("127.0.0.1", keepalive_interval=-1)


# --- the server as Teco's manual describes it -----------------------------------------------


@pytest.mark.parametrize(
    "options",
    [
        PlcComsOptions(),  # flags after the type, as the changelog prints them
        PlcComsOptions(flags_after_name=True),
        PlcComsOptions(enabled_flag=True),  # what was assumed before the manual
    ],
    ids=["manual", "after-name", "old-enabled-flag"],
)
async def test_a_server_listing_every_variable_disabled_serves_them(
    start: Start, options: PlcComsOptions
) -> None:
    # PF_VAR_DISABLED = Yes, as Teco ships it: LIST:plcType,UINT* until EN:.
    sim, coms, client = await start(options=options)
    events = Events(client)

    catalogue = client.catalogue
    assert catalogue is not None
    assert len(catalogue.points) == len(coms.variables) - 2
    assert catalogue.points["plctype"].kind is ValueKind.INTEGER
    assert client.variables["plctype"].type == "UINT"
    await client.enable(["plcType"])
    listed = {v.key: v for v in await client.list_variables()}
    if not options.enabled_flag:
        assert listed["plctype"].enabled
        assert not listed["plcname"].enabled
    sim.set_value("plcType", 7)
    await coms.scan()
    assert (await events.value("plcType")).value == 7


async def test_a_server_enabling_every_variable_pushes_only_what_is_enabled(
    start: Start,
) -> None:
    # PF_VAR_DISABLED = No: a new connection has every variable enabled.
    sim, coms, client = await start(options=PlcComsOptions(var_disabled=False))
    events = Events(client)
    assert "DI:*" in coms.commands
    await client.enable(["plcType"])

    sim.set_value("plcName", "other")
    sim.set_value("plcType", 7)
    await coms.scan()

    assert (await events.value("plcType")).value == 7
    assert [e.name for e in events.of(ValueChanged)] == ["plcType"]
    assert coms.enabled() == [{"plctype"}]


@pytest.mark.parametrize("answer", ["warning", "value", "none"])
async def test_enable_and_disable_answers_are_never_values_or_answers(
    start: Start, answer: str
) -> None:
    # WARNING:252 (the manual), the values (older servers), or nothing.
    sim, _, client = await start(options=PlcComsOptions(enable_answer=answer))
    events = Events(client)

    await client.enable(["plcType", "plcName"])
    sim.set_value("plcType", 7)
    assert await client.get(["plcType"]) == {"plcType": 7}
    await client.disable(["plcName"])
    await client.enable(["Main.myObject*.value"])
    sim.set_value("plcName", "x")
    assert await client.get(["plcName", "plcType"]) == {"plcName": "x", "plcType": 7}

    assert events.of(ValueChanged) == []
    health = client.health
    assert (health.server_errors, health.malformed_lines) == (0, 0)
    assert client.enabled == {"plcType", "Main.myObject*.value"}
    assert client.connected


async def test_errors_are_told_by_their_code_not_their_text(
    scripted: tuple[ScriptedServer, PlcComsClient],
) -> None:
    server, client = scripted
    server.replies["GET:temp"] = [
        b"ERROR:33 Chybne jmeno promenne v dotazu: 'GET:temp'\n",
        b"ERROR:34 Zakazana promenna v dotazu: 'GET:temp'\n",
    ]
    server.replies["SET:temp,5"] = [b"ERROR:35 Spatna hodnota: 'SET:temp,5'\n"]
    server.replies["GETINFO:"] = [b"ERROR:11 Too many connections\n"]

    with pytest.raises(VariableNotFoundError) as missing:
        await client.get(["name", "temp"])
    assert (missing.value.path, missing.value.code) == ("temp", "33")
    with pytest.raises(VariableDisabledError) as disabled:
        await client.get(["temp"])
    assert disabled.value.path == "temp"
    with pytest.raises(ValueRejectedError) as rejected:
        await client.set("temp", 5)
    assert (rejected.value.path, rejected.value.code) == ("temp", "35")
    with pytest.raises(PlcConnectionError, match="refuses more connections"):
        await client.get_info()


async def test_an_error_is_matched_to_the_name_its_request_quotes(
    scripted: tuple[ScriptedServer, PlcComsClient],
) -> None:
    server, client = scripted
    server.listing.append(b"LIST:temp2,REAL")
    server.values["temp2"] = b"1"
    # Its text holds "temp" too: the quoted request tells which name failed.
    server.replies["GET:temp2"] = [
        b"ERROR:33 Unknown variable name in request: 'GET:temp2'\n"
    ]
    await client.list_variables()

    with pytest.raises(VariableNotFoundError) as missing:
        await client.get(["temp", "temp2"])

    assert missing.value.path == "temp2"


async def test_a_server_that_cannot_reach_its_plc_is_told_apart(start: Start) -> None:
    _, coms, _ = await start()
    coms.faults.plc_unreachable = True
    client = PlcComsClient("127.0.0.1", coms.port, timeout=2.0)

    with pytest.raises(PlcUnreachableError, match="cannot reach its PLC"):
        await client.connect()

    assert not client.connected
    assert isinstance(client.failure, PlcUnreachableError)
    coms.faults.plc_unreachable = False
    await client.connect()
    assert client.failure is None
    await client.close()


async def test_a_plc_lost_behind_the_server_is_followed_until_it_is_back(
    start: Start,
) -> None:
    sim, coms, client = await start()
    events = Events(client)
    await client.enable(["plcType"])

    coms.faults.plc_unreachable = True
    with pytest.raises(PlcUnreachableError):
        await client.get(["plcType"])
    assert not client.connected
    assert isinstance(client.failure, PlcUnreachableError)
    # The server keeps answering, with ERROR:10: the client keeps trying.
    await coms.wait_for_connections(3)
    assert isinstance(client.failure, PlcUnreachableError)
    sim.set_value("plcType", 9)  # changed while the PLC was out of reach
    coms.faults.plc_unreachable = False

    await events.connection(True)
    reread = await events.value("plcType")
    assert (reread.value, reread.pushed) == (9, False)
    assert client.failure is None
    assert await client.get(["plcType"]) == {"plcType": 9}


@pytest.mark.parametrize(
    "options",
    [
        PlcComsOptions(),  # DATE_TIME_DECIMAL = No: the double's 8 bytes
        PlcComsOptions(date_time_decimal=True),
        PlcComsOptions(date_seconds=True),  # what was assumed before the manual
    ],
    ids=["integer", "decimal", "old-seconds"],
)
async def test_dates_are_read_and_written_in_the_server_s_form(
    start: Start, options: PlcComsOptions
) -> None:
    sim, coms, client = await start(options=options)
    moment = datetime(2024, 2, 29, 23, 59, 58, 0, tzinfo=UTC)

    await client.set("plcData.varDT", moment)
    await client.set("plcData.varDate", date(2024, 3, 1))

    assert sim.get_value("plcData.varDT") == "2024-02-29T23:59:58.000Z"
    assert sim.get_value("plcData.varDate") == "2024-03-01"
    assert await client.get(["plcData.varDT", "plcData.varDate"]) == {
        "plcData.varDT": moment,
        "plcData.varDate": date(2024, 3, 1),
    }
    # The form was learnt once, from the first DATE/DT read.
    assert coms.commands.count("GET:plcData.varDT") == 2


async def test_a_date_of_zero_proves_no_date_form(start: Start) -> None:
    """DATE_TIME_DECIMAL = No (the default) sends a DT never set as 0 (0.0's bytes).

    That 0 is the same in every form: it must not make the next write a count
    of seconds (1795680000 read as a double's bytes is 1970-01-01), nor turn a
    form learnt from another value around.
    """
    sim, _, client = await start()
    epoch = datetime(1970, 1, 1, tzinfo=UTC)
    sim.set_value("plcData.varDT", "1970-01-01T00:00:00.000Z")
    assert await client.get(["plcData.varDT"]) == {"plcData.varDT": epoch}

    await client.set("plcData.varDT", datetime(2026, 11, 26, tzinfo=UTC))
    assert sim.get_value("plcData.varDT") == "2026-11-26T00:00:00.000Z"

    # The form proven by that DT's bytes stays across another variable's 0.
    sim.set_value("plcData.varDate", "1970-01-01")
    assert await client.get(["plcData.varDT", "plcData.varDate"]) == {
        "plcData.varDT": datetime(2026, 11, 26, tzinfo=UTC),
        "plcData.varDate": epoch.date(),
    }
    await client.set("plcData.varDate", date(2026, 11, 27))
    assert sim.get_value("plcData.varDate") == "2026-11-27"


async def test_a_restarted_server_s_date_form_is_learnt_again(start: Start) -> None:
    """DATE_TIME_DECIMAL changed while PLCComS was restarted: the old form is gone."""
    sim, coms, client = await start(options=PlcComsOptions(date_time_decimal=True))
    events = Events(client)
    await client.get(["plcData.varDT"])  # a decimal with a fraction: proven
    coms.options = PlcComsOptions()  # restarted with DATE_TIME_DECIMAL = No
    sim.set_value("plcData.varDT", "1970-01-01T00:00:00.000Z")  # 0: proves nothing

    await coms.restart()
    await events.connection(False)
    await events.connection(True)
    await client.set("plcData.varDT", datetime(2026, 11, 26, tzinfo=UTC))

    assert sim.get_value("plcData.varDT") == "2026-11-26T00:00:00.000Z"


@pytest.mark.parametrize(
    "text",
    [
        "253402300799.9995",  # 9999-12-31T23:59:59.9995: 10000-01-01 once rounded
        str(int.from_bytes(struct.pack("<d", 253402300799.9995), "little")),
    ],
    ids=["decimal", "integer"],
)
async def test_a_date_beyond_9999_costs_only_its_own_value(
    start: Start, text: str
) -> None:
    """One value a datetime cannot hold: that point is None, the connection stays."""
    sim, coms, client = await start()
    events = Events(client)
    coms.faults.raw_values["plcData.varDT"] = text

    assert await client.get(["plcData.varDT", "plcType"]) == {
        "plcData.varDT": None,
        "plcType": sim.get_value("plcType"),
    }
    await client.enable(["plcData.varDT"])
    sim.set_value("plcData.varDT", "2020-01-01T00:00:00.000Z")
    assert await coms.scan() == 1
    assert (await events.value("plcData.varDT")).value is None
    await client.set("plcType", 7)
    assert await client.get(["plcType"]) == {"plcType": 7}

    assert client.connected
    assert coms.connections_accepted == 1
    assert client.health.reconnects == 0
    assert not events.of(ConnectionChanged)


async def test_a_time_of_day_beyond_a_day_is_no_value(
    scripted: tuple[ScriptedServer, PlcComsClient],
) -> None:
    server, client = scripted
    server.listing += [b"LIST:clock,TOD", b"LIST:moment,DT"]
    server.values |= {"clock": b"86400000", "moment": b"1600000000000"}
    await client.list_variables()

    assert await client.get(["clock", "moment"]) == {"clock": None, "moment": None}


async def test_an_unasked_error_10_drops_the_connection_until_the_plc_answers(
    scripted: tuple[ScriptedServer, PlcComsClient],
) -> None:
    server, client = scripted
    events = Events(client)

    await server.push(b"ERROR:10 Unable to connect to PLC.\r\n")

    lost = await events.connection(False)
    assert "cannot reach its PLC" in lost.reason
    await events.connection(True)  # the scripted server answers the next setup
    assert server.connections == 2
    assert client.failure is None
