"""HTTP Basic and Digest authentication as a TecoApi web server does it (RFC 2617/7616).

The Digest challenge copies the real device's:
`Digest realm="TecoApi",qop="auth,auth-int",nonce="…",opaque="…"` (MD5). Both
`qop=auth` (curl) and `qop=auth-int` (aiohttp's DigestAuthMiddleware, which hashes
the body into HA2) are accepted, as is MD5-sess. A nonce may be reused with a new
`nc` until it expires after `nonce_max_uses` uses or `nonce_ttl` seconds; a replayed
`nc`, an expired or an unknown nonce answer 401.020 with a fresh `stale=true`
challenge — but only when the digest itself is right, otherwise 401.021.

The `uri` field must name the request target; it is compared percent-decoded, because
aiohttp before 3.14 signs the decoded target (`/GetObject?arr1[5]`) while it sends the
encoded one (`/GetObject?arr1%5B5%5D`). The digest is computed over `uri` as sent.
"""

import base64
import binascii
from collections.abc import Callable
from dataclasses import dataclass, field
import hashlib
import hmac
import re
import secrets
import time
from typing import Final, Literal
from urllib.parse import unquote

from . import errors
from .errors import TecoError

type AuthMode = Literal["digest", "basic", "both"]
AUTH_MODES: Final = ("digest", "basic", "both")
REALM: Final = "TecoApi"
# Nonces kept at once; the oldest are forgotten first (they then answer "stale").
MAX_NONCES: Final = 1024
_PARAMETER: Final = re.compile(
    r'\s*([A-Za-z0-9_-]+)\s*=\s*(?:"((?:[^"\\]|\\.)*)"|([^\s,"]*))\s*(?:,|$)'
)
_NONCE_COUNT: Final = re.compile(r"[0-9a-fA-F]{8}")


class AuthenticationError(Exception):
    """The request is not authenticated: the error to answer and the challenges."""

    def __init__(self, error: TecoError, challenges: list[str]) -> None:
        """Carry the TecoApi error and the WWW-Authenticate values to send."""
        super().__init__(error.message)
        self.error = error
        self.challenges = challenges


@dataclass(slots=True)
class _Nonce:
    issued: float
    uses: int = 0
    counts: set[int] = field(default_factory=set)


def _md5(text: bytes) -> str:
    return hashlib.md5(text, usedforsecurity=False).hexdigest()


def parse_digest_parameters(text: str) -> dict[str, str] | None:
    """The `key=value` pairs after `Digest `, quoted or not; None if malformed."""
    parameters: dict[str, str] = {}
    position = 0
    text = text.strip()
    while position < len(text):
        match = _PARAMETER.match(text, position)
        if match is None:
            return None
        quoted, bare = match.group(2), match.group(3)
        value = re.sub(r"\\(.)", r"\1", quoted) if quoted is not None else (bare or "")
        parameters[match.group(1).lower()] = value
        position = match.end()
    return parameters


class Authenticator:
    """Checks Authorization headers against one user name and password."""

    def __init__(
        self,
        *,
        nonce_max_uses: int | None = None,
        nonce_ttl: float | None = None,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        """Expire nonces after so many uses and/or seconds (None: never)."""
        self.nonce_max_uses = nonce_max_uses
        self.nonce_ttl = nonce_ttl
        self._clock = clock
        self._nonces: dict[str, _Nonce] = {}
        self._opaque = secrets.token_hex(12)

    def challenges(self, mode: AuthMode, *, stale: bool = False) -> list[str]:
        """The WWW-Authenticate values for a 401: Digest first, then Basic."""
        offered: list[str] = []
        if mode in {"digest", "both"}:
            nonce = secrets.token_hex(12)
            self._nonces[nonce] = _Nonce(self._clock())
            while len(self._nonces) > MAX_NONCES:
                del self._nonces[next(iter(self._nonces))]
            challenge = (
                f'Digest realm="{REALM}",qop="auth,auth-int",'
                f'nonce="{nonce}",opaque="{self._opaque}"'
            )
            offered.append(challenge + (",stale=true" if stale else ""))
        if mode in {"basic", "both"}:
            offered.append(f'Basic realm="{REALM}"')
        return offered

    def check(
        self,
        header: str | None,
        *,
        mode: AuthMode,
        username: str,
        password: str,
        method: str,
        uri: str,
        body: bytes,
    ) -> None:
        """Return if the request is authenticated, raise AuthenticationError if not."""
        if not header or not header.strip():
            raise self._failure(errors.authentication_requested(), mode)
        scheme, _, credentials = header.strip().partition(" ")
        scheme = scheme.lower()
        offered = {"digest", "basic"} if mode == "both" else {mode}
        if scheme not in offered:
            raise AuthenticationError(errors.unsupported_authentication(), [])
        if scheme == "basic":
            self._check_basic(credentials, mode, username, password)
        else:
            self._check_digest(
                credentials,
                mode=mode,
                username=username,
                password=password,
                method=method,
                uri=uri,
                body=body,
            )

    def _failure(
        self, error: TecoError, mode: AuthMode, *, stale: bool = False
    ) -> AuthenticationError:
        return AuthenticationError(error, self.challenges(mode, stale=stale))

    def _rejected(self, mode: AuthMode) -> AuthenticationError:
        return self._failure(errors.unknown_credentials(), mode)

    def _check_basic(
        self, credentials: str, mode: AuthMode, username: str, password: str
    ) -> None:
        try:
            decoded = base64.b64decode(credentials.strip(), validate=True).decode()
        except (binascii.Error, UnicodeDecodeError):
            raise self._failure(errors.unknown_credentials(), mode) from None
        given_user, _, given_password = decoded.partition(":")
        if not (
            hmac.compare_digest(given_user.encode(), username.encode())
            and hmac.compare_digest(given_password.encode(), password.encode())
        ):
            raise self._failure(errors.unknown_credentials(), mode)

    def _check_digest(
        self,
        credentials: str,
        *,
        mode: AuthMode,
        username: str,
        password: str,
        method: str,
        uri: str,
        body: bytes,
    ) -> None:
        fields = parse_digest_parameters(credentials)
        if fields is None:
            raise self._rejected(mode)
        algorithm = fields.get("algorithm", "MD5").upper()
        if algorithm not in {"MD5", "MD5-SESS"}:
            raise AuthenticationError(errors.unsupported_authentication(), [])
        required = ("username", "realm", "nonce", "uri", "response", "opaque")
        if any(name not in fields for name in required):
            raise self._rejected(mode)
        qop = fields.get("qop")
        nonce_count = fields.get("nc", "")
        cnonce = fields.get("cnonce", "")
        if (
            fields["realm"] != REALM
            or fields["opaque"] != self._opaque
            or unquote(fields["uri"]) != unquote(uri)
            or fields["username"] != username
            or qop not in {None, "auth", "auth-int"}
            or (
                qop is not None
                and (not cnonce or not _NONCE_COUNT.fullmatch(nonce_count))
            )
            or (algorithm == "MD5-SESS" and not cnonce)
        ):
            raise self._rejected(mode)
        nonce = fields["nonce"]
        ha1 = _md5(f"{username}:{REALM}:{password}".encode())
        if algorithm == "MD5-SESS":
            ha1 = _md5(f"{ha1}:{nonce}:{cnonce}".encode())
        a2 = f"{method}:{fields['uri']}"
        if qop == "auth-int":
            a2 += ":" + _md5(body)
        ha2 = _md5(a2.encode())
        if qop is None:
            expected = _md5(f"{ha1}:{nonce}:{ha2}".encode())
        else:
            expected = _md5(
                f"{ha1}:{nonce}:{nonce_count}:{cnonce}:{qop}:{ha2}".encode()
            )
        if not hmac.compare_digest(expected, fields["response"].lower()):
            raise self._rejected(mode)
        self._use_nonce(nonce, int(nonce_count, 16) if qop else None, mode)

    def _use_nonce(self, nonce: str, count: int | None, mode: AuthMode) -> None:
        """Count one use of a nonce; 401.020 if it is unknown, expired or replayed."""
        state = self._nonces.get(nonce)
        expired = state is None or (
            (self.nonce_max_uses is not None and state.uses >= self.nonce_max_uses)
            or (
                self.nonce_ttl is not None
                and self._clock() - state.issued >= self.nonce_ttl
            )
        )
        if expired:
            self._nonces.pop(nonce, None)
        if state is None or expired or (count is not None and count in state.counts):
            raise self._failure(errors.stale_nonce(), mode, stale=True)
        state.uses += 1
        if count is not None:
            state.counts.add(count)
