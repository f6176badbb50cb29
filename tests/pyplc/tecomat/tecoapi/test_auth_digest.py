"""The Digest middleware signs the request target exactly as it is sent."""

import hashlib

import aiohttp
from aiohttp import web
from aiohttp.test_utils import TestServer
import pytest
from yarl import URL

from custom_components.tecoapi.pyplc.tecomat.tecoapi.auth import (
    DigestAuth,
    basic_authorization,
    is_tecoapi_challenge,
    offered_schemes,
)

CHALLENGE = 'Digest realm="TecoApi", nonce="abc", qop="auth"'


async def signed(target: str) -> tuple[str, str]:
    """Send GET ``target`` through the middleware to a server that asks for Digest.

    Return the target the server received with the credentials, and their header.
    """
    received: list[tuple[str, str]] = []

    async def handler(request: web.Request) -> web.Response:
        header = request.headers.get("Authorization")
        if header is None:
            return web.Response(status=401, headers={"WWW-Authenticate": CHALLENGE})
        received.append((request.raw_path, header))
        return web.Response(text="{}")

    app = web.Application()
    app.router.add_route("*", "/{tail:.*}", handler)
    async with (
        TestServer(app, host="127.0.0.1") as server,
        aiohttp.ClientSession(middlewares=(DigestAuth("admin", "pw"),)) as http,
    ):
        url = URL(f"http://127.0.0.1:{server.port}{target}", encoded=True)
        async with http.get(url) as response:
            assert response.status == 200
    assert len(received) == 1
    return received[0]


@pytest.mark.usefixtures("socket_enabled")
@pytest.mark.parametrize(
    "target",
    [
        "/TecoApi/SetObject?myObject.favorites.color=%22R%22%20%26%20b%3D1",
        "/TecoApi/GetObject?arr1&Main.myObject3.value",
    ],
)
async def test_the_uri_field_and_the_hash_use_the_raw_target(target: str) -> None:
    sent, header = await signed(target)
    assert sent == target
    fields = dict(
        part.strip().split("=", 1) for part in header.removeprefix("Digest ").split(",")
    )
    assert fields["uri"] == f'"{target}"'

    def md5(text: str) -> str:
        return hashlib.md5(text.encode(), usedforsecurity=False).hexdigest()

    ha1 = md5("admin:TecoApi:pw")
    ha2 = md5(f"GET:{target}")
    nonce_count, cnonce = fields["nc"], fields["cnonce"].strip('"')
    expected = md5(f"{ha1}:abc:{nonce_count}:{cnonce}:auth:{ha2}")
    assert fields["response"] == f'"{expected}"'


def test_challenges_are_read() -> None:
    digest = 'Digest realm="TecoApi",qop="auth,auth-int",nonce="1",opaque="2"'
    assert offered_schemes([digest]) == {"digest"}
    assert offered_schemes([digest, 'Basic realm="TecoApi"']) == {"digest", "basic"}
    assert offered_schemes(['Basic realm="TecoApi", Digest realm="x"']) == {
        "digest",
        "basic",
    }
    assert offered_schemes(["Bearer"]) == set()
    assert is_tecoapi_challenge([digest])
    assert not is_tecoapi_challenge(['Basic realm="Router"'])


def test_basic_credentials_are_utf8() -> None:
    assert basic_authorization("jmeno", "heslo") == "Basic am1lbm86aGVzbG8="
    assert basic_authorization("a", "ř") == "Basic YTrFmQ=="
