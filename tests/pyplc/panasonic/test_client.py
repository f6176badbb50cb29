"""The FP-I4C client over HTTP: the simulated gateway, and servers that are none.

The simulator answers as the seed documents (strictly, or as the manual
prints JSON); a small server of the test's own answers what a gateway must
not (a web page, another JSON, too much), each a real HTTP exchange.
"""

from collections.abc import AsyncIterator
from dataclasses import dataclass
import socket
from typing import Any

import aiohttp
from aiohttp import web
import pytest

from custom_components.tecoapi.pyplc import (
    MalformedResponseError,
    NotAPlcError,
    PlcConnectionError,
    PlcResponseError,
    ResponseTooLargeError,
)
from custom_components.tecoapi.pyplc.panasonic import FpI4cClient
from custom_components.tecoapi.pyplc.panasonic.address import WireType
from custom_components.tecoapi.pyplc.panasonic.client import (
    MAX_BODY_BYTES,
    GatewayError,
    as_real,
    decode_value,
)
from tests.simulator.fpi4c import NO_RESPONSE, FpI4cSimulator

INT10 = {"area": "DT", "type": "INT", "start": 0, "count": 6}


async def test_a_post_reads_each_request_in_order(
    gateway: FpI4cSimulator, http: aiohttp.ClientSession
) -> None:
    client = FpI4cClient(http, gateway.url)
    answers = await client.post(
        [
            INT10,
            {"area": "DT", "type": "STRING", "start": 300},
            {"area": "Y", "type": "BOOL", "start": "0", "count": 2},
            {"area": "DT", "type": "REAL", "start": 210, "count": 1},
            {"area": "DT", "type": "UDINT", "start": 200, "count": 2},
        ],
        station=1,
    )
    assert [answer.request for answer in answers] == [
        "DT0",
        "DT300",
        "Y0",
        "DT210",
        "DT200",
    ]
    assert answers[0].values == (652, 452, 381, -35, 498, 214)
    assert answers[1].values == ("Heating",)
    assert answers[2].values == (True, False)
    assert answers[3].values == (1.8,)
    assert answers[4].values == (12_345, 3_456)
    assert all(answer.error is None for answer in answers)
    body = gateway.posts[-1]
    assert body["station"] == 1
    assert "interface" not in body
    assert client.statistics.posts == 1
    assert client.statistics.bytes_sent > 0
    assert client.statistics.bytes_received > 0
    assert client.statistics.lenient_answers == 0


async def test_the_interface_and_station_go_with_every_post(
    gateway: FpI4cSimulator, http: aiohttp.ClientSession
) -> None:
    client = FpI4cClient(http, gateway.url, interface=4)
    await client.post([INT10])
    assert gateway.posts[-1] == {"req": [INT10], "interface": 4}
    with pytest.raises(GatewayError, match="Interface 1 is not enabled"):
        await FpI4cClient(http, gateway.url, interface=1).post([INT10], 1)


async def test_an_answer_printed_as_the_manual_does_is_read(
    gateway: FpI4cSimulator, http: aiohttp.ClientSession
) -> None:
    gateway.lenient = True
    client = FpI4cClient(http, gateway.url)
    answers = await client.post([INT10, {"area": "X", "type": "BOOL", "start": "0"}], 1)
    assert answers[0].values == (652, 452, 381, -35, 498, 214)
    assert answers[1].values == (True,)
    assert client.statistics.lenient_answers == 1


async def test_a_failed_item_costs_nothing_else(
    gateway: FpI4cSimulator, http: aiohttp.ClientSession
) -> None:
    gateway.item_errors[1, "DT3"] = (61, "Data error")
    client = FpI4cClient(http, gateway.url)
    answers = await client.post(
        [INT10, {"area": "DT", "type": "INT", "start": 100, "count": 1}], 1
    )
    error = answers[0].error
    assert error is not None
    assert (error.code, error.message, error.request) == ("61", "Data error", "DT0")
    assert str(error) == "DT0: Data error (err_code 61)"
    assert answers[1].values == (450,)
    gateway.silent.add(1)
    (answer,) = await client.post([INT10], 1)
    assert answer.error is not None
    assert answer.error.code == str(NO_RESPONSE[0])


async def test_a_write_answers_without_values(
    gateway: FpI4cSimulator, http: aiohttp.ClientSession
) -> None:
    client = FpI4cClient(http, gateway.url)
    (answer,) = await client.post(
        [{"area": "DT", "type": "INT", "start": 100, "count": 1, "value": 222}], 1
    )
    assert answer == type(answer)("DT100")
    assert gateway.get(1, "DT100", "INT") == 222


async def test_nothing_answering_is_a_connection_error(
    http: aiohttp.ClientSession, socket_enabled: None
) -> None:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    client = FpI4cClient(http, f"127.0.0.1:{port}", timeout=2)
    with pytest.raises(PlcConnectionError):
        await client.post([INT10])


@dataclass
class Crafted:
    """A server answering every POST with what the test sets."""

    status: int = 200
    content_type: str = "application/json"
    body: bytes = b"{}"
    url: str = ""


@pytest.fixture
async def crafted(socket_enabled: None) -> AsyncIterator[Crafted]:
    answer = Crafted()

    async def handle(request: web.Request) -> web.Response:
        await request.read()
        return web.Response(
            status=answer.status, body=answer.body, content_type=answer.content_type
        )

    app = web.Application()
    app.router.add_route("*", "/{tail:.*}", handle)
    runner = web.AppRunner(app, access_log=None)
    await runner.setup()
    site = web.TCPSite(runner, "127.0.0.1", 0)
    await site.start()
    answer.url = f"http://127.0.0.1:{runner.addresses[0][1]}"
    yield answer
    await runner.cleanup()


@pytest.mark.parametrize(
    ("answer", "error", "message"),
    [
        ((404, "text/plain", b"Not Found"), NotAPlcError, "HTTP 404"),
        ((302, "text/plain", b""), NotAPlcError, "HTTP 302"),
        ((405, "text/plain", b"Method Not Allowed"), NotAPlcError, "HTTP 405"),
        ((200, "text/html", b"<html>login</html>"), NotAPlcError, "web page"),
        ((200, "text/plain", b"<html>login</html>"), NotAPlcError, "web page"),
        ((200, "text/plain", b"Hello there"), NotAPlcError, "other than JSON"),
        ((200, "text/plain", b"OK"), NotAPlcError, "not as an FP-I4C"),
        ((200, "application/json", b'{"result": 1}'), NotAPlcError, "not as an FP-I4C"),
        ((200, "application/json", b"[1, 2]"), NotAPlcError, "not as an FP-I4C"),
        ((200, "application/json", b'{"data": ['), MalformedResponseError, "not JSON"),
        (
            (200, "application/json", b'{"err": false, "data": []}'),
            MalformedResponseError,
            "0 items for 1 requests",
        ),
        ((500, "application/json", b"{}"), PlcResponseError, "HTTP 500"),
        (
            (
                200,
                "application/json",
                b'{"err": true, "err_msg": "Too many requests", "data": []}',
            ),
            GatewayError,
            "Too many requests",
        ),
        (
            (200, "application/json", b'{"err": "true", "data": []}'),
            GatewayError,
            "refused",
        ),
    ],
)
async def test_what_no_fp_i4c_answers_is_refused(
    crafted: Crafted,
    http: aiohttp.ClientSession,
    answer: tuple[int, str, bytes],
    error: type[Exception],
    message: str,
) -> None:
    crafted.status, crafted.content_type, crafted.body = answer
    with pytest.raises(error, match=message):
        await FpI4cClient(http, crafted.url).post([INT10])


async def test_an_answer_is_read_no_further_than_its_cap(
    crafted: Crafted, http: aiohttp.ClientSession
) -> None:
    crafted.body = b'{"err": false, "data": ["' + b"x" * MAX_BODY_BYTES + b'"]}'
    with pytest.raises(ResponseTooLargeError) as raised:
        await FpI4cClient(http, crafted.url).post([INT10])
    # A declared length past the cap fails before the body is read.
    assert raised.value.limit == MAX_BODY_BYTES
    assert raised.value.received == 0


async def test_an_endless_answer_stops_at_the_cap(
    socket_enabled: None, http: aiohttp.ClientSession
) -> None:
    async def endless(request: web.Request) -> web.StreamResponse:
        response = web.StreamResponse()
        response.enable_chunked_encoding()
        await response.prepare(request)
        chunk = b" " * 65536
        while True:
            await response.write(chunk)

    app = web.Application()
    app.router.add_post("/plcpost", endless)
    runner = web.AppRunner(app, access_log=None)
    await runner.setup()
    site = web.TCPSite(runner, "127.0.0.1", 0)
    await site.start()
    try:
        client = FpI4cClient(http, f"127.0.0.1:{runner.addresses[0][1]}")
        with pytest.raises(ResponseTooLargeError) as raised:
            await client.post([INT10])
        assert MAX_BODY_BYTES < raised.value.received <= MAX_BODY_BYTES + 1
    finally:
        await runner.cleanup()


async def test_items_that_are_not_what_was_asked(
    crafted: Crafted, http: aiohttp.ClientSession
) -> None:
    crafted.body = (
        b'{"err": false, "data": ['
        b'"nonsense",'
        b'{"err": false, "request": "DT0"},'
        b'{"err": false, "int": [1, "two", 3.0, 70000]},'
        b'{"err": false, "string": 5},'
        b'{"err": false, "state": [1]},'
        b'{"err": 1, "err_code": 66}'
        b"]}"
    )
    requests: list[dict[str, Any]] = [
        INT10,
        INT10,
        {"area": "DT", "type": "INT", "start": 0, "count": 4},
        {"area": "DT", "type": "STRING", "start": 0},
        {"area": "R", "type": "BOOL", "start": "1A", "count": 3},
        INT10,
    ]
    first, second, third, fourth, fifth, sixth = await FpI4cClient(
        http, crafted.url
    ).post(requests)
    assert first.error is not None
    assert "not an object" in first.error.message
    assert second.error is not None
    assert "no 'int'" in second.error.message
    assert third.values == (1, None, 3, None)
    assert fourth.values == (None,)
    assert fifth.values == (True, None, None)
    assert fifth.request == "R1A"
    assert sixth.error is not None
    assert (sixth.error.code, sixth.error.message) == ("66", "failed")


async def test_a_failed_write_item_as_the_seed_prints_it_has_only_its_code(
    crafted: Crafted, http: aiohttp.ClientSession
) -> None:
    crafted.body = (
        b'{"err": false, "data": [{"request": "DT10", "err": true, "err_code": 65}]}'
    )
    (written,) = await FpI4cClient(http, crafted.url).post([{**INT10, "value": 1}])
    assert written.error is not None
    assert (written.error.code, written.error.message) == ("65", "")
    assert written.error.detail == "err_code 65"
    assert str(written.error) == "DT10: err_code 65"


@pytest.mark.parametrize(
    ("wire", "value", "decoded"),
    [
        (WireType.BOOL, 1, True),
        (WireType.BOOL, False, False),
        (WireType.BOOL, 2, None),
        (WireType.BOOL, "1", None),
        (WireType.INT, -32768, -32768),
        (WireType.INT, 32768, None),
        (WireType.INT, 7.0, 7),
        (WireType.INT, True, None),
        (WireType.UINT, -1, None),
        (WireType.UINT, 65535, 65535),
        (WireType.DINT, -(2**31), -(2**31)),
        (WireType.UDINT, 2**32, None),
        (WireType.REAL, 22.8799991607666, 22.88),
        (WireType.REAL, 5.969307950918661e-39, 5.969307e-39),
        (WireType.REAL, 1e39, None),
        (WireType.REAL, "1.5", None),
        (WireType.REAL, True, None),
        (WireType.STRING, "x", "x"),
        (WireType.STRING, 1, None),
    ],
)
def test_values_are_decoded_by_their_type(
    wire: WireType, value: Any, decoded: Any
) -> None:
    assert decode_value(wire, value) == decoded


def test_a_real_is_shown_as_a_float32_holds_it() -> None:
    assert as_real(22.88) == 22.88
    assert as_real(float("nan")) is None
    assert as_real(float("inf")) is None
    assert as_real(3.4e38) == 3.4e38
