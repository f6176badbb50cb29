"""Reading points at the lower bound: one range per variable, requests packed full.

Members of a function block or struct share their parent's CommUid at
different offsets. A poll reads each CommUid once, as one ID whose
``[offset,length]`` covers the wanted members from the first to the last, and
slices each member out of the answer. The IDs are then packed, in CommUid order,
into as few ``values.cgi`` requests as the controller's two limits allow: at
most ``max_variables`` IDs, and a body of at most ``max_bytes`` (the body is
measured exactly as it is sent, credentials included).

The fewest requests any client needs for the same IDs is
``max(⌈IDs / max_variables⌉, ⌈(ID bytes + commas) / room for IDs in a body⌉)``
(a body of ``k`` IDs holds ``k - 1`` commas: one more per ID, one more of room): a plan
keeps that ``lower_bound`` beside its ``requests``. An ID longer than the room (a
``max_bytes`` below the body of that ID alone) fits no body: it is sent alone, over the
limit, and the bound counts it as one request; only the IDs that fit count by bytes.
So the bound never exceeds the plan, however small ``max_bytes`` is.
"""

from collections.abc import Collection, Iterable, Mapping, Sequence
from dataclasses import dataclass
import json
import math
from typing import Any, Final

from ..core.models import Point
from .ids import Address, IdStyle

DEFAULT_MAX_VARIABLES: Final = 64
"""IDs per request until the controller says or refuses: what a public client
sends real controllers (the seed's uPLC example allows 5; it is learned)."""
DEFAULT_MAX_REQUEST_SIZE: Final = 4096
"""Body bytes per request until the controller says or refuses: 64 long IDs
with credentials fit (the seed's uPLC example allows 1,500; it is learned)."""


def request_body(credentials: Mapping[str, Any] | None, ids: Sequence[Any]) -> bytes:
    """Return a request's body as it is sent: compact JSON, ``c`` when signed in."""
    payload: dict[str, Any] = {"ver": 1}
    if credentials is not None:
        payload["c"] = credentials
    payload["v"] = list(ids)
    return json.dumps(payload, separators=(",", ":"), ensure_ascii=False).encode()


@dataclass(frozen=True, slots=True)
class RangeRead:
    """One ID of a request: some bytes of a variable, and the points in them."""

    address: Address
    members: tuple[tuple[str, Address], ...]
    """Each point's key and its own bytes (within ``address``)."""

    def slice(self, raw: bytes, member: Address) -> bytes:
        """Return a member's bytes out of this range's."""
        start = member.offset - self.address.offset
        return raw[start : start + member.length]


@dataclass(frozen=True, slots=True)
class PlannedRequest:
    """One ``values.cgi`` request: its IDs and the bytes of its body."""

    reads: tuple[RangeRead, ...]
    body_bytes: int


@dataclass(frozen=True, slots=True)
class ReadPlan:
    """How the points are read: requests, against the fewest there can be.

    ``unreadable`` are the points whose address is none (not read).
    """

    requests: tuple[PlannedRequest, ...]
    point_keys: frozenset[str]
    max_variables: int
    max_bytes: int
    style: IdStyle
    lower_bound: int
    unreadable: frozenset[str] = frozenset()

    @property
    def ids(self) -> int:
        """How many IDs the plan reads."""
        return sum(len(request.reads) for request in self.requests)


def ranges(
    points: Iterable[Point],
    *,
    breaks: Collection[str] = (),
    alone: Collection[str] = (),
) -> tuple[list[RangeRead], frozenset[str]]:
    """Return one range per variable covering its points' bytes, in variable order.

    A point in ``breaks`` begins a range of its own (its variable's members
    before it are another), one in ``alone`` is a range of itself (a point the
    controller refuses: its neighbours are read without it). Also the points
    whose address is not ``CommUid[offset,length]``.
    """
    by_variable: dict[tuple[str, int], list[tuple[str, Address]]] = {}
    unreadable: set[str] = set()
    for point in points:
        try:
            address = Address.parse(point.address)
        except ValueError:
            unreadable.add(point.key)
            continue
        by_variable.setdefault(address.variable, []).append((point.key, address))
    reads: list[RangeRead] = []
    for variable in sorted(by_variable):
        members = sorted(by_variable[variable], key=lambda item: (item[1], item[0]))
        reads.extend(spanning(part) for part in _cut(members, breaks, alone))
    return reads, frozenset(unreadable)


def spanning(members: Sequence[tuple[str, Address]]) -> RangeRead:
    """Return the range of one variable's members: from the first byte to the last."""
    start = min(address.offset for _, address in members)
    end = max(address.end for _, address in members)
    first = members[0][1]
    return RangeRead(first.with_bytes(start, end - start), tuple(members))


def _cut(
    members: list[tuple[str, Address]],
    breaks: Collection[str],
    alone: Collection[str],
) -> list[list[tuple[str, Address]]]:
    """Cut a variable's members (in order) where a break begins; each lone one apart.

    A lone member does not cut the others: their range spans its bytes, as it
    spans any gap between members. The parts are in the order of their first
    bytes.
    """
    parts: list[list[tuple[str, Address]]] = []
    current: list[tuple[str, Address]] = []
    for member in members:
        key = member[0]
        if key in alone:
            parts.append([member])
            continue
        if current and key in breaks:
            parts.append(current)
            current = []
        current.append(member)
    if current:
        parts.append(current)
    return sorted(parts, key=lambda part: part[0][1])


def plan_reads(
    points: Iterable[Point],
    *,
    max_variables: int,
    max_bytes: int,
    style: IdStyle,
    credentials: Mapping[str, Any] | None = None,
    breaks: Collection[str] = (),
    alone: Collection[str] = (),
) -> ReadPlan:
    """Plan reading ``points`` (see the module's docstring).

    ``breaks`` and ``alone`` as :func:`ranges` takes them.
    """
    listed = list(points)
    reads, unreadable = ranges(listed, breaks=breaks, alone=alone)
    return pack(
        reads,
        point_keys=frozenset(point.key for point in listed),
        max_variables=max_variables,
        max_bytes=max_bytes,
        style=style,
        credentials=credentials,
        unreadable=unreadable,
    )


def pack(
    reads: Sequence[RangeRead],
    *,
    point_keys: frozenset[str],
    max_variables: int,
    max_bytes: int,
    style: IdStyle,
    credentials: Mapping[str, Any] | None = None,
    unreadable: frozenset[str] = frozenset(),
) -> ReadPlan:
    """Pack ranges into requests under both limits, in their order."""
    max_variables = max(1, max_variables)
    empty = len(request_body(credentials, []))
    requests: list[PlannedRequest] = []
    current: list[RangeRead] = []
    size = empty
    costs: list[int] = []
    for read in reads:
        cost = _id_cost(read, style)
        costs.append(cost)
        added = cost + (1 if current else 0)
        if current and (len(current) >= max_variables or size + added > max_bytes):
            requests.append(PlannedRequest(tuple(current), size))
            current, size, added = [], empty, cost
        current.append(read)
        size += added
    if current:
        requests.append(PlannedRequest(tuple(current), size))
    lower_bound = max(
        math.ceil(len(reads) / max_variables),
        _byte_bound(costs, max_bytes - empty),
    )
    return ReadPlan(
        requests=tuple(requests),
        point_keys=point_keys,
        max_variables=max_variables,
        max_bytes=max_bytes,
        style=style,
        lower_bound=lower_bound,
        unreadable=unreadable,
    )


def _byte_bound(costs: Sequence[int], room: int) -> int:
    """Return the fewest requests the IDs' bytes need, with ``room`` for IDs a body.

    An ID that does not fit the room is a request of its own; the others need at
    least their bytes and commas over the room (one comma fewer than IDs: one more
    byte of room).
    """
    fitting = [cost for cost in costs if cost <= room]
    alone = len(costs) - len(fitting)
    if not fitting:
        return alone
    return alone + math.ceil((sum(fitting) + len(fitting)) / (room + 1))


def _id_cost(read: RangeRead, style: IdStyle) -> int:
    """Return the bytes one ID adds to a body (its JSON string, no comma)."""
    return len(json.dumps(read.address.variable_id(style)))
