"""The opcconnector client over real HTTP: its calls, the Text URLs, errors and sizes."""

from collections.abc import AsyncIterator, Awaitable, Callable
import contextlib
import socket

import aiohttp
from aiohttp import web
import pytest

from custom_components.tecoapi.pyplc import (
    AccessDeniedError,
    MalformedResponseError,
    NotAPlcError,
    PlcConnectionError,
    PlcResponseError,
    PlcTlsError,
    ResponseTooLargeError,
    ServiceUnavailableError,
    ValueRejectedError,
    WritesDisabledError,
)
from custom_components.tecoapi.pyplc.tekon.client import (
    MAX_ANSWER_BYTES,
    TEXT_SINCE,
    SessionLostError,
    TekonClient,
    api_version,
    decode,
    item_updates,
)
from tests.conftest import Certificate
from tests.simulator.tekon import TekonGateway, large_building
from tests.simulator.tekon.building import CONTROLLER

SETPOINT = f"{CONTROLLER}.Уставка"
DOOR = f"{CONTROLLER}.Дверь подъезда"

type Handler = Callable[[web.Request], Awaitable[web.StreamResponse]]


@contextlib.asynccontextmanager
async def serving(handler: Handler) -> AsyncIterator[str]:
    """A web server answering every path with ``handler``; yields its URL."""
    app = web.Application()
    app.router.add_route("*", "/{tail:.*}", handler)
    runner = web.AppRunner(app, access_log=None)
    await runner.setup()
    site = web.TCPSite(runner, "127.0.0.1", 0)
    await site.start()
    try:
        yield f"http://127.0.0.1:{runner.addresses[0][1]}"
    finally:
        await runner.cleanup()


async def test_a_session_reads_hash_address_space_and_updates(
    gateway: TekonGateway, http: aiohttp.ClientSession
) -> None:
    client = TekonClient(http, gateway.url)
    info = await client.server_information()
    assert (info.api_version, info.connector_version) == ("2.2", "2.2.0.41")
    assert info.current_time is not None
    assert info.start_time is not None
    session_id = await client.open_session()
    assert client.session_id == session_id
    assert await client.address_space_hash() == gateway.building.hash()
    items = await client.address_space(keep={5001})
    assert len(items) == len(gateway.building.items)
    door = next(item for item in items if item.name == DOOR)
    assert door.properties == {5001: "3000"}
    assert await client.subscribe([DOOR, SETPOINT]) == 2
    # Subscribed, nothing changed: nothing to tell until the values are asked for.
    assert await client.updates(1) == []
    assert await client.read_all() == 2
    first = await client.updates(2)
    assert {update.name: update.value for update in first} == {
        DOOR: "0",
        SETPOINT: "20",
    }
    assert all(update.quality == 192 and update.time for update in first)
    assert await client.updates(3) == []
    assert await client.subscribers_count() == 2
    assert await client.unsubscribe([DOOR]) == 1
    read = await client.read(SETPOINT)
    assert read is not None
    assert read.value == "20"
    assert await client.read("Nothing.Here") is None
    assert await client.write([(SETPOINT, "21.5")]) == 1
    assert gateway.value(SETPOINT) == "21.5"
    await client.close_session()
    assert client.session_id is None
    assert session_id not in gateway.sessions
    # Closing what is closed sends nothing.
    calls = client.request_count
    await client.close_session()
    assert client.request_count == calls
    assert client.calls["GetUpdatesText"] == 3
    assert client.calls["ReadAllItemsValues"] == 1


async def test_subscriptions_go_a_thousand_names_at_a_time(
    socket_enabled: None, http: aiohttp.ClientSession
) -> None:
    async with TekonGateway(large_building(2_500)) as gateway:
        client = TekonClient(http, gateway.url)
        await client.open_session()
        names = [item.name for item in gateway.building.items]
        assert await client.subscribe(names) == 2_500
        assert gateway.calls["SubscriberText"] == 3
        assert await client.unsubscribe(names) == 2_500
        assert gateway.calls["UnSubscriberText"] == 3


async def test_text_calls_without_text_in_the_url(
    gateway: TekonGateway, http: aiohttp.ClientSession
) -> None:
    """A gateway answering 404 at ``SubscriberText`` is asked at ``Subscriber``, once."""
    gateway.text_urls = "plain"
    client = TekonClient(http, gateway.url)
    await client.open_session()
    assert await client.subscribe([DOOR]) == 1
    assert await client.subscribe([SETPOINT]) == 1
    assert gateway.calls["SubscriberText"] == 1
    assert gateway.calls["Subscriber"] == 2
    await client.read_all()
    updates = await client.updates(1)
    # Plain GetUpdates answers by ID.
    assert {(update.name, update.item_id) for update in updates} == {
        (None, gateway.building.by_name[DOOR].item_id),
        (None, gateway.building.by_name[SETPOINT].item_id),
    }
    assert await client.write([(SETPOINT, "22")]) == 1
    assert client.plain_text_calls == {"Subscriber", "GetUpdates", "WriteItemsValues"}


async def test_errors_by_status(
    gateway: TekonGateway, http: aiohttp.ClientSession
) -> None:
    client = TekonClient(http, gateway.url)
    with pytest.raises(SessionLostError):
        await client.address_space_hash()  # no session opened
    await client.open_session()
    gateway.expire_sessions()
    with pytest.raises(SessionLostError):
        await client.address_space_hash()
    assert client.session_id is None
    await client.open_session()
    gateway.opc_available = False
    with pytest.raises(ServiceUnavailableError):
        await client.updates(1)
    assert client.session_id is None
    with pytest.raises(ServiceUnavailableError):
        await client.open_session()
    gateway.opc_available = True
    gateway.allowed = frozenset({"192.0.2.1"})
    with pytest.raises(AccessDeniedError):
        await client.server_information()
    with pytest.raises(AccessDeniedError):
        await client.open_session()
    gateway.allowed = None
    await client.open_session()
    gateway.writes_enabled = False
    with pytest.raises(WritesDisabledError):
        await client.write([(SETPOINT, "22")])
    gateway.writes_enabled = True
    with pytest.raises(ValueRejectedError):
        await client.write([(DOOR, "1")])  # a discrete input: not taken
    assert gateway.value(DOOR) == "0"


async def test_what_is_not_an_opcconnector(
    http: aiohttp.ClientSession, socket_enabled: None
) -> None:
    async def not_found(request: web.Request) -> web.Response:
        return web.Response(status=404, text="No such page")

    async def page(request: web.Request) -> web.Response:
        return web.Response(text="<html>Router</html>", content_type="text/html")

    async def other_json(request: web.Request) -> web.Response:
        return web.json_response({"name": "something"})

    for handler in (not_found, page, other_json):
        async with serving(handler) as url:
            with pytest.raises(NotAPlcError):
                await TekonClient(http, url).server_information()


async def test_answers_that_cannot_be_read(
    http: aiohttp.ClientSession, socket_enabled: None
) -> None:
    sessions = [{"session": "x"}, {"sessionid": "S"}]
    answers: dict[str, web.Response] = {
        "/GetAddressSpaceHash": web.Response(text="{broken"),
        "/GetAddressSpace": web.json_response({"items": []}),
        "/GetSubscribersCount": web.json_response({"result": "many"}),
        "/GetUpdatesText": web.json_response({"result": 1}),
        "/SubscriberText": web.json_response({"count": 1}),
        "/UnSubscriberText": web.Response(text="{broken"),
        "/ReadItemValueSyncText": web.Response(status=500),
    }

    async def handler(request: web.Request) -> web.Response:
        if request.path == "/NewSession":
            return web.json_response(sessions.pop(0))
        assert request.query["sessionid"] == "S"
        return answers[request.path]

    async with serving(handler) as url:
        client = TekonClient(http, url)
        with pytest.raises(MalformedResponseError):
            await client.open_session()
        assert client.session_id is None
        assert await client.open_session() == "S"
        with pytest.raises(MalformedResponseError):
            await client.address_space_hash()
        with pytest.raises(MalformedResponseError):
            await client.address_space()
        with pytest.raises(MalformedResponseError):
            await client.subscribers_count()
        with pytest.raises(MalformedResponseError):
            await client.updates(1)
        with pytest.raises(MalformedResponseError):
            await client.subscribe(["a"])
        with pytest.raises(MalformedResponseError):
            await client.unsubscribe(["a"])
        with pytest.raises(PlcResponseError) as err:
            await client.read("a")
        assert err.value.status == 500


async def test_counts_may_come_as_text(
    http: aiohttp.ClientSession, socket_enabled: None
) -> None:
    async def handler(request: web.Request) -> web.Response:
        if request.path == "/NewSession":
            return web.json_response({"sessionid": "S"})
        if request.path == "/GetAddressSpaceHash":
            return web.json_response({"result": ""})
        return web.json_response({"result": "10"})

    async with serving(handler) as url:
        client = TekonClient(http, url)
        await client.open_session()
        assert await client.subscribers_count() == 10
        with pytest.raises(MalformedResponseError):
            await client.address_space_hash()


async def test_an_answer_past_its_cap_is_refused(
    http: aiohttp.ClientSession, socket_enabled: None
) -> None:
    """Declared too long, or endless: refused at the cap, never read whole."""
    sent: list[int] = []

    async def handler(request: web.Request) -> web.StreamResponse:
        if request.path == "/ServerInformation":
            return web.Response(body=b"x" * (MAX_ANSWER_BYTES + 1))
        if request.path == "/NewSession":
            return web.json_response({"sessionid": "S"})
        response = web.StreamResponse()
        await response.prepare(request)
        chunk = b"[" + b" " * 65_535
        with contextlib.suppress(ConnectionError):
            for _ in range(64):
                await response.write(chunk)
                sent.append(len(chunk))
        return response

    async with serving(handler) as url:
        client = TekonClient(http, url)
        # A web server that is no gateway: too large is not an opcconnector.
        with pytest.raises(NotAPlcError) as err:
            await client.server_information()
        assert isinstance(err.value.__cause__, ResponseTooLargeError)
        await client.open_session()
        with pytest.raises(ResponseTooLargeError) as too_large:
            await client.subscribers_count()
        assert too_large.value.received > MAX_ANSWER_BYTES
        assert too_large.value.received <= MAX_ANSWER_BYTES + 65_536


async def test_nothing_answering_and_untrusted_certificates(
    http: aiohttp.ClientSession, closed_url: str, certificate: Certificate
) -> None:
    with pytest.raises(PlcConnectionError):
        await TekonClient(http, closed_url, timeout=2).server_information()
    async with TekonGateway() as gateway:
        await gateway.stop()
        await gateway.start(ssl_context=certificate.server_context())
        assert gateway.url.startswith("https://")
        with pytest.raises(PlcTlsError):
            await TekonClient(http, gateway.url).server_information()
        unchecked = TekonClient(http, gateway.url, verify_ssl=False)
        assert (await unchecked.server_information()).api_version == "2.2"


@pytest.fixture
def closed_url(socket_enabled: None) -> str:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    return f"http://127.0.0.1:{port}"


def test_answers_in_windows_1251_and_malformed_values() -> None:
    assert decode("Лифт".encode("cp1251")) == "Лифт"
    assert decode("Лифт".encode()) == "Лифт"
    updates = item_updates(
        [
            {"UpTime": "2024-05-02 10:36:06", "V": "10", "ItemName": "A", "Qual": 192},
            {"V": None, "ItemID": 3, "Qual": 0},
            {"V": "1", "ItemName": "B"},  # no quality
            {"V": "1", "ItemID": True, "Qual": 192},  # neither a name nor an ID
            {"V": "1", "ItemName": "C", "Qual": 192, "UpTime": "yesterday"},
            "not a value",
        ]
    )
    assert [(u.name, u.item_id, u.value, u.quality) for u in updates] == [
        ("A", None, "10", 192),
        (None, 3, "", 0),
        ("C", None, "1", 192),
    ]
    assert updates[0].time is not None
    assert updates[2].time is None


async def test_the_alldata_session(
    gateway: TekonGateway, http: aiohttp.ClientSession
) -> None:
    """Every change between two updates is the default (seed: NewSession alldata=1)."""
    client = TekonClient(http, gateway.url)
    assert client.alldata
    await client.open_session()
    assert client.session_id is not None
    assert gateway.sessions[client.session_id].alldata
    await client.subscribe([DOOR])
    await client.updates(1)
    gateway.set_value(DOOR, "1")
    gateway.set_value(DOOR, "0")
    assert [update.value for update in await client.updates(2)] == ["1", "0"]


def test_api_versions_are_read_as_numbers() -> None:
    assert api_version("2.1") == (2, 1)
    assert api_version(" 2.2.0 ") == (2, 2, 0)
    assert api_version("2.x") is None
    assert api_version("") is None


async def test_a_version_that_is_none_asks_every_text_call_at_its_text_url(
    gateway: TekonGateway, http: aiohttp.ClientSession
) -> None:
    """What ServerInformation tells is a hint: a version it cannot read moves no call."""
    client = TekonClient(http, gateway.url)
    gateway.reported_version = "two"
    server = await client.server_information()
    assert (server.api_version, server.version) == ("two", None)
    assert client.plain_text_calls == set()
    gateway.reported_version = "2.0"
    await client.server_information()
    assert client.plain_text_calls == set(TEXT_SINCE)
