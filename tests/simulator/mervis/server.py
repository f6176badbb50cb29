"""The simulated Mervis controller's web panel API on aiohttp, with its switches.

``POST /login.cgi``, ``/values.cgi`` and ``/command.cgi`` take and answer JSON
as the seed and the released revision describe them (see README.md, *Mervis
web panel simulator*); anything else is the panel's web page (HTML). Every
switch is a field of :class:`Switches` and may change at any time.
"""

from dataclasses import dataclass, field
from datetime import UTC, datetime
import json
import logging
import random
import re
import secrets
from typing import Any, Final, Literal

from aiohttp import web

from tests.simulator.base import HttpSimulator

from .project import Project, ProjectError, Row, encode, house

_LOGGER: Final = logging.getLogger(__package__)

type Spelling = Literal["released", "seed", "both"]
type Order = Literal["asked", "reversed", "shuffled"]
type WriteEncoding = Literal["plain", "hex", "both"]

SPELLINGS: Final = ("released", "seed", "both")
ORDERS: Final = ("asked", "reversed", "shuffled")
WRITE_ENCODINGS: Final = ("plain", "hex", "both")
_RELEASED: Final = re.compile(r"svc://([^/]+)/(.*)", re.IGNORECASE)
_SEED: Final = re.compile(r"svc:(?!//)([^/]+)/(.*)", re.IGNORECASE)
DEFAULT: Final = "defaultconnection"
_ADDRESS: Final = re.compile(r"\s*([0-9]+)\s*\[\s*([0-9]+)\s*,\s*([0-9]+)\s*\]\s*")
WEB_PAGE: Final = b"<html><body><h1>Mervis web panel</h1></body></html>\n"


@dataclass
class Switches:
    """What the controller does where the documents differ or leave it open.

    - ``spelling``: the IDs it knows: the released ``svc://DefaultConnection/``,
      the seed's ``svc:defaultConnection/``, or both; its answers spell ``i``
      its own way (as asked, for both). An ID it does not know is an item error.
    - ``quality``: how a good value's quality is spelled (``G``, ``good``).
    - ``item_errors``: CommUids answered with an item error ``e``;
      ``qualities``: CommUids answered with another quality (``"B"``).
    - ``order``: answers as asked, reversed, or shuffled.
    - ``max_variables``/``max_request_size``: limits enforced with an error
      (None: none); ``tell_limits``: the login's answer and the refusal carry
      them (the seed's *Configuration Response*).
    - ``write_encoding``: what ``set`` must be: a JSON value, the bytes as hex,
      or either.
    - ``session_requests``: a login's ``c`` expires after this many requests
      (None: never); ``accept_plain``: requests may carry the plain password.
    """

    spelling: Spelling = "both"
    quality: str = "G"
    item_errors: set[int] = field(default_factory=set)
    qualities: dict[int, str] = field(default_factory=dict)
    order: Order = "asked"
    max_variables: int | None = None
    max_request_size: int | None = None
    tell_limits: bool = False
    write_encoding: WriteEncoding = "plain"
    session_requests: int | None = None
    accept_plain: bool = True
    platform: str = "uPLC"


@dataclass(slots=True)
class RequestRecord:
    """One request: the service, the variables it named, its body's bytes, the code."""

    service: str
    variables: int = 0
    body_bytes: int = 0
    code: str = ""


class MervisSimulator(HttpSimulator[RequestRecord]):
    """A Mervis controller's web panel serving a project.

    ``username`` None: a project without credentials. Start it with ``await
    sim.start()`` (or ``async with``), point a client at ``sim.url``, change
    ``switches`` or values (``project.set``) while it runs, and read
    ``requests`` afterwards.
    """

    def __init__(
        self,
        project: Project | None = None,
        *,
        username: str | None = "admin",
        password: str = "secret",  # noqa: S107 - the documented test default
        switches: Switches | None = None,
        seed: int = 0,
    ) -> None:
        """Prepare a controller; nothing listens before :meth:`start`."""
        super().__init__()
        self.project = project if project is not None else house()
        self.username = username
        self.password = password
        self.switches = switches or Switches()
        self.writes: list[tuple[str, Any]] = []
        self.connections: dict[str, Project] = {}
        """Other connections' projects by name (lower case): read, never written."""
        self._sessions: dict[str, int | None] = {}
        self._random = random.Random(seed)

    def _routes(self, app: web.Application) -> None:
        app.router.add_route("*", "/{tail:.*}", self._handle)

    def expire_sessions(self) -> None:
        """Every ``c`` a login gave stops being taken (sessions expire)."""
        self._sessions.clear()

    def count(self, service: str) -> int:
        """How many requests of a service arrived (``values``, ``login``, ``command``)."""
        return sum(1 for record in self.requests if record.service == service)

    # --- HTTP ------------------------------------------------------------------------

    async def _handle(self, request: web.Request) -> web.StreamResponse:
        service = request.path.strip("/").removesuffix(".cgi").lower()
        if request.method != "POST" or service not in ("login", "values", "command"):
            return web.Response(body=WEB_PAGE, content_type="text/html")
        body = await request.read()
        record = RequestRecord(service, body_bytes=len(body))
        self._record(record)
        try:
            message = json.loads(body)
        except ValueError:
            return self._answer(record, "error", "not JSON")
        if not isinstance(message, dict) or message.get("ver") != 1:
            return self._answer(record, "error", "unknown version")
        if service == "login":
            return self._login(record, message)
        items = message.get("v")
        if not isinstance(items, list):
            return self._answer(record, "error", "no variables")
        record.variables = len(items)
        if not self._signed_in(message.get("c")):
            return self._answer(record, "unauthorized", "invalid credentials")
        switches = self.switches
        if switches.max_request_size is not None and len(body) > (
            switches.max_request_size
        ):
            return self._refuse_limits(record, "request too large")
        if service == "values":
            if switches.max_variables is not None and len(items) > (
                switches.max_variables
            ):
                return self._refuse_limits(record, "too many variables")
            return self._values(record, items)
        return self._command(record, items)

    def _answer(
        self, record: RequestRecord, code: str, msg: str = "", **extra: Any
    ) -> web.Response:
        record.code = code
        return web.json_response({"ver": 1, "code": code, "msg": msg, **extra})

    def _limits(self) -> dict[str, Any]:
        switches = self.switches
        if not switches.tell_limits:
            return {}
        told: dict[str, Any] = {"platform": switches.platform}
        if switches.max_variables is not None:
            told["maxVariablesInRequest"] = switches.max_variables
        if switches.max_request_size is not None:
            told["maxRequestSize"] = switches.max_request_size
        return told

    def _refuse_limits(self, record: RequestRecord, msg: str) -> web.Response:
        return self._answer(record, "error", msg, **self._limits())

    # --- login and sessions ------------------------------------------------------------

    def _login(self, record: RequestRecord, message: dict[str, Any]) -> web.Response:
        if self.username is None:
            return self._answer(record, "ok", **self._limits())
        given = message.get("c")
        if (
            not isinstance(given, dict)
            or given.get("u") != self.username
            or given.get("p") != self.password
        ):
            return self._answer(record, "unauthorized", "wrong user or password")
        token = secrets.token_hex(16)
        self._sessions[token] = self.switches.session_requests
        return self._answer(
            record, "ok", c={"u": self.username, "p": token}, **self._limits()
        )

    def _signed_in(self, given: Any) -> bool:
        """Whether a request's ``c`` is taken (always, for a project without credentials)."""
        if self.username is None:
            return True
        if not isinstance(given, dict) or given.get("u") != self.username:
            return False
        secret = given.get("p")
        if secret == self.password:
            return self.switches.accept_plain
        if not isinstance(secret, str) or secret not in self._sessions:
            return False
        left = self._sessions[secret]
        if left is not None:
            if left <= 0:
                del self._sessions[secret]
                return False
            self._sessions[secret] = left - 1
        return True

    # --- values ----------------------------------------------------------------------

    def _address(self, ident: Any) -> tuple[int, int, int] | None:
        """The bytes an ID of the default connection names, if it is spelled as this
        controller spells IDs."""
        found = self._read_target(ident)
        if found is None or found[0] is not self.project:
            return None
        return found[1]

    def _read_target(self, ident: Any) -> tuple[Project, tuple[int, int, int]] | None:
        """The project (its connection's) and the bytes an ID names, if spelled so."""
        if not isinstance(ident, str):
            return None
        spelling = self.switches.spelling
        match = None
        if spelling in ("released", "both"):
            match = _RELEASED.fullmatch(ident)
        if match is None and spelling in ("seed", "both"):
            match = _SEED.fullmatch(ident)
        if match is None or (found := _ADDRESS.fullmatch(match.group(2))) is None:
            return None
        connection = match.group(1).lower()
        project = (
            self.project if connection == DEFAULT else self.connections.get(connection)
        )
        if project is None:
            return None
        commuid, offset, length = (int(part) for part in found.groups())
        return project, (commuid, offset, length)

    def _spelled(self, ident: str, address: tuple[int, int, int] | None) -> str:
        """An answer's ``i``: the controller's own spelling (as asked, for both,
        and for another connection)."""
        if address is None or self.switches.spelling == "both":
            return ident
        prefix = (
            "svc://DefaultConnection/"
            if self.switches.spelling == "released"
            else "svc:defaultConnection/"
        )
        commuid, offset, length = address
        return f"{prefix}{commuid}[{offset},{length}]"

    def _values(self, record: RequestRecord, items: list[Any]) -> web.Response:
        switches = self.switches
        now = int(datetime.now(UTC).timestamp() * 1000)
        answered: list[dict[str, Any]] = []
        for ident in items:
            target = self._read_target(ident)
            project, address = (None, None) if target is None else target
            spelled = self._spelled(
                str(ident), address if project is self.project else None
            )
            raw = None
            if project is not None and address is not None:
                raw = project.read(*address)
            if address is None or raw is None or address[0] in switches.item_errors:
                answered.append({"i": spelled, "e": "unknown variable"})
                continue
            quality = switches.qualities.get(address[0], switches.quality)
            answered.append(
                {"i": spelled, "v": raw.hex().upper(), "q": quality, "t": now}
            )
        if switches.order == "reversed":
            answered.reverse()
        elif switches.order == "shuffled":
            self._random.shuffle(answered)
        return self._answer(record, "ok", v=answered)

    # --- commands ----------------------------------------------------------------------

    def _command(self, record: RequestRecord, items: list[Any]) -> web.Response:
        # uPLC: only the first item of a command is used.
        item = items[0] if items else None
        if not isinstance(item, dict) or "set" not in item:
            return self._answer(record, "error", "no command")
        address = self._address(item.get("i"))
        row = None if address is None else self.project.at(*address)
        if address is None or row is None:
            return self._answer(record, "error", "unknown variable")
        try:
            raw = self._written(row, item["set"])
        except (ProjectError, ValueError) as err:
            return self._answer(record, "error", f"value refused: {err}")
        self.project.write(address[0], address[1], raw)
        self.writes.append((row.key, item["set"]))
        return self._answer(record, "ok")

    def _written(self, row: Row, value: Any) -> bytes:
        """The bytes a command's ``set`` writes, as ``write_encoding`` takes it."""
        encoding = self.switches.write_encoding
        hexed = isinstance(value, str) and (
            row.type.lower() != "string" or encoding == "hex"
        )
        if hexed:
            if encoding == "plain":
                raise ProjectError("a value, not text, is expected")
            raw = bytes.fromhex(value)
            if len(raw) != row.length:
                raise ProjectError(f"{len(raw)} bytes, not {row.length}")
            return raw
        if encoding == "hex":
            raise ProjectError("hex bytes are expected")
        return encode(row, value)
