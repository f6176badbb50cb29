"""The web panel client over real HTTP: sign-in, reads, limits, writes, failures."""

import json
import logging
import socket

import aiohttp
from aiohttp import web
import pytest

from custom_components.tecoapi.pyplc import (
    NotAPlcError,
    PlcAuthenticationError,
    PlcConnectionError,
    PlcResponseError,
    PlcTlsError,
    ResponseTooLargeError,
    ValueRejectedError,
)
from custom_components.tecoapi.pyplc.core.pointmap import data_type
from custom_components.tecoapi.pyplc.mervis import (
    Address,
    IdStyle,
    MervisClient,
    RequestRefusedError,
)
from custom_components.tecoapi.pyplc.mervis.client import answer_limit
from tests.conftest import Certificate
from tests.simulator.mervis import MervisSimulator

from .conftest import PASSWORD, USER, Serve, StartMervis, client_of


def address_of(sim: MervisSimulator, name: str) -> Address:
    row = sim.project.row(name)
    return Address(row.commuid, row.offset, row.length)


async def test_sign_in_then_read_with_the_c_it_gave(
    http: aiohttp.ClientSession, mervis: MervisSimulator
) -> None:
    client = client_of(http, mervis)
    address = address_of(mervis, "koupelna.temperature")
    items = await client.values([address])
    assert items[address].value == bytes.fromhex("41AC0000")
    assert items[address].good
    assert [record.service for record in mervis.requests] == ["login", "values"]
    # What came back, not the password, is what the read carried.
    assert client.session_credentials["p"] != PASSWORD
    assert (client.request_count, client.logins) == (2, 1)


async def test_a_project_without_credentials_is_read_without_c(
    http: aiohttp.ClientSession, start_mervis: StartMervis
) -> None:
    sim = await start_mervis(username=None)
    client = MervisClient(http, sim.url)
    await client.login()
    address = address_of(sim, "away")
    assert (await client.values([address]))[address].value == b"\x00"
    assert [record.service for record in sim.requests] == ["values"]
    assert not client.signs_in


async def test_wrong_credentials_are_refused(
    http: aiohttp.ClientSession, mervis: MervisSimulator
) -> None:
    client = client_of(http, mervis, password="wrong")
    with pytest.raises(PlcAuthenticationError, match="refused the credentials"):
        await client.login()


async def test_a_project_with_credentials_asks_a_client_without(
    http: aiohttp.ClientSession, mervis: MervisSimulator
) -> None:
    client = MervisClient(http, mervis.url)
    with pytest.raises(PlcAuthenticationError, match="asks for credentials"):
        await client.values([address_of(mervis, "away")])


async def test_an_expired_session_signs_in_again(
    http: aiohttp.ClientSession, start_mervis: StartMervis
) -> None:
    sim = await start_mervis(session_requests=2, accept_plain=False)
    client = client_of(http, sim)
    address = address_of(sim, "away")
    for _ in range(3):
        await client.values([address])
    assert client.logins == 2
    sim.expire_sessions()
    await client.values([address])
    assert client.logins == 3


async def test_a_refusal_that_says_nothing_is_a_limit_only_after_a_fresh_sign_in(
    http: aiohttp.ClientSession, serve: Serve
) -> None:
    """An expired session may refuse a read larger than any taken without a word.

    Such a refusal was taken as the limits' (lowered, and kept in the entry's
    store for good); the read is sent again after signing in first.
    """
    tokens = iter(["s1", "s2", "s3"])
    valid: set[str] = set()

    async def panel(request: web.Request) -> web.Response:
        message = await request.json()
        if request.path == "/login.cgi":
            valid.add(token := next(tokens))
            return web.json_response({"ver": 1, "code": "ok", "c": {"p": token}})
        if message["c"]["p"] not in valid or len(message["v"]) > 3:
            return web.json_response({"ver": 1, "code": "error", "msg": ""})
        return web.json_response({"ver": 1, "code": "ok", "v": []})

    client = MervisClient(http, await serve(panel), "u", "p")
    addresses = [Address(index, 0, 1) for index in range(1, 5)]
    await client.values(addresses[:2])
    valid.clear()  # the session expires
    await client.values(addresses[:3])  # refused, signed in again, taken
    assert (client.logins, client.request_count) == (2, 5)
    assert client.limits_state()["refused"] == [None, None]
    assert client.max_variables == 64
    # A refusal that stands after a fresh sign-in is the limits'.
    with pytest.raises(RequestRefusedError) as refused:
        await client.values(addresses)
    assert (client.logins, client.request_count) == (3, 8)
    assert client.learn_refusal(refused.value)
    assert client.max_variables == 3


async def test_a_password_changed_meanwhile_is_an_authentication_error(
    http: aiohttp.ClientSession, mervis: MervisSimulator
) -> None:
    client = client_of(http, mervis)
    address = address_of(mervis, "away")
    await client.values([address])
    mervis.password = "changed"
    mervis.switches.accept_plain = False
    mervis.expire_sessions()
    with pytest.raises(PlcAuthenticationError):
        await client.values([address])


@pytest.mark.parametrize("spelling", ["released", "seed"])
async def test_answers_match_by_variable_in_any_order_and_spelling(
    http: aiohttp.ClientSession, start_mervis: StartMervis, spelling: str
) -> None:
    sim = await start_mervis(spelling=spelling, order="reversed", quality="good")
    client = client_of(http, sim)
    client.id_style = IdStyle.RELEASED if spelling == "released" else IdStyle.SEED
    wanted = [address_of(sim, name) for name in ("outside_temp", "away", "boost")]
    items = await client.values(wanted)
    assert [items[address].value for address in wanted] == [
        bytes.fromhex("40900000"),
        b"\x00",
        (30 * 60 * 10_000_000).to_bytes(8, "big"),
    ]
    assert all(item.good for item in items.values())


async def test_an_id_in_a_spelling_the_controller_does_not_know_is_an_item_error(
    http: aiohttp.ClientSession, start_mervis: StartMervis
) -> None:
    sim = await start_mervis(spelling="seed")
    client = client_of(http, sim)
    address = address_of(sim, "away")
    item = (await client.values([address]))[address]
    assert (item.good, item.error) == (False, "unknown variable")


async def test_item_errors_and_qualities_are_the_items_own(
    http: aiohttp.ClientSession, start_mervis: StartMervis
) -> None:
    sim = await start_mervis()
    away, boost, clock = (address_of(sim, name) for name in ("away", "boost", "clock"))
    sim.switches.item_errors.add(away.commuid)
    sim.switches.qualities[boost.commuid] = "B"
    items = await client_of(http, sim).values([away, boost, clock])
    assert items[away].error == "unknown variable"
    assert (items[boost].good, items[boost].quality) == (False, "B")
    assert items[boost].value is not None
    assert items[clock].good


async def test_limits_the_controller_tells_are_taken(
    http: aiohttp.ClientSession, start_mervis: StartMervis
) -> None:
    sim = await start_mervis(max_variables=5, max_request_size=1500, tell_limits=True)
    client = client_of(http, sim)
    await client.login()
    assert (client.max_variables, client.max_request_size) == (5, 1500)
    assert client.limits_told
    assert client.platform == "uPLC"
    # Told limits are kept while a refused request held more than they allow.
    assert client.learn_refusal(RequestRefusedError("", variables=6, body_bytes=300))
    assert client.learn_refusal(RequestRefusedError("", variables=5, body_bytes=1501))
    assert (client.max_variables, client.max_request_size) == (5, 1500)
    assert client.limits_told


def test_a_refusal_within_the_limits_told_lowers_them() -> None:
    """The controller takes fewer than it told (or than a store kept): learned anew.

    Such a refusal taught nothing: every poll was refused and split again.
    """
    client = MervisClient(None, "127.0.0.1")  # type: ignore[arg-type]
    assert client.restore_limits(
        {
            "max_variables": 10,
            "max_request_size": 1500,
            "told": True,
            "taken": [10, 600],
            "refused": [None, None],
            "platform": "uPLC",
        }
    )
    assert client.learn_refusal(RequestRefusedError("", variables=8, body_bytes=500))
    assert (client.max_variables, client.max_request_size) == (4, 1500)
    assert not client.limits_told
    # One variable refused is that variable's, whatever was told.
    client.limits_told = True
    assert not client.learn_refusal(RequestRefusedError("", variables=1))
    assert client.limits_told


async def test_a_refused_request_lowers_the_limits_and_they_converge(
    http: aiohttp.ClientSession, start_mervis: StartMervis
) -> None:
    """No limit told: the count of IDs is searched between taken and refused."""
    sim = await start_mervis(max_variables=5)
    client = client_of(http, sim)
    wanted = [Address(17000 + index, 0, 1) for index in range(18)]
    with pytest.raises(RequestRefusedError) as refused:
        await client.values(wanted[:64])
    assert refused.value.variables == 18
    assert client.learn_refusal(refused.value)
    assert client.max_variables == 9
    learned = []
    for _ in range(6):
        refusal: RequestRefusedError | None = None
        try:
            await client.values(wanted[: client.max_variables])
        except RequestRefusedError as err:
            refusal = err
        if refusal is not None:
            assert client.learn_refusal(refusal)
        learned.append(client.max_variables)
    # 9 refused: 4; 4 taken: halfway up, 6; 6 refused: 5; 5 taken, and it stays.
    assert learned == [4, 6, 5, 5, 5, 5]


async def test_a_body_too_large_lowers_the_byte_limit(
    http: aiohttp.ClientSession, start_mervis: StartMervis
) -> None:
    """As many IDs as were taken, but longer ones: the bytes are to blame."""
    sim = await start_mervis(max_request_size=400)
    client = client_of(http, sim)
    await client.values([Address(17000 + index, 0, 1) for index in range(8)])
    longer = [Address(1234567890 + index, 1000000, 1) for index in range(8)]
    with pytest.raises(RequestRefusedError) as refused:
        await client.values(longer)
    assert refused.value.body_bytes > 400
    assert client.learn_refusal(refused.value)
    assert client.max_variables == 64
    assert 300 < client.max_request_size < refused.value.body_bytes


def test_a_refusal_of_what_was_taken_means_the_limits_changed() -> None:
    """What was learned is forgotten; the count is searched again from nothing."""
    client = MervisClient(None, "127.0.0.1")  # type: ignore[arg-type]
    kept = {**client.limits_state(), "taken": [10, 1000]}  # from an earlier run
    assert client.restore_limits(kept)
    assert client.learn_refusal(
        RequestRefusedError("busy", variables=6, body_bytes=500)
    )
    assert client.max_variables == 3
    assert client.limits_state()["taken"] == [0, 0]
    assert not client.learn_refusal(RequestRefusedError("busy", variables=1))


async def test_writes_go_one_variable_at_a_time_as_json_values(
    http: aiohttp.ClientSession, mervis: MervisSimulator
) -> None:
    client = client_of(http, mervis)
    setpoint = address_of(mervis, "koupelna.setpoint")
    await client.write(setpoint, data_type("real"), "koupelna.setpoint", 23.5)  # type: ignore[arg-type]
    relay = address_of(mervis, "hw.neuron_l203_ro_2.01")
    await client.write(relay, data_type("bool"), "relay", True)  # type: ignore[arg-type]
    assert mervis.project.get("koupelna.setpoint") == 23.5
    assert mervis.project.get("hw.neuron_l203_ro_2.01") is True
    assert client.write_format == "plain"
    assert mervis.writes == [("koupelna.setpoint", 23.5), ("hw.neuron_l203_ro_2.01", 1)]


async def test_a_bool_carries_what_a_public_client_sends(
    http: aiohttp.ClientSession, serve: Serve
) -> None:
    bodies: list[dict[str, object]] = []

    async def panel(request: web.Request) -> web.Response:
        bodies.append(await request.json())
        return web.json_response({"ver": 1, "code": "ok", "msg": ""})

    client = MervisClient(http, await serve(panel))
    await client.write(Address(1, 0, 1), data_type("bool"), "x", True)  # type: ignore[arg-type]
    assert bodies == [
        {
            "ver": 1,
            "v": [
                {
                    "i": "svc://DefaultConnection/1[0,1]",
                    "set": 1,
                    "defaultValue": 1,
                    "time": "0",
                }
            ],
        }
    ]


async def test_a_controller_taking_hex_writes_learns_it_once(
    http: aiohttp.ClientSession, start_mervis: StartMervis
) -> None:
    sim = await start_mervis(write_encoding="hex")
    client = client_of(http, sim)
    setpoint = address_of(sim, "jidelna.setpoint")
    await client.write(setpoint, data_type("real"), "jidelna.setpoint", 20.0)  # type: ignore[arg-type]
    assert client.write_format == "hex"
    assert sim.project.get("jidelna.setpoint") == 20.0
    sim.clear_requests()
    await client.write(setpoint, data_type("real"), "jidelna.setpoint", 21.0)  # type: ignore[arg-type]
    assert sim.count("command") == 1


async def test_a_refused_value_changes_nothing_and_says_why(
    http: aiohttp.ClientSession, mervis: MervisSimulator
) -> None:
    client = client_of(http, mervis)
    with pytest.raises(ValueRejectedError, match="unknown variable"):
        await client.write(Address(99, 0, 4), data_type("real"), "nowhere", 1.0)  # type: ignore[arg-type]
    assert mervis.writes == []


async def test_a_command_item_error_is_a_refusal(
    http: aiohttp.ClientSession, serve: Serve
) -> None:
    async def panel(request: web.Request) -> web.Response:
        return web.json_response(
            {"ver": 1, "code": "ok", "v": [{"i": "x", "e": "read only"}]}
        )

    client = MervisClient(http, await serve(panel))
    with pytest.raises(ValueRejectedError, match="read only"):
        await client.write(Address(1, 0, 2), data_type("int"), "x", 5)  # type: ignore[arg-type]


@pytest.mark.parametrize(
    ("answer", "error"),
    [
        ((404, b"<html>Not found</html>", "text/html"), NotAPlcError),
        ((200, b"<html>Hello</html>", "text/html"), NotAPlcError),
        ((200, b'{"hello": "world"}', "application/json"), NotAPlcError),
        ((302, b"", "text/plain"), NotAPlcError),
        ((401, b"", "text/plain"), PlcAuthenticationError),
        ((403, b"{}", "application/json"), PlcAuthenticationError),
        ((500, b"oops", "text/plain"), PlcResponseError),
    ],
)
async def test_what_is_no_web_panel(
    http: aiohttp.ClientSession,
    serve: Serve,
    answer: tuple[int, bytes, str],
    error: type[Exception],
) -> None:
    status, body, content_type = answer

    async def device(request: web.Request) -> web.Response:
        return web.Response(status=status, body=body, content_type=content_type)

    client = MervisClient(http, await serve(device), USER, PASSWORD)
    with pytest.raises(error):
        await client.login()


async def test_http_413_is_a_refusal_of_the_request(
    http: aiohttp.ClientSession, serve: Serve
) -> None:
    async def device(request: web.Request) -> web.Response:
        return web.Response(status=413, text="too large")

    client = MervisClient(http, await serve(device))
    with pytest.raises(RequestRefusedError) as refused:
        await client.values([Address(1, 0, 1), Address(2, 0, 1)])
    assert (refused.value.variables, refused.value.code) == (2, "413")


async def test_an_answer_too_large_is_cut(
    http: aiohttp.ClientSession, serve: Serve
) -> None:
    async def endless(request: web.Request) -> web.StreamResponse:
        response = web.StreamResponse()
        await response.prepare(request)
        for _ in range(64):
            await response.write(b" " * 65536)
        return response

    async def declared(request: web.Request) -> web.Response:
        return web.Response(body=b" " * (answer_limit([1]) + 1))

    for handler in (endless, declared):
        client = MervisClient(http, await serve(handler))
        with pytest.raises(ResponseTooLargeError):
            await client.values([Address(1, 0, 1)])


async def test_malformed_items_are_errors_of_their_own(
    http: aiohttp.ClientSession, serve: Serve
) -> None:
    async def device(request: web.Request) -> web.Response:
        return web.json_response(
            {
                "ver": 1,
                "code": "ok",
                "v": [
                    {"i": "svc://DefaultConnection/1[0,1]", "v": "zz", "q": "G"},
                    {"i": "svc://DefaultConnection/2[0,1]", "v": 5},
                    {"i": "svc://DefaultConnection/3[0,1]", "e": ""},
                    {"i": "svc://DefaultConnection/9[0,1]", "v": "01", "q": "G"},
                    "junk",
                ],
            }
        )

    client = MervisClient(http, await serve(device))
    wanted = [Address(index, 0, 1) for index in (1, 2, 3, 4)]
    items = await client.values(wanted)
    assert items[wanted[0]].error == "not hex"
    assert items[wanted[1]].error == "not hex"
    assert items[wanted[1]].quality == ""
    assert items[wanted[2]].error == "error"
    assert wanted[3] not in items


async def test_an_answer_without_a_list_is_malformed(
    http: aiohttp.ClientSession, serve: Serve
) -> None:
    async def device(request: web.Request) -> web.Response:
        return web.json_response({"ver": 1, "code": "ok"})

    with pytest.raises(PlcResponseError, match="without a list"):
        await MervisClient(http, await serve(device)).values([Address(1, 0, 1)])


async def test_nothing_answering_is_a_connection_error(
    http: aiohttp.ClientSession, socket_enabled: None
) -> None:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    client = MervisClient(http, f"127.0.0.1:{port}", USER, PASSWORD, timeout=2)
    with pytest.raises(PlcConnectionError):
        await client.login()


async def test_credentials_never_reach_the_log(
    http: aiohttp.ClientSession,
    start_mervis: StartMervis,
    caplog: pytest.LogCaptureFixture,
) -> None:
    caplog.set_level(logging.DEBUG)
    sim = await start_mervis(max_variables=2, session_requests=1, accept_plain=False)
    client = client_of(http, sim)
    wanted = [address_of(sim, name) for name in ("away", "boost", "clock")]
    with pytest.raises(RequestRefusedError):
        await client.values(wanted)
    await client.values(wanted[:1])
    with pytest.raises(PlcAuthenticationError) as refused:
        await client_of(http, sim, password="wrong-" + PASSWORD).login()
    logged = caplog.text + str(refused.value)
    assert "Signed in" in logged
    assert PASSWORD not in logged
    assert json.dumps(PASSWORD)[1:-1] not in logged


async def test_a_certificate_not_trusted_is_said(
    http: aiohttp.ClientSession, socket_enabled: None, certificate: Certificate
) -> None:
    sim = MervisSimulator(password=PASSWORD)
    await sim.start(ssl_context=certificate.server_context())
    try:
        with pytest.raises(PlcTlsError):
            await client_of(http, sim).login()
        trusting = client_of(http, sim, verify_ssl=False)
        await trusting.login()
        assert trusting.base_url.startswith("https://")
    finally:
        await sim.stop()


async def test_a_byte_limit_learned_grows_back_towards_the_refusal(
    http: aiohttp.ClientSession, start_mervis: StartMervis
) -> None:
    sim = await start_mervis(max_request_size=400)
    client = client_of(http, sim)
    await client.values([Address(17000 + index, 0, 1) for index in range(8)])
    longer = [Address(1234567890 + index, 1000000, 1) for index in range(8)]
    with pytest.raises(RequestRefusedError) as refused:
        await client.values(longer)
    client.learn_refusal(refused.value)
    lowered = client.max_request_size
    # Eight IDs a little longer than the first, within the lowered limit.
    medium = [Address(17000 + index, 100, 1) for index in range(8)]
    await client.values(medium)
    assert lowered < client.max_request_size < refused.value.body_bytes


async def test_an_answer_in_windows_1250_is_read(
    http: aiohttp.ClientSession, serve: Serve
) -> None:
    async def device(request: web.Request) -> web.Response:
        body = '{"ver":1,"code":"chyba","msg":"Příliš mnoho proměnných"}'
        return web.Response(body=body.encode("cp1250"), content_type="application/json")

    with pytest.raises(RequestRefusedError, match="Příliš mnoho"):
        await MervisClient(http, await serve(device)).values([Address(1, 0, 1)])
