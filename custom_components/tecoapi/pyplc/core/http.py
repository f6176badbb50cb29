"""HTTP for every source: one exchange of requests and answers with a device.

Every HTTP client of the library (TecoApi, Mervis, the FP-I4C, Tekon) talks
through an :class:`HttpExchange` and keeps only its protocol: what to ask, and
what an answer means. The exchange does the rest alike for all of them:

- the aiohttp session is injected and never created or closed here;
- requests go one at a time where the device needs it (``one_at_a_time``),
  each within the client's timeout, with ``ssl`` verification as configured
  and no redirect followed;
- an answer is read within a cap (:func:`read_limited`), so nothing a device
  sends grows memory without bound;
- a failure to talk is the core's :class:`PlcConnectionError` (an untrusted
  certificate :class:`PlcTlsError`); what a status means on the device is the
  client's small table of :data:`StatusRule`;
- every request on the wire is counted in one :class:`WireCounts` (a Digest
  challenge's round trip too), and so are the bodies' bytes; a source reads
  its requests there;
- what goes stale between two requests (a session, a nonce, the scheme a device
  asks for) is renewed by the client's :class:`Renewal`, inside the same turn;
- a JSON answer is decoded with ``orjson`` when it is importable (Home
  Assistant always installs it), else with the standard library, to the same
  result (:func:`loads_json`; an integer wider than 64 bits, which no PLC
  has, is a float by orjson and an int by the standard library).
"""

import asyncio
from collections.abc import AsyncIterator, Callable, Mapping
from contextlib import asynccontextmanager
from dataclasses import dataclass, field
import json
import time
from types import MappingProxyType
from typing import Any, Final, Protocol

import aiohttp
from multidict import CIMultiDictProxy
from yarl import URL

from .exceptions import (
    PlcConnectionError,
    PlcError,
    PlcResponseError,
    PlcTlsError,
    ResponseTooLargeError,
)
from .models import WireCounts

READ_CHUNK: Final = 64 * 1024
"""Bytes taken from the connection at a time."""
MAX_RESENDS: Final = 2
"""The most times one request is sent again after a renewal."""

type TextDecoder = Callable[[bytes], str]
"""Turns an answer's bytes into text (UTF-8, or what the device writes otherwise)."""
type JsonLoads = Callable[[bytes, TextDecoder], Any]
"""Decodes an answer's JSON: its bytes, and how they become text if not UTF-8."""


async def read_limited(
    response: aiohttp.ClientResponse,
    limit: int,
    *,
    sender: str = "a device",
    chunk_size: int = READ_CHUNK,
) -> bytes:
    """Read a response's body, failing as soon as it passes ``limit`` bytes.

    An answer that declares more fails before a byte is read; one without a
    length (or lying about it) fails once it has passed the limit. Never more
    than ``limit + 1`` bytes are taken from the connection. ``sender`` names
    what would never send that much, for the message (``"a PLC"``).
    """
    declared = response.content_length
    if declared is not None and declared > limit:
        raise ResponseTooLargeError(
            f"The answer declares {declared} bytes, more than {sender} ever sends "
            f"({limit})",
            status=response.status,
            limit=limit,
        )
    chunks: list[bytes] = []
    received = 0
    while chunk := await response.content.read(min(chunk_size, limit + 1 - received)):
        received += len(chunk)
        if received > limit:
            raise ResponseTooLargeError(
                f"The answer passed {limit} bytes, more than {sender} ever sends",
                status=response.status,
                limit=limit,
                received=received,
            )
        chunks.append(chunk)
    return b"".join(chunks)


# --- JSON ----------------------------------------------------------------------


def utf8_or(encoding: str) -> TextDecoder:
    """Return a decoder of UTF-8 text that falls back to ``encoding`` (bad bytes replaced)."""

    def decode(content: bytes) -> str:
        try:
            return content.decode("utf-8")
        except UnicodeDecodeError:
            return content.decode(encoding, errors="replace")

    return decode


_utf8: Final = utf8_or("utf-8")


FAST_JSON_BYTES: Final = 256 * 1024
"""The largest answer decoded by orjson: a poll's answers are smaller. A larger one
(a gateway's address space, read once) is decoded by the standard library, whose
peak memory is half orjson's for it (orjson builds a document of its own first)."""


def json_loads(fast: Callable[[bytes], Any] | None) -> JsonLoads:
    """Return a JSON decoder of answers: ``fast`` first where given, the standard library else.

    ``fast`` (``orjson.loads``) decodes answers up to :data:`FAST_JSON_BYTES`;
    it reads UTF-8 bytes and refuses what is not
    strict JSON; whatever it refuses -- other text encodings, ``NaN``, a
    number beyond a double, a lone surrogate -- is decoded to text and read by
    :func:`json.loads`, so both give the same result and raise the same errors
    (:class:`ValueError`, :class:`RecursionError`). The one difference: an
    integer wider than 64 bits (no PLC type is) is a float by ``fast``.
    """
    if fast is None:

        def standard(content: bytes, decode: TextDecoder) -> Any:
            return json.loads(decode(content))

        return standard

    def fast_first(content: bytes, decode: TextDecoder) -> Any:
        if len(content) <= FAST_JSON_BYTES:
            try:
                return fast(content)
            except ValueError:
                pass
        return json.loads(decode(content))

    return fast_first


def _orjson_loads() -> Callable[[bytes], Any] | None:
    """Return ``orjson.loads`` when orjson is installed (None: it is not)."""
    try:
        import orjson  # noqa: PLC0415 (optional)
    except ImportError:
        return None
    loads: Callable[[bytes], Any] = orjson.loads
    return loads


FAST_JSON: Final = _orjson_loads()
"""``orjson.loads`` when orjson is importable (None: the standard library decodes)."""
loads_json: Final = json_loads(FAST_JSON)
"""Decode an answer's JSON (see :func:`json_loads`)."""


# --- the exchange ----------------------------------------------------------------


@dataclass(slots=True)
class Reply:
    """One answer of a device: its status, headers and body (read within the cap).

    ``target`` is what was asked (path and query); ``sent`` the bytes of the
    request's body; ``content_type`` the body's media type as aiohttp reads it
    (``text/html``); ``decode`` how its text is decoded when it is not UTF-8.
    :meth:`json` decodes the body once, however often it is asked.
    """

    target: str
    status: int
    headers: CIMultiDictProxy[str]
    body: bytes
    content_type: str = ""
    sent: int = 0
    decode: TextDecoder = field(default=_utf8, repr=False)
    _json: Any = field(default=None, init=False, repr=False)
    _decoded: bool = field(default=False, init=False, repr=False)

    @property
    def ok(self) -> bool:
        """Whether the status is a success (2xx)."""
        return 200 <= self.status < 300

    @property
    def html(self) -> bool:
        """Whether the answer says it is a web page."""
        return "html" in self.headers.get("Content-Type", "").lower()

    @property
    def challenges(self) -> list[str]:
        """The answer's ``WWW-Authenticate`` headers."""
        return self.headers.getall("WWW-Authenticate", [])

    def text(self) -> str:
        """Return the body as text (UTF-8, else as the exchange decodes the device's)."""
        return self.decode(self.body)

    def json(self) -> Any:
        """Return the body's JSON; :class:`ValueError` or :class:`RecursionError` if not JSON."""
        if not self._decoded:
            self._json = loads_json(self.body, self.decode)
            self._decoded = True
        return self._json


type StatusRule = Callable[[Reply], PlcError | None]
"""What an answer's status means on a device: the error to raise (None: none)."""


class Renewal(Protocol):
    """What a client renews when it goes stale: a session, a nonce, a scheme.

    Both run inside the request's turn (no other request passes them), and may
    send requests of their own with :meth:`HttpExchange.send`.
    """

    async def prepare(self) -> None:
        """Get ready before a request is sent (sign in when not signed in)."""

    async def renew(self, reply: Reply, resent: int) -> bool:
        """Whether to send the request again after this answer (renewed first).

        ``resent`` is how often it was sent again already; every answer comes
        here, the last included.
        """


@dataclass(frozen=True, slots=True)
class HttpAuth:
    """How requests authenticate: headers they carry, middlewares they pass."""

    headers: Mapping[str, str] = field(default_factory=lambda: MappingProxyType({}))
    middlewares: tuple[aiohttp.ClientMiddlewareType, ...] = ()


NO_AUTH: Final = HttpAuth()
"""Requests that carry no credentials."""
ACCEPT_JSON: Final[Mapping[str, str]] = MappingProxyType({"Accept": "application/json"})
"""What every request of the library accepts."""


class HttpExchange:
    """The HTTP requests of one client to one device (see the module's docstring).

    ``sender`` names the device in messages (``"a PLC"``); ``limit`` is the most
    bytes of an answer read unless a request says otherwise; ``statuses`` maps
    an HTTP status (or a ``range`` of them) to what it means on the device,
    ``otherwise`` what any other status but a 2xx means; ``renewal`` renews
    what goes stale; ``decode`` turns an answer that is not UTF-8 into text.
    """

    def __init__(
        self,
        session: aiohttp.ClientSession,
        base_url: str,
        *,
        sender: str,
        limit: int,
        timeout: float = 10.0,
        verify_ssl: bool = True,
        one_at_a_time: bool = True,
        statuses: Mapping[int | range, StatusRule] | None = None,
        otherwise: StatusRule | None = None,
        renewal: Renewal | None = None,
        decode: TextDecoder | None = None,
        chunk_size: int = READ_CHUNK,
    ) -> None:
        """Prepare the exchange; nothing is sent until the first request."""
        self.base_url = base_url
        self.wire = WireCounts()
        self.last_sent = time.monotonic()
        """The monotonic time the latest request went out."""
        self._session = session
        self._sender = sender
        self._limit = limit
        self._timeout = aiohttp.ClientTimeout(total=timeout)
        self._ssl = verify_ssl
        self._turn = asyncio.Lock() if one_at_a_time else None
        self._statuses: dict[int, StatusRule] = {}
        for key, rule in (statuses or {}).items():
            self._statuses.update(
                dict.fromkeys(key if isinstance(key, range) else (key,), rule)
            )
        self._otherwise = otherwise or self._unexpected
        self._renewal = renewal
        self._decode = decode or _utf8
        self._chunk_size = chunk_size
        self._headers: Mapping[str, str] = {}
        self._body_headers: Mapping[str, str] = {}
        self._middlewares: tuple[aiohttp.ClientMiddlewareType, ...] | None = None
        self.auth = NO_AUTH

    @property
    def auth(self) -> HttpAuth:
        """How requests authenticate from now on."""
        return self._auth

    @auth.setter
    def auth(self, auth: HttpAuth) -> None:
        """Authenticate requests so from now on (headers and middlewares made once)."""
        self._auth = auth
        self._headers = {**ACCEPT_JSON, **auth.headers}
        self._body_headers = {**self._headers, "Content-Type": "application/json"}
        # A middleware may send a request again (a Digest challenge's answer):
        # counted after it, every request on the wire is counted.
        self._middlewares = (
            (*auth.middlewares, self._count) if auth.middlewares else None
        )

    @asynccontextmanager
    async def turn(self) -> AsyncIterator[None]:
        """Hold the device's turn: no other request goes out meanwhile."""
        await self._take_turn()
        try:
            yield
        finally:
            self._end_turn()

    async def _take_turn(self) -> None:
        """Wait for the device's turn (:meth:`turn` without a context manager)."""
        if self._turn is not None:
            await self._turn.acquire()

    def _end_turn(self) -> None:
        """Give the device's turn to the next request."""
        if self._turn is not None:
            self._turn.release()

    async def request(
        self,
        method: str,
        target: str,
        *,
        body: bytes | Callable[[], bytes] | None = None,
        limit: int | None = None,
        check: bool = True,
    ) -> Reply:
        """Send a request in its turn (renewed and sent again where the renewal says).

        ``target`` is the path and query, already encoded; ``body`` the bytes
        of JSON to send, or what makes them (made again for a request sent
        again). Raises what the status means (``check``) or a failure to talk.
        """
        # The turn is taken and given back by hand: a context manager a request
        # costs more than the lock itself.
        await self._take_turn()
        try:
            renewal = self._renewal
            if renewal is not None:
                await renewal.prepare()
            reply = await self.send(
                method, target, body=body() if callable(body) else body, limit=limit
            )
            if renewal is not None:
                resent = 0
                while await renewal.renew(reply, resent) and resent < MAX_RESENDS:
                    resent += 1
                    reply = await self.send(
                        method,
                        target,
                        body=body() if callable(body) else body,
                        limit=limit,
                    )
        finally:
            self._end_turn()
        if check:
            self.check(reply)
        return reply

    async def send(
        self,
        method: str,
        target: str,
        *,
        body: bytes | None = None,
        limit: int | None = None,
    ) -> Reply:
        """Send one request on the wire, without waiting for the turn: for a caller in it.

        Its status is not checked (:meth:`check`).
        """
        wire = self.wire
        if self._middlewares is None:
            wire.requests += 1
        if body is not None:
            wire.bytes_sent += len(body)
        self.last_sent = time.monotonic()
        try:
            async with self._session.request(
                method,
                URL(self.base_url + target, encoded=True),
                data=body,
                headers=self._headers if body is None else self._body_headers,
                middlewares=self._middlewares,
                timeout=self._timeout,
                ssl=self._ssl,
                allow_redirects=False,
            ) as response:
                content = await read_limited(
                    response,
                    self._limit if limit is None else limit,
                    sender=self._sender,
                    chunk_size=self._chunk_size,
                )
                reply = Reply(
                    target,
                    response.status,
                    response.headers,
                    content,
                    content_type=response.content_type,
                    sent=0 if body is None else len(body),
                    decode=self._decode,
                )
        except aiohttp.ClientConnectorCertificateError as err:
            raise PlcTlsError(
                f"The TLS certificate of {self.base_url} is not trusted"
            ) from err
        except (aiohttp.ClientError, TimeoutError) as err:
            raise PlcConnectionError(
                f"Cannot talk to {self.base_url}: {type(err).__name__}"
            ) from err
        wire.bytes_received += len(content)
        return reply

    def check(self, reply: Reply) -> None:
        """Raise what an answer's status means on the device (a 2xx: nothing, unless told)."""
        rule = self._statuses.get(reply.status)
        if rule is None:
            if reply.ok:
                return
            rule = self._otherwise
        if (error := rule(reply)) is not None:
            raise error

    async def _count(
        self, request: aiohttp.ClientRequest, handler: aiohttp.ClientHandlerType
    ) -> aiohttp.ClientResponse:
        """Count one request on the wire and send it (the last middleware)."""
        self.wire.requests += 1
        return await handler(request)

    def _unexpected(self, reply: Reply) -> PlcError:
        """Return what a status means when the client's table does not say."""
        sender = self._sender
        return PlcResponseError(
            f"{sender[:1].upper()}{sender[1:]} answered HTTP {reply.status}",
            status=reply.status,
        )


class HttpClient:
    """What every HTTP client of the library shows of its exchange (``_http``).

    A client speaks its protocol through one :class:`HttpExchange`; what went
    over the wire is counted there, and read here.
    """

    _http: HttpExchange

    @property
    def wire(self) -> WireCounts:
        """What went over the wire: every request, and the bodies' bytes."""
        return self._http.wire

    @property
    def request_count(self) -> int:
        """The requests sent on the wire so far."""
        return self._http.wire.requests
