"""The one HTTP exchange every client talks through, over real HTTP on 127.0.0.1.

One request at a time where the device needs it, timeouts, answers read within a
cap, a status as the client's table says, every request and byte counted (a
Digest challenge's round trip too), a renewal inside the turn, ``ssl`` as asked,
the session never closed, and JSON decoded alike with and without orjson.
"""

import asyncio
from collections.abc import AsyncIterator, Awaitable, Callable
import contextlib
import json
import math
from typing import Any

import aiohttp
from aiohttp import web
import pytest

from custom_components.tecoapi.pyplc import (
    NotAPlcError,
    PlcConnectionError,
    PlcError,
    PlcResponseError,
    PlcTlsError,
    ResponseTooLargeError,
)
from custom_components.tecoapi.pyplc.core.http import (
    FAST_JSON,
    FAST_JSON_BYTES,
    MAX_RESENDS,
    HttpAuth,
    HttpExchange,
    Reply,
    json_loads,
    loads_json,
    utf8_or,
)
from tests.conftest import Certificate

type Handler = Callable[[web.Request], Awaitable[web.StreamResponse]]

WAIT = 5.0
"""Safety net: a broken exchange fails the test instead of hanging it."""


@contextlib.asynccontextmanager
async def serving(handler: Handler, *, ssl_context: Any = None) -> AsyncIterator[str]:
    """A web server answering every path with ``handler``; yields its base URL."""
    app = web.Application()
    app.router.add_route("*", "/{tail:.*}", handler)
    runner = web.AppRunner(app, access_log=None)
    await runner.setup()
    site = web.TCPSite(runner, "127.0.0.1", 0, ssl_context=ssl_context)
    await site.start()
    scheme = "https" if ssl_context is not None else "http"
    try:
        yield f"{scheme}://127.0.0.1:{runner.addresses[0][1]}"
    finally:
        await runner.cleanup()


@pytest.fixture
async def http(socket_enabled: None) -> AsyncIterator[aiohttp.ClientSession]:
    """An HTTP session (the exchange never closes the one it is given)."""
    async with aiohttp.ClientSession() as session:
        yield session


def exchange(session: aiohttp.ClientSession, url: str, **options: Any) -> HttpExchange:
    """An exchange with a device of ``url`` that reads 1 KiB answers."""
    options.setdefault("limit", 1024)
    return HttpExchange(session, url, sender="a device", **options)


async def echo(request: web.Request) -> web.Response:
    """Answer the method, the path and query, and the body as JSON."""
    return web.json_response(
        {
            "method": request.method,
            "target": request.path_qs,
            "body": (await request.read()).decode(),
            "accept": request.headers.get("Accept"),
            "type": request.headers.get("Content-Type"),
        }
    )


async def test_a_request_goes_to_its_target_and_its_json_comes_back(
    http: aiohttp.ClientSession,
) -> None:
    """The target is sent as encoded; a body goes as JSON; the session stays open."""
    async with serving(echo) as url:
        device = exchange(http, url)
        got = await device.request("GET", "/a%22b?x=%20&y=1")
        posted = await device.request("POST", "/set", body=b'{"v": 1}')

    assert got.ok
    assert got.json() == {
        "method": "GET",
        "target": "/a%22b?x=%20&y=1",
        "body": "",
        "accept": "application/json",
        "type": None,
    }
    assert posted.json()["body"] == '{"v": 1}'
    assert posted.json()["type"] == "application/json"
    assert posted.json() is posted.json()
    assert not http.closed


async def test_every_request_and_byte_is_counted(
    http: aiohttp.ClientSession,
) -> None:
    async with serving(echo) as url:
        device = exchange(http, url)
        replies = [
            await device.request("POST", "/one", body=b"12345"),
            await device.request("GET", "/two"),
        ]

    assert device.wire.requests == 2
    assert device.wire.bytes_sent == 5
    assert device.wire.bytes_received == sum(len(reply.body) for reply in replies)
    assert replies[0].sent == 5


async def test_a_digest_challenge_round_trip_is_counted_as_a_request(
    http: aiohttp.ClientSession,
) -> None:
    """A middleware that answers a challenge sends twice: both go on the wire."""
    seen: list[str | None] = []

    async def challenging(request: web.Request) -> web.Response:
        seen.append(request.headers.get("Authorization"))
        if request.headers.get("Authorization", "").startswith("Digest "):
            return web.json_response({})
        return web.Response(
            status=401,
            headers={"WWW-Authenticate": 'Digest realm="r", nonce="n", qop="auth"'},
        )

    async with serving(challenging) as url:
        device = exchange(http, url)
        device.auth = HttpAuth(middlewares=(aiohttp.DigestAuthMiddleware("u", "p"),))
        await device.request("GET", "/first")
        await device.request("GET", "/second")

    assert len(seen) == device.wire.requests == 3


async def test_requests_go_one_at_a_time_unless_told_otherwise(
    http: aiohttp.ClientSession,
) -> None:
    """The first request is held until a second arrives (or a moment passes)."""
    inside = 0
    most = 0
    second = asyncio.Event()

    async def holding(request: web.Request) -> web.Response:
        nonlocal inside, most
        inside += 1
        most = max(most, inside)
        if inside > 1:
            second.set()
        with contextlib.suppress(TimeoutError):
            await asyncio.wait_for(second.wait(), 0.2)
        inside -= 1
        return web.json_response({})

    async with serving(holding) as url:
        one = exchange(http, url)
        await asyncio.gather(one.request("GET", "/a"), one.request("GET", "/b"))
        alone = most
        second.clear()
        most = 0
        many = exchange(http, url, one_at_a_time=False)
        await asyncio.wait_for(
            asyncio.gather(many.request("GET", "/a"), many.request("GET", "/b")), WAIT
        )

    assert (alone, most) == (1, 2)


async def test_an_answer_that_never_comes_is_a_connection_error(
    http: aiohttp.ClientSession,
) -> None:
    never = asyncio.Event()

    async def silent(request: web.Request) -> web.Response:
        await asyncio.wait_for(never.wait(), WAIT)
        return web.json_response({})

    async with serving(silent) as url:
        device = exchange(http, url, timeout=0.1)
        with pytest.raises(PlcConnectionError, match="TimeoutError"):
            await device.request("GET", "/")


async def test_nothing_listening_is_a_connection_error(
    http: aiohttp.ClientSession,
) -> None:
    async with serving(echo) as url:
        pass
    with pytest.raises(PlcConnectionError, match="Cannot talk to"):
        await exchange(http, url).request("GET", "/")


async def test_an_answer_is_read_within_its_cap(http: aiohttp.ClientSession) -> None:
    """The exchange's cap, or a request's own; an answer past it fails."""

    async def large(request: web.Request) -> web.Response:
        return web.Response(body=b"x" * 100)

    async with serving(large) as url:
        device = exchange(http, url, limit=99)
        with pytest.raises(ResponseTooLargeError) as raised:
            await device.request("GET", "/")
        reply = await device.request("GET", "/", limit=100)

    assert raised.value.limit == 99
    assert raised.value.message.endswith("more than a device ever sends (99)")
    assert reply.body == b"x" * 100


async def test_a_status_means_what_the_client_s_table_says(
    http: aiohttp.ClientSession,
) -> None:
    """A status in the table, one in a range of it, any other, a success."""

    async def by_path(request: web.Request) -> web.Response:
        return web.json_response({}, status=int(request.path.strip("/")))

    def gone(reply: Reply) -> PlcError:
        return NotAPlcError(f"{reply.target} is gone")

    async with serving(by_path) as url:
        device = exchange(
            http, url, statuses={404: gone, range(300, 400): gone, 299: lambda _: None}
        )
        with pytest.raises(NotAPlcError, match="/404 is gone"):
            await device.request("GET", "/404")
        with pytest.raises(NotAPlcError, match="/302 is gone"):
            await device.request("GET", "/302")
        with pytest.raises(PlcResponseError, match="A device answered HTTP 500"):
            await device.request("GET", "/500")
        unchecked = await device.request("GET", "/500", check=False)
        fine = [await device.request("GET", f"/{status}") for status in (200, 299)]

    assert unchecked.status == 500
    assert [reply.status for reply in fine] == [200, 299]


async def test_a_renewal_sends_the_request_again_in_the_same_turn(
    http: aiohttp.ClientSession,
) -> None:
    """Prepared once, renewed after every answer, the body made again, at most twice."""
    bodies: list[bytes] = []

    async def recording(request: web.Request) -> web.Response:
        bodies.append(await request.read())
        return web.json_response({}, status=401)

    class Stale:
        """A session that goes stale: renewed after every refusal."""

        def __init__(self) -> None:
            self.session = 0
            self.told: list[tuple[int, int]] = []

        async def prepare(self) -> None:
            self.session += 1

        async def renew(self, reply: Reply, resent: int) -> bool:
            self.told.append((reply.status, resent))
            self.session += 1
            return reply.status == 401

    stale = Stale()
    async with serving(recording) as url:
        device = exchange(http, url, statuses={401: lambda _: None}, renewal=stale)
        reply = await device.request(
            "POST", "/", body=lambda: str(stale.session).encode()
        )

    assert reply.status == 401
    assert bodies == [b"1", b"2", b"3"]
    assert len(bodies) == 1 + MAX_RESENDS
    assert stale.told == [(401, 0), (401, 1), (401, 2)]
    assert device.wire.requests == 3


async def test_a_certificate_is_verified_unless_told_not_to(
    http: aiohttp.ClientSession, certificate: Certificate
) -> None:
    async with serving(echo, ssl_context=certificate.server_context()) as url:
        with pytest.raises(PlcTlsError, match="not trusted"):
            await exchange(http, url).request("GET", "/")
        reply = await exchange(http, url, verify_ssl=False).request("GET", "/")

    assert reply.ok


async def test_a_web_page_and_its_text_are_told(http: aiohttp.ClientSession) -> None:
    async def page(request: web.Request) -> web.Response:
        return web.Response(
            body="<p>Přihlášení</p>".encode("cp1250"),
            content_type="text/html",
            headers={"WWW-Authenticate": "Basic"},
        )

    async with serving(page) as url:
        reply = await exchange(http, url, decode=utf8_or("cp1250")).request("GET", "/")

    assert reply.html
    assert reply.content_type == "text/html"
    assert reply.challenges == ["Basic"]
    assert reply.text() == "<p>Přihlášení</p>"
    with pytest.raises(ValueError):
        reply.json()


# --- JSON ------------------------------------------------------------------------

STANDARD = json_loads(None)
"""The standard library's decoding, as the library does without orjson."""

ANSWERS = [
    b'{"a": 1, "b": [true, false, null], "c": "\\u00e9\\u0161", "d": 1.5}',
    '{"název": "teplota °C"}'.encode(),
    '{"název": "teplota °C"}'.encode("cp1250"),
    b'{"a": 1, "a": 2}',
    b'{"widest": [18446744073709551615, -9223372036854775808]}',
    b'{"real": 29.0, "tiny": 1e-300, "negative zero": -0.0, "zero": -0}',
    b'{"surrogate": "\\ud800"}',
    b'\n {"spaced": 1} \r\n',
    b"[" * 200 + b"]" * 200,
]
"""Answers both decoders must read alike: odd encodings, numbers, duplicates."""
BROKEN = [
    b"",
    b"{",
    b'{"a": 1,}',
    b'{"a": 1} trailing',
    b"\xef\xbb\xbf{}",
    b"[" * 100_000 + b"]" * 100_000,
    b"<html></html>",
]
"""Answers neither decoder reads."""


def decoders() -> list[Any]:
    """The standard decoding, and orjson's first where it is installed."""
    found = [STANDARD]
    with contextlib.suppress(ImportError):
        import orjson

        found.append(json_loads(orjson.loads))
    return found


@pytest.mark.parametrize("answer", ANSWERS)
def test_json_is_read_alike_with_or_without_orjson(answer: bytes) -> None:
    decode = utf8_or("cp1250")
    expected = json.loads(decode(answer))
    for loads in [*decoders(), loads_json]:
        assert repr(loads(answer, decode)) == repr(expected)


@pytest.mark.parametrize("answer", BROKEN)
def test_what_is_not_json_fails_alike_with_or_without_orjson(answer: bytes) -> None:
    for loads in [*decoders(), loads_json]:
        with pytest.raises((ValueError, RecursionError)):
            loads(answer, utf8_or("cp1250"))


def test_an_integer_wider_than_64_bits_is_a_number_either_way() -> None:
    """orjson reads it as a float, the standard library as an int (no PLC has one)."""
    for loads in decoders():
        assert loads(b"[18446744073709551616]", utf8_or("utf-8")) == [2**64]


def test_an_answer_larger_than_a_poll_s_is_read_by_the_standard_library() -> None:
    """orjson takes poll-sized answers; a larger one (an address space, read once)
    goes to the standard library, which needs half the memory for it."""
    asked: list[int] = []

    def fast(content: bytes) -> Any:
        asked.append(len(content))
        return json.loads(content)

    loads = json_loads(fast)
    small = b"[" + b"1," * 100 + b"1]"
    large = b"[" + b"1," * (FAST_JSON_BYTES // 2) + b"1]"

    assert loads(small, utf8_or("utf-8")) == [1] * 101
    assert loads(large, utf8_or("utf-8")) == [1] * (FAST_JSON_BYTES // 2 + 1)
    assert asked == [len(small)]


def test_nan_is_read_as_the_standard_library_reads_it() -> None:
    """orjson refuses NaN; the standard library's reading stands."""
    for loads in decoders():
        assert math.isnan(loads(b'{"x": NaN}', utf8_or("utf-8"))["x"])


def test_orjson_decodes_where_it_is_installed() -> None:
    """Home Assistant installs orjson: its decoding is the one used there."""
    try:
        import orjson
    except ImportError:
        assert FAST_JSON is None
    else:
        assert FAST_JSON is orjson.loads
