"""Authentication against the simulator: Digest, Basic, stale nonces, bad passwords."""

import aiohttp
import pytest

from custom_components.tecoapi.pyplc import PlcAuthenticationError
from custom_components.tecoapi.pyplc.tecomat import TecoApiClient
from tests.conftest import SIM_PASSWORD, SIM_USERNAME
from tests.pyplc.conftest import HeaderLog, StartSimulator, make_client


async def test_digest_one_challenge_then_one_round_trip_per_request(
    start_simulator: StartSimulator,
    session: aiohttp.ClientSession,
    header_log: HeaderLog,
) -> None:
    sim = await start_simulator(auth="digest")
    client = make_client(session, sim)
    await client.get_info()
    await client.get_list()
    await client.get_object(["plcName"])
    assert client.auth_scheme == "digest"
    assert client.request_count == len(sim.requests) == 4
    assert [record.status for record in sim.requests] == [401, 200, 200, 200]
    first, *rest = header_log.authorizations
    assert first is None
    assert all(header is not None and header.startswith("Digest ") for header in rest)


async def test_basic_only_when_the_plc_offers_nothing_else(
    start_simulator: StartSimulator,
    session: aiohttp.ClientSession,
    header_log: HeaderLog,
) -> None:
    sim = await start_simulator(auth="basic")
    client = make_client(session, sim)
    info = await client.get_info()
    assert info.serial_number == "VN 1957"
    await client.get_object(["plcType"])
    assert client.auth_scheme == "basic"
    assert client.request_count == len(sim.requests) == 3
    assert [record.status for record in sim.requests] == [401, 200, 200]
    first, *rest = header_log.authorizations
    assert first is None
    assert all(header is not None and header.startswith("Basic ") for header in rest)


async def test_digest_is_preferred_when_both_are_offered(
    start_simulator: StartSimulator,
    session: aiohttp.ClientSession,
    header_log: HeaderLog,
) -> None:
    sim = await start_simulator(auth="both")
    client = make_client(session, sim)
    await client.get_info()
    await client.get_list()
    assert client.auth_scheme == "digest"
    assert not any(
        header is not None and header.startswith("Basic")
        for header in header_log.authorizations
    )
    assert client.request_count == 3


async def test_stale_nonces_are_renewed_without_an_error(
    start_simulator: StartSimulator, session: aiohttp.ClientSession
) -> None:
    sim = await start_simulator(auth="digest", nonce_max_uses=1)
    client = make_client(session, sim)
    await client.get_info()
    for _ in range(3):
        assert await client.get_object(["plcType"]) == {"plcType": 2005}
    # Each later request: the used nonce is stale (401.020), the fresh one works.
    assert [record.status for record in sim.requests] == [401, 200] + [401, 200] * 3
    assert client.request_count == 8


async def test_a_nonce_expiring_mid_session_is_renewed(
    start_simulator: StartSimulator, session: aiohttp.ClientSession
) -> None:
    sim = await start_simulator(auth="digest", nonce_max_uses=3)
    client = make_client(session, sim)
    for _ in range(5):
        await client.get_object(["plcName"])
    assert [record.status for record in sim.requests] == [
        401,
        200,
        200,
        200,
        401,
        200,
        200,
    ]


@pytest.mark.parametrize("auth", ["digest", "basic", "both"])
async def test_a_wrong_password_is_an_authentication_error(
    start_simulator: StartSimulator, session: aiohttp.ClientSession, auth: str
) -> None:
    sim = await start_simulator(auth=auth)
    wrong = "Wr0ng-Pa55-zz"
    client = TecoApiClient(session, sim.url, SIM_USERNAME, wrong)
    with pytest.raises(PlcAuthenticationError) as caught:
        await client.get_info()
    assert "401.021" in str(caught.value)
    assert wrong not in str(caught.value)
    assert wrong not in repr(caught.value.args)


async def test_a_password_changed_on_the_plc_is_noticed(
    start_simulator: StartSimulator, session: aiohttp.ClientSession
) -> None:
    sim = await start_simulator(auth="digest")
    client = make_client(session, sim)
    await client.get_info()
    sim.password = "changed-on-the-plc"
    with pytest.raises(PlcAuthenticationError):
        await client.get_list()
    sim.password = SIM_PASSWORD
    assert await client.get_list()


async def test_an_unknown_user_is_an_authentication_error(
    start_simulator: StartSimulator, session: aiohttp.ClientSession
) -> None:
    sim = await start_simulator(auth="basic")
    client = TecoApiClient(session, sim.url, "nobody", SIM_PASSWORD)
    with pytest.raises(PlcAuthenticationError):
        await client.get_info()


async def test_a_user_name_with_a_colon_is_refused(
    session: aiohttp.ClientSession,
) -> None:
    with pytest.raises(PlcAuthenticationError, match="':'"):
        TecoApiClient(session, "127.0.0.1", "ad:min", "x")


async def test_a_plc_switched_from_basic_to_digest_is_followed(
    start_simulator: StartSimulator,
    session: aiohttp.ClientSession,
    header_log: HeaderLog,
) -> None:
    sim = await start_simulator(auth="basic")
    client = make_client(session, sim)
    await client.get_info()
    assert client.auth_scheme == "basic"
    sim.auth = "digest"
    await client.get_list()
    assert client.auth_scheme == "digest"
    # Basic refused (403.022), a fresh challenge, then Digest.
    assert [record.status for record in sim.requests[-3:]] == [403, 401, 200]
    assert header_log.authorizations[-3].startswith("Basic ")
    assert header_log.authorizations[-2] is None
    assert header_log.authorizations[-1].startswith("Digest ")
    assert client.request_count == len(sim.requests)


async def test_every_request_asks_for_json(
    manual_client: TecoApiClient, header_log: HeaderLog
) -> None:
    await manual_client.get_info()
    await manual_client.get_object(["plcName"])
    assert header_log.accepts == ["application/json"] * 3
