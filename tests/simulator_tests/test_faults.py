"""Faults: the Faults object itself, and what each fault does to a client over HTTP."""

import asyncio
import json

import aiohttp
import pytest

from tests.conftest import SIM_PASSWORD, SIM_USERNAME
from tests.simulator import Faults, Simulator
from tests.simulator_tests.conftest import fetch

# --- the Faults object --------------------------------------------------------------------


def test_defaults_are_a_healthy_plc() -> None:
    faults = Faults()

    assert faults.take_transport_fault() is None
    assert (faults.mode, faults.latency, faults.remaining) == ("RUN", 0.0, None)


def test_one_transport_fault_per_request_in_order_of_precedence() -> None:
    faults = Faults(malformed_json=True, http_500=True, drop_connection=True)

    assert faults.take_transport_fault() == "drop_connection"
    faults.drop_connection = False
    assert faults.take_transport_fault() == "http_500"
    faults.http_500 = False
    assert faults.take_transport_fault() == "malformed_json"


def test_remaining_counts_down_then_clears_the_transport_faults() -> None:
    faults = Faults(truncated_json=True, remaining=2, latency=0.5, mode="HALT")

    taken = [faults.take_transport_fault() for _ in range(3)]

    assert taken == ["truncated_json", "truncated_json", None]
    assert (faults.truncated_json, faults.remaining) == (False, None)
    assert (faults.latency, faults.mode) == (0.5, "HALT")


def test_remaining_zero_means_no_fault() -> None:
    faults = Faults(hang=True, remaining=0)

    assert faults.take_transport_fault() is None
    assert faults.hang is False


def test_clear_restores_everything() -> None:
    faults = Faults(
        latency=1.0,
        latency_per_item=0.1,
        hang=True,
        http_500=True,
        mode="ERR",
        hidden_from_list={"a"},
        rejected_by_object={"b"},
        remaining=3,
    )

    faults.clear()

    assert faults == Faults()


def test_mode_must_be_a_plc_mode() -> None:
    with pytest.raises(ValueError, match="RUN, HALT, ERR"):
        Faults(mode="STOP")


def test_names_compare_case_insensitively() -> None:
    faults = Faults(hidden_from_list={"MyObject"}, rejected_by_object={"ARR1"})

    assert faults.hides("myobject")
    assert faults.rejects("arr1")
    assert not faults.hides("arr1")


def test_listeners_hear_every_change_until_removed() -> None:
    faults = Faults()
    heard: list[str] = []
    faults.add_listener(heard.append)

    faults.latency = 0.1
    faults.clear()
    faults.remove_listener(heard.append)
    faults.remove_listener(heard.append)
    faults.hang = True

    assert heard[0] == "latency"
    assert "hang" in heard
    assert heard.count("hang") == 1


# --- over HTTP -------------------------------------------------------------------------------


@pytest.fixture
async def plc(socket_enabled: None) -> Simulator:
    sim = Simulator("manual", username=SIM_USERNAME, password=SIM_PASSWORD, auth="both")
    await sim.start()
    yield sim  # type: ignore[misc]
    await sim.stop()


async def test_drop_connection_closes_without_an_answer_and_writes_nothing(
    session: aiohttp.ClientSession, plc: Simulator
) -> None:
    plc.faults.drop_connection = True

    with pytest.raises(aiohttp.ServerDisconnectedError):
        await fetch(session, plc, "/TecoApi/SetObject?plcType=1")

    record = plc.requests[-1]
    assert (record.status, record.authorized) == (0, True)
    assert plc.get_value("plcType") == 2005


async def test_http_500_answers_an_error_and_writes_nothing(
    session: aiohttp.ClientSession, plc: Simulator
) -> None:
    plc.faults.http_500 = True

    reply = await fetch(session, plc, "/TecoApi/SetObject?plcType=1")

    assert (reply.status, reply.error_code) == (500, "500.012")
    assert plc.get_value("plcType") == 2005


async def test_truncated_json_is_the_first_half_of_the_body(
    session: aiohttp.ClientSession, plc: Simulator
) -> None:
    whole = await fetch(session, plc, "/TecoApi/GetObject?myObject")
    plc.faults.truncated_json = True

    reply = await fetch(session, plc, "/TecoApi/GetObject?myObject")

    assert reply.status == 200
    assert reply.body == whole.body[: len(whole.body) // 2]
    assert int(reply.headers["Content-Length"]) == len(reply.body)
    with pytest.raises(json.JSONDecodeError):
        json.loads(reply.body)


async def test_malformed_json_is_not_json(
    session: aiohttp.ClientSession, plc: Simulator
) -> None:
    plc.faults.malformed_json = True

    reply = await fetch(session, plc, "/TecoApi/GetInfo")

    assert reply.status == 200
    assert reply.headers["Content-Type"] == "application/json"
    with pytest.raises(json.JSONDecodeError):
        json.loads(reply.body)


async def test_body_faults_leave_writes_and_empty_answers_alone(
    session: aiohttp.ClientSession, plc: Simulator
) -> None:
    plc.faults.malformed_json = True

    reply = await fetch(session, plc, "/TecoApi/SetObject?plcType=9")

    assert (reply.status, reply.body) == (200, b"")
    assert plc.get_value("plcType") == 9


async def test_remaining_limits_a_fault_to_the_next_requests(
    session: aiohttp.ClientSession, plc: Simulator
) -> None:
    plc.faults = Faults(http_500=True, remaining=2)

    statuses = [
        (await fetch(session, plc, "/TecoApi/GetInfo")).status for _ in range(3)
    ]

    assert statuses == [500, 500, 200]
    assert plc.faults.http_500 is False


async def test_transport_faults_spare_unauthenticated_requests(
    session: aiohttp.ClientSession, plc: Simulator
) -> None:
    plc.faults = Faults(http_500=True, remaining=1)

    challenge = await fetch(session, plc, "/TecoApi/GetInfo", basic=False)
    failed = await fetch(session, plc, "/TecoApi/GetInfo")
    healthy = await fetch(session, plc, "/TecoApi/GetInfo")

    assert [challenge.status, failed.status, healthy.status] == [401, 500, 200]


async def test_hang_answers_once_switched_off(
    session: aiohttp.ClientSession, plc: Simulator
) -> None:
    plc.faults.hang = True
    request = asyncio.create_task(fetch(session, plc, "/TecoApi/SetObject?plcType=3"))
    await plc.wait_for_hung_requests(1)
    assert not request.done()
    assert plc.requests[0].status == 0

    plc.faults.hang = False
    reply = await request

    assert reply.status == 200
    assert plc.get_value("plcType") == 3
    assert plc.requests[0].status == 200


async def test_hang_for_one_request_lets_the_next_through(
    session: aiohttp.ClientSession, plc: Simulator
) -> None:
    plc.faults = Faults(hang=True, remaining=1)
    hung = asyncio.create_task(fetch(session, plc, "/TecoApi/GetInfo"))
    await plc.wait_for_hung_requests(1)

    second = await fetch(session, plc, "/TecoApi/GetObject?plcName")

    assert second.status == 200
    assert not hung.done()
    assert plc.hung_requests == 1
    plc.faults.clear()
    assert (await hung).status == 200


async def test_hang_until_stop_drops_the_connection(
    session: aiohttp.ClientSession, plc: Simulator
) -> None:
    plc.faults.hang = True
    hung = asyncio.create_task(fetch(session, plc, "/TecoApi/GetInfo"))
    await plc.wait_for_hung_requests(1)

    await plc.stop()

    with pytest.raises(aiohttp.ClientConnectionError):
        await hung
    assert plc.requests[0].status == 0


async def test_replacing_the_faults_releases_hung_requests(
    session: aiohttp.ClientSession, plc: Simulator
) -> None:
    plc.faults = Faults(hang=True)
    hung = asyncio.create_task(fetch(session, plc, "/TecoApi/GetInfo"))
    await plc.wait_for_hung_requests(1)

    plc.faults = Faults(mode="HALT")

    reply = await hung
    assert reply.json()["plc"]["mode"] == "HALT"


@pytest.mark.parametrize(
    ("field", "target"),
    [
        ("latency", "/TecoApi/GetInfo"),
        ("latency_per_item", "/TecoApi/GetObject?plcData"),
    ],
)
async def test_slow_answers_are_cut_off_by_stop(
    session: aiohttp.ClientSession, plc: Simulator, field: str, target: str
) -> None:
    setattr(plc.faults, field, 3600.0)
    slow = asyncio.create_task(fetch(session, plc, target))
    await plc.wait_for_requests(1)

    await plc.stop()

    with pytest.raises(aiohttp.ClientConnectionError):
        await slow
    assert plc.requests[0].status == 0


async def test_small_latency_still_answers(
    session: aiohttp.ClientSession, plc: Simulator
) -> None:
    plc.faults.latency = 0.001
    plc.faults.latency_per_item = 0.0001

    reply = await fetch(session, plc, "/TecoApi/GetObject?myObject")

    assert reply.status == 200
    assert plc.requests[-1].items == 13


async def test_halted_plc_still_serves_and_stores(
    session: aiohttp.ClientSession, plc: Simulator
) -> None:
    plc.mode = "HALT"

    info = await fetch(session, plc, "/TecoApi/GetInfo")
    write = await fetch(session, plc, "/TecoApi/SetObject?plcType=4")
    read = await fetch(session, plc, "/TecoApi/GetObject?plcType")

    assert info.json()["plc"]["mode"] == "HALT"
    assert plc.faults.mode == "HALT"
    assert (write.status, read.json()) == (200, {"plcType": 4})


async def test_a_root_hidden_from_the_list_is_still_served(
    session: aiohttp.ClientSession, plc: Simulator
) -> None:
    plc.faults.hidden_from_list.add("MYOBJECT")

    listing = await fetch(session, plc, "/TecoApi/GetList")
    read = await fetch(session, plc, "/TecoApi/GetObject?myObject.age")

    assert "myObject" not in listing.json()
    assert "arr1" in listing.json()
    assert read.json() == {"myObject": {"age": 39}}


async def test_a_root_listed_but_rejected(
    session: aiohttp.ClientSession, plc: Simulator
) -> None:
    plc.faults.rejected_by_object.add("main")

    listing = await fetch(session, plc, "/TecoApi/GetList?listType=array")
    read = await fetch(session, plc, "/TecoApi/GetObject?Main.myObject1.value")
    set_write = await fetch(session, plc, "/TecoApi/SetObject?Main.myObject3.value=20")
    put_write = await fetch(
        session,
        plc,
        "/TecoApi/PutObject",
        method="PUT",
        data=b'{"Main": {"myObject3": {"value": 20}}}',
    )

    assert {"Main": {}} in listing.json()
    assert read.error_message == "Variable 'Main.myObject1.value' is not found"
    assert set_write.error_code == put_write.error_code == "400.005"
    assert plc.get_value("Main.myObject3.value") == 23.0


async def test_aiohttp_retries_one_dropped_get_by_itself(
    session: aiohttp.ClientSession, plc: Simulator
) -> None:
    plc.faults = Faults(drop_connection=True, remaining=1)
    absorbed = await fetch(session, plc, "/TecoApi/GetInfo")

    plc.faults = Faults(drop_connection=True, remaining=2)
    with pytest.raises(aiohttp.ServerDisconnectedError):
        await fetch(session, plc, "/TecoApi/GetInfo")

    assert absorbed.status == 200
    assert [r.status for r in plc.requests] == [0, 200, 0, 0]
