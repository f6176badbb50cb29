"""The simulated FP-I4C gateway: the seed's requests and answers, its limits, its switches.

Raw HTTP against the simulator (no client of the library's): what a real
gateway is documented to do, and what the simulator assumes where the seed
is silent (``tests/simulator/README.md``).
"""

import asyncio
from collections.abc import AsyncIterator
import json
from pathlib import Path
import re
import signal
import sys
from typing import Any

import aiohttp
import pytest

from tests.simulator.fpi4c import (
    EXAMPLE_CSV,
    NO_RESPONSE,
    FpI4cSimulator,
    StationMemory,
    demo_stations,
    tick,
)
from tests.simulator.fpi4c.__main__ import parse_arguments, serve
from tests.simulator.fpi4c.memory import DATA_ERROR, RefusalError

pytestmark = pytest.mark.usefixtures("socket_enabled")

REPOSITORY = Path(__file__).resolve().parents[2]
SEED = REPOSITORY / "tests" / "pyplc" / "panasonic" / "seed_examples.txt"


def seed_examples() -> list[str]:
    body = SEED.read_text(encoding="utf-8").split("\n\n", 1)[1]
    return [block.strip() for block in body.split("\n=====\n")]


@pytest.fixture
async def gateway() -> AsyncIterator[FpI4cSimulator]:
    async with FpI4cSimulator(demo_stations(), interface=0, station=1) as simulator:
        yield simulator


async def post(gateway: FpI4cSimulator, body: Any) -> Any:
    text = body if isinstance(body, str) else json.dumps(body)
    async with (
        aiohttp.ClientSession() as http,
        http.post(f"{gateway.url}/plcpost", data=text.encode()) as response,
    ):
        assert response.status == 200
        return json.loads(await response.text())


async def get(gateway: FpI4cSimulator, query: str) -> tuple[int, str]:
    async with (
        aiohttp.ClientSession() as http,
        http.get(f"{gateway.url}/plcget?{query}") as response,
    ):
        return response.status, await response.text()


# --- the seed ------------------------------------------------------------------


async def test_the_seed_s_requests_are_answered_as_it_shows(
    gateway: FpI4cSimulator,
) -> None:
    """The manual's requests, sent as it prints them (``"start": f``, commas)."""
    memory = gateway.stations[1]
    memory.write("DT", "INT", 10, [20])
    request, _, single, _, several, _, _, writes, _ = seed_examples()
    # Station 0 is not the demo's; the first request is sent to station 1.
    answer = await post(gateway, request.replace('"station": 0', '"station": 1'))
    assert answer["err"] is False
    dt, string, y, written = answer["data"]
    assert dt["request"] == "DT0"
    assert len(dt["int"]) == 10
    assert string["string"] == ""
    assert y["request"] == "YF"
    assert len(y["state"]) == 10
    assert written == {"request": "DT100", "err": False, "err_code": 0}
    assert memory.read("DT", "INT", 100, 10) == list(range(1, 11))
    memory.write_string("DT", 673, "This is a string")
    memory.write("DT", "UINT", 100, list(range(1, 11)))
    answer = await post(gateway, single)
    assert answer["data"][0]["int"][0] == 20
    answer = await post(gateway, several)
    text, registers, bits = answer["data"]
    assert text["string"] == "This is a string"
    assert registers["udint"][:2] == [131073, 262147]
    assert registers["hex"][-1] == "000A"
    assert registers["real"][0] == pytest.approx(5.969307950918661e-39)
    assert bits["request"] == "Y0"
    assert bits["state"][:2] == [1, 0]
    answer = await post(gateway, writes)
    assert [item["request"] for item in answer["data"]] == ["DT10", "Y0", "DT20"]
    assert memory.read("DT", "INT", 10, 2) == [22, 33]
    assert memory.read("Y", "BOOL", 0, 2) == [1, 0]
    assert memory.read("DT", "REAL", 20, 1)[0] == pytest.approx(22.88)


async def test_a_lenient_gateway_prints_json_as_the_manual_does(
    gateway: FpI4cSimulator,
) -> None:
    gateway.lenient = True
    async with (
        aiohttp.ClientSession() as http,
        http.post(
            f"{gateway.url}/plcpost",
            json={
                "req": [
                    {"area": "DT", "type": "INT", "start": 0, "count": 2},
                    {"area": "DT", "type": "ANY", "start": 0, "count": 2},
                ]
            },
        ) as response,
    ):
        text = await response.text()
    with pytest.raises(ValueError):
        json.loads(text)
    assert re.search(r"652,\s+452,\s+\]", text)
    assert '"err_code": 0,\n' in text
    assert re.search(r'"hex": \[028C, 01C4,\]', text)
    assert text.rstrip().endswith("]\n}"), "the root's last member has no comma"


# --- the limits --------------------------------------------------------------------


async def test_twenty_requests_a_post(gateway: FpI4cSimulator) -> None:
    read = {"area": "DT", "type": "INT", "start": 0, "count": 1}
    assert len((await post(gateway, {"req": [read] * 20}))["data"]) == 20
    answer = await post(gateway, {"req": [read] * 21})
    assert answer == {
        "err": True,
        "err_msg": "Too many requests: at most 20",
        "data": [],
    }


async def test_a_gateway_with_a_lower_request_limit(gateway: FpI4cSimulator) -> None:
    """``max_requests``: a POST of more is refused as a whole; back at 20, taken."""
    read = {"area": "DT", "type": "INT", "start": 0, "count": 1}
    gateway.max_requests = 1
    answer = await post(gateway, {"req": [read] * 2})
    assert answer == {
        "err": True,
        "err_msg": "Too many requests: at most 1",
        "data": [],
    }
    assert len((await post(gateway, {"req": [read]}))["data"]) == 1
    gateway.max_requests = 20
    assert len((await post(gateway, {"req": [read] * 2}))["data"]) == 2


@pytest.mark.parametrize(
    ("request_", "message"),
    [
        ({"area": "DT", "type": "INT", "start": 0, "count": 101}, "At most 100"),
        ({"area": "DT", "type": "DINT", "start": 0, "count": 51}, "(102)"),
        ({"area": "R", "type": "BOOL", "start": "0", "count": 101}, "At most 100"),
        ({"area": "DT", "type": "INT", "start": 0, "count": 0}, "Invalid count"),
        ({"area": "DT", "type": "INT", "start": "0"}, "start is a number"),
        ({"area": "DT", "type": "BOOL", "start": 0}, "not BOOL"),
        ({"area": "Y", "type": "INT", "start": "0"}, "BOOL only"),
        ({"area": "Y", "type": "BOOL", "start": "G"}, "Invalid flag address"),
        ({"area": "Q", "type": "INT", "start": 0}, "Invalid area"),
        ({"area": "DT", "type": "LREAL", "start": 0}, "Invalid type"),
        ({"area": "DT", "type": "STRING", "start": 0, "value": "x" * 1001}, "1000"),
        ({"area": "DT", "type": "STRING", "start": 0, "value": 5}, "1000"),
        ({"area": "DT", "type": "ANY", "start": 0, "value": 5}, "read-only"),
        ({"area": "DT", "type": "INT", "start": 0, "count": 2, "value": 5}, "count 2"),
        ({"area": "DT", "type": "INT", "start": 0, "value": 40000}, "outside INT"),
        ({"area": "DT", "type": "INT", "start": 0, "value": "x"}, "not an integer"),
        ({"area": "DT", "type": "REAL", "start": 0, "value": 1e39}, "outside a REAL"),
        ({"area": "DT", "type": "REAL", "start": 0, "value": "x"}, "not a REAL"),
        ({"area": "Y", "type": "BOOL", "start": "0", "value": 2}, "not a bit"),
        ({"area": "DT", "type": "INT", "start": 32765}, "past DT32764"),
        ({"area": "DT", "type": "STRING", "start": 0, "value": "€"}, "cannot hold"),
        ("not an object", "not an object"),
    ],
)
async def test_a_request_the_gateway_refuses_fails_its_item_only(
    gateway: FpI4cSimulator, request_: Any, message: str
) -> None:
    """Each refusal's reason (a write's with ``write_messages``: the seed's has none)."""
    gateway.write_messages = True
    good = {"area": "DT", "type": "INT", "start": 0, "count": 1}
    answer = await post(gateway, {"req": [request_, good], "station": 1})
    failed, answered = answer["data"]
    assert failed["err"] is True
    assert message in failed["err_msg"]
    assert answered["int"] == 652


@pytest.mark.parametrize(
    ("body", "message"),
    [
        ({"req": [], "interface": 2}, "Interface 2 is not enabled"),
        ({"req": [], "station": 100}, "Invalid station 100"),
        ({"req": [], "station": True}, "Invalid station True"),
        ({"request": []}, "no request list"),
        ("{{{", "not JSON"),
    ],
)
async def test_a_post_the_gateway_refuses_as_a_whole(
    gateway: FpI4cSimulator, body: Any, message: str
) -> None:
    answer = await post(gateway, body)
    assert answer["err"] is True
    assert message in answer["err_msg"]
    assert answer["data"] == []


# --- the switches ------------------------------------------------------------------


async def test_a_silent_station_and_one_that_is_not_there(
    gateway: FpI4cSimulator,
) -> None:
    read = {"area": "DT", "type": "INT", "start": 0}
    gateway.silent.add(2)
    for station in (2, 7):
        (item,) = (await post(gateway, {"req": [read], "station": station}))["data"]
        assert (item["err_code"], item["err_msg"]) == NO_RESPONSE
    (item,) = (await post(gateway, {"req": [read]}))["data"]
    assert item["int"] == 652


async def test_item_errors_fail_the_items_covering_their_address(
    gateway: FpI4cSimulator,
) -> None:
    gateway.item_errors[1, "DT5"] = (61, "Data error")
    gateway.write_errors[1, "Y1"] = (65, "Protect error")
    answer = await post(
        gateway,
        {
            "req": [
                {"area": "DT", "type": "INT", "start": 0, "count": 5},
                {"area": "DT", "type": "INT", "start": 0, "count": 6},
                {"area": "DT", "type": "DINT", "start": 4, "count": 1},
                {"area": "Y", "type": "BOOL", "start": "1", "count": 1},
                {"area": "Y", "type": "BOOL", "start": "1", "value": True},
            ]
        },
    )
    errors = [item["err"] for item in answer["data"]]
    assert errors == [False, True, True, False, True]
    assert answer["data"][1]["err_code"] == 61
    # A write's item is the seed's: request, err and err_code, no message.
    assert answer["data"][4] == {"request": "Y1", "err": True, "err_code": 65}
    gateway.write_messages = True
    answer = await post(
        gateway, {"req": [{"area": "Y", "type": "BOOL", "start": "1", "value": 1}]}
    )
    assert answer["data"][0]["err_msg"] == "Protect error"


async def test_broken_and_dropped_answers(gateway: FpI4cSimulator) -> None:
    read = {"area": "DT", "type": "INT", "start": 0}
    gateway.broken = True
    async with (
        aiohttp.ClientSession() as http,
        http.post(f"{gateway.url}/plcpost", json={"req": [read]}) as response,
    ):
        with pytest.raises(ValueError):
            json.loads(await response.text())
    gateway.broken = False
    gateway.dropped.add(2)
    async with aiohttp.ClientSession() as http:
        with pytest.raises(aiohttp.ClientError):
            async with http.post(
                f"{gateway.url}/plcpost", json={"req": [read], "station": 2}
            ) as response:
                await response.read()
    assert (await post(gateway, {"req": [read], "station": 1}))["err"] is False


async def test_the_get_form(gateway: FpI4cSimulator) -> None:
    status, text = await get(gateway, "DT0")
    assert status == 200
    assert json.loads(text)["data"][0]["int"] == 652
    status, text = await get(gateway, "DDT200&I=0&A=1")
    assert json.loads(text)["data"][0]["dint"] == 12_345
    assert (await get(gateway, "R10"))[0] == 200
    assert json.loads((await get(gateway, "R10"))[1])["data"][0]["state"] == 1
    status, _ = await get(gateway, "DT7=122")
    assert gateway.get(1, "DT7", "INT") == 122
    status, text = await get(gateway, "DT0&I=3&A=1")
    assert json.loads(text)["err_msg"] == "Interface 3 is not enabled"
    for query in ("", "DT0&I=0", "Q0", "DTx", "DT0=x"):
        assert (await get(gateway, query))[0] == 400
    gateway.get_form = False
    assert (await get(gateway, "DT0"))[0] == 404


async def test_an_answer_is_held_until_released(gateway: FpI4cSimulator) -> None:
    read = {"area": "DT", "type": "INT", "start": 0}
    async with gateway.hold() as hold:
        answer = asyncio.create_task(post(gateway, {"req": [read]}))
        await hold.reached()
        assert not answer.done()
        gateway.set(1, "DT0", "INT", 1)
        hold.release()
        # Read before it was held: what the PLC held then.
        assert (await answer)["data"][0]["int"] == 652


# --- memory ------------------------------------------------------------------------


def test_memory_types_words_and_bits() -> None:
    memory = StationMemory()
    memory.write("DT", "DINT", 0, [-2])
    assert memory.read("DT", "UINT", 0, 2) == [0xFFFE, 0xFFFF]
    memory.write("DT", "UDINT", 2, [131073])
    assert memory.read("DT", "UINT", 2, 2) == [1, 2]
    memory.write("DT", "REAL", 4, [22.88])
    assert memory.read("DT", "REAL", 4, 1)[0] == pytest.approx(22.88)
    memory.write("WR", "UINT", 1, [0])
    memory.write("R", "BOOL", 26, [True])  # R1A
    assert memory.read("WR", "UINT", 1, 1) == [1 << 10]
    memory.write("R", "BOOL", 26, [0])
    assert memory.bit("R", 26) == 0
    memory.write_string("DT", 10, "abc")
    assert memory.read("DT", "UINT", 10, 4) == [
        3,
        3,
        ord("a") | ord("b") << 8,
        ord("c"),
    ]
    memory.write_string("DT", 10, "ab")
    assert memory.read_string("DT", 10) == "ab"
    assert memory.word("DT", 10) == 3, "the capacity stays"
    with pytest.raises(RefusalError) as raised:
        memory.read("WX", "INT", 127, 2)
    assert raised.value.code == DATA_ERROR
    with pytest.raises(RefusalError):
        memory.write("X", "BOOL", 128 * 16, [True])


def test_the_demo_holds_what_its_map_reads_and_its_door_moves() -> None:
    assert EXAMPLE_CSV.read_text(encoding="utf-8").count("\n") == 29
    stations = demo_stations()
    garage = stations[2]
    garage.write("DT", "INT", 11, [25])
    tick(stations)
    assert garage.read("DT", "INT", 10, 1) == [10]
    assert garage.bit("R", 0) == 1
    assert garage.bit("X", 0) == 0
    tick(stations)
    tick(stations)
    assert garage.read("DT", "INT", 10, 1) == [25]
    assert garage.bit("R", 0) == 0
    tick({})


async def test_serve_runs_the_demo_until_stopped() -> None:
    arguments = parse_arguments(["--port", "0", "--lenient", "--silent", "2"])
    assert (arguments.lenient, arguments.silent) == (True, [2])
    stop = asyncio.Event()
    stop.set()
    await serve(arguments, stop)
    assert parse_arguments([]).port == 2000


async def test_the_demo_runs_as_a_process_and_stops_on_sigterm() -> None:
    process = await asyncio.create_subprocess_exec(
        sys.executable,
        "-m",
        "tests.simulator.fpi4c",
        "--port",
        "0",
        cwd=REPOSITORY,
        stdout=asyncio.subprocess.PIPE,
    )
    assert process.stdout is not None
    line = await asyncio.wait_for(process.stdout.readline(), 60)
    found = re.match(rb"FP-I4C REST API on (http://127\.0\.0\.1:\d+)/plcpost", line)
    assert found is not None, line
    async with (
        aiohttp.ClientSession() as http,
        http.post(
            f"{found[1].decode()}/plcpost",
            json={"req": [{"area": "DT", "type": "INT", "start": 0}], "station": 1},
        ) as response,
    ):
        assert (await response.json())["data"][0]["int"] == 652
    process.send_signal(signal.SIGTERM)
    assert await asyncio.wait_for(process.wait(), 60) == 0
