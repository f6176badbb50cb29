"""The TecoApi client: one async class speaking HTTP to a Tecomat PLC.

The aiohttp session is injected and never closed here. Requests go out one at a
time (the PLC's embedded server answers one ``Connection: close`` request at a
time), each with ``Accept: application/json`` and the client's timeout. What an
error answer means, and what of a failed read is tried again, is :mod:`.errors`'s.
"""

from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass
import json
import logging
from types import MappingProxyType
from typing import Any, Final

import aiohttp

from ...core.codec import NOT_A_PATH
from ...core.exceptions import (
    InvalidValueError,
    MalformedResponseError,
    NotAPlcError,
    PlcAuthenticationError,
    PlcError,
    PlcResponseError,
    TooManyItemsError,
    ValueRejectedError,
    VariableNotFoundError,
)
from ...core.host import normalize_host
from ...core.http import HttpAuth, HttpClient, HttpExchange, Reply
from ...core.models import Catalogue, Point, PointAttributes, SourceInfo
from ..points import value_path
from ..writes import WireValue, encode_json_value, validate_write
from .auth import (
    AuthScheme,
    DigestAuth,
    basic_authorization,
    is_tecoapi_challenge,
    offered_schemes,
)
from .body import MAX_BODY_BYTES, decode_text
from .catalogue import build_catalogue, parse_meta, parse_root_list
from .errors import (
    ARRAY_ELEMENT,
    AUTH_CODES,
    REJECTED_CODES,
    error_body,
    named,
    refusal,
    response_error,
    split_failed,
    split_helps,
)
from .info import ITEM_LIMIT_UNKNOWN, item_limit_for_type, parse_plc_info
from .paths import (
    MAX_TARGET_LENGTH,
    MISSING,
    SERVICE_PREFIX,
    SET_OBJECT,
    Steps,
    encode_name,
    encode_value,
    get_object_target,
    lookup,
    member,
    path_steps,
    readable_name,
    split_path,
    walk,
)
from .planner import plan_reads
from .plans import PlannedRequest, PollResult, ReadPlan
from .roots import RootReading
from .values import TEXT_KINDS, RememberedParser, value_parser

_LOGGER = logging.getLogger(__name__)


def _covers(name: str, key: str) -> bool:
    """Whether reading ``name`` answers for the point ``key``."""
    name = name.lower()
    return (
        key == name
        or key.startswith((f"{name}.", f"{name}["))
        or name == f"{key}.value"
    )


type _Reading = tuple[
    str, tuple[str, ...] | None, Steps | None, Callable[[Any], Any], bool
]
"""How a point is read from an answer: its key, its path's member names where no
step is indexed (else None), its path's steps (None: not a path), what types its
value, and whether it is a T_ApiObject."""

type _PlanReadings = tuple[frozenset[str], tuple[list[_Reading], ...]]
"""A plan's points the read's points lack, and each request's readings."""

READINGS_KEPT: Final = 4
"""Plans whose readings are kept (a poll's, with attributes, a few points')."""


def _reading(key: str, point: Point) -> _Reading:
    """Work out once how a point is read from every answer."""
    try:
        steps: Steps | None = path_steps(point.path)
    except ValueError:
        steps = None
    names = (
        None
        if steps is None or any(indexes for _, indexes, _ in steps)
        else tuple(name for name, _, _ in steps)
    )
    kind = point.kind
    parse = RememberedParser(kind) if kind in TEXT_KINDS else value_parser(kind)
    return key, names, steps, parse, point.described


class _Poll:
    """What one poll has gathered so far.

    ``known_meta`` outlives the poll: the last ``attr`` object read for each point
    and its parsed attributes, so an unchanged ``attr`` is not parsed again.
    """

    def __init__(
        self,
        points: Mapping[str, Point],
        known_meta: dict[str, tuple[Any, PointAttributes | None]],
    ) -> None:
        self.points = points
        self.known_meta = known_meta
        self.values: dict[str, Any] = {}
        self.attributes: dict[str, PointAttributes] = {}
        self.missing: set[str] = set()

    def readings(self, keys: Iterable[str]) -> list[_Reading]:
        """Return how the points ``keys`` are read."""
        points = self.points
        return [_reading(key, points[key]) for key in keys]

    def take(self, tree: Mapping[str, Any], readings: Iterable[_Reading]) -> None:
        """Map one response back to its points, ignoring case.

        The loop every point of every poll takes: a path without indexes is
        followed here, member by member (the exact spelling first, as
        :func:`member`), any other by :func:`walk`.
        """
        values, missing, attributes = self.values, self.missing, self.attributes
        known_meta = self.known_meta
        bracketed: dict[int, bool] = {}
        for key, names, steps, parse, described in readings:
            node: Any = tree
            if names is None:
                node = MISSING if steps is None else walk(tree, steps, bracketed)
            else:
                for name in names:
                    if not isinstance(node, dict):
                        node = MISSING
                        break
                    found = node.get(name, MISSING)
                    node = member(node, name) if found is MISSING else found
                    if node is MISSING:
                        break
            if described:
                if isinstance(node, dict):
                    raw = node.get("value", MISSING)
                    if raw is MISSING:
                        raw = member(node, "value")
                    attr = node.get("attr", MISSING)
                    if attr is MISSING:
                        attr = member(node, "attr")
                    if attr is not MISSING:
                        # Parsed again only if it changed (inline: every poll).
                        known = known_meta.get(key)
                        if known is not None and known[0] == attr:
                            parsed = known[1]
                        else:
                            parsed = parse_meta(attr)
                            known_meta[key] = (attr, parsed)
                        if parsed:
                            attributes[key] = parsed
                else:
                    raw = MISSING
            else:
                raw = node
            if raw is MISSING:
                missing.add(key)
                continue
            values[key] = parse(raw)


class TecoApiClient(HttpClient):
    """An async client of one PLC's TecoApi.

    ``request_count`` counts HTTP requests sent on the wire, Digest challenge
    round trips included. ``item_limit`` is the learned per-response item limit:
    128 until :meth:`get_info` tells the CPU type, lowered when the PLC answers
    413 with a smaller limit.
    """

    def __init__(
        self,
        session: aiohttp.ClientSession,
        host: str,
        username: str,
        password: str,
        *,
        verify_ssl: bool = True,
        timeout: float = 10.0,
    ) -> None:
        """Prepare a client; nothing is sent until the first call."""
        self.base_url = normalize_host(host)
        if ":" in username:
            raise PlcAuthenticationError("A user name must not contain ':'")
        # The two ways to authenticate, made once: Digest (answering the PLC's
        # challenge, then pre-emptively) and Basic (only where nothing else is
        # offered).
        self._digest = HttpAuth(
            middlewares=(DigestAuth(username, password, preemptive=True),)
        )
        self._basic = HttpAuth(
            headers=MappingProxyType(
                {"Authorization": basic_authorization(username, password)}
            )
        )
        self._scheme: AuthScheme | None = None
        self._http = HttpExchange(
            session,
            self.base_url,
            sender="a PLC",
            limit=MAX_BODY_BYTES,
            timeout=timeout,
            verify_ssl=verify_ssl,
            statuses={401: self._unauthorized},
            otherwise=self._refused,
            renewal=self,
            decode=decode_text,
        )
        self._http.auth = self._digest
        self._info_limit = ITEM_LIMIT_UNKNOWN
        self._learned_limit: int | None = None
        self._catalogue: Catalogue | None = None
        self._known_meta: dict[str, tuple[Any, PointAttributes | None]] = {}
        self._readings: dict[
            int, tuple[ReadPlan, Mapping[str, Point], _PlanReadings]
        ] = {}

    @property
    def item_limit(self) -> int:
        """The per-response item limit the planner uses."""
        if self._learned_limit is None:
            return self._info_limit
        return min(self._info_limit, self._learned_limit)

    @property
    def auth_scheme(self) -> AuthScheme | None:
        """The scheme the PLC asked for (None before its first challenge)."""
        return self._scheme

    # --- HTTP: the scheme the PLC asks for, what an error answer means ---------

    async def prepare(self) -> None:
        """Nothing to do before a request: the scheme is learned from its answer."""

    async def renew(self, reply: Reply, resent: int) -> bool:
        """Learn the scheme from the PLC's answer; whether to send the request again.

        Basic only when the PLC offers nothing else; a PLC that stops taking
        Basic (a 403.022, or a 401 offering Digest) is asked again for its
        challenge. A first success without a scheme is Digest's.
        """
        status = reply.status
        if status in (401, 403):
            offered = offered_schemes(reply.challenges)
            if (
                resent == 0
                and self._scheme == "basic"
                and (status == 403 or "digest" in offered)
            ):
                self._use(None)
                return True
            if status == 401 and self._scheme is None and offered == {"basic"}:
                self._use("basic")
                return True
        elif self._scheme is None and reply.ok:
            self._scheme = "digest"
        return False

    def _use(self, scheme: AuthScheme | None) -> None:
        """Authenticate as ``scheme`` from now on (None: answer the next challenge)."""
        self._scheme = scheme
        self._http.auth = self._basic if scheme == "basic" else self._digest

    def _unauthorized(self, reply: Reply) -> PlcError:
        """Return what a final 401 means: rejected credentials, or not a TecoApi server."""
        error = error_body(reply.body)
        if error is None and not is_tecoapi_challenge(reply.challenges):
            return NotAPlcError(
                f"{self.base_url} asks for credentials but is not a TecoApi server"
            )
        code, message = error or ("401.000", "Unauthorized")
        return PlcAuthenticationError(
            f"The PLC rejected the credentials ({code}: {message})"
        )

    def _refused(self, reply: Reply) -> PlcError:
        """Return what an answer other than a 2xx means: its error body's code, or status."""
        status = reply.status
        error = error_body(reply.body)
        if error is None:
            if status == 404 or 300 <= status < 400:
                return NotAPlcError(
                    f"{self.base_url} answered HTTP {status}: not a TecoApi server"
                )
            if reply.html:
                return NotAPlcError(
                    f"{self.base_url} answered a web page: not a TecoApi server"
                )
            return PlcResponseError(
                f"HTTP {status} without a TecoApi error body",
                code=f"{status}.000",
                status=status,
            )
        code, message = error
        if code in AUTH_CODES:
            return PlcAuthenticationError(
                f"The PLC rejected the credentials ({code}: {message})"
            )
        return response_error(code, status, message)

    async def _get_json(self, target: str) -> Any:
        """GET a target and decode its JSON body."""
        reply = await self._http.request("GET", target)
        try:
            return reply.json()
        except (ValueError, RecursionError) as err:
            if reply.html:
                raise NotAPlcError(
                    f"{self.base_url} answered a web page: not a TecoApi server"
                ) from err
            raise MalformedResponseError(
                "The PLC answered malformed JSON",
                code=f"{reply.status}.000",
                status=reply.status,
            ) from err

    # --- services -------------------------------------------------------------

    async def get_info(self) -> SourceInfo:
        """GetInfo: the PLC and its program; also sets the item limit from its type."""
        info = parse_plc_info(await self._get_json(f"{SERVICE_PREFIX}GetInfo"))
        self._info_limit = item_limit_for_type(info.model)
        return info

    async def get_list(self) -> tuple[str, ...]:
        """GetList: the names of the public roots, as the PLC spells them."""
        return parse_root_list(await self._get_json(f"{SERVICE_PREFIX}GetList"))

    async def get_object(self, names: Sequence[str]) -> dict[str, Any]:
        """GetObject of ``names`` in one request: the PLC's JSON object."""
        return await self._get_object(get_object_target(names))

    async def get_planned(self, request: PlannedRequest) -> dict[str, Any]:
        """GetObject of a planned request (its target made once, by the planner)."""
        return await self._get_object(request.target)

    async def _get_object(self, target: str) -> dict[str, Any]:
        """GetObject of a target: the PLC's JSON object."""
        body = await self._get_json(target)
        if not isinstance(body, dict):
            raise MalformedResponseError(
                "GetObject answered something other than an object", status=200
            )
        return body

    # --- discovery ------------------------------------------------------------

    async def discover(self) -> Catalogue:
        """GetList, then the roots read with as few GetObject requests as it takes.

        Batches are cut to the 256-character target and to the sizes the answers
        so far suggest; an answer too large (413) costs one 413 per root that
        turns out too big to share its request (see ``roots``); a root GetObject
        rejects (400.005) is dropped. Both are reported in ``skipped_roots``; the
        cost, against its bound, in ``Catalogue.discovery``.
        """
        roots = await self.get_list()
        reading = RootReading(roots, item_limit=self.item_limit)
        while (batch := reading.next_batch()) is not None:
            try:
                answer = await self.get_object(batch)
            except PlcResponseError as err:
                if isinstance(err, TooManyItemsError):
                    self._learn_limit(err)
                reading.failed(batch, err, self.item_limit)
                _LOGGER.debug("Reading roots %s failed: %s", batch, err)
                continue
            reading.answered(batch, answer)
        self._catalogue = build_catalogue(
            roots,
            reading.tree,
            skipped_roots=reading.skipped,
            discovery=reading.stats(),
        )
        self._known_meta.clear()
        return self._catalogue

    # --- polling --------------------------------------------------------------

    def plan(self, points: Iterable[Point], *, with_attrs: bool) -> ReadPlan:
        """Plan a poll of ``points`` under the learned limit (see ``plan_reads``)."""
        return plan_reads(
            points,
            item_limit=self.item_limit,
            with_attrs=with_attrs,
            catalogue=self._catalogue,
        )

    async def read(self, plan: ReadPlan, points: Mapping[str, Point]) -> PollResult:
        """Execute a plan: typed values by point key, metadata, missing points.

        A request the PLC rejects with 400.005 is split until the missing names are
        isolated; only their points are reported missing. A 413 lowers the learned
        item limit and re-plans that request.
        """
        poll = _Poll(points, self._known_meta)
        absent, plan_readings = self._plan_readings(plan, points)
        poll.missing.update(plan.unreadable)
        poll.missing.update(absent)
        for request, readings in zip(plan.requests, plan_readings, strict=True):
            await self._read_names(
                request.names, readings, plan.with_attrs, poll, request.target
            )
        return PollResult(
            values=poll.values,
            attributes=poll.attributes,
            missing=frozenset(poll.missing),
        )

    def _plan_readings(
        self, plan: ReadPlan, points: Mapping[str, Point]
    ) -> _PlanReadings:
        """Return how each request of a plan is read, worked out once per plan.

        With them, the plan's points ``points`` lacks. The readings of the few
        plans read last are kept (by the plan and the points they were worked
        out for).
        """
        kept = self._readings.pop(id(plan), None)
        if kept is None or kept[0] is not plan or kept[1] is not points:
            readings = tuple(
                [
                    _reading(key, points[key])
                    for key in request.point_keys
                    if key in points
                ]
                for request in plan.requests
            )
            absent = frozenset(key for key in plan.point_keys if key not in points)
            kept = (plan, points, (absent, readings))
            if len(self._readings) >= READINGS_KEPT:
                del self._readings[next(iter(self._readings))]
        self._readings[id(plan)] = kept
        return kept[2]

    async def _read_names(
        self,
        names: Sequence[str],
        readings: list[_Reading],
        with_attrs: bool,
        poll: _Poll,
        target: str | None = None,
    ) -> None:
        """Read ``names`` for the points of ``readings``, isolating failures.

        ``target`` is the request's, made by the planner (None: made here).
        """
        try:
            tree = await self._get_object(target or get_object_target(names))
        except PlcResponseError as err:
            keys = [reading[0] for reading in readings]
            if isinstance(err, TooManyItemsError) and self._learn_limit(err):
                replanned = plan_reads(
                    (poll.points[key] for key in keys),
                    item_limit=self.item_limit,
                    with_attrs=with_attrs,
                    catalogue=self._catalogue,
                )
                poll.missing.update(replanned.unreadable)
                for request in replanned.requests:
                    await self._read_request(request, with_attrs, poll)
                return
            if not split_helps(err):
                raise
            if len(names) == 1:
                _LOGGER.debug("%s is not readable: %s", names[0], err)
                poll.missing.update(keys)
                return
            for part in split_failed(list(names), err):
                part_readings = [
                    reading
                    for reading in readings
                    if any(_covers(name, reading[0]) for name in part)
                ]
                await self._read_names(part, part_readings, with_attrs, poll)
            if name := named(names, err):
                poll.missing.update(key for key in keys if _covers(name, key))
            return
        poll.take(tree, readings)

    async def _read_request(
        self, request: PlannedRequest, with_attrs: bool, poll: _Poll
    ) -> None:
        """Read one planned request."""
        readings = poll.readings(
            key for key in request.point_keys if key in poll.points
        )
        await self._read_names(
            request.names, readings, with_attrs, poll, request.target
        )

    def _learn_limit(self, err: TooManyItemsError) -> bool:
        """Lower the item limit to what a 413 allowed; whether it went down."""
        if err.allowed is None or not 0 < err.allowed < self.item_limit:
            return False
        self._learned_limit = err.allowed
        _LOGGER.debug("The PLC allows %s items per response", self._learned_limit)
        return True

    async def read_path(self, path: str) -> Any:
        """Return the JSON-shaped value of any public variable path.

        An array element is read through its array, as every read of this client.
        """
        try:
            segments = split_path(path)
        except ValueError:
            segments = [path]
        name = readable_name(path) if len(segments) > 1 else path
        try:
            tree = await self.get_object([name])
        except PlcResponseError as err:
            if not isinstance(err, TooManyItemsError) or name == path:
                raise
            tree = await self.get_object([path])
        value = lookup(tree, segments)
        if value is MISSING:
            raise VariableNotFoundError(
                f"The PLC's answer does not hold {path!r}", path=path, status=200
            )
        return value

    # --- writes ---------------------------------------------------------------

    async def write(self, point: Point, value: Any) -> None:
        """Validate and write a point's value; returns once the PLC acknowledged."""
        await self._write(value_path(point), value, validate_write(point, value))

    async def write_path(self, path: str, value: Any) -> None:
        """Write a JSON-shaped value to any public variable path, unvalidated.

        Its shape is checked only as far as the wire needs (no scientific
        notation, ASCII text); the PLC judges the rest.
        """
        await self._write(path, value, encode_json_value(path, value))

    async def write_many(self, items: Sequence[tuple[str, Any, WireValue]]) -> None:
        """Write validated values, ``(path, value, wire)``, in the fewest requests.

        The manual's services carry several: ``SetObject?name1=val1&name2=val2``
        (within the 256 characters) and a PutObject body ``{"name": value,
        ...}``. Consecutive writes of one form share a request, so the order
        given is the order sent; a PutObject carries each root once. Returns
        once every request was acknowledged; a refusal names the variable the
        PLC named, else the request's first.
        """
        request: list[_Piece] = []
        for piece in [_piece(path, value, wire) for path, value, wire in items]:
            if request and not _joins(request, piece):
                await self._send_pieces(request)
                request = []
            request.append(piece)
        if request:
            await self._send_pieces(request)

    async def _write(self, path: str, value: Any, wire: WireValue) -> None:
        """SetObject for member/element paths, PutObject for top-level variables.

        A struct member that SetObject cannot carry -- a structured value, or a
        target that would pass 256 characters (a long string) -- goes as a
        PutObject of the nested member (``{"a": {"b": ...}}``) instead; that form
        is our reading, the manual shows PutObject of whole variables only.
        """
        await self._send_pieces([_piece(path, value, wire)])

    async def _send_pieces(self, pieces: "list[_Piece]") -> None:
        """Send one SetObject or PutObject of its pieces (see :meth:`write_many`)."""
        if pieces[0].pair is not None:
            pairs = "&".join(piece.pair or "" for piece in pieces)
            method, target, body = "GET", f"{SET_OBJECT}{pairs}", None
        else:
            members = ", ".join(piece.member or "" for piece in pieces)
            method, target = "PUT", f"{SERVICE_PREFIX}PutObject"
            body = ("{" + members + "}").encode("ascii")
        try:
            await self._http.request(method, target, body=body)
        except PlcResponseError as err:
            if err.code in REJECTED_CODES:
                piece = _refused(pieces, err.message)
                reason = refusal(err.message, piece.value)
                raise ValueRejectedError(
                    err.message if reason is None else str(reason),
                    path=piece.path,
                    value=piece.value,
                    code=err.code,
                    status=err.status,
                    said=err.said if reason is None else "",
                    why=reason,
                ) from err
            raise


@dataclass(frozen=True, slots=True)
class _Piece:
    """One write as a request carries it: a SetObject pair or a PutObject member."""

    path: str
    value: Any
    root: str
    pair: str | None
    """``name=value`` of a SetObject (None: a PutObject member)."""
    member: str | None
    """``"root": value`` of a PutObject body (None: a SetObject pair)."""


def _piece(path: str, value: Any, wire: WireValue) -> _Piece:
    """Spell a write as :meth:`TecoApiClient._write` sends it alone."""
    member = "." in path or "[" in path
    pair = f"{encode_name(path)}="
    if member and wire.query is not None:
        pair += encode_value(wire.query)
    root = path.split(".", 1)[0].split("[", 1)[0].lower()
    if (
        member
        and wire.query is not None
        and len(SET_OBJECT) + len(pair) <= MAX_TARGET_LENGTH
    ):
        return _Piece(path, value, root, pair, None)
    body = _nested_body(path, value, wire).decode("ascii")
    return _Piece(path, value, root, None, body[1:-1])


def _joins(request: list[_Piece], piece: _Piece) -> bool:
    """Whether a piece may join a request: its form, the limit, each root once."""
    if (request[0].pair is None) != (piece.pair is None):
        return False
    if piece.pair is not None:
        pairs = sum(len(item.pair or "") + 1 for item in request)
        return len(SET_OBJECT) + pairs + len(piece.pair) <= MAX_TARGET_LENGTH
    return all(item.root != piece.root for item in request)


def _refused(pieces: list[_Piece], message: str) -> _Piece:
    """Return the piece a refusal names (400.015: 'NNN'), else the request's first."""
    for piece in pieces:
        if f"'{piece.path.lower()}'" in message.lower():
            return piece
    return pieces[0]


def _nested_body(path: str, value: Any, wire: WireValue) -> bytes:
    """Build a PutObject body writing ``path``: ``{"a": {"b": <value>}}`` for ``a.b``."""
    try:
        segments = split_path(path)
    except ValueError as err:
        raise InvalidValueError(path, value, NOT_A_PATH()) from err
    if any(isinstance(segment, int) for segment in segments):
        raise InvalidValueError(path, value, ARRAY_ELEMENT(length=MAX_TARGET_LENGTH))
    text = wire.json
    for segment in reversed(segments):
        text = f"{{{json.dumps(segment)}: {text}}}"
    return text.encode("ascii")
