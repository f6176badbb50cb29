"""The simulated opcconnector speaks the API as the seed writes it, with its switches.

Raw HTTP against it on 127.0.0.1 (no client of the library): what each call
answers, the seed's error table, and each switch real gateways may have.
"""

import asyncio
from collections.abc import AsyncIterator
from datetime import datetime, timedelta
import json
from pathlib import Path
import re
import signal
import sys
from typing import Any

import aiohttp
import pytest

from tests.simulator.tekon import (
    TekonGateway,
    channel,
    large_building,
    lift_state,
    small_building,
)
from tests.simulator.tekon.building import CONTROLLER, LIFT, NUMBER, READ_WRITE, VT_R4

REPOSITORY = Path(__file__).resolve().parents[2]
SETPOINT = f"{CONTROLLER}.Уставка"
DOOR = f"{CONTROLLER}.Дверь подъезда"


@pytest.fixture
async def gateway(socket_enabled: None) -> AsyncIterator[TekonGateway]:
    async with TekonGateway() as running:
        yield running


@pytest.fixture
async def http() -> AsyncIterator[aiohttp.ClientSession]:
    async with aiohttp.ClientSession() as session:
        yield session


async def call(
    http: aiohttp.ClientSession,
    gateway: TekonGateway,
    name: str,
    body: Any = None,
    **query: Any,
) -> tuple[int, Any]:
    """One call; its status and its JSON (None for an error's text)."""
    url = f"{gateway.url}/{name}"
    method = "GET" if body is None else "POST"
    data = None if body is None else json.dumps(body, ensure_ascii=False)
    async with http.request(method, url, params=query, data=data) as response:
        text = await response.text()
        return response.status, json.loads(text) if response.status == 200 else None


async def session(
    http: aiohttp.ClientSession, gateway: TekonGateway, **query: Any
) -> str:
    status, answer = await call(http, gateway, "NewSession", **{"alldata": 0, **query})
    assert status == 200
    sessionid: str = answer["sessionid"]
    return sessionid


async def test_server_information_and_zabbix_need_no_session(
    gateway: TekonGateway, http: aiohttp.ClientSession
) -> None:
    status, info = await call(http, gateway, "ServerInformation")
    assert status == 200
    assert info["version"] == "2.2"
    assert set(info) == {"opconn_version", "version", "currenttime", "starttime"}
    status, statuses = await call(http, gateway, "Zabbix")
    assert status == 200
    assert {entry["ItemName"] for entry in statuses} == {
        f"{CONTROLLER}.Status",
        f"{LIFT}.Status",
        "Дом 1.Счётчики.Электросчётчик.Status",
        "Дом 1.Счётчики.Водосчётчик.Status",
    }
    assert all(entry["Qual"] == 192 and entry["V"] == "10" for entry in statuses)


async def test_a_session_subscribes_by_name_and_gets_changes_once(
    gateway: TekonGateway, http: aiohttp.ClientSession
) -> None:
    sid = await session(http, gateway)
    status, answer = await call(
        http, gateway, "SubscriberText", {"itemstext": [SETPOINT, DOOR]}, sessionid=sid
    )
    assert (status, answer) == (200, {"result": 2})
    # Subscribed again: ignored.
    _, answer = await call(
        http, gateway, "SubscriberText", {"itemstext": [SETPOINT]}, sessionid=sid
    )
    assert answer == {"result": 0}
    # Only what changed since the previous request: nothing yet.
    _, nothing = await call(http, gateway, "GetUpdatesText", sessionid=sid, rid=1)
    assert nothing == []
    # Asked for, every subscribed item's value comes with the next updates.
    _, asked = await call(http, gateway, "ReadAllItemsValues", sessionid=sid)
    assert asked == {"result": 2}
    _, first = await call(http, gateway, "GetUpdatesText", sessionid=sid, rid=2)
    assert {entry["ItemName"]: entry["V"] for entry in first} == {
        SETPOINT: "20",
        DOOR: "0",
    }
    _, quiet = await call(http, gateway, "GetUpdatesText", sessionid=sid, rid=3)
    assert quiet == []
    gateway.set_value(DOOR, "1")
    _, changed = await call(http, gateway, "GetUpdatesText", sessionid=sid, rid=4)
    assert [(entry["ItemName"], entry["V"], entry["Qual"]) for entry in changed] == [
        (DOOR, "1", 192)
    ]
    # The same rid again: the same answer (a lost answer is not lost).
    _, again = await call(http, gateway, "GetUpdatesText", sessionid=sid, rid=4)
    assert again == changed
    _, count = await call(http, gateway, "GetSubscribersCount", sessionid=sid)
    assert count == {"result": 2}
    _, names = await call(http, gateway, "GetSubscribersTextList", sessionid=sid)
    assert sorted(names["itemstext"]) == sorted([SETPOINT, DOOR])
    _, removed = await call(
        http, gateway, "UnSubscriberText", {"itemstext": [DOOR]}, sessionid=sid
    )
    assert removed == {"result": 1}
    assert await call(http, gateway, "CloseSession", sessionid=sid) == (
        200,
        {"result": "ok"},
    )
    assert (await call(http, gateway, "GetUpdatesText", sessionid=sid, rid=5))[0] == 409


async def test_read_all_items_values_and_the_initial_update_switch(
    gateway: TekonGateway, http: aiohttp.ClientSession
) -> None:
    """The seed: values only once asked for or changed; OPC DA's initial update a switch."""
    sid = await session(http, gateway)
    # Nothing subscribed: 0, the seed's "error, no items in the subscription".
    assert await call(http, gateway, "ReadAllItemsValues", sessionid=sid) == (
        200,
        {"result": 0},
    )
    gateway.initial_data = True
    await call(http, gateway, "SubscriberText", {"itemstext": [DOOR]}, sessionid=sid)
    _, first = await call(http, gateway, "GetUpdatesText", sessionid=sid, rid=1)
    assert [(entry["ItemName"], entry["V"]) for entry in first] == [(DOOR, "0")]
    # An item subscribed and gone from the address space is not read.
    gateway.building.remove([DOOR])
    assert await call(http, gateway, "ReadAllItemsValues", sessionid=sid) == (
        200,
        {"result": 0},
    )
    # A call failing for a while (any status).
    gateway.failing["ReadAllItemsValues"] = 500
    assert (await call(http, gateway, "ReadAllItemsValues", sessionid=sid))[0] == 500
    gateway.failing.clear()
    # A gateway without the call (older than the seed's API 2.2, assumed).
    gateway.read_all = False
    assert (await call(http, gateway, "ReadAllItemsValues", sessionid=sid))[0] == 404
    assert (await call(http, gateway, "ReadAllItemsValues"))[0] == 404


async def test_lost_answers_are_carried_out_and_asked_again(
    gateway: TekonGateway, http: aiohttp.ClientSession
) -> None:
    """``lost_answers``: the call is carried out, its answer never arrives.

    The updates it took are answered again to the same ``rid``.
    """
    sid = await session(http, gateway)
    await call(http, gateway, "SubscriberText", {"itemstext": [DOOR]}, sessionid=sid)
    await call(http, gateway, "GetUpdatesText", sessionid=sid, rid=1)
    gateway.set_value(DOOR, "1")
    # Two: aiohttp sends a GET again by itself once when the connection drops.
    gateway.lost_answers = 2
    with pytest.raises(aiohttp.ServerDisconnectedError):
        await call(http, gateway, "GetUpdatesText", sessionid=sid, rid=2)
    assert gateway.lost_answers == 0
    _, again = await call(http, gateway, "GetUpdatesText", sessionid=sid, rid=2)
    assert [(entry["ItemName"], entry["V"]) for entry in again] == [(DOOR, "1")]


async def test_by_id_and_all_data(
    gateway: TekonGateway, http: aiohttp.ClientSession
) -> None:
    sid = await session(http, gateway, alldata=1)
    item_id = gateway.building.by_name[DOOR].item_id
    _, answer = await call(
        http, gateway, "Subscriber", {"items": [item_id]}, sessionid=sid
    )
    assert answer == {"result": 1}
    await call(http, gateway, "GetUpdates", sessionid=sid, rid=1)
    gateway.set_value(DOOR, "1")
    gateway.set_value(DOOR, "0")
    _, changes = await call(http, gateway, "GetUpdates", sessionid=sid, rid=2)
    assert [(entry["ItemID"], entry["V"]) for entry in changes] == [
        (item_id, "1"),
        (item_id, "0"),
    ]
    _, everything = await call(http, gateway, "SubscriberAll", {}, sessionid=sid)
    assert everything == {"result": len(gateway.building.items) - 1}


async def test_all_data_answers_every_change_in_order_with_its_up_time(
    gateway: TekonGateway, http: aiohttp.ClientSession
) -> None:
    """alldata=1 (seed §6): every change between two updates, each with its UpTime."""
    every = await session(http, gateway, alldata=1)
    last = await session(http, gateway, alldata=0)
    for sid in (every, last):
        await call(
            http,
            gateway,
            "SubscriberText",
            {"itemstext": [DOOR, SETPOINT]},
            sessionid=sid,
        )
        await call(http, gateway, "GetUpdatesText", sessionid=sid, rid=1)
    start = datetime(2025, 3, 18, 12, 0, 0)  # noqa: DTZ001 (the gateway's local time)
    gateway.set_value(DOOR, "1", at=start)
    gateway.set_value(SETPOINT, "21", at=start + timedelta(seconds=1))
    gateway.set_value(DOOR, "0", at=start + timedelta(seconds=1))

    def shown(answer: list[dict[str, Any]]) -> list[tuple[str, str, str]]:
        return [(entry["ItemName"], entry["V"], entry["UpTime"]) for entry in answer]

    _, changes = await call(http, gateway, "GetUpdatesText", sessionid=every, rid=2)
    assert shown(changes) == [
        (DOOR, "1", "2025-03-18 12:00:00"),
        (SETPOINT, "21", "2025-03-18 12:00:01"),
        (DOOR, "0", "2025-03-18 12:00:01"),
    ]
    _, latest = await call(http, gateway, "GetUpdatesText", sessionid=last, rid=2)
    assert shown(latest) == [
        (DOOR, "0", "2025-03-18 12:00:01"),
        (SETPOINT, "21", "2025-03-18 12:00:01"),
    ]
    # A gateway that groups an answer's changes by item (assumed: a switch).
    gateway.updates_order = "items"
    gateway.set_value(DOOR, "1", at=start + timedelta(seconds=2))
    gateway.set_value(SETPOINT, "22", at=start + timedelta(seconds=3))
    gateway.set_value(DOOR, "0", at=start + timedelta(seconds=4))
    _, grouped = await call(http, gateway, "GetUpdatesText", sessionid=every, rid=3)
    assert [(name, value) for name, value, _ in shown(grouped)] == [
        (DOOR, "1"),
        (DOOR, "0"),
        (SETPOINT, "22"),
    ]
    # A thousand changes between two updates: every one answered.
    for value in range(1000):
        gateway.set_value(SETPOINT, str(value))
    _, chattering = await call(http, gateway, "GetUpdatesText", sessionid=every, rid=4)
    assert [entry["V"] for entry in chattering] == [str(v) for v in range(1000)]


async def test_api_versions_before_2_2(
    gateway: TekonGateway, http: aiohttp.ClientSession
) -> None:
    """2.1 added subscribing by name, 2.2 reading and writing by name (seed: history)."""
    door_id = gateway.building.by_name[DOOR].item_id
    setpoint_id = gateway.building.by_name[SETPOINT].item_id
    gateway.api_version = "2.1"
    assert (await call(http, gateway, "ServerInformation"))[1]["version"] == "2.1"
    sid = await session(http, gateway)
    _, added = await call(
        http, gateway, "SubscriberText", {"itemstext": [DOOR]}, sessionid=sid
    )
    assert added == {"result": 1}
    assert (await call(http, gateway, "GetUpdatesText", sessionid=sid, rid=1))[0] == 200
    assert (
        await call(http, gateway, "ReadItemValueSyncText", sessionid=sid, itemname=DOOR)
    )[0] == 404
    # The plain read takes an ID only; a name beside it is not read.
    _, by_name = await call(
        http, gateway, "ReadItemValueSync", sessionid=sid, itemname=DOOR
    )
    assert by_name == []
    _, both = await call(
        http, gateway, "ReadItemValueSync", sessionid=sid, itemname=DOOR, item=door_id
    )
    assert both[0]["ItemID"] == door_id
    write = [{"ItemName": SETPOINT, "Value": "22"}]
    assert (await call(http, gateway, "WriteItemsValuesText", write, sessionid=sid))[
        0
    ] == 404
    _, ignored = await call(http, gateway, "WriteItemsValues", write, sessionid=sid)
    assert ignored == {"result": 0}
    _, written = await call(
        http,
        gateway,
        "WriteItemsValues",
        [{"ItemID": setpoint_id, "ItemName": SETPOINT, "Value": "22"}],
        sessionid=sid,
    )
    assert written == {"result": 1}
    assert gateway.value(SETPOINT) == "22"
    gateway.api_version = "2.0"
    for text_call in ("SubscriberText", "UnSubscriberText"):
        assert (
            await call(http, gateway, text_call, {"itemstext": [DOOR]}, sessionid=sid)
        )[0] == 404
    assert (await call(http, gateway, "GetUpdatesText", sessionid=sid, rid=2))[0] == 404
    assert (await call(http, gateway, "GetSubscribersTextList", sessionid=sid))[
        0
    ] == 404
    temperature = f"{CONTROLLER}.Температура"
    _, not_by_name = await call(
        http, gateway, "Subscriber", {"itemstext": [temperature]}, sessionid=sid
    )
    assert not_by_name == {"result": 0}
    temperature_id = gateway.building.by_name[temperature].item_id
    _, by_id = await call(
        http, gateway, "Subscriber", {"items": [temperature_id]}, sessionid=sid
    )
    assert by_id == {"result": 1}
    # A gateway may tell another version than the one it speaks.
    gateway.reported_version = "2.2"
    assert (await call(http, gateway, "ServerInformation"))[1]["version"] == "2.2"


async def test_the_seed_error_table(
    gateway: TekonGateway, http: aiohttp.ClientSession
) -> None:
    sid = await session(http, gateway)
    assert (await call(http, gateway, "GetAddressSpaceHash"))[0] == 400
    assert (await call(http, gateway, "GetAddressSpaceHash", sessionid="nope"))[
        0
    ] == 409
    assert (await call(http, gateway, "NoSuchCall", sessionid=sid))[0] == 404
    async with http.post(
        f"{gateway.url}/SubscriberText", params={"sessionid": sid}
    ) as response:
        assert response.status == 415
    gateway.opc_available = False
    assert (await call(http, gateway, "GetAddressSpaceHash", sessionid=sid))[0] == 503
    assert (await call(http, gateway, "NewSession", alldata=0))[0] == 503
    assert (await call(http, gateway, "ServerInformation"))[0] == 200
    gateway.allowed = frozenset({"10.0.0.1"})
    assert (await call(http, gateway, "ServerInformation"))[0] == 403


async def test_the_address_space_and_its_hash(
    gateway: TekonGateway, http: aiohttp.ClientSession
) -> None:
    sid = await session(http, gateway)
    _, first = await call(http, gateway, "GetAddressSpaceHash", sessionid=sid)
    assert len(first["result"]) == 32
    _, items = await call(http, gateway, "GetAddressSpace", sessionid=sid)
    assert [item["ItemID"] for item in items] == list(range(len(items)))
    door = next(item for item in items if item["ItemName"] == DOOR)
    assert {prop["ID"]: prop["Value"] for prop in door["ItemProps"]}[5001] == "3000"
    # Configuration mode: sessions closed, a new item first (every ID moves).
    gateway.configuration_mode(
        add=[channel("Дом 1.Новый", NUMBER, "1", vartype=VT_R4)], first=True
    )
    assert (await call(http, gateway, "GetAddressSpaceHash", sessionid=sid))[0] == 409
    sid = await session(http, gateway)
    _, second = await call(http, gateway, "GetAddressSpaceHash", sessionid=sid)
    assert second != first
    assert gateway.building.by_name[DOOR].item_id == door["ItemID"] + 1
    gateway.configuration_mode(remove=["Дом 1.Новый"])
    sid = await session(http, gateway)
    _, third = await call(http, gateway, "GetAddressSpaceHash", sessionid=sid)
    assert third == first


async def test_text_calls_with_and_without_text_in_the_url(
    gateway: TekonGateway, http: aiohttp.ClientSession
) -> None:
    sid = await session(http, gateway)
    gateway.text_urls = "plain"
    assert (
        await call(
            http, gateway, "SubscriberText", {"itemstext": [DOOR]}, sessionid=sid
        )
    )[0] == 404
    _, added = await call(
        http, gateway, "Subscriber", {"itemstext": [DOOR]}, sessionid=sid
    )
    assert added == {"result": 1}
    await call(http, gateway, "ReadAllItemsValues", sessionid=sid)
    _, updates = await call(http, gateway, "GetUpdates", sessionid=sid, rid=1)
    assert updates[0]["ItemID"] == gateway.building.by_name[DOOR].item_id
    _, read = await call(
        http, gateway, "ReadItemValueSync", sessionid=sid, itemname=DOOR
    )
    assert read[0]["ItemName"] == DOOR
    gateway.text_urls = "text"
    _, ignored = await call(
        http, gateway, "Subscriber", {"itemstext": [SETPOINT]}, sessionid=sid
    )
    assert ignored == {"result": 0}
    _, by_id = await call(
        http,
        gateway,
        "ReadItemValueSync",
        sessionid=sid,
        item=gateway.building.by_name[SETPOINT].item_id,
    )
    assert by_id[0]["V"] == "20"
    _, nothing = await call(
        http, gateway, "ReadItemValueSync", sessionid=sid, itemname=DOOR
    )
    assert nothing == []


async def test_writes_by_name_decimal_commas_and_writes_disabled(
    gateway: TekonGateway, http: aiohttp.ClientSession
) -> None:
    sid = await session(http, gateway)
    _, done = await call(
        http,
        gateway,
        "WriteItemsValuesText",
        [{"ItemName": SETPOINT, "Value": "22.5"}, {"ItemName": DOOR, "Value": "1"}],
        sessionid=sid,
    )
    # The door is a discrete input: read only.
    assert done == {"result": 1}
    assert gateway.value(SETPOINT) == "22.5"
    gateway.decimal_commas = True
    _, refused = await call(
        http,
        gateway,
        "WriteItemsValues",
        [{"ItemName": SETPOINT, "Value": "23.5"}],
        sessionid=sid,
    )
    assert refused == {"result": 0}
    await call(
        http,
        gateway,
        "WriteItemsValues",
        [{"ItemName": SETPOINT, "Value": "23,5"}],
        sessionid=sid,
    )
    # Written items join the subscription; reals go out with a comma.
    _, updates = await call(http, gateway, "GetUpdatesText", sessionid=sid, rid=1)
    assert [(entry["ItemName"], entry["V"]) for entry in updates] == [
        (SETPOINT, "23,5")
    ]
    gateway.writes_enabled = False
    _, disabled = await call(
        http,
        gateway,
        "WriteItemsValuesText",
        [{"ItemName": SETPOINT, "Value": "24,5"}],
        sessionid=sid,
    )
    assert disabled == {"result": -1}
    assert gateway.value(SETPOINT) == "23.5"


async def test_sessions_idle_too_long_are_closed(
    gateway: TekonGateway, http: aiohttp.ClientSession
) -> None:
    gateway.session_timeout = 0.0
    sid = await session(http, gateway)
    assert (await call(http, gateway, "GetAddressSpaceHash", sessionid=sid))[0] == 409
    gateway.session_timeout = 120.0
    sid = await session(http, gateway)
    gateway.expire_sessions()
    assert (await call(http, gateway, "GetAddressSpaceHash", sessionid=sid))[0] == 409


async def test_values_with_bad_quality_and_local_time(
    gateway: TekonGateway, http: aiohttp.ClientSession
) -> None:
    gateway.zone = timedelta(hours=5)
    sid = await session(http, gateway)
    await call(
        http,
        gateway,
        "SubscriberText",
        {"itemstext": [f"{LIFT}.Status"]},
        sessionid=sid,
    )
    await call(http, gateway, "GetUpdatesText", sessionid=sid, rid=1)
    gateway.set_value(f"{LIFT}.Status", "0", quality=0x18)
    _, updates = await call(http, gateway, "GetUpdatesText", sessionid=sid, rid=2)
    assert (updates[0]["V"], updates[0]["Qual"]) == ("0", 0x18)
    assert updates[0]["UpTime"] == gateway.now().strftime("%Y-%m-%d %H:%M:%S")


def test_the_buildings() -> None:
    small = small_building()
    assert small.hash() == small_building().hash()
    assert small.by_name[f"{LIFT}.Состояние"].value == lift_state()
    large = large_building(10_000)
    assert len(large.items) == 10_000
    assert len({item.name for item in large.items}) == 10_000
    kinds = {item.channel_type for item in large.items}
    assert kinds == {3000, 3001, 3002, 3005, 3060, 3061}
    assert large.by_name["Район.КУН-IP8 - 1.Устройство 1.Канал 2"].writable
    assert channel("x.y", None, "0", access=READ_WRITE).writable


async def test_a_slow_address_space(
    gateway: TekonGateway, http: aiohttp.ClientSession
) -> None:
    gateway.address_space_delay = 0.01
    sid = await session(http, gateway)
    status, items = await call(http, gateway, "GetAddressSpace", sessionid=sid)
    assert status == 200
    assert len(items) == len(gateway.building.items)
    gateway.clear_requests()
    await call(http, gateway, "GetSubscribersCount", sessionid=sid)
    await gateway.wait_for_call("GetSubscribersCount")
    assert gateway.requests == ["GetSubscribersCount"]


async def test_the_gateway_as_a_program_lives_like_a_building(
    socket_enabled: None, http: aiohttp.ClientSession
) -> None:
    """``python -m tests.simulator.tekon``: its URL, a moving lift, a clean stop."""
    process = await asyncio.create_subprocess_exec(
        sys.executable,
        "-m",
        "tests.simulator.tekon",
        "--port",
        "0",
        "--animate",
        "0.01",
        "--decimal-commas",
        "--initial-data",
        "--api-version",
        "2.1",
        cwd=REPOSITORY,
        stdout=asyncio.subprocess.PIPE,
        stderr=asyncio.subprocess.PIPE,
    )
    assert process.stdout is not None
    try:
        line = await asyncio.wait_for(process.stdout.readline(), 60)
        found = re.fullmatch(rb"Tekon gateway at (http://127\.0\.0\.1:\d+)\n", line)
        assert found is not None, line
        url = found.group(1).decode()
        async with http.get(f"{url}/ServerInformation") as response:
            assert (await response.json())["version"] == "2.1"
        async with http.get(f"{url}/NewSession?alldata=1") as response:
            sid = (await response.json())["sessionid"]
        body = json.dumps({"itemstext": [f"{LIFT}.Состояние"]})
        params = {"sessionid": sid}
        async with http.post(f"{url}/SubscriberText", params=params, data=body):
            pass
        states: set[str] = set()
        rid = 0
        async with asyncio.timeout(30):
            while len(states) < 3:
                rid += 1
                async with http.get(
                    f"{url}/GetUpdatesText", params={**params, "rid": rid}
                ) as response:
                    states.update(entry["V"] for entry in await response.json())
    finally:
        process.send_signal(signal.SIGTERM)
        await asyncio.wait_for(process.communicate(), 60)
    assert process.returncode == 0
