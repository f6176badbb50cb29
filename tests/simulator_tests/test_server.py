"""The Simulator object: lifecycle, headers, request records, programs, values, logging."""

import base64
import logging

import aiohttp
import pytest

from tests.conftest import SIM_PASSWORD, SIM_USERNAME, Certificate
from tests.simulator import Program, RequestRecord, Simulator, load_program
from tests.simulator_tests.conftest import fetch

pytestmark = pytest.mark.usefixtures("socket_enabled")


async def test_addresses_after_start() -> None:
    sim = Simulator("manual")
    assert sim.port == 0

    await sim.start()
    try:
        assert sim.port > 0
        assert sim.host == f"127.0.0.1:{sim.port}"
        assert sim.url == f"http://127.0.0.1:{sim.port}"
        with pytest.raises(RuntimeError, match="already running"):
            await sim.start()
    finally:
        await sim.stop()
        await sim.stop()


async def test_restart_after_stop(session: aiohttp.ClientSession) -> None:
    sim = Simulator(
        "manual", username=SIM_USERNAME, password=SIM_PASSWORD, auth="basic"
    )
    await sim.start()
    await sim.stop()
    await sim.start()
    try:
        reply = await fetch(session, sim, "/TecoApi/GetInfo")
    finally:
        await sim.stop()

    assert reply.status == 200


async def test_port_in_use_is_reported() -> None:
    async with Simulator("manual") as first:
        second = Simulator("manual")
        with pytest.raises(OSError):
            await second.start(port=first.port)
        await second.stop()


async def test_https_with_a_self_signed_certificate(certificate: Certificate) -> None:
    sim = Simulator("manual", username=SIM_USERNAME, password=SIM_PASSWORD)
    await sim.start(ssl_context=certificate.server_context())
    middleware = aiohttp.DigestAuthMiddleware(SIM_USERNAME, SIM_PASSWORD)
    try:
        assert sim.url == f"https://127.0.0.1:{sim.port}"
        async with aiohttp.ClientSession(middlewares=(middleware,)) as client:
            async with client.get(
                sim.url + "/TecoApi/GetInfo", ssl=certificate.client_context()
            ) as response:
                trusted = response.status
            with pytest.raises(aiohttp.ClientConnectorCertificateError):
                async with client.get(sim.url + "/TecoApi/GetInfo"):
                    pass
    finally:
        await sim.stop()

    assert trusted == 200


async def test_success_headers(
    session: aiohttp.ClientSession, manual_plc: Simulator
) -> None:
    reply = await fetch(session, manual_plc, "/TecoApi/GetObject?plcName")

    assert reply.headers["Server"] == "TecoApi/1.0.0 (sim CP-W32I v1.1 VN 1957)"
    assert reply.headers["Content-Type"] == "application/json"
    assert reply.headers["Cache-Control"] == "no-cache"
    assert reply.headers["Connection"] == "close"


async def test_the_plc_web_pages_need_no_authentication(
    session: aiohttp.ClientSession, manual_plc: Simulator
) -> None:
    index = await fetch(session, manual_plc, "/", basic=False)
    other = await fetch(session, manual_plc, "/index.htm", basic=False)
    near = await fetch(session, manual_plc, "/TecoApiX/GetInfo", basic=False)

    assert index.status == 200
    assert b"CP-W32" in index.body
    assert (other.status, near.status) == (404, 404)
    assert [r.service for r in manual_plc.requests] == ["", "", ""]


async def test_requests_are_recorded_in_order(
    session: aiohttp.ClientSession, manual_plc: Simulator
) -> None:
    await fetch(session, manual_plc, "/TecoApi/GetInfo", basic=False)
    await fetch(session, manual_plc, "/TecoApi/GetObject?myObject&arr1%5B1%5D")
    await fetch(
        session, manual_plc, "/TecoApi/PutObject", method="PUT", data=b'{"plcType": 1}'
    )
    await fetch(session, manual_plc, "/TecoApi/GetObject?missing")

    assert manual_plc.requests == [
        RequestRecord("GET", "GetInfo", "", 401, authorized=False, items=0),
        RequestRecord("GET", "GetObject", "myObject&arr1%5B1%5D", 200, True, 14),
        RequestRecord("PUT", "PutObject", "", 204, True, 0),
        RequestRecord("GET", "GetObject", "missing", 400, True, 0),
    ]

    manual_plc.clear_requests()

    assert manual_plc.requests == []


async def test_load_program_changes_the_stamp_and_keeps_the_hardware(
    session: aiohttp.ClientSession, manual_plc: Simulator
) -> None:
    before = (await fetch(session, manual_plc, "/TecoApi/GetInfo")).json()["plc"]

    manual_plc.load_program("demo")

    after = (await fetch(session, manual_plc, "/TecoApi/GetInfo")).json()["plc"]
    listing = (await fetch(session, manual_plc, "/TecoApi/GetList")).json()
    assert after["userProg"]["stamp"] == manual_plc.stamp != before["userProg"]["stamp"]
    assert after["userProg"]["name"] == "FAMILY_HOUSE v1.3"
    assert (after["serialNumber"], after["type"], after["mac"]) == (
        before["serialNumber"],
        before["type"],
        before["mac"],
    )
    assert "Heating" in listing
    assert "myObject" not in listing


async def test_a_changed_program_gets_a_new_stamp_and_fresh_values(
    manual_plc: Simulator,
) -> None:
    manual_plc.set_value("plcType", 1)
    source = manual_plc.program.to_mapping()
    source["variables"]["newVariable"] = {"type": "INT", "value": 5}
    stamp = manual_plc.stamp

    manual_plc.load_program(Program.from_mapping(source))

    assert manual_plc.stamp != stamp
    assert manual_plc.get_value("newVariable") == 5
    assert manual_plc.get_value("plcType") == 2005


async def test_reloading_the_same_program_keeps_the_stamp(
    manual_plc: Simulator,
) -> None:
    stamp = manual_plc.stamp

    manual_plc.load_program(load_program("manual"))

    assert manual_plc.stamp == stamp


async def test_identity_can_be_changed(
    session: aiohttp.ClientSession, manual_plc: Simulator
) -> None:
    assert manual_plc.item_limit == 128
    manual_plc.serial_number = "XY 0001"
    manual_plc.plc_type = "CP2000"

    plc = (await fetch(session, manual_plc, "/TecoApi/GetInfo")).json()["plc"]

    assert (plc["serialNumber"], plc["type"]) == ("XY 0001", "CP2000")
    assert (manual_plc.serial_number, manual_plc.plc_type) == ("XY 0001", "CP2000")
    assert manual_plc.item_limit == 256


async def test_get_and_set_value(manual_plc: Simulator) -> None:
    manual_plc.set_value("MAIN.myObject2.value", 19)
    manual_plc.set_value("myObject", {"favorites": {"color": "green"}})

    assert manual_plc.get_value("Main.myObject2.value") == 19.0
    assert manual_plc.get_value("arr2[1][3]") == 1.3
    assert manual_plc.get_value("myObject")["favorites"]["color"] == "green"
    with pytest.raises(KeyError):
        manual_plc.get_value("nothing")
    with pytest.raises(KeyError):
        manual_plc.set_value("nothing", 1)
    with pytest.raises(KeyError):
        manual_plc.set_value("myObject", {"nothing": 1})
    with pytest.raises(ValueError, match=r"type of variable is USINT"):
        manual_plc.set_value("myObject.age", 256)


async def test_get_value_returns_a_copy(manual_plc: Simulator) -> None:
    value = manual_plc.get_value("arr1")
    value[0] = "changed"

    assert manual_plc.get_value("arr1[0]") == "zero"


async def test_requests_are_logged_without_credentials(
    session: aiohttp.ClientSession,
    manual_plc: Simulator,
    caplog: pytest.LogCaptureFixture,
) -> None:
    caplog.set_level(logging.INFO, logger="tests.simulator")
    token = base64.b64encode(f"{SIM_USERNAME}:{SIM_PASSWORD}".encode()).decode()

    await fetch(session, manual_plc, "/TecoApi/GetObject?myObject")
    await fetch(session, manual_plc, "/TecoApi/GetInfo", basic=False)

    messages = [r.getMessage() for r in caplog.records if r.name == "tests.simulator"]
    assert messages == [
        "GET /TecoApi/GetObject?myObject -> 200 (13 items)",
        "GET /TecoApi/GetInfo -> 401",
    ]
    assert all(record.levelno == logging.INFO for record in caplog.records)
    assert SIM_PASSWORD not in caplog.text
    assert token not in caplog.text
