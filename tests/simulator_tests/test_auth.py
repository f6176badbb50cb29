"""Basic and Digest authentication, in the Authenticator and over HTTP."""

import hashlib
import re

import aiohttp
import pytest

from tests.conftest import SIM_PASSWORD, SIM_USERNAME
from tests.simulator import Simulator
from tests.simulator.auth import (
    AuthenticationError,
    Authenticator,
    parse_digest_parameters,
)
from tests.simulator_tests.conftest import basic_authorization, fetch, manual_text

CHALLENGE = re.compile(
    r'Digest realm="TecoApi",qop="auth,auth-int",'
    r'nonce="[0-9a-f]{24}",opaque="[0-9a-f]{24}"(,stale=true)?'
)


def md5(text: str | bytes) -> str:
    data = text.encode() if isinstance(text, str) else text
    return hashlib.md5(data, usedforsecurity=False).hexdigest()


def challenge_fields(challenge: str) -> dict[str, str]:
    return dict(re.findall(r'(\w+)="([^"]*)"', challenge))


def digest(
    challenge: str,
    *,
    method: str = "GET",
    uri: str,
    username: str = SIM_USERNAME,
    password: str = SIM_PASSWORD,
    qop: str | None = "auth",
    nc: str = "00000001",
    cnonce: str = "0a4f113b",
    body: bytes = b"",
    algorithm: str | None = None,
    overrides: dict[str, str] | None = None,
    omit: tuple[str, ...] = (),
) -> str:
    """A Digest Authorization value computed by hand (RFC 2617 3.2.2)."""
    fields = challenge_fields(challenge)
    realm, nonce = fields["realm"], fields["nonce"]
    ha1 = md5(f"{username}:{realm}:{password}")
    if algorithm == "MD5-sess":
        ha1 = md5(f"{ha1}:{nonce}:{cnonce}")
    a2 = f"{method}:{uri}"
    if qop == "auth-int":
        a2 += ":" + md5(body)
    ha2 = md5(a2)
    if qop is None:
        response = md5(f"{ha1}:{nonce}:{ha2}")
    else:
        response = md5(f"{ha1}:{nonce}:{nc}:{cnonce}:{qop}:{ha2}")
    parameters = {
        "username": f'"{username}"',
        "realm": f'"{realm}"',
        "nonce": f'"{nonce}"',
        "uri": f'"{uri}"',
        "response": f'"{response}"',
        "opaque": f'"{fields["opaque"]}"',
    }
    if qop is not None:
        parameters |= {"qop": qop, "nc": nc, "cnonce": f'"{cnonce}"'}
    if algorithm is not None:
        parameters["algorithm"] = algorithm
    parameters |= overrides or {}
    return "Digest " + ", ".join(
        f"{key}={value}" for key, value in parameters.items() if key not in omit
    )


async def first_challenge(session: aiohttp.ClientSession, sim: Simulator) -> str:
    reply = await fetch(session, sim, "/TecoApi/GetInfo", basic=False)
    assert reply.status == 401
    return reply.challenges[0]


async def with_header(
    session: aiohttp.ClientSession,
    sim: Simulator,
    target: str,
    authorization: str,
    *,
    method: str = "GET",
    body: bytes | None = None,
) -> tuple[int, str, list[str]]:
    reply = await fetch(
        session,
        sim,
        target,
        method=method,
        data=body,
        headers={"Authorization": authorization},
        basic=False,
    )
    code = reply.error_code if reply.status >= 400 else ""
    return reply.status, code, reply.challenges


# --- the challenge ------------------------------------------------------------------------


async def test_no_credentials_get_the_manual_challenge(
    session: aiohttp.ClientSession, manual_simulator: Simulator
) -> None:
    reply = await fetch(
        session, manual_simulator, "/TecoApi/GetObject?plcDesc", basic=False
    )

    assert reply.status == 401
    assert len(reply.challenges) == 1
    assert CHALLENGE.fullmatch(reply.challenges[0])
    assert "stale" not in reply.challenges[0]
    assert reply.headers["Connection"] == "keep-alive"
    assert reply.headers["Server"] == "TecoApi/1.0.0 (sim CP-W32I v1.1 VN 1957)"
    time = reply.json()["error"]["time"]
    assert reply.body == manual_text(
        f"""
        {{
          "error": {{
            "code": "401.023",
            "message": "Authentication Requested",
            "time": "{time}"
          }}
        }}
        """
    )
    assert int(reply.headers["Content-Length"]) == 133
    assert manual_simulator.requests[-1].authorized is False


async def test_each_challenge_has_a_fresh_nonce_and_the_same_opaque(
    session: aiohttp.ClientSession, manual_simulator: Simulator
) -> None:
    first = challenge_fields(await first_challenge(session, manual_simulator))
    second = challenge_fields(await first_challenge(session, manual_simulator))

    assert first["nonce"] != second["nonce"]
    assert first["opaque"] == second["opaque"]


@pytest.mark.parametrize(
    ("auth", "expected"),
    [
        ("digest", ["Digest"]),
        ("basic", ['Basic realm="TecoApi"']),
        ("both", ["Digest", 'Basic realm="TecoApi"']),
    ],
)
async def test_auth_modes_offer_their_schemes(
    session: aiohttp.ClientSession, socket_enabled: None, auth: str, expected: list[str]
) -> None:
    async with Simulator("manual", auth=auth) as sim:  # type: ignore[arg-type]
        reply = await fetch(session, sim, "/TecoApi/GetInfo", basic=False)

    assert reply.error_code == "401.023"
    assert [
        c.split(" ")[0] if c.startswith("Digest") else c for c in reply.challenges
    ] == (expected)


# --- Digest ---------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("qop", "algorithm"),
    [
        ("auth", None),
        ("auth", "MD5"),
        ("auth-int", None),
        ("auth-int", "MD5"),
        ("auth", "MD5-sess"),
        ("auth-int", "MD5-sess"),
        (None, None),  # RFC 2069
        (None, "MD5"),
    ],
)
async def test_hand_built_digest_is_accepted(
    session: aiohttp.ClientSession,
    manual_simulator: Simulator,
    qop: str | None,
    algorithm: str | None,
) -> None:
    challenge = await first_challenge(session, manual_simulator)
    uri = "/TecoApi/GetObject?plcDesc"

    status, _, _ = await with_header(
        session,
        manual_simulator,
        uri,
        digest(challenge, uri=uri, qop=qop, algorithm=algorithm),
    )

    assert status == 200
    assert manual_simulator.requests[-1].authorized is True


async def test_auth_int_hashes_the_body(
    session: aiohttp.ClientSession, manual_simulator: Simulator
) -> None:
    challenge = await first_challenge(session, manual_simulator)
    uri = "/TecoApi/PutObject"
    body = b'{"plcType": 1005}'

    wrong = await with_header(
        session,
        manual_simulator,
        uri,
        digest(challenge, method="PUT", uri=uri, qop="auth-int", body=b"{}"),
        method="PUT",
        body=body,
    )
    right = await with_header(
        session,
        manual_simulator,
        uri,
        digest(
            challenge, method="PUT", uri=uri, qop="auth-int", body=body, nc="00000002"
        ),
        method="PUT",
        body=body,
    )

    assert wrong[:2] == (401, "401.021")
    assert right[:2] == (204, "")
    assert manual_simulator.get_value("plcType") == 1005


async def test_a_nonce_is_reused_with_increasing_nc(
    session: aiohttp.ClientSession, manual_simulator: Simulator
) -> None:
    challenge = await first_challenge(session, manual_simulator)
    uri = "/TecoApi/GetInfo"

    statuses = [
        (
            await with_header(
                session, manual_simulator, uri, digest(challenge, uri=uri, nc=nc)
            )
        )[0]
        for nc in ("00000001", "00000002", "0000000a")
    ]

    assert statuses == [200, 200, 200]


async def test_a_replayed_nc_is_stale(
    session: aiohttp.ClientSession, manual_simulator: Simulator
) -> None:
    challenge = await first_challenge(session, manual_simulator)
    uri = "/TecoApi/GetInfo"
    header = digest(challenge, uri=uri)

    first = await with_header(session, manual_simulator, uri, header)
    replay = await with_header(session, manual_simulator, uri, header)

    assert first[0] == 200
    assert replay[:2] == (401, "401.020")
    assert CHALLENGE.fullmatch(replay[2][0])
    assert replay[2][0].endswith(",stale=true")


async def test_an_unknown_nonce_is_stale_when_the_digest_is_right(
    session: aiohttp.ClientSession, manual_simulator: Simulator
) -> None:
    challenge = await first_challenge(session, manual_simulator)
    forged = challenge.replace(challenge_fields(challenge)["nonce"], "0" * 24)
    uri = "/TecoApi/GetInfo"

    right = await with_header(session, manual_simulator, uri, digest(forged, uri=uri))
    wrong = await with_header(
        session, manual_simulator, uri, digest(forged, uri=uri, password="guess")
    )

    assert right[:2] == (401, "401.020")
    assert "stale=true" in right[2][0]
    assert wrong[:2] == (401, "401.021")
    assert "stale" not in wrong[2][0]


@pytest.mark.parametrize(
    ("changes", "code"),
    [
        ({"password": "wrong"}, "401.021"),
        ({"username": "root"}, "401.021"),
        ({"overrides": {"realm": '"Other"'}}, "401.021"),
        ({"overrides": {"opaque": '"0123"'}}, "401.021"),
        ({"overrides": {"uri": '"/TecoApi/GetList"'}}, "401.021"),
        ({"overrides": {"nc": "1"}}, "401.021"),
        ({"overrides": {"qop": "auth-conf"}}, "401.021"),
        ({"omit": ("cnonce",)}, "401.021"),
        ({"omit": ("opaque",)}, "401.021"),
        ({"omit": ("response",)}, "401.021"),
        ({"overrides": {"response": '"' + "0" * 32 + '"'}}, "401.021"),
        ({"algorithm": "SHA-256"}, "403.022"),
    ],
)
async def test_wrong_digest_fields(
    session: aiohttp.ClientSession,
    manual_simulator: Simulator,
    changes: dict[str, object],
    code: str,
) -> None:
    challenge = await first_challenge(session, manual_simulator)
    uri = "/TecoApi/GetInfo"

    status, error, challenges = await with_header(
        session,
        manual_simulator,
        uri,
        digest(challenge, uri=uri, **changes),  # type: ignore[arg-type]
    )

    assert (status, error) == (int(code[:3]), code)
    if status == 401:
        assert CHALLENGE.fullmatch(challenges[0])
    else:
        assert challenges == []
    assert manual_simulator.requests[-1].authorized is False


async def test_malformed_digest_header(
    session: aiohttp.ClientSession, manual_simulator: Simulator
) -> None:
    status, code, _ = await with_header(
        session, manual_simulator, "/TecoApi/GetInfo", 'Digest username="admin" realm'
    )

    assert (status, code) == (401, "401.021")


async def test_uri_is_compared_percent_decoded(
    session: aiohttp.ClientSession, manual_simulator: Simulator
) -> None:
    challenge = await first_challenge(session, manual_simulator)
    sent = "/TecoApi/GetObject?arr1%5B2%5D"

    status, _, _ = await with_header(
        session,
        manual_simulator,
        sent,
        digest(challenge, uri="/TecoApi/GetObject?arr1[2]"),
    )

    assert status == 200


# --- aiohttp's DigestAuthMiddleware (qop=auth-int) -----------------------------------------


async def test_aiohttp_digest_middleware_needs_one_round_trip_per_request(
    manual_simulator: Simulator,
) -> None:
    middleware = aiohttp.DigestAuthMiddleware(SIM_USERNAME, SIM_PASSWORD)
    async with aiohttp.ClientSession(middlewares=(middleware,)) as client:
        for _ in range(3):
            async with client.get(
                manual_simulator.url + "/TecoApi/GetInfo"
            ) as response:
                assert response.status == 200
        async with client.put(
            manual_simulator.url + "/TecoApi/PutObject", data=b'{"plcType": 7}'
        ) as response:
            assert response.status == 204

    assert [r.status for r in manual_simulator.requests] == [401, 200, 200, 200, 204]
    assert manual_simulator.get_value("plcType") == 7


async def test_aiohttp_recovers_from_stale_nonces(socket_enabled: None) -> None:
    middleware = aiohttp.DigestAuthMiddleware("admin", "secret")
    async with (
        Simulator("manual", nonce_max_uses=2) as sim,
        aiohttp.ClientSession(middlewares=(middleware,)) as client,
    ):
        for _ in range(5):
            async with client.get(sim.url + "/TecoApi/GetInfo") as response:
                assert response.status == 200

    statuses = [r.status for r in sim.requests]
    assert statuses == [401, 200, 200, 401, 200, 200, 401, 200]
    stale = [r for r in sim.requests if r.status == 401][1:]
    assert all(not r.authorized for r in stale)


async def test_nonce_ttl_zero_makes_every_reuse_stale(
    session: aiohttp.ClientSession, socket_enabled: None
) -> None:
    async with Simulator(
        "manual", username=SIM_USERNAME, password=SIM_PASSWORD, nonce_ttl=0
    ) as sim:
        challenge = await first_challenge(session, sim)
        uri = "/TecoApi/GetInfo"
        status, code, challenges = await with_header(
            session, sim, uri, digest(challenge, uri=uri)
        )

    assert (status, code) == (401, "401.020")
    assert challenges[0].endswith(",stale=true")


async def test_nonce_limits_can_change_at_runtime(
    session: aiohttp.ClientSession, manual_simulator: Simulator
) -> None:
    challenge = await first_challenge(session, manual_simulator)
    uri = "/TecoApi/GetInfo"
    assert (
        await with_header(session, manual_simulator, uri, digest(challenge, uri=uri))
    )[0] == 200

    manual_simulator.nonce_max_uses = 1

    assert manual_simulator.nonce_max_uses == 1
    again = await with_header(
        session, manual_simulator, uri, digest(challenge, uri=uri, nc="00000002")
    )
    assert again[:2] == (401, "401.020")
    manual_simulator.nonce_ttl = 30.0
    assert manual_simulator.nonce_ttl == 30.0


async def test_changed_password_revokes_credentials(
    manual_simulator: Simulator,
) -> None:
    middleware = aiohttp.DigestAuthMiddleware(SIM_USERNAME, SIM_PASSWORD)
    async with aiohttp.ClientSession(middlewares=(middleware,)) as client:
        async with client.get(manual_simulator.url + "/TecoApi/GetInfo") as response:
            assert response.status == 200
        manual_simulator.password = "changed"
        async with client.get(manual_simulator.url + "/TecoApi/GetInfo") as response:
            assert response.status == 401
            assert (await response.json())["error"]["code"] == "401.021"


# --- Basic and unsupported schemes -------------------------------------------------------


async def test_basic_credentials(
    session: aiohttp.ClientSession, manual_plc: Simulator
) -> None:
    right = await with_header(
        session,
        manual_plc,
        "/TecoApi/GetInfo",
        basic_authorization(SIM_USERNAME, SIM_PASSWORD),
    )
    wrong = await with_header(
        session,
        manual_plc,
        "/TecoApi/GetInfo",
        basic_authorization(SIM_USERNAME, "nope"),
    )
    garbage = await with_header(session, manual_plc, "/TecoApi/GetInfo", "Basic %%%")

    assert right[0] == 200
    assert wrong[:2] == (401, "401.021")
    assert garbage[:2] == (401, "401.021")
    assert [c.split(" ")[0] for c in wrong[2]] == ["Digest", "Basic"]


async def test_basic_to_a_digest_only_plc_is_unsupported(
    session: aiohttp.ClientSession, manual_simulator: Simulator
) -> None:
    reply = await fetch(session, manual_simulator, "/TecoApi/GetInfo")

    assert (reply.status, reply.error_code) == (403, "403.022")
    assert reply.error_message == "Unsupported authentication method"
    assert reply.challenges == []
    assert reply.headers["Connection"] == "close"


@pytest.mark.parametrize("authorization", ["Bearer abc", "Negotiate xyz", "Digest"])
async def test_other_schemes_are_unsupported_or_rejected(
    session: aiohttp.ClientSession, socket_enabled: None, authorization: str
) -> None:
    async with Simulator("manual", auth="basic") as sim:
        status, code, _ = await with_header(
            session, sim, "/TecoApi/GetInfo", authorization
        )

    assert (status, code) == (403, "403.022")


async def test_auth_mode_changes_at_runtime(
    session: aiohttp.ClientSession, manual_simulator: Simulator
) -> None:
    manual_simulator.auth = "basic"

    reply = await fetch(session, manual_simulator, "/TecoApi/GetInfo")

    assert reply.status == 200


async def test_unknown_auth_mode_is_refused() -> None:
    with pytest.raises(ValueError, match="auth must be one of"):
        Simulator("manual", auth="ntlm")  # type: ignore[arg-type]


# --- the Authenticator alone: time-based expiry with a fake clock --------------------------


class FakeClock:
    def __init__(self) -> None:
        self.now = 1000.0

    def __call__(self) -> float:
        return self.now


def test_nonce_ttl_expires_by_the_clock() -> None:
    clock = FakeClock()
    authenticator = Authenticator(nonce_ttl=10.0, clock=clock)
    challenge = authenticator.challenges("digest")[0]

    def check(nc: str) -> None:
        authenticator.check(
            digest(challenge, uri="/TecoApi/GetInfo", nc=nc),
            mode="digest",
            username=SIM_USERNAME,
            password=SIM_PASSWORD,
            method="GET",
            uri="/TecoApi/GetInfo",
            body=b"",
        )

    clock.now += 9.9
    check("00000001")
    clock.now += 0.1
    with pytest.raises(AuthenticationError) as stale:
        check("00000002")
    assert stale.value.error.code == "401.020"
    assert stale.value.challenges[0].endswith(",stale=true")


def test_old_nonces_are_forgotten_beyond_the_store_limit() -> None:
    authenticator = Authenticator()
    first = authenticator.challenges("digest")[0]
    for _ in range(1100):
        authenticator.challenges("digest")

    with pytest.raises(AuthenticationError) as stale:
        authenticator.check(
            digest(first, uri="/x"),
            mode="digest",
            username=SIM_USERNAME,
            password=SIM_PASSWORD,
            method="GET",
            uri="/x",
            body=b"",
        )
    assert stale.value.error.code == "401.020"


@pytest.mark.parametrize(
    ("text", "parsed"),
    [
        (
            'username="jmeno",realm="TecoApi", nc=00000001 ,qop="auth"',
            {"username": "jmeno", "realm": "TecoApi", "nc": "00000001", "qop": "auth"},
        ),
        (r'uri="/a?b=\"c\"", response=abc', {"uri": '/a?b="c"', "response": "abc"}),
        ("", {}),
        ("username", None),
        ('username="open', None),
    ],
)
def test_parse_digest_parameters(text: str, parsed: dict[str, str] | None) -> None:
    assert parse_digest_parameters(text) == parsed
