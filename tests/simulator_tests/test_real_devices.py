"""What real devices do unlike the manual, each behind a switch of the simulator."""

import json
from typing import Any

import aiohttp
import pytest

from tests.conftest import SIM_PASSWORD, SIM_USERNAME
from tests.simulator import Program, Simulator, load_program
from tests.simulator.faults import HUGE_BODY_BYTES
from tests.simulator_tests.conftest import basic_authorization, fetch

# --- service names in any case -------------------------------------------------------


async def test_a_third_party_client_reads_and_writes_with_lower_case_services(
    manual_simulator: Simulator,
) -> None:
    """A heat-pump vendor's client: `/tecoapi/getlist`, `getobject`, `setobject`."""
    middleware = aiohttp.DigestAuthMiddleware(SIM_USERNAME, SIM_PASSWORD)
    url = manual_simulator.url
    async with aiohttp.ClientSession(middlewares=(middleware,)) as client:
        async with client.get(f"{url}/tecoapi/getlist") as response:
            assert response.status == 200
            assert "plcName" in await response.json()
        async with client.get(f"{url}/tecoapi/getobject?plcName") as response:
            assert response.status == 200
            assert await response.json() == {"plcName": "myFoxtrot"}
        async with client.get(f"{url}/TECOAPI/SETOBJECT?plcType=7") as response:
            assert response.status == 200

    assert manual_simulator.get_value("plcType") == 7
    # Recorded under the manual's spelling, whatever was sent.
    assert [r.service for r in manual_simulator.requests if r.authorized] == [
        "GetList",
        "GetObject",
        "SetObject",
    ]


@pytest.mark.parametrize(
    ("target", "status", "code"),
    [
        ("/TecoApi/getinfo", 501, "501.013"),
        ("/TecoApi/GETLIST", 501, "501.013"),
        ("/tecoapi/GetInfo", 404, None),
        ("/TecoApi/GetInfo", 200, None),
    ],
)
async def test_exact_service_names_answer_only_the_manuals_spelling(
    manual_simulator: Simulator, target: str, status: int, code: str | None
) -> None:
    manual_simulator.faults.exact_service_names = True
    async with aiohttp.ClientSession() as session:
        reply = await fetch(session, manual_simulator, target, basic=False)
        if reply.status == 401:
            manual_simulator.auth = "both"
            reply = await fetch(session, manual_simulator, target)

    assert reply.status == status
    if code is not None:
        assert reply.error_code == code
        assert reply.error_message.endswith(
            f"'HTTP GET | {target.rsplit('/', maxsplit=1)[-1]}'"
        )


# --- Windows-1250 text and short REALs ------------------------------------------------


async def test_windows_1250_text_in_answers_and_errors(
    session: aiohttp.ClientSession, socket_enabled: None
) -> None:
    source: dict[str, Any] = load_program("manual").to_mapping()
    main = source["variables"]["Main"]["variables"]
    main["myObject2"]["value"]["attr"]["title"] = "Teplota obývák"
    source["variables"]["plcDesc"]["value"] = "≥ 5"
    sim = Simulator(
        Program.from_mapping(source),
        username=SIM_USERNAME,
        password=SIM_PASSWORD,
        auth="both",
    )
    async with sim:
        sim.faults.text_encoding = "windows-1250"
        reply = await fetch(session, sim, "/TecoApi/GetObject?Main.myObject2.attr")
        error = await fetch(session, sim, "/TecoApi/GetObject?ob%C3%BDv%C3%A1k")
        unknown = await fetch(session, sim, "/TecoApi/GetObject?plcDesc")

    assert b'"title": "Teplota ob\xfdv\xe1k"' in reply.body
    assert b'"units": "\xb0C"' in reply.body
    assert (
        json.loads(reply.body.decode("cp1250"))["Main"]["myObject2"]["attr"]["units"]
        == "°C"
    )
    assert b"Variable 'ob\xfdv\xe1k' is not found" in error.body
    # A character Windows-1250 lacks is printed as a Windows program would: `?`.
    assert unknown.json() == {"plcDesc": "? 5"}


async def test_short_reals(
    session: aiohttp.ClientSession, manual_plc: Simulator
) -> None:
    manual_plc.set_value("Main.myObject1.value", -0.0)
    manual_plc.faults.short_reals = True

    reply = await fetch(
        session, manual_plc, "/TecoApi/GetObject?Main.myObject1&Main.myObject3"
    )

    assert b'"value": -0.0,\r\n' in reply.body
    assert b'"value": 23.0,\r\n' in reply.body
    assert b'"maxValue": 30.0,\r\n' in reply.body
    manual_plc.faults.short_reals = False
    reply = await fetch(session, manual_plc, "/TecoApi/GetObject?Main.myObject1")
    assert b'"value": -0.000000,\r\n' in reply.body


# --- huge and endless answers ----------------------------------------------------------


@pytest.mark.parametrize("fault", ["huge_body", "endless_body"])
async def test_huge_and_endless_answers_stream_until_the_client_hangs_up(
    session: aiohttp.ClientSession, manual_plc: Simulator, fault: str
) -> None:
    setattr(manual_plc.faults, fault, True)
    manual_plc.faults.remaining = 1
    async with session.get(
        manual_plc.url + "/TecoApi/GetObject?plcName",
        headers={"Authorization": basic_authorization(SIM_USERNAME, SIM_PASSWORD)},
    ) as response:
        start = await response.content.readexactly(1024 * 1024)
        assert response.status == 200
        assert response.headers["Content-Type"] == "application/json"
        if fault == "huge_body":
            assert response.content_length == HUGE_BODY_BYTES
        else:
            assert response.headers["Transfer-Encoding"] == "chunked"
    # Closed here, long before the end (if any).

    assert start.startswith(b'{\r\n  "noise": "xxx')
    assert manual_plc.requests[-1].status == 200
    # The fault hit one request; the next is answered as usual.
    reply = await fetch(session, manual_plc, "/TecoApi/GetObject?plcName")
    assert reply.json() == {"plcName": "myFoxtrot"}
