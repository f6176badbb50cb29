"""Every failure becomes the client's own error: faults, TLS, strangers, silence."""

from collections.abc import AsyncIterator, Awaitable, Callable
import socket
import ssl

import aiohttp
from aiohttp import web
from aiohttp.test_utils import TestServer
import pytest

from custom_components.tecoapi.pyplc import (
    NoPublicVariablesError,
    NotAPlcError,
    PlcAuthenticationError,
    PlcConnectionError,
    PlcError,
    PlcResponseError,
    PlcTlsError,
    VariableListTooLargeError,
    VariableListUnreadableError,
)
from custom_components.tecoapi.pyplc.tecomat import TecoApiClient
from tests.conftest import SIM_PASSWORD, SIM_USERNAME
from tests.pyplc.conftest import StartSimulator, make_client
from tests.simulator import Program, Simulator, load_program

type Handler = Callable[[web.Request], Awaitable[web.StreamResponse]]


@pytest.fixture
async def stranger(
    socket_enabled: None,
) -> AsyncIterator[Callable[[Handler], Awaitable[str]]]:
    """Start a web server that is not a PLC; return its host."""
    servers: list[TestServer] = []

    async def start(handler: Handler) -> str:
        app = web.Application()
        app.router.add_route("*", "/{tail:.*}", handler)
        server = TestServer(app, host="127.0.0.1")
        await server.start_server()
        servers.append(server)
        return f"127.0.0.1:{server.port}"

    yield start
    for server in servers:
        await server.close()


@pytest.mark.parametrize(
    ("fault", "code", "status"),
    [
        ("http_500", "500.012", 500),
        ("truncated_json", "200.000", 200),
        ("malformed_json", "200.000", 200),
    ],
)
async def test_broken_answers_are_response_errors(
    manual_client: TecoApiClient,
    manual_simulator: Simulator,
    fault: str,
    code: str,
    status: int,
) -> None:
    await manual_client.get_info()
    setattr(manual_simulator.faults, fault, True)
    with pytest.raises(PlcResponseError) as caught:
        await manual_client.get_list()
    assert caught.value.code == code
    assert caught.value.status == status
    setattr(manual_simulator.faults, fault, False)
    assert "plcName" in await manual_client.get_list()


async def test_a_dropped_connection_is_a_connection_error(
    manual_client: TecoApiClient, manual_simulator: Simulator
) -> None:
    await manual_client.get_info()
    manual_simulator.faults.drop_connection = True
    with pytest.raises(PlcConnectionError):
        await manual_client.get_list()
    manual_simulator.faults.drop_connection = False
    assert "plcName" in await manual_client.get_list()


async def test_one_dropped_connection_is_retried_by_aiohttp(
    manual_client: TecoApiClient, manual_simulator: Simulator
) -> None:
    await manual_client.get_info()
    manual_simulator.faults.drop_connection = True
    manual_simulator.faults.remaining = 1
    assert "plcName" in await manual_client.get_list()
    assert [record.status for record in manual_simulator.requests[-2:]] == [0, 200]
    assert manual_client.request_count == len(manual_simulator.requests)


async def test_latency_beyond_the_timeout_is_a_connection_error(
    start_simulator: StartSimulator, session: aiohttp.ClientSession
) -> None:
    sim = await start_simulator()
    client = make_client(session, sim, timeout=0.3)
    await client.get_info()
    sim.faults.latency = 2.0
    with pytest.raises(PlcConnectionError):
        await client.get_list()


async def test_a_hung_response_is_a_connection_error(
    start_simulator: StartSimulator, session: aiohttp.ClientSession
) -> None:
    sim = await start_simulator()
    client = make_client(session, sim, timeout=0.3)
    await client.get_info()
    sim.faults.hang = True
    with pytest.raises(PlcConnectionError):
        await client.get_list()
    sim.faults.hang = False


async def test_an_unreachable_plc_is_a_connection_error(
    session: aiohttp.ClientSession, socket_enabled: None
) -> None:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    client = TecoApiClient(session, f"127.0.0.1:{port}", "u", "p", timeout=2)
    with pytest.raises(PlcConnectionError) as caught:
        await client.get_info()
    assert not isinstance(caught.value, PlcTlsError)


async def test_plc_error_codes_come_with_their_message(
    start_simulator: StartSimulator, session: aiohttp.ClientSession
) -> None:
    source = load_program("manual").to_mapping()
    source["publicFile"] = "missing"
    sim = await start_simulator(Program.from_mapping(source))
    client = make_client(session, sim)
    with pytest.raises(PlcResponseError) as caught:
        await client.get_list()
    assert caught.value.code == "500.010"
    assert caught.value.status == 500
    assert "Public file" in caught.value.message


@pytest.mark.parametrize(
    ("public_file", "code", "error"),
    [
        ("missing", "500.010", NoPublicVariablesError),
        ("too_big", "500.011", VariableListTooLargeError),
        ("unreadable", "500.012", VariableListUnreadableError),
        ("empty", "400.006", NoPublicVariablesError),
    ],
)
async def test_each_public_file_error_is_its_own(
    start_simulator: StartSimulator,
    session: aiohttp.ClientSession,
    public_file: str,
    code: str,
    error: type[PlcResponseError],
) -> None:
    """The manual's §3.7: no public file, one over 128 KB, one the PLC cannot read.

    Only the first (and an empty list) mean that the program publishes nothing.
    """
    source = load_program("manual").to_mapping()
    source["publicFile"] = public_file
    sim = await start_simulator(Program.from_mapping(source))
    client = make_client(session, sim)
    with pytest.raises(PlcResponseError) as caught:
        await client.get_list()
    assert type(caught.value) is error
    assert caught.value.code == code


async def test_https_with_an_untrusted_certificate_is_a_tls_error(
    start_simulator: StartSimulator,
    session: aiohttp.ClientSession,
    server_tls: ssl.SSLContext,
) -> None:
    sim = await start_simulator(ssl_context=server_tls)
    assert sim.url.startswith("https://")
    client = make_client(session, sim)
    with pytest.raises(PlcTlsError):
        await client.get_info()


async def test_https_without_verification_works(
    start_simulator: StartSimulator,
    session: aiohttp.ClientSession,
    server_tls: ssl.SSLContext,
) -> None:
    sim = await start_simulator(ssl_context=server_tls)
    client = make_client(session, sim, verify_ssl=False)
    info = await client.get_info()
    assert info.serial_number == "VN 1957"
    catalogue = await client.discover()
    assert "main.myobject3" in catalogue.points


async def test_https_with_a_trusted_certificate_verifies_and_works(
    start_simulator: StartSimulator,
    server_tls: ssl.SSLContext,
    certificate: tuple[object, object],
) -> None:
    sim = await start_simulator(ssl_context=server_tls)
    trusting = ssl.create_default_context(cafile=str(certificate[0]))
    connector = aiohttp.TCPConnector(ssl=trusting)
    async with aiohttp.ClientSession(connector=connector) as session:
        client = TecoApiClient(session, sim.url, SIM_USERNAME, SIM_PASSWORD)
        assert (await client.get_info()).serial_number == "VN 1957"


async def test_a_web_page_is_not_tecoapi(
    stranger: Callable[[Handler], Awaitable[str]], session: aiohttp.ClientSession
) -> None:
    async def page(request: web.Request) -> web.Response:
        return web.Response(text="<html>router</html>", content_type="text/html")

    client = TecoApiClient(session, await stranger(page), "u", "p")
    with pytest.raises(NotAPlcError):
        await client.get_info()


async def test_a_404_is_not_tecoapi(
    stranger: Callable[[Handler], Awaitable[str]], session: aiohttp.ClientSession
) -> None:
    async def missing(request: web.Request) -> web.Response:
        return web.Response(status=404, text="Not Found")

    client = TecoApiClient(session, await stranger(missing), "u", "p")
    with pytest.raises(NotAPlcError):
        await client.get_info()


async def test_a_foreign_login_is_not_tecoapi(
    stranger: Callable[[Handler], Awaitable[str]], session: aiohttp.ClientSession
) -> None:
    async def login(request: web.Request) -> web.Response:
        return web.Response(
            status=401, headers={"WWW-Authenticate": 'Basic realm="Router"'}
        )

    client = TecoApiClient(session, await stranger(login), "u", "p")
    with pytest.raises(NotAPlcError):
        await client.get_info()


async def test_json_without_a_plc_is_not_tecoapi(
    stranger: Callable[[Handler], Awaitable[str]], session: aiohttp.ClientSession
) -> None:
    async def other_api(request: web.Request) -> web.Response:
        return web.json_response({"status": "ok"})

    client = TecoApiClient(session, await stranger(other_api), "u", "p")
    with pytest.raises(NotAPlcError):
        await client.get_info()


async def test_a_redirect_is_not_followed(
    stranger: Callable[[Handler], Awaitable[str]], session: aiohttp.ClientSession
) -> None:
    async def moved(request: web.Request) -> web.Response:
        raise web.HTTPFound("https://elsewhere.invalid/login")

    client = TecoApiClient(session, await stranger(moved), "u", "p")
    with pytest.raises(NotAPlcError):
        await client.get_info()


async def test_an_error_without_a_teco_body_keeps_its_status(
    stranger: Callable[[Handler], Awaitable[str]], session: aiohttp.ClientSession
) -> None:
    async def busy(request: web.Request) -> web.Response:
        return web.Response(status=503, text="busy")

    client = TecoApiClient(session, await stranger(busy), "u", "p")
    with pytest.raises(PlcResponseError) as caught:
        await client.get_info()
    assert caught.value.code == "503.000"
    assert caught.value.status == 503


async def test_no_error_message_ever_holds_the_password(
    start_simulator: StartSimulator, session: aiohttp.ClientSession
) -> None:
    sim = await start_simulator(password="Sup3r-S3cret-Pw")
    messages: list[str] = []
    for password in ("Sup3r-S3cret-Pw", "Wr0ng-S3cret-Pw"):
        client = TecoApiClient(session, sim.url, SIM_USERNAME, password, timeout=0.3)
        for fault in ("http_500", "malformed_json", "drop_connection", "hang", None):
            sim.faults.clear()
            if fault is not None:
                setattr(sim.faults, fault, True)
            try:
                await client.get_info()
            except PlcError as err:
                messages.append(f"{err!s} {err!r}")
        sim.faults.clear()
    assert len(messages) >= 5
    for message in messages:
        assert "S3cret" not in message


async def test_a_web_page_as_an_error_is_not_tecoapi(
    stranger: Callable[[Handler], Awaitable[str]], session: aiohttp.ClientSession
) -> None:
    async def crash(request: web.Request) -> web.Response:
        return web.Response(status=500, text="<h1>oops</h1>", content_type="text/html")

    client = TecoApiClient(session, await stranger(crash), "u", "p")
    with pytest.raises(NotAPlcError):
        await client.get_list()


async def test_an_unsupported_method_answer_is_an_authentication_error(
    stranger: Callable[[Handler], Awaitable[str]], session: aiohttp.ClientSession
) -> None:
    async def refuse(request: web.Request) -> web.Response:
        body = {
            "error": {"code": "403.022", "message": "Unsupported authentication method"}
        }
        return web.json_response(body, status=403)

    client = TecoApiClient(session, await stranger(refuse), "u", "p")
    with pytest.raises(PlcAuthenticationError, match=r"403\.022"):
        await client.get_info()


async def test_get_object_must_answer_an_object(
    stranger: Callable[[Handler], Awaitable[str]], session: aiohttp.ClientSession
) -> None:
    async def listing(request: web.Request) -> web.Response:
        return web.json_response([1, 2])

    client = TecoApiClient(session, await stranger(listing), "u", "p")
    with pytest.raises(PlcResponseError, match="other than an object"):
        await client.get_object(["x"])


async def test_other_errors_during_discovery_and_polling_are_raised(
    manual_client: TecoApiClient, manual_simulator: Simulator
) -> None:
    catalogue = await manual_client.discover()
    plan = manual_client.plan(catalogue.points.values(), with_attrs=False)
    manual_simulator.faults.http_500 = True
    with pytest.raises(PlcResponseError, match=r"500\.012"):
        await manual_client.discover()
    with pytest.raises(PlcResponseError, match=r"500\.012"):
        await manual_client.read(plan, catalogue.points)
    manual_simulator.faults.http_500 = False
    # The failed discovery left the catalogue the planner uses as it was.
    assert manual_client.plan(catalogue.points.values(), with_attrs=False) == plan
