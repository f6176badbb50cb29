"""The simulated PLC's web server: TecoApi over aiohttp, with authentication and faults."""

import asyncio
from dataclasses import dataclass
import datetime as dt
import logging
from typing import Any, Final
from urllib.parse import unquote

from aiohttp import hdrs, web
from multidict import CIMultiDict

from . import errors, services
from .auth import AUTH_MODES, AuthenticationError, Authenticator, AuthMode
from .base import ConnectionDroppedError, HttpSimulator
from .errors import TecoError
from .faults import HUGE_BODY_BYTES, Faults, TransportFault
from .json_render import render_error
from .memory import LinkMotion
from .plc import Plc
from .program import Program, load_program

_LOGGER: Final = logging.getLogger(__package__)

API_PREFIX: Final = "/TecoApi"
SERVER_VERSION: Final = "TecoApi/1.0.0"
ACCEPTED_MEDIA: Final = frozenset({"*/*", "application/*", "application/json"})
MALFORMED_BODY: Final = b"<html><body><h1>Web server is busy</h1></body></html>\r\n"
# The huge and endless bodies: an object whose one string never ends, written a
# chunk at a time (the simulator never holds more than one).
STREAM_OPENING: Final = b'{\r\n  "noise": "'
STREAM_CHUNK: Final = b"x" * 65536


@dataclass(slots=True)
class RequestRecord:
    """One HTTP request the simulator received; `status` 0 until (or if never) answered."""

    method: str
    service: str
    query: str
    status: int = 0
    authorized: bool = False
    items: int = 0


@dataclass(frozen=True, slots=True)
class _Answer:
    status: int
    body: bytes
    items: int = 0
    challenges: tuple[str, ...] = ()
    stream: TransportFault | None = None


class Simulator(HttpSimulator[RequestRecord]):
    """A Tecomat PLC's TecoApi web server running a declarative program.

    Start it with `await sim.start()` (or `async with`), point a client at `sim.url`,
    change `faults`, `password`, `auth` or the program while it runs, and inspect
    `requests` and values (`get_value`) afterwards.
    """

    def __init__(
        self,
        program: str | Program = "demo",
        *,
        username: str = "admin",
        password: str = "secret",  # noqa: S107 - the documented test default
        auth: AuthMode = "digest",
        nonce_max_uses: int | None = None,
        nonce_ttl: float | None = None,
        serialize: bool = True,
    ) -> None:
        """Prepare a PLC running `program` (a shipped name, a file path or a Program).

        `serialize` answers one request at a time, as the PLC's web server does.
        """
        if auth not in AUTH_MODES:
            raise ValueError(f"auth must be one of {', '.join(AUTH_MODES)}")
        super().__init__(serialize=serialize)
        self._plc = Plc(
            program if isinstance(program, Program) else load_program(program)
        )
        self.username = username
        self.password = password
        self.auth: AuthMode = auth
        self._authenticator = Authenticator(
            nonce_max_uses=nonce_max_uses, nonce_ttl=nonce_ttl
        )
        self._faults = Faults()
        self._faults.add_listener(self._fault_changed)
        self._hang_released = asyncio.Event()
        self._hung = 0

    # --- lifecycle -------------------------------------------------------------------

    def _routes(self, app: web.Application) -> None:
        app.router.add_route("*", "/{tail:.*}", self._handle)

    def _starting(self) -> None:
        self._hang_released = asyncio.Event()

    def _stopped(self) -> None:
        self._release_hung_requests()

    # --- what a test reads and changes ----------------------------------------------

    @property
    def faults(self) -> Faults:
        """The faults in effect; change its fields or assign a new Faults."""
        return self._faults

    @faults.setter
    def faults(self, faults: Faults) -> None:
        self._faults.remove_listener(self._fault_changed)
        self._faults = faults
        faults.add_listener(self._fault_changed)
        if not faults.hang:
            self._release_hung_requests()

    @property
    def nonce_max_uses(self) -> int | None:
        """Digest nonces expire after this many uses (None: never)."""
        return self._authenticator.nonce_max_uses

    @nonce_max_uses.setter
    def nonce_max_uses(self, uses: int | None) -> None:
        self._authenticator.nonce_max_uses = uses

    @property
    def nonce_ttl(self) -> float | None:
        """Digest nonces expire this many seconds after they were issued (None: never)."""
        return self._authenticator.nonce_ttl

    @nonce_ttl.setter
    def nonce_ttl(self, seconds: float | None) -> None:
        self._authenticator.nonce_ttl = seconds

    @property
    def plc(self) -> Plc:
        """The simulated PLC itself, for another protocol serving the same memory.

        The object stays the same for the simulator's life (a program download
        replaces its program and memory, not the PLC), so a PLCComS server holding
        it sees every write made through TecoApi and the other way round.
        """
        return self._plc

    @property
    def link_motion(self) -> LinkMotion:
        """How the program's links move what they copy: set ``rate`` to move over time.

        By default a linked value follows at once; ``sim.link_motion.rate = 20``
        moves a blind 20 % a second towards its target, as a real one moves, and
        ``clock`` may be a test's frozen clock (seconds).
        """
        return self._plc.motion

    @property
    def program(self) -> Program:
        """The program running now."""
        return self._plc.program

    @property
    def stamp(self) -> str:
        """`userProg.stamp` of the running program."""
        return self._plc.program.stamp

    @property
    def serial_number(self) -> str:
        """The PLC's serial number (GetInfo `plc.serialNumber`)."""
        return self._plc.identity.serial_number

    @serial_number.setter
    def serial_number(self, serial_number: str) -> None:
        self._plc.set_identity(serial_number=serial_number)

    @property
    def plc_type(self) -> str:
        """The PLC's type (GetInfo `plc.type`); it sets the request limits."""
        return self._plc.identity.type

    @plc_type.setter
    def plc_type(self, plc_type: str) -> None:
        self._plc.set_identity(type=plc_type)

    @property
    def item_limit(self) -> int:
        """Items per response and names per request for the PLC type (128 or 256)."""
        return self._plc.limit

    @property
    def mode(self) -> str:
        """`RUN`, `HALT` or `ERR` (the same as `faults.mode`)."""
        return self._faults.mode

    @mode.setter
    def mode(self, mode: str) -> None:
        self._faults.mode = mode

    @property
    def hung_requests(self) -> int:
        """How many requests are hanging right now (the `hang` fault)."""
        return self._hung

    async def wait_for_hung_requests(self, count: int) -> None:
        """Wait until at least `count` requests are hanging."""
        await self._progress.wait_until(lambda: self._hung >= count)

    def load_program(self, program: str | Program) -> None:
        """Download a new program into the running PLC (new values and stamp)."""
        self._plc.download(
            program if isinstance(program, Program) else load_program(program)
        )

    def get_value(self, path: str) -> Any:
        """The JSON-shaped value at a case-insensitive path; KeyError if none."""
        return self._plc.get_value(path)

    def set_value(self, path: str, value: Any) -> None:
        """Change a value as the PLC program would (type-checked like a PutObject)."""
        self._plc.set_value(path, value)

    # --- HTTP -----------------------------------------------------------------------

    async def _handle(self, request: web.Request) -> web.StreamResponse:
        raw_target = request.raw_path
        path, _, raw_query = raw_target.partition("?")
        prefix = path[: len(API_PREFIX)]
        exact = self._faults.exact_service_names
        if (
            prefix != API_PREFIX if exact else prefix.lower() != API_PREFIX.lower()
        ) or (path[len(API_PREFIX) : len(API_PREFIX) + 1] not in {"", "/"}):
            return self._web_page(request, raw_query)
        service = services.service_name(
            unquote(path[len(API_PREFIX) + 1 :]), exact=exact
        )
        record = RequestRecord(request.method, service, raw_query)
        self._record(record)
        try:
            answer = await self._answer(request, record, service, raw_query)
        except ConnectionDroppedError:
            _LOGGER.info("%s %s -> connection dropped", request.method, raw_target)
            raise
        record.status = answer.status
        record.items = answer.items
        detail = f" ({answer.items} items)" if answer.items else ""
        if answer.stream is not None:
            detail = f" ({answer.stream})"
        _LOGGER.info("%s %s -> %d%s", request.method, raw_target, answer.status, detail)
        if answer.stream is not None:
            return await self._stream(request, endless=answer.stream == "endless_body")
        return self._response(answer)

    async def _answer(
        self, request: web.Request, record: RequestRecord, service: str, raw_query: str
    ) -> _Answer:
        body = await request.read()
        async with self._turn():
            await self._pause(self._faults.latency)
            try:
                self._authenticator.check(
                    request.headers.get(hdrs.AUTHORIZATION),
                    mode=self.auth,
                    username=self.username,
                    password=self.password,
                    method=request.method,
                    uri=request.raw_path,
                    body=body,
                )
            except AuthenticationError as failure:
                return self._error(failure.error, tuple(failure.challenges))
            record.authorized = True
            fault = self._faults.take_transport_fault()
            if fault is None or fault in {"truncated_json", "malformed_json"}:
                answer = await self._serve(request, service, raw_query, body)
        if fault == "hang":
            _LOGGER.info("%s %s -> hanging", request.method, request.raw_path)
            await self._hang()
            async with self._turn():
                answer = await self._serve(request, service, raw_query, body)
        elif fault == "drop_connection":
            raise ConnectionDroppedError
        elif fault == "http_500":
            return self._error(errors.public_file_unreadable(services.PUBLIC_FILE_NAME))
        elif fault in {"huge_body", "endless_body"}:
            return _Answer(200, b"", stream=fault)
        return _mangled(answer, fault)

    async def _serve(
        self, request: web.Request, service: str, raw_query: str, body: bytes
    ) -> _Answer:
        try:
            _check_accept(request.headers.get(hdrs.ACCEPT))
            result = services.serve(
                self._plc,
                self._faults,
                method=request.method,
                service=service,
                raw_query=raw_query,
                raw_target=request.raw_path,
                body=body,
                now=dt.datetime.now(dt.UTC),
            )
        except TecoError as error:
            return self._error(error)
        await self._pause(self._faults.latency_per_item * result.items)
        return _Answer(result.status, result.body, result.items)

    def _error(self, error: TecoError, challenges: tuple[str, ...] = ()) -> _Answer:
        body = render_error(
            error, services.plc_time(dt.datetime.now(dt.UTC)), self._faults.printing
        )
        return _Answer(error.status, body, challenges=challenges)

    def _headers(self, *, keep_alive: bool) -> CIMultiDict[str]:
        identity = self._plc.identity
        headers: CIMultiDict[str] = CIMultiDict()
        headers[hdrs.SERVER] = (
            f"{SERVER_VERSION} ({identity.version} {identity.serial_number})"
        )
        headers[hdrs.CONNECTION] = "keep-alive" if keep_alive else "close"
        return headers

    def _response(self, answer: _Answer) -> web.Response:
        # The manual's transcripts: keep-alive after a 401 challenge, close otherwise.
        keep_alive = answer.status == 401
        headers = self._headers(keep_alive=keep_alive)
        for challenge in answer.challenges:
            headers.add(hdrs.WWW_AUTHENTICATE, challenge)
        if answer.body:
            headers[hdrs.CONTENT_TYPE] = "application/json"
            headers[hdrs.CACHE_CONTROL] = "no-cache"
        response = web.Response(status=answer.status, body=answer.body, headers=headers)
        if not keep_alive:
            response.force_close()
        return response

    async def _stream(
        self, request: web.Request, *, endless: bool
    ) -> web.StreamResponse:
        """A 200 answer of 64 MiB (`Content-Length` declared), or one without end.

        It is written a chunk at a time while the client reads; it ends when the
        client closes the connection or the simulator stops.
        """
        response = web.StreamResponse(
            status=200, headers=self._headers(keep_alive=False)
        )
        response.content_type = "application/json"
        response.force_close()
        if endless:
            response.enable_chunked_encoding()
        else:
            response.content_length = HUGE_BODY_BYTES
        left = None if endless else HUGE_BODY_BYTES
        try:
            await response.prepare(request)
            chunk = STREAM_OPENING
            while not self._stopping.is_set() and (left is None or left > 0):
                if left is not None:
                    chunk = chunk[:left]
                    left -= len(chunk)
                await response.write(chunk)
                chunk = STREAM_CHUNK
            if left == 0:
                await response.write_eof()
        except (ConnectionError, RuntimeError):
            # The client hung up (what a client that caps its reads does).
            _LOGGER.info("%s %s -> the client closed", request.method, request.raw_path)
        return response

    def _web_page(self, request: web.Request, raw_query: str) -> web.Response:
        """The PLC's own web pages: a title page at `/`, nothing else."""
        record = RequestRecord(request.method, "", raw_query)
        self._record(record)
        identity = self._plc.identity
        if request.path == "/" and request.method == "GET":
            record.status = 200
            page = (
                f"<!DOCTYPE html><html><head><title>{identity.type}</title></head>"
                f"<body><h1>Tecomat {identity.type}</h1>"
                f"<p>{self._plc.program.name}</p></body></html>"
            )
            return web.Response(text=page, content_type="text/html")
        record.status = 404
        return web.Response(status=404, text="Not Found")

    # --- timing and faults -------------------------------------------------------------

    async def _hang(self) -> None:
        """Wait until `hang` is switched off (then answer) or the simulator stops."""
        released = self._hang_released
        stopping = asyncio.ensure_future(self._stopping.wait())
        release = asyncio.ensure_future(released.wait())
        self._hung += 1
        self._progress.notify()
        try:
            await asyncio.wait({stopping, release}, return_when=asyncio.FIRST_COMPLETED)
        finally:
            self._hung -= 1
            stopping.cancel()
            release.cancel()
        if self._stopping.is_set():
            raise ConnectionDroppedError

    def _fault_changed(self, name: str) -> None:
        if name == "hang" and not self._faults.hang:
            self._release_hung_requests()

    def _release_hung_requests(self) -> None:
        self._hang_released.set()
        self._hang_released = asyncio.Event()


def _check_accept(accept: str | None) -> None:
    """Manual: `Accept`, if sent, must allow JSON; anything else answers 400.016."""
    if accept is None:
        return
    ranges = {part.split(";")[0].strip().lower() for part in accept.split(",")}
    if not ranges & ACCEPTED_MEDIA:
        raise errors.unknown_parameter_value("Accept", accept)


def _mangled(answer: _Answer, fault: TransportFault | None) -> _Answer:
    """Apply the truncated/malformed JSON faults to an answer that has a body."""
    if not answer.body or fault not in {"truncated_json", "malformed_json"}:
        return answer
    body = (
        answer.body[: len(answer.body) // 2]
        if fault == "truncated_json"
        else MALFORMED_BODY
    )
    return _Answer(answer.status, body, answer.items, answer.challenges)
