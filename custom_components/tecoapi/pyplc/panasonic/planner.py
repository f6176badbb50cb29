"""The read planner: a register map's points in as few POSTs as the gateway allows.

The gateway's rules (the seed): a POST carries at most :data:`MAX_REQUESTS`
requests, all for the one station the POST names; a request reads one
contiguous run of one area in one type, at most :data:`MAX_REGISTERS`
registers or bits (the seed says "registres ou drapeaux": a DINT, UDINT or
REAL takes two registers, so a request reads at most 50 of them); a STRING
request reads one string (it has no count).

**The bound.** Take one station. Its points fall into *chains*: those of one
area and one type (double words also by their address's parity: a request's
values sit at even offsets from its start, so a DINT at DT101 is never in
the request of a DINT at DT100). No request serves two chains, and a chain's
points, in order, need at least as many requests as the greedy cover makes:
a window of the request's length starting at the first point not yet
covered, again and again (the classic proof: each greedy window ends at
least as far right as the same-numbered window of any cover). A string needs
a request of its own. So the station needs at least ``R`` requests, the sum
of its chains' greedy windows and its strings, and at least ``ceil(R / 20)``
POSTs; a poll needs at least the sum of that over the stations. The planner
makes exactly the greedy windows and packs them 20 to a POST, so **every plan
meets the bound**: ``len(plan.posts) == plan.lower_bound``
(``tests/pyplc/panasonic/test_planner_bound.py`` checks it against brute
force on small maps, and the inequality on random ones).

**Gaps.** A greedy window reads the unused registers between its points: it
bridges every gap in it. A station's last POST usually has room for more
requests (up to ``20 · POSTs - R``); those spare slots split windows at the
gaps where reading the unused values would cost more bytes than a request of
their own does (:data:`REQUEST_BYTES` against each type's
:data:`VALUE_BYTES`), largest saving first. Splitting only fills slots the
POSTs have anyway, so the bound holds; small gaps stay bridged.

**Apart.** A request fails as a whole when one of its addresses is one the
PLC lacks (a typo near an area's end). The source then learns which points
must be read apart (:func:`covering` reads exactly some points) and plans
with them: ``breaks`` begin a request of their own (no request reads across
them), ``alone`` are read each in a request of their own. The chains are cut
there, each piece covered greedily: the plan meets the bound of plans that
keep those points apart.
"""

from collections import defaultdict
from collections.abc import Collection, Iterable, Mapping
from dataclasses import dataclass
import itertools
import math
from typing import Any, Final

from .address import Address, Area, WireType, bit_start

MAX_REQUESTS: Final = 20
"""Requests one POST may carry."""
MAX_REGISTERS: Final = 100
"""Registers (or bits) one request may read."""
REQUEST_BYTES: Final = 150
"""About what one more request costs on the wire: its text and its answer's envelope."""
VALUE_BYTES: Final[Mapping[WireType, int]] = {
    WireType.BOOL: 2,
    WireType.INT: 7,
    WireType.UINT: 6,
    WireType.DINT: 12,
    WireType.UDINT: 11,
    WireType.REAL: 14,
    WireType.STRING: 0,
}
"""About what one value costs in an answer (``-12345,``)."""


@dataclass(frozen=True, slots=True)
class Target:
    """A point to read: its key, its station (None: the gateway's), address and type."""

    key: str
    station: int | None
    address: Address
    type: WireType


@dataclass(frozen=True, slots=True)
class ReadRequest:
    """One request of a POST: a run of values, and the points that are in it.

    ``start`` is the first value's position in the area (a register's word, a
    bit's word·16 + bit); ``count`` the values read (None for a STRING);
    ``points`` each point's key and its value's index in the answer.
    """

    area: Area
    type: WireType
    start: int
    count: int | None
    points: tuple[tuple[str, int], ...]

    def body(self) -> dict[str, Any]:
        """Return the request as the gateway takes it."""
        start: int | str = bit_start(self.start) if self.area.bits else self.start
        body: dict[str, Any] = {
            "area": self.area.value,
            "type": self.type.value,
            "start": start,
        }
        if self.count is not None:
            body["count"] = self.count
        return body

    @property
    def name(self) -> str:
        """The first value's address as the gateway names it (``DT100``, ``R1A``)."""
        if self.area.bits:
            return f"{self.area}{bit_start(self.start)}"
        return f"{self.area}{self.start}"

    @property
    def indices(self) -> frozenset[int]:
        """The values' indices its points need (each value once)."""
        return frozenset(index for _, index in self.points)

    @property
    def unused(self) -> int:
        """Values read that no point needs."""
        if self.count is None:
            return 0
        return self.count - len(self.indices)


@dataclass(frozen=True, slots=True)
class Post:
    """One POST: a station's requests (at most :data:`MAX_REQUESTS`)."""

    station: int | None
    requests: tuple[ReadRequest, ...]


@dataclass(frozen=True, slots=True)
class ReadPlan:
    """The POSTs that read some points, and the fewest any plan needs."""

    posts: tuple[Post, ...]
    point_keys: frozenset[str]
    lower_bound: int
    """The fewest POSTs any plan following the gateway's rules needs."""
    minimal_requests: int
    """The fewest requests (each POST's first ones); the rest split gaps."""
    unused_values: int
    """Values read that no point needs (bridged gaps)."""

    @property
    def requests(self) -> int:
        """Requests in all the POSTs."""
        return sum(len(post.requests) for post in self.posts)


def values_per_request(wire: WireType, max_registers: int = MAX_REGISTERS) -> int:
    """Return the values of a type one request reads at most."""
    return max_registers // max(wire.registers, 1)


def _chain_key(target: Target) -> tuple[Area, WireType, int]:
    """Return the chain a point belongs to: area, type, a double word's parity."""
    registers = target.type.registers
    parity = target.address.word % 2 if registers == 2 else 0
    return target.address.area, target.type, parity


def _slot(target: Target) -> int:
    """Return a point's position among the values of its chain."""
    index = target.address.index
    if target.type.registers == 2:
        return index // 2
    return index


@dataclass(slots=True)
class _Window:
    """A run of one chain's values: the first slot and the points' slots in it."""

    area: Area
    type: WireType
    parity: int
    slots: list[tuple[int, str]]

    def request(self) -> ReadRequest:
        first = self.slots[0][0]
        last = self.slots[-1][0]
        if self.type is WireType.STRING:
            return ReadRequest(
                self.area,
                self.type,
                first,
                None,
                tuple((key, 0) for _, key in self.slots),
            )
        width = self.type.registers
        start = first * 2 + self.parity if width == 2 else first
        return ReadRequest(
            self.area,
            self.type,
            start,
            last - first + 1,
            tuple((key, slot - first) for slot, key in self.slots),
        )

    def gaps(self) -> list[tuple[int, int]]:
        """Each split point (index into ``slots``) and the unused values before it."""
        return [
            (position, self.slots[position][0] - self.slots[position - 1][0] - 1)
            for position in range(1, len(self.slots))
            if self.slots[position][0] - self.slots[position - 1][0] > 1
        ]


def _windows(
    chain: tuple[Area, WireType, int],
    targets: list[Target],
    max_registers: int,
    apart: tuple[Collection[str], Collection[str]] = ((), ()),
) -> list[_Window]:
    """Return the greedy cover of one chain (a string: a window per address).

    ``apart`` are the keys that begin a window, and those that are alone in one.
    """
    area, wire, parity = chain
    breaks, alone = apart
    ordered = sorted((_slot(target), target.key) for target in targets)
    windows: list[_Window] = []
    width = 1 if wire is WireType.STRING else values_per_request(wire, max_registers)
    closed = False
    for slot, key in ordered:
        if (
            windows
            and not closed
            and key not in breaks
            and key not in alone
            and slot - windows[-1].slots[0][0] < width
        ):
            windows[-1].slots.append((slot, key))
        else:
            windows.append(_Window(area, wire, parity, [(slot, key)]))
        closed = key in alone
    return windows


def covering(targets: Iterable[Target]) -> ReadRequest:
    """Return the one request that reads exactly some points of one chain.

    Raises :class:`ValueError` when they are of several chains, or too far
    apart for one request.
    """
    chains: dict[tuple[Area, WireType, int], list[Target]] = defaultdict(list)
    for target in targets:
        chains[_chain_key(target)].append(target)
    if len(chains) != 1:
        raise ValueError("one request reads the points of one chain")
    ((chain, chained),) = chains.items()
    (window, *rest) = _windows(chain, chained, MAX_REGISTERS)
    if rest:
        raise ValueError("the points do not fit one request")
    return window.request()


def _split(windows: list[_Window], spare: int) -> list[_Window]:
    """Split windows at their costliest gaps, at most ``spare`` times."""
    savings: list[tuple[int, int, int]] = []
    for number, window in enumerate(windows):
        for position, unused in window.gaps():
            saving = unused * VALUE_BYTES[window.type] - REQUEST_BYTES
            if saving > 0:
                savings.append((saving, number, position))
    savings.sort(key=lambda item: (-item[0], item[1], item[2]))
    cuts: dict[int, list[int]] = defaultdict(list)
    for _, number, position in savings[:spare]:
        cuts[number].append(position)
    result: list[_Window] = []
    for number, window in enumerate(windows):
        edges = [0, *sorted(cuts.get(number, ())), len(window.slots)]
        result.extend(
            _Window(window.area, window.type, window.parity, window.slots[low:high])
            for low, high in itertools.pairwise(edges)
        )
    return result


def plan_reads(
    targets: Iterable[Target],
    *,
    max_requests: int = MAX_REQUESTS,
    max_registers: int = MAX_REGISTERS,
    split_gaps: bool = True,
    breaks: Collection[str] = frozenset(),
    alone: Collection[str] = frozenset(),
) -> ReadPlan:
    """Plan the reads of some points (see the module: the bound, the gaps, apart).

    ``split_gaps`` False bridges every gap (the plan of fewest requests);
    ``breaks`` are points that begin a request, ``alone`` points read each
    in a request of its own.
    """
    by_station: dict[int | None, dict[tuple[Area, WireType, int], list[Target]]] = (
        defaultdict(lambda: defaultdict(list))
    )
    keys: set[str] = set()
    for target in targets:
        by_station[target.station][_chain_key(target)].append(target)
        keys.add(target.key)
    posts: list[Post] = []
    bound = 0
    minimal = 0
    unused = 0
    for station in sorted(by_station, key=lambda item: -1 if item is None else item):
        windows = [
            window
            for chain, chained in sorted(
                by_station[station].items(), key=lambda item: _order(item[0])
            )
            for window in _windows(chain, chained, max_registers, (breaks, alone))
        ]
        needed = math.ceil(len(windows) / max_requests)
        bound += needed
        minimal += len(windows)
        if split_gaps:
            windows = _split(windows, needed * max_requests - len(windows))
        requests = [window.request() for window in windows]
        requests.sort(
            key=lambda request: (request.area.value, request.type.value, request.start)
        )
        unused += sum(request.unused for request in requests)
        posts.extend(
            Post(station, tuple(requests[low : low + max_requests]))
            for low in range(0, len(requests), max_requests)
        )
    return ReadPlan(
        posts=tuple(posts),
        point_keys=frozenset(keys),
        lower_bound=bound,
        minimal_requests=minimal,
        unused_values=unused,
    )


def _order(chain: tuple[Area, WireType, int]) -> tuple[str, str, int]:
    """Return a chain's place in a plan (stable from poll to poll)."""
    area, wire, parity = chain
    return area.value, wire.value, parity
