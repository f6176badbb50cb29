"""Authentication plumbing: which scheme the PLC offers, and Digest signing.

TecoApi takes Basic or Digest (RFC 2617). The client sends its first request
through aiohttp's ``DigestAuthMiddleware`` without credentials; the PLC's 401
says what it offers. Digest is answered by the middleware itself (and from then
on pre-emptively, one round trip per request); Basic is used only when the PLC
offers nothing else, so Basic credentials never go to a PLC that asked for Digest.
"""

import base64
from collections.abc import Iterable
import re
from typing import Final, Literal

import aiohttp
from aiohttp.payload import Payload
from yarl import URL

type AuthScheme = Literal["digest", "basic"]

_CHALLENGE: Final = re.compile(r"(?:^|,)\s*(Basic|Digest)\b", re.IGNORECASE)
_REALM: Final = re.compile(r'realm\s*=\s*"?([^",]*)"?', re.IGNORECASE)
TECOAPI_REALM: Final = "TecoApi"


def offered_schemes(challenges: Iterable[str]) -> set[AuthScheme]:
    """Return the schemes (``digest``/``basic``) that WWW-Authenticate headers offer."""
    schemes: set[AuthScheme] = set()
    for header in challenges:
        for match in _CHALLENGE.finditer(header):
            schemes.add("digest" if match.group(1).lower() == "digest" else "basic")
    return schemes


def is_tecoapi_challenge(challenges: Iterable[str]) -> bool:
    """Whether any challenge names the ``TecoApi`` realm."""
    return any(
        match.group(1) == TECOAPI_REALM
        for header in challenges
        for match in _REALM.finditer(header)
    )


def basic_authorization(username: str, password: str) -> str:
    """Return the ``Authorization`` value of Basic credentials (RFC 7617, UTF-8)."""
    token = base64.b64encode(f"{username}:{password}".encode()).decode("ascii")
    return f"Basic {token}"


def _signs_decoded_target() -> bool:
    """Whether this aiohttp signs Digest over the decoded request target.

    aiohttp before aio-libs/aiohttp#12436 (e.g. 3.13.3, the floor target) puts
    ``path_qs`` -- ``"five"`` for ``%22five%22`` -- in the ``uri`` field, which
    neither matches the request sent nor survives the quotes of the header.
    """
    probe = aiohttp.DigestAuthMiddleware("probe", "probe")
    probe._challenge = {"realm": "probe", "nonce": "probe"}  # noqa: SLF001
    coroutine = probe._encode("GET", URL("http://probe/?a=%20", encoded=True), b"")  # noqa: SLF001
    try:
        coroutine.send(None)
    except StopIteration as done:
        return 'uri="/?a=%20"' not in str(done.value)
    coroutine.close()
    return False


SIGNS_DECODED_TARGET: Final = _signs_decoded_target()


class DigestAuth(aiohttp.DigestAuthMiddleware):
    """aiohttp's Digest middleware, made to sign the request target as sent."""

    async def _encode(self, method: str, url: URL, body: Payload | Literal[b""]) -> str:
        """Sign ``url``; on an old aiohttp hand it a target that decodes to the raw one."""
        if SIGNS_DECODED_TARGET:
            url = URL(url.raw_path_qs.replace("%", "%25"), encoded=True)
        return await super()._encode(method, url, body)
