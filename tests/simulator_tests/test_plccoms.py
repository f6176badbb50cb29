"""The PLCComS simulator, driven by a raw asyncio TCP client: bytes on the wire."""

import asyncio
from collections.abc import AsyncIterator
import re
import signal
import struct

import aiohttp
import pytest

from tests.simulator import Simulator
from tests.simulator.__main__ import parse_arguments
from tests.simulator.plccoms import PlcComsOptions, PlcComsServer
from tests.simulator_tests.conftest import fetch
from tests.simulator_tests.test_main import launch

pytestmark = pytest.mark.usefixtures("socket_enabled")

# A safety net so a broken server fails a test instead of hanging it.
WAIT = 5.0


def legacy(**settings: object) -> PlcComsOptions:
    """The forms this project assumed before Teco's manual, every switch on.

    The tests written against them stay, as tests of the switches; the manual's
    defaults have tests of their own (the end of this file).
    """
    return PlcComsOptions(
        flags_after_name=True,
        enabled_flag=True,
        enable_answer="none",
        legacy_errors=True,
        date_seconds=True,
        lower_case_info=True,
        **settings,  # type: ignore[arg-type]
    )


class RawClient:
    """A bare TCP client: sends bytes, reads lines exactly as they arrive."""

    def __init__(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter):
        self.reader = reader
        self.writer = writer

    @classmethod
    async def open(cls, server: PlcComsServer) -> "RawClient":
        reader, writer = await asyncio.open_connection(server.host, server.port)
        return cls(reader, writer)

    async def send(self, *lines: str, end: str = "\n") -> None:
        self.writer.write("".join(line + end for line in lines).encode("cp1250"))
        await self.writer.drain()

    async def line(self) -> bytes:
        """The next line with its line end."""
        async with asyncio.timeout(WAIT):
            return await self.reader.readuntil(b"\n")

    async def lines(self, count: int) -> list[bytes]:
        return [await self.line() for _ in range(count)]

    async def until(self, last: bytes) -> list[bytes]:
        """Lines up to and including `last` (line end included)."""
        lines = [await self.line()]
        while lines[-1] != last:
            lines.append(await self.line())
        return lines

    async def ask(self, command: str) -> bytes:
        await self.send(command)
        return await self.line()

    async def close(self) -> None:
        self.writer.close()
        await self.writer.wait_closed()


@pytest.fixture
async def manual() -> AsyncIterator[tuple[Simulator, PlcComsServer]]:
    """The manual's PLC served over PLCComS only; scans only when a test asks."""
    sim = Simulator("manual")
    async with PlcComsServer(sim, options=legacy(), scan_interval=None) as server:
        yield sim, server


@pytest.fixture
async def raw(manual: tuple[Simulator, PlcComsServer]) -> AsyncIterator[RawClient]:
    client = await RawClient.open(manual[1])
    await manual[1].wait_for_open_connections(1)
    yield client
    await client.close()


# --- LIST:, GET:, GETINFO: ---------------------------------------------------------------


async def test_list_names_every_leaf_in_the_server_spelling(raw: RawClient) -> None:
    await raw.send("LIST:")

    lines = await raw.until(b"LIST:\r\n")

    assert lines[:2] == [b"LIST:__PLC_RUN,BOOL\r\n", b"LIST:__PF_CRC,DWORD\r\n"]
    assert b"LIST:plcName,STRING\r\n" in lines
    assert b"LIST:plcData.varStringArray[5],STRING\r\n" in lines
    assert b"LIST:plcData.varDT,DT\r\n" in lines
    assert b"LIST:myObject.favorites.sport,STRING\r\n" in lines
    assert b"LIST:arr2[1][3],REAL\r\n" in lines
    assert b"LIST:arr3[1][2][3],BYTE\r\n" in lines
    # A T_ApiObject appears as its members; a program instance as its prefix.
    assert b"LIST:Main.myObject3.value,REAL\r\n" in lines
    assert b"LIST:Main.myObject3.attr.maxValue,REAL\r\n" in lines
    assert b"LIST:Main.myObject3.attr.title,STRING\r\n" in lines
    # 2 server variables, plcName/Type/Desc 3, plcData 23, myObject 13, arr1 6,
    # arr2 12, arr3 24, Main 3 T_ApiObjects of 8, and the bare LIST: at the end.
    assert len(lines) == 2 + 3 + 23 + 13 + 6 + 12 + 24 + 24 + 1


async def test_a_variable_the_public_file_lacks_is_unknown() -> None:
    sim = Simulator("manual")
    async with PlcComsServer(
        sim, scan_interval=None, unpublished={"plcData.varDT"}
    ) as server:
        raw = await RawClient.open(server)
        await raw.send("LIST:plcData.varD*")
        listed = [line.split(b",")[0] for line in await raw.until(b"LIST:\r\n")]
        assert b"LIST:plcData.varDate" in listed
        assert b"LIST:plcData.varDT" not in listed
        assert await raw.ask("GET:plcData.varDT") == (
            b"ERROR:33 Unknown variable name in request: 'GET:plcData.varDT'\r\n"
        )
        assert "plcdata.vardt" not in {v.name.lower() for v in server.variables}
        await raw.close()


async def test_list_with_a_mask(raw: RawClient) -> None:
    await raw.send("LIST:Main.myObject1.attr.*")

    lines = await raw.until(b"LIST:\r\n")

    assert [line.split(b",")[0] for line in lines[:-1]] == [
        b"LIST:Main.myObject1.attr." + member
        for member in (
            b"enable",
            b"visibility",
            b"readOnly",
            b"title",
            b"minValue",
            b"maxValue",
            b"units",
        )
    ]


async def test_get_answers_every_type_as_text(raw: RawClient) -> None:
    await raw.send(
        "GET:plcData.varBool1",
        "GET:plcData.varSint",
        "GET:plcData.varReal",
        "GET:plcData.varLreal",
        "GET:arr2[1][3]",
        "GET:plcName",
        "GET:plcData.varTime",
        "GET:plcData.varDate",
        "GET:plcData.varDT",
        "GET:Main.myObject1.attr.units",
        "GET:__PLC_RUN",
    )

    assert await raw.lines(11) == [
        b"GET:plcData.varBool1,1\r\n",
        b"GET:plcData.varSint,-11\r\n",
        b"GET:plcData.varReal,1000.0\r\n",
        b"GET:plcData.varLreal,1000000.0\r\n",
        b"GET:arr2[1][3],1.3\r\n",
        b'GET:plcName,"myFoxtrot"\r\n',
        b"GET:plcData.varTime,3723450\r\n",  # 01:02:03.450 in milliseconds
        b"GET:plcData.varDate,1434499200\r\n",  # 2015-06-17, seconds since 1970
        b"GET:plcData.varDT,1526037753\r\n",  # 2018-05-11T11:22:33 UTC
        b'GET:Main.myObject1.attr.units,"\xb0C"\r\n',  # Windows-1250
        b"GET:__PLC_RUN,1\r\n",
    ]


async def test_commands_are_case_insensitive_and_take_crlf(raw: RawClient) -> None:
    await raw.send("get:PLCNAME", "Get:plctype", end="\r\n")

    assert await raw.lines(2) == [
        b'GET:plcName,"myFoxtrot"\r\n',
        b"GET:plcType,2005\r\n",
    ]


async def test_empty_lines_are_ignored(
    manual: tuple[Simulator, PlcComsServer], raw: RawClient
) -> None:
    await raw.send("", "  ", "GET:plcType")

    assert await raw.line() == b"GET:plcType,2005\r\n"
    assert manual[1].commands == ["GET:plcType"]


async def test_get_with_a_mask_and_an_unknown_name(raw: RawClient) -> None:
    await raw.send("GET:Main.myObject*.value")
    assert await raw.lines(3) == [
        b"GET:Main.myObject1.value,-0.5\r\n",
        b"GET:Main.myObject2.value,22.1\r\n",
        b"GET:Main.myObject3.value,23.0\r\n",
    ]

    assert await raw.ask("GET:nothing") == b"ERROR:2 Variable 'nothing' not found\r\n"


async def test_getinfo(raw: RawClient) -> None:
    await raw.send("GETINFO:")
    lines = await raw.until(b"GETINFO:\r\n")

    assert lines == [
        b"GETINFO:version,6.1\r\n",
        b"GETINFO:version_plc,sim CP-W32I v1.1\r\n",
        b"GETINFO:ipaddr,127.0.0.1\r\n",
        b"GETINFO:epsport,61682\r\n",
        b"GETINFO:pubfile,DOC_TECOAPI v1.0.pub\r\n",
        b"GETINFO:network,1 clients\r\n",
        b"GETINFO:\r\n",
    ]
    await raw.send("getinfo:VERSION")
    assert await raw.lines(2) == [b"GETINFO:version,6.1\r\n", b"GETINFO:\r\n"]
    assert (
        await raw.ask("GETINFO:colour") == b"ERROR:6 Unknown GETINFO key 'colour'\r\n"
    )


async def test_errors(raw: RawClient) -> None:
    assert await raw.ask("HELLO") == b"ERROR:1 Unknown command 'HELLO'\r\n"
    assert await raw.ask("FLY:away") == b"ERROR:1 Unknown command 'FLY'\r\n"
    assert await raw.ask("EN:plcType -1") == (
        b"ERROR:4 Invalid delta '-1' of variable 'plcType'\r\n"
    )
    assert await raw.ask("SET:__PLC_RUN,0") == (
        b"ERROR:5 Variable '__PLC_RUN' cannot be set to '0'\r\n"
    )
    assert await raw.ask("SET:plcType") == (
        b"ERROR:5 Variable 'plcType' cannot be set to ''\r\n"
    )
    await raw.send("X" * 5000)
    assert await raw.line() == b"ERROR:7 Line too long\r\n"


# --- SET: and the memory TecoApi serves --------------------------------------------------


async def test_set_writes_the_plc_memory_and_answers_with_a_diff(
    manual: tuple[Simulator, PlcComsServer], raw: RawClient
) -> None:
    sim, _ = manual

    await raw.send(
        "SET:plcType,42",
        "set:plcData.varReal,21,5",  # a decimal comma
        "SET:plcData.varBool0,true",
        'SET:plcName,"Žluťoučký"',
        "SET:plcData.varTime,1500",
        "SET:plcData.varDate,86400",
        "SET:plcData.varDT,2018-05-11T11:22:33.456Z",
        "SET:plcData.varLreal,1.5e3",
        "SET:plcDesc,bare text",
    )

    assert await raw.lines(9) == [
        b"DIFF:plcType,42\r\n",
        b"DIFF:plcData.varReal,21.5\r\n",
        b"DIFF:plcData.varBool0,1\r\n",
        b'DIFF:plcName,"\x8elu\x9dou\xe8k\xfd"\r\n',
        b"DIFF:plcData.varTime,1500\r\n",
        b"DIFF:plcData.varDate,86400\r\n",
        b"DIFF:plcData.varDT,1526037753\r\n",
        b"DIFF:plcData.varLreal,1500.0\r\n",
        b'DIFF:plcDesc,"bare text"\r\n',
    ]
    assert sim.get_value("plcType") == 42
    assert sim.get_value("plcData.varReal") == 21.5
    assert sim.get_value("plcData.varBool0") is True
    assert sim.get_value("plcName") == "Žluťoučký"
    assert sim.get_value("plcData.varTime") == "00:00:01.500"
    assert sim.get_value("plcData.varDate") == "1970-01-02"
    assert sim.get_value("plcData.varDT") == "2018-05-11T11:22:33.456Z"


@pytest.mark.parametrize(
    ("command", "shown"),
    [
        ("SET:plcType,70000", b"Invalid value '70000' of variable 'plcType' (UINT)"),
        ("SET:plcType,1.5", b"Invalid value '1.5' of variable 'plcType' (UINT)"),
        ("SET:plcData.varBool0,2", b"Invalid value '2' of variable 'plcData.varBool0'"),
        (
            "SET:plcData.varReal,abc",
            b"Invalid value 'abc' of variable 'plcData.varReal'",
        ),
        ("SET:plcData.varReal,1e39", b"Invalid value '1e39' of variable"),
        ('SET:plcName,"much too long"', b"of variable 'plcName' (STRING[10])"),
        ("SET:plcData.varTime,-1", b"of variable 'plcData.varTime' (TIME)"),
        ("SET:plcData.varTime,1:00", b"of variable 'plcData.varTime'"),
        ("SET:plcData.varTime,2147483648", b"of variable 'plcData.varTime'"),
        ("SET:plcData.varTime,1000:00:00", b"of variable 'plcData.varTime'"),
        ("SET:plcData.varTime,100:00:00.5", None),  # TIME may pass 24 hours
        ("SET:plcData.varDate,1969-12-31", b"of variable 'plcData.varDate'"),
        ("SET:plcData.varDate,2015-06-17", None),
        ("SET:plcData.varDT,2018-05-11T11:22:33", None),
        ("SET:plcData.varDT,yesterday", b"of variable 'plcData.varDT'"),
        ("SET:plcData.varDT,99999999999999999", b"of variable 'plcData.varDT'"),
        ("SET:nothing,1", b"ERROR:2 Variable 'nothing' not found"),
    ],
)
async def test_set_refuses_what_the_type_cannot_hold(
    raw: RawClient, command: str, shown: bytes | None
) -> None:
    line = await raw.ask(command)

    if shown is None:
        assert line.startswith(b"DIFF:")
    else:
        assert line.startswith(b"ERROR:")
        assert shown in line


async def test_a_write_through_tecoapi_is_pushed_over_plccoms(
    session: aiohttp.ClientSession, demo_plc: Simulator
) -> None:
    async with PlcComsServer(demo_plc, options=legacy(), scan_interval=None) as server:
        raw = await RawClient.open(server)
        await raw.send("EN:outsideTemp.value", "GET:outsideTemp.value")
        assert await raw.line() == b"GET:outsideTemp.value,4.5\r\n"

        reply = await fetch(
            session, demo_plc, "/TecoApi/SetObject?outsideTemp.value=-2.5"
        )
        assert reply.status == 200
        assert await server.scan() == 1

        assert await raw.line() == b"DIFF:outsideTemp.value,-2.5\r\n"
        await raw.send("SET:outsideTemp.value,7.25")
        assert await raw.line() == b"DIFF:outsideTemp.value,7.25\r\n"
        reply = await fetch(session, demo_plc, "/TecoApi/GetObject?outsideTemp.value")
        assert reply.json() == {"outsideTemp": {"value": 7.25}}
        # The DIFF of the SET: was the change: the next scan has nothing to add.
        assert await server.scan() == 0
        await raw.close()


# --- EN:, DI:, deltas and change detection -----------------------------------------------


async def test_variables_start_disabled(
    manual: tuple[Simulator, PlcComsServer], raw: RawClient
) -> None:
    sim, server = manual
    sim.set_value("plcType", 7)

    assert await server.scan() == 0

    await raw.send("EN:plcType")
    await server.wait_for_commands(1)
    sim.set_value("plcType", 8)
    assert await server.scan() == 1
    assert await raw.line() == b"DIFF:plcType,8\r\n"
    assert await server.scan() == 0  # no change, no DIFF


async def test_delta_for_numbers(
    manual: tuple[Simulator, PlcComsServer], raw: RawClient
) -> None:
    sim, server = manual
    await raw.send("EN:plcData.varReal 0,5", "EN:plcType 10")
    await server.wait_for_commands(2)

    sim.set_value("plcData.varReal", 1000.3)
    sim.set_value("plcType", 2014)
    assert await server.scan() == 0  # both below their delta

    sim.set_value("plcData.varReal", 1000.6)  # 0.6 from the last value sent
    sim.set_value("plcType", 2015)
    assert await server.scan() == 2
    assert await raw.lines(2) == [
        b"DIFF:plcData.varReal,1000.6\r\n",
        b"DIFF:plcType,2015\r\n",
    ]


async def test_enable_with_a_mask_shows_in_list_and_di_stops_it(
    manual: tuple[Simulator, PlcComsServer], raw: RawClient
) -> None:
    sim, server = manual
    await raw.send("EN:Main.myObject*.value")
    await server.wait_for_commands(1)
    assert server.enabled() == [
        {"main.myobject1.value", "main.myobject2.value", "main.myobject3.value"}
    ]
    await raw.send("LIST:Main.myObject1.*")
    lines = await raw.until(b"LIST:\r\n")
    assert lines[0] == b"LIST:Main.myObject1.value*,REAL\r\n"
    assert lines[1] == b"LIST:Main.myObject1.attr.enable,BOOL\r\n"

    await raw.send("DI:Main.myObject2.value", "DI:Main.myObject3.value 1")
    await server.wait_for_commands(4)
    sim.set_value("Main.myObject2.value", 1.0)
    sim.set_value("Main.myObject1.value", 2.0)
    assert await server.scan() == 1
    assert await raw.line() == b"DIFF:Main.myObject1.value,2.0\r\n"


async def test_plc_run_follows_the_mode(
    manual: tuple[Simulator, PlcComsServer], raw: RawClient
) -> None:
    sim, server = manual
    await raw.send("EN:__PLC_RUN")
    await server.wait_for_commands(1)

    sim.mode = "HALT"
    assert await server.scan() == 1
    assert await raw.line() == b"DIFF:__PLC_RUN,0\r\n"
    assert await raw.ask("GET:__PLC_RUN") == b"GET:__PLC_RUN,0\r\n"
    sim.mode = "ERR"
    assert await server.scan() == 0
    sim.mode = "RUN"
    assert await server.scan() == 1
    assert await raw.line() == b"DIFF:__PLC_RUN,1\r\n"


async def test_a_program_download_changes_list_and_dips_plc_run(
    manual: tuple[Simulator, PlcComsServer], raw: RawClient
) -> None:
    sim, server = manual
    crc_before = await raw.ask("GET:__PF_CRC")
    await raw.send("EN:__PLC_RUN", "EN:plcType", "EN:Main.myObject1.value")
    await server.wait_for_commands(4)

    sim.load_program("demo")

    # The fixed variables are always pushed: the run state and the new stamp.
    assert await server.scan() == 2
    assert sorted(await raw.lines(2)) == [
        f"DIFF:__PF_CRC,{int(sim.stamp, 16)}\r\n".encode(),
        b"DIFF:__PLC_RUN,0\r\n",
    ]
    assert await server.scan() == 1
    assert await raw.line() == b"DIFF:__PLC_RUN,1\r\n"
    # Enabled variables the new program does not have are forgotten; EN: does
    # not apply to the fixed ones.
    assert server.enabled() == [set()]
    await raw.send("LIST:")
    lines = await raw.until(b"LIST:\r\n")
    assert b"LIST:outsideTemp.value,REAL\r\n" in lines
    assert b"LIST:plcType,UINT\r\n" not in lines
    assert (
        await raw.ask("GET:__PF_CRC")
        == f"GET:__PF_CRC,{int(sim.stamp, 16)}\r\n".encode()
    )
    assert await raw.ask("GET:__PF_CRC") != crc_before


async def test_periodic_scans_push_without_being_asked(
    manual: tuple[Simulator, PlcComsServer],
) -> None:
    sim, _ = manual
    async with PlcComsServer(sim, options=legacy(), scan_interval=0.01) as server:
        raw = await RawClient.open(server)
        await raw.send("EN:plcType")
        await server.wait_for_commands(1)
        sim.set_value("plcType", 3)

        assert await raw.line() == b"DIFF:plcType,3\r\n"
        await server.wait_for_scans(2)
        await raw.close()


# --- options -------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("options", "real", "lreal"),
    [
        (PlcComsOptions(), b"1000.0", b"1000000.0"),
        (PlcComsOptions(decimals=2), b"1000.00", b"1000000.00"),
        (PlcComsOptions(decimals=0), b"1000", b"1000000"),
        (PlcComsOptions(decimal_comma=True), b"1000,0", b"1000000,0"),
        (PlcComsOptions(scientific=True), b"1.000000e+03", b"1.000000e+06"),
        (
            PlcComsOptions(scientific=True, decimals=2, decimal_comma=True),
            b"1,00e+03",
            b"1,00e+06",
        ),
    ],
)
async def test_real_number_options(
    manual: tuple[Simulator, PlcComsServer],
    raw: RawClient,
    options: PlcComsOptions,
    real: bytes,
    lreal: bytes,
) -> None:
    manual[1].options = options

    await raw.send("GET:plcData.varReal", "GET:plcData.varLreal")

    assert await raw.lines(2) == [
        b"GET:plcData.varReal," + real + b"\r\n",
        b"GET:plcData.varLreal," + lreal + b"\r\n",
    ]


async def test_lf_line_ends(
    manual: tuple[Simulator, PlcComsServer], raw: RawClient
) -> None:
    manual[1].options.crlf = False

    await raw.send("GET:plcType", "LIST:plcName")

    # LIST: is answered at once, GET: after the read's commands (a PLC read).
    assert await raw.lines(3) == [
        b"LIST:plcName,STRING\n",
        b"LIST:\n",
        b"GET:plcType,2005\n",
    ]


async def test_a_string_windows_1250_cannot_hold_is_refused(raw: RawClient) -> None:
    # 0x81 is unassigned in Windows-1250: it cannot be stored as text.
    raw.writer.write(b"SET:plcName,\x81\n")

    assert (await raw.line()).startswith(b"ERROR:3 Invalid value")


# --- faults --------------------------------------------------------------------------------


async def test_out_of_order_reverses_the_get_answers_of_one_read(
    manual: tuple[Simulator, PlcComsServer], raw: RawClient
) -> None:
    manual[1].faults.out_of_order = True

    await raw.send("GET:plcType", "GET:nothing", "GET:plcName", "GET:plcData.varSint")

    assert await raw.lines(4) == [
        b"ERROR:2 Variable 'nothing' not found\r\n",  # errors come first, in order
        b"GET:plcData.varSint,-11\r\n",
        b'GET:plcName,"myFoxtrot"\r\n',
        b"GET:plcType,2005\r\n",
    ]


async def test_split_writes_send_each_line_in_two_writes(
    manual: tuple[Simulator, PlcComsServer], raw: RawClient
) -> None:
    server = manual[1]
    server.faults.split_writes = True
    writes = server.writes

    await raw.send("GET:plcType", "GET:plcName")

    assert await raw.lines(2) == [
        b"GET:plcType,2005\r\n",
        b'GET:plcName,"myFoxtrot"\r\n',
    ]
    assert server.writes - writes == 4
    assert server.lines_sent == 2


async def test_stall_keeps_the_connection_open_and_silent(
    manual: tuple[Simulator, PlcComsServer], raw: RawClient
) -> None:
    sim, server = manual
    await raw.send("EN:plcType")
    await server.wait_for_commands(1)
    server.faults.stall = True
    sim.set_value("plcType", 1)

    assert await server.scan() == 0
    await raw.send("GET:plcName")
    with pytest.raises(TimeoutError):
        async with asyncio.timeout(0.2):
            await raw.reader.readuntil(b"\n")
    assert server.connections == 1

    server.faults.stall = False
    # What was asked during the stall is answered once it ends.
    assert await raw.line() == b'GET:plcName,"myFoxtrot"\r\n'
    assert await server.scan() == 1
    assert await raw.line() == b"DIFF:plcType,1\r\n"


async def test_restart_drops_every_connection_and_accepts_again(
    manual: tuple[Simulator, PlcComsServer],
) -> None:
    _, server = manual
    first = await RawClient.open(server)
    second = await RawClient.open(server)
    await server.wait_for_open_connections(2)

    await server.restart()

    for client in (first, second):
        async with asyncio.timeout(WAIT):
            assert await client.reader.read() == b""
    assert (server.restarts, server.connections) == (1, 0)
    third = await RawClient.open(server)
    assert await third.ask("GET:plcType") == b"GET:plcType,2005\r\n"
    assert server.connections_accepted == 3
    await third.close()


async def test_refuse_closes_new_connections_before_a_byte(
    manual: tuple[Simulator, PlcComsServer],
) -> None:
    _, server = manual
    server.faults.refuse = True
    client = await RawClient.open(server)

    async with asyncio.timeout(WAIT):
        assert await client.reader.read() == b""
    await server.wait_for_connections(1)
    assert server.connections == 0


async def test_stop_is_idempotent_and_start_only_once(
    manual: tuple[Simulator, PlcComsServer],
) -> None:
    _, server = manual
    with pytest.raises(RuntimeError):
        await server.start()
    await server.stop()
    await server.stop()
    assert server.variables[0].name == "__PLC_RUN"


# --- the command line ------------------------------------------------------------------------


async def test_command_line_serves_plccoms_beside_tecoapi() -> None:
    process = await launch(
        "--program", "manual",
        "--port", "0",
        "--plccoms-port", "0",
        "--plccoms-lf",
        "--plccoms-decimal-comma",
        "--plccoms-decimals", "2",
        "--plccoms-scan-ms", "10",
        "--no-console",
    )  # fmt: skip
    assert process.stdout is not None
    try:
        async with asyncio.timeout(60):
            await process.stdout.readline()  # Serving http://...
            line = (await process.stdout.readline()).decode()
        match = re.fullmatch(r"Serving PLCComS on 127\.0\.0\.1:(\d+) .*\n", line)
        assert match is not None, line
        reader, writer = await asyncio.open_connection("127.0.0.1", int(match.group(1)))
        writer.write(b"GET:plcData.varReal\n")
        async with asyncio.timeout(WAIT):
            assert await reader.readline() == b"GET:plcData.varReal,1000,00\n"
        writer.close()
    finally:
        process.send_signal(signal.SIGINT)
        async with asyncio.timeout(60):
            await process.communicate()
    assert process.returncode == 0


def test_command_line_checks_the_plccoms_options() -> None:
    assert parse_arguments([]).plccoms_port is None
    with pytest.raises(SystemExit):
        parse_arguments(["--plccoms-decimals", "-1"])
    with pytest.raises(SystemExit):
        parse_arguments(["--plccoms-scan-ms", "0"])


# --- the manual's server, the default ------------------------------------------------------


@pytest.fixture
async def teco() -> AsyncIterator[tuple[Simulator, PlcComsServer, RawClient]]:
    """The manual's PLC on a server as Teco ships it (no option set)."""
    sim = Simulator("manual")
    async with PlcComsServer(sim, scan_interval=None) as server:
        client = await RawClient.open(server)
        await server.wait_for_open_connections(1)
        yield sim, server, client
        await client.close()


def double_bits(seconds: float) -> bytes:
    """A DATE/DT as the manual sends it: a double's 8 bytes as an unsigned integer."""
    return str(int.from_bytes(struct.pack("<d", seconds), "little")).encode()


async def test_list_flags_follow_the_type_and_variables_start_disabled(
    teco: tuple[Simulator, PlcComsServer, RawClient],
) -> None:
    _, _, raw = teco
    await raw.send("LIST:")
    lines = await raw.until(b"LIST:\r\n")
    assert lines[:3] == [
        b"LIST:__PLC_RUN,BOOL\r\n",  # the fixed variables: always enabled
        b"LIST:__PF_CRC,DWORD\r\n",
        b"LIST:plcName,STRING*\r\n",
    ]

    assert await raw.ask("EN:plcName") == (
        b"WARNING:252 Changed active variables in public file: '[1/105]'\r\n"
    )
    assert await raw.ask("HIDE:plcType") == (
        b"WARNING:253 Changed hidden variables in public file: '[1/107]'\r\n"
    )
    await raw.send("LIST:plc*")
    assert await raw.until(b"LIST:\r\n") == [
        b"LIST:plcName,STRING\r\n",
        b"LIST:plcType,UINT*~\r\n",
        *[line for line in lines if line.startswith(b"LIST:plcDesc,")],
        *[line for line in lines if line.startswith(b"LIST:plcData.")],
        b"LIST:\r\n",
    ]
    # A mask leaves the hidden ones out (changelog 4.1); a bare EN: is all.
    assert await raw.ask("EN:") == (
        b"WARNING:252 Changed active variables in public file: '[104/105]'\r\n"
    )
    assert await raw.ask("DI:*") == (
        b"WARNING:252 Changed active variables in public file: '[0/105]'\r\n"
    )
    assert await raw.ask("UNHIDE:plcType") == (
        b"WARNING:253 Changed hidden variables in public file: '[0/107]'\r\n"
    )


async def test_the_fixed_variables_are_pushed_without_en(
    teco: tuple[Simulator, PlcComsServer, RawClient],
) -> None:
    sim, server, raw = teco
    await raw.ask("EN:__PLC_RUN")  # does not apply to them
    sim.mode = "HALT"

    assert await server.scan() == 1
    assert await raw.line() == b"DIFF:__PLC_RUN,0\r\n"
    assert server.enabled() == [set()]


async def test_errors_carry_the_manual_s_codes(
    teco: tuple[Simulator, PlcComsServer, RawClient],
) -> None:
    _, _, raw = teco
    assert await raw.ask("GET:test") == (
        b"ERROR:33 Unknown variable name in request: 'GET:test'\r\n"
    )
    assert await raw.ask("EN:plcType a") == (
        b"ERROR:35 Wrong parameter value in request: 'EN:plcType a'\r\n"
    )
    assert await raw.ask("SET:plcType,-1") == (
        b"ERROR:35 Wrong parameter value in request: 'SET:plcType,-1'\r\n"
    )
    assert await raw.ask("SET:__PLC_RUN,0") == (
        b"ERROR:35 Wrong parameter value in request: 'SET:__PLC_RUN,0'\r\n"
    )
    assert await raw.ask("FLY:away") == (
        b"ERROR:32 Unknown command in request: 'FLY:away'\r\n"
    )
    assert await raw.ask("GETINFO:colour") == (
        b"ERROR:60 Unknown GETINFO name in request: 'GETINFO:colour'\r\n"
    )
    await raw.send("X" * 5000)
    assert await raw.line() == b"ERROR:30 Request too long\r\n"


async def test_getinfo_keys_are_upper_case(
    teco: tuple[Simulator, PlcComsServer, RawClient],
) -> None:
    _, server, raw = teco
    second = await RawClient.open(server)
    await server.wait_for_open_connections(2)
    await raw.send("GETINFO:")
    lines = await raw.until(b"GETINFO:\r\n")

    keys = [line.split(b",")[0] for line in lines[:-1]]
    assert keys == [
        b"GETINFO:VERSION",
        b"GETINFO:VERSION_EPSNET",
        b"GETINFO:VERSION_INI",
        b"GETINFO:VERSION_PLC",
        b"GETINFO:IPADDR",
        b"GETINFO:EPSADDR",
        b"GETINFO:EPSPORT",
        b"GETINFO:PUBFILE",
        b"GETINFO:NETWORK",
        b"GETINFO:NETWORK",
    ]
    assert lines[0] == b"GETINFO:VERSION,Ver 6.1 Jun  1 2023 13:15:36\r\n"
    assert (
        lines[7] == b"GETINFO:PUBFILE,2/2 [FIXED_Foxtrot.pub,DOC_TECOAPI v1.0.pub]\r\n"
    )
    assert re.fullmatch(
        rb"GETINFO:NETWORK,2/128 \[127\.0\.0\.1  \d{4}-\d\d-\d\d \d\d:\d\d:\d\d\]\r\n",
        lines[9],
    )
    # One key answers its line (in any case); NETWORK is a list, ended as one.
    assert await raw.ask("getinfo:version_plc") == (
        b"GETINFO:VERSION_PLC,sim CP-W32I v1.1\r\n"
    )
    await raw.send("GETINFO:NETWORK")
    assert len(await raw.until(b"GETINFO:\r\n")) == 3
    await second.close()


@pytest.mark.parametrize(
    ("options", "dt", "date"),
    [
        (
            PlcComsOptions(),
            double_bits(1526037753.456),
            double_bits(1434499200.0),
        ),
        (
            PlcComsOptions(date_time_decimal=True),
            b"1526037753.456",
            b"1434499200.0",
        ),
        (PlcComsOptions(date_seconds=True), b"1526037753", b"1434499200"),
    ],
    ids=["integer", "decimal", "old-seconds"],
)
async def test_dates_and_times_in_the_server_s_form(
    options: PlcComsOptions, dt: bytes, date: bytes
) -> None:
    sim = Simulator("manual")
    async with PlcComsServer(sim, options=options, scan_interval=None) as server:
        raw = await RawClient.open(server)
        assert (
            await raw.ask("GET:plcData.varDT") == b"GET:plcData.varDT," + dt + b"\r\n"
        )
        assert await raw.ask("GET:plcData.varDate") == (
            b"GET:plcData.varDate," + date + b"\r\n"
        )
        # TIME: a 32-bit unsigned count of milliseconds.
        assert (
            await raw.ask("GET:plcData.varTime") == b"GET:plcData.varTime,3723450\r\n"
        )
        # SET: takes the same form back.
        moment = double_bits(1700000000.25) if dt.isdigit() and len(dt) > 12 else None
        text = moment or (b"1700000000.25" if b"." in dt else b"1700000000")
        assert await raw.ask("SET:plcData.varDT," + text.decode()) == (
            b"DIFF:plcData.varDT," + text + b"\r\n"
        )
        stored = "2023-11-14T22:13:20.250Z" if b"." in text or moment else None
        assert sim.get_value("plcData.varDT") == (stored or "2023-11-14T22:13:20.000Z")
        await raw.close()


async def test_a_plain_count_of_seconds_is_a_tiny_double_to_the_manual_s_server(
    teco: tuple[Simulator, PlcComsServer, RawClient],
) -> None:
    sim, _, raw = teco
    await raw.ask("SET:plcData.varDT,1700000000")

    assert sim.get_value("plcData.varDT") == "1970-01-01T00:00:00.000Z"
    assert (await raw.ask("SET:plcData.varDT,1.5")).startswith(b"ERROR:35 ")
    assert (await raw.ask(f"SET:plcData.varDT,{2**64}")).startswith(b"ERROR:35 ")
    nan = struct.unpack("<Q", struct.pack("<d", float("nan")))[0]
    assert (await raw.ask(f"SET:plcData.varDT,{nan}")).startswith(b"ERROR:35 ")


@pytest.mark.parametrize(
    ("variable", "held", "beyond"),
    [
        ("plcData.varTime", "2147483647", "2147483648"),
        ("plcData.varDate", double_bits(0).decode(), double_bits(-86400).decode()),
        ("plcData.varDT", double_bits(0).decode(), double_bits(-0.001).decode()),
    ],
)
async def test_what_the_plc_s_variable_cannot_hold_is_refused_with_35(
    teco: tuple[Simulator, PlcComsServer, RawClient],
    variable: str,
    held: str,
    beyond: str,
) -> None:
    """The wire's 32 bits and doubles say more than the PLC's TIME, DATE and DT hold."""
    _, _, raw = teco
    assert (await raw.ask(f"SET:{variable},{held}")).startswith(b"DIFF:")
    assert (await raw.ask(f"SET:{variable},{beyond}")).startswith(b"ERROR:35 ")


async def test_a_plc_out_of_reach_answers_error_10_to_all_but_getinfo(
    teco: tuple[Simulator, PlcComsServer, RawClient],
) -> None:
    sim, server, raw = teco
    await raw.ask("EN:plcType")
    server.faults.plc_unreachable = True

    for command in ("LIST:", "GET:plcType", "EN:plcName", "SET:plcType,5", "FLY:x"):
        assert await raw.ask(command) == b"ERROR:10 Unable to connect to PLC.\r\n"
    await raw.send("GETINFO:")
    lines = await raw.until(b"GETINFO:\r\n")
    assert b"GETINFO:VERSION_PLC,\r\n" in lines
    sim.set_value("plcType", 7)
    assert await server.scan() == 0  # nothing pushed
    assert sim.get_value("plcType") == 7
    server.faults.plc_unreachable = False
    assert await server.scan() == 1
    assert await raw.line() == b"DIFF:plcType,7\r\n"


async def test_a_server_enabling_every_variable(
    manual: tuple[Simulator, PlcComsServer],
) -> None:
    sim = manual[0]
    options = PlcComsOptions(var_disabled=False)
    async with PlcComsServer(sim, options=options, scan_interval=None) as server:
        raw = await RawClient.open(server)
        await raw.send("LIST:plcType")
        assert await raw.until(b"LIST:\r\n") == [b"LIST:plcType,UINT\r\n", b"LIST:\r\n"]
        sim.set_value("plcType", 8)
        assert await server.scan() == 1
        assert await raw.line() == b"DIFF:plcType,8\r\n"
        await raw.close()


async def test_older_servers_answer_en_with_the_values() -> None:
    sim = Simulator("manual")
    options = PlcComsOptions(enable_answer="value")
    async with PlcComsServer(sim, options=options, scan_interval=None) as server:
        raw = await RawClient.open(server)
        await raw.send("EN:plcType")
        assert await raw.line() == b"GET:plcType,2005\r\n"
        await raw.send("LIST:plcName")
        assert await raw.until(b"LIST:\r\n") == [
            b"LIST:plcName,STRING*\r\n",
            b"LIST:\r\n",
        ]
        await raw.close()
