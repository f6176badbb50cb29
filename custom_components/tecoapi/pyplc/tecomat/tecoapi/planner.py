"""The read planner: the fewest GetObject requests that poll a set of points.

Two limits bind every request: its target (``/TecoApi/GetObject?`` and the
encoded names joined by ``&``) stays within 256 characters, and its response
within the CPU's item limit (a struct or array counts all its leaves; a
T_ApiObject is 8 items, its ``value`` alone 1).

Reading rules. A point can be read through any of its ancestors that has no
array index in its name (``Main``, ``Main.myObject3``), and a T_ApiObject also
through its ``.value`` member when attributes are not wanted. Array elements are
read through their array (or a parent of it) -- never as ``arr[2]``, which the
manual does not document -- except for an array too large for one response, whose
elements are then read by index because nothing else can reach them.

Choosing what to read is a tree problem (a node whole or its parts: a *cover* of
the polled points) and packing the chosen names into requests is a
two-dimensional bin packing (characters ``c`` of a name with its separator, at
most ``B`` = 238 per request; items ``i``, at most ``L`` per request).

Lower bound. Give every possible read a weight ``w(c, i)`` such that the reads of
any one request weigh at most 1. A plan reads some cover (drop its redundant
reads first: that only lowers its weight, never adds a request), so it needs at
least ``ceil(min over covers of Σ w)`` requests, and that minimum is an exact
tree dynamic programme. The weights, for a share ``λ`` in [0, 1] and a density
``r`` (characters per item):

- plain: ``w = λ·c/B + (1-λ)·i/L``; a request holds at most ``B`` characters
  and ``L`` items, so it weighs at most ``λ + (1-λ) = 1``.
- a *large* read (``i > L/2``, at most one per request) leaves ``L - i`` items,
  which hold at most ``r·(L - i)`` characters of reads no denser than ``r``, and
  at most ``B - c`` in any case; it weighs
  ``max(plain, 1 - λ·min(B - c, r·(L - i))/B - (1-λ)·(L - i)/L)``, and each
  other read either
  - *capped*: weighs ``λ·min(c, r·i)/B + (1-λ)·i/L``, so the reads next to a
    large one weigh at most what it leaves and every request at most 1; or
  - *offset*: keeps its plain weight; then a request weighs at most 1 plus
    ``λ/B`` times the characters of its reads beyond ``r`` per item, and the
    plan's reads have at most ``E`` of those (the sum over the polled nodes of
    the most any of their reads has), so the bound is taken less ``λ·E/B``.

``lower_bound`` is the best of these over a grid of ``λ`` and ``r``; ``λ = 1``
alone is the character bound, ``λ = 0`` the item bound.

Plan. Candidate covers are those of the pricings with the best bounds, the same
with some nodes read through their parts instead (one node at a time, while that
lowers the requests the cover fills by volume: one pricing trades characters for
items at a single rate, a plan may need a mix), and those of plain pricings
across the shares; the ones that fill the fewest requests by volume are packed.

Packing goes request by request (sequential bin completion): a request starts
with the largest read left and takes the set of other reads that wastes the least
of what the requests still to come can afford to waste if they are to end at the
lower bound; the set is found exactly by a dynamic programme over (characters,
items), the table held as one integer bit set. A T_ApiObject read whole may turn
into its ``.value`` read (6 characters more, 7 items fewer): the programme counts
reads in their whole shape and lets a request hold more items than the limit as
long as its characters pay for the turns (a request whose reads cannot all turn
is found out when traced back, and a cell within the limit taken instead); the
turns the cover needs anyway to fit in the aimed-at number of requests are made
beforehand, on the shortest names.

A packing more than one request above the bound is tried again aiming one
request higher, then with the other covers, and its loosest requests are finally
packed again together; the search stops within one request of the bound. The
plan with the fewest requests wins (then the fewest items); nothing is random,
so the same points always give the same plan. Each request then turns as many
T_ApiObjects into ``.value`` reads as its characters allow, so attributes are
polled only where that costs no request.

Measured on the generated programs (seeds 0-4 of 50/300/1000 points, CP-2080 and
CP-1000, with and without attributes): every plan within one request of the
bound, most at it; 1000 points take 0.05-0.2 s of CPU. Beyond those seeds, 1000
points on a CP-1000 without attributes end two or three above the bound about
half the time: there both limits are nearly full, and for the cover packed in
one such case the configuration LP (solved offline) already needs 44.3 requests
where this bound says 43, so much of the gap is the bound's; closing it would take
that LP, with a solver, rather than a grid of weighings.

A CP-1000 whose 400 T_ApiObjects fill 27 program instances, structs and arrays of up
to 128 items (``generate_program(400, plc_type="CP-1000", roots=27)``, the shape of
an installation seen drawing 413s; measured over HTTP against the simulator): a poll
without attributes takes 23 requests where this bound says 21; with attributes 26
where it says 25. Four of the roots are arrays of 16 T_ApiObjects, exactly 128 items,
which can only be read whole (elements go through their array): four requests that
hold 14-22 characters and nothing else. Of the other 19, 16 are full in both
dimensions (238 characters, 112-127 items), one is full in characters (48 items),
one reads a 128-item struct whole and one holds the leftovers (5 items). Offline
(HiGHS): the configuration LP of this cover problem (every request pattern, priced
exactly by a knapsack over characters and items) lies between 20.52 and 21.08, so
no bound of that kind proves more than 22; an integer programme proves that a plan
reading none of the nine full (128-item) instances and structs whole needs 23 (the
points outside the four arrays need 19 requests), and in 13 minutes found no plan
of 22 that reads some of them whole, without proving there is none. So the optimum
is 21, 22 or 23 and the gap is not closed. What the bound cannot see is that a read
of 128 items leaves its request's 220-odd other characters unusable; what is open is
whether reading more full roots whole than the one this plan reads saves a request.
"""

from collections import Counter
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass, field
import math
from typing import Final

from ...core.models import Catalogue, Point
from .catalogue import API_OBJECT_ITEMS
from .paths import GET_OBJECT, MAX_TARGET_LENGTH, encode_name, join_path, split_path
from .plans import PlannedRequest, ReadPlan

NAME_BUDGET: Final = MAX_TARGET_LENGTH - len(GET_OBJECT) + 1
"""Characters for names in one request, counting one separator (``?``/``&``) each."""

VALUE_MEMBER: Final = ".value"
_TURN_CHARS: Final = len(VALUE_MEMBER)
"""Characters a T_ApiObject read gains when it turns into its ``.value`` read."""
_TURN_ITEMS: Final = API_OBJECT_ITEMS - 1
"""Items it sheds."""

_SHARES: Final = 8
"""Steps of the share ``λ`` from 0 to 1 in the lower bound's grid."""
_DENSITIES: Final = 16
"""Densities ``r`` per share in the grid, spread over those the reads have."""
_SWEEP: Final = 16
"""Steps of ``λ`` whose plain covers are candidates for packing."""
_BEST_PRICINGS: Final = 4
"""Pricings with the best fractional bounds whose covers are candidates too."""
_PACKED_COVERS: Final = 3
"""Candidate covers packed at most (the most promising first)."""
_REPACK_ROUNDS: Final = 6
"""Times the loosest requests are packed again, at most, while that saves one."""
_REPACK_EXTRA: Final = (0, 2, 4, 8)
"""Requests beyond the loose ones packed again with them, for room to move."""
_LOOSE: Final = 0.02
"""A request leaving more than this share of its characters and items is loose."""
_MAX_MISSES: Final = 4
"""Cells above the item limit traced back in vain before only plain ones are tried."""
_MAX_TABLE_ITEMS: Final = 4096
"""Widest item axis of the packing programme; beyond it requests are first-fit."""

type _Kind = tuple[int, int, bool]


@dataclass(slots=True, eq=False)
class _Node:
    """A prefix of point paths: a struct, array, element, T_ApiObject or scalar."""

    name: str
    order: int
    depth: int
    parent: "_Node | None"
    children: "dict[str | int, _Node]" = field(default_factory=dict)
    point: Point | None = None
    items: int = 0
    is_array: bool = False
    eligible: bool = True
    required: bool = False


@dataclass(frozen=True, slots=True)
class _Shape:
    """One name to put in a request, with what it costs there."""

    name: str
    chars: int
    items: int


@dataclass(frozen=True, slots=True)
class _Unit:
    """A read of a cover: its shape, and the ``.value`` read it may turn into.

    ``shape`` is the read with the fewest characters (a T_ApiObject whole, when
    that is allowed); ``turned`` is its ``.value`` read, kept only when it costs
    exactly ``_TURN_CHARS`` more and ``_TURN_ITEMS`` fewer.
    """

    order: int
    keys: frozenset[str]
    shape: _Shape
    turned: _Shape | None = None

    @property
    def kind(self) -> _Kind:
        """What packing needs to know: characters, items, whether it turns."""
        return (self.shape.chars, self.shape.items, self.turned is not None)


def _chars(name: str) -> int:
    """Characters a name takes in a target, with its separator."""
    return len(encode_name(name)) + 1


def _subtree(node: _Node) -> Iterator[_Node]:
    """Yield the node and everything under it."""
    stack = [node]
    while stack:
        current = stack.pop()
        yield current
        stack.extend(current.children.values())


class _Tree:
    """The readable tree of a catalogue, marked with the points to poll."""

    def __init__(
        self,
        universe: Iterable[Point],
        polled: set[str],
        item_limit: int,
        with_attrs: bool,
    ) -> None:
        self.item_limit = item_limit
        self.with_attrs = with_attrs
        self.polled = polled
        self._reads: dict[_Node, tuple[_Shape | None, _Shape | None]] = {}
        self._shapes: dict[_Node, tuple[_Shape, ...]] = {}
        self._sizes: dict[_Node, tuple[tuple[int, int], ...]] = {}
        self._units: dict[_Node, _Unit] = {}
        self.roots: dict[str | int, _Node] = {}
        self.unparsable: set[str] = set()
        self._count = 0
        for point in universe:
            self._add(point)
        self.nodes = list(self._preorder())
        for node in self.nodes:
            parent = node.parent
            node.eligible = parent is None or (
                parent.eligible and (not parent.is_array or parent.items > item_limit)
            )
        self.unreadable = self._mark(polled)
        self.required = [node for node in reversed(self.nodes) if node.required]
        """The nodes holding polled points, children before parents."""

    def _add(self, point: Point) -> None:
        """Add a point's path, counting its leaves in every ancestor."""
        try:
            segments = split_path(point.path)
        except ValueError:
            self.unparsable.add(point.key)
            return
        leaves = API_OBJECT_ITEMS if point.described else 1
        level = self.roots
        parent: _Node | None = None
        for depth, segment in enumerate(segments):
            folded = segment.lower() if isinstance(segment, str) else segment
            node = level.get(folded)
            if node is None:
                node = _Node(
                    join_path(segments[: depth + 1]), self._count, depth, parent
                )
                self._count += 1
                level[folded] = node
                if parent is not None and isinstance(segment, int):
                    parent.is_array = True
            node.items += leaves
            parent, level = node, node.children
        assert parent is not None
        parent.point = parent.point or point

    def _preorder(self) -> Iterator[_Node]:
        """Every node, parents before children, in the PLC's order."""
        stack = list(reversed(self.roots.values()))
        while stack:
            node = stack.pop()
            yield node
            stack.extend(reversed(node.children.values()))

    def reads(self, node: _Node) -> tuple[_Shape | None, _Shape | None]:
        """Return the node read whole and as a ``.value``, each if allowed."""
        reads = self._reads.get(node)
        if reads is None:
            whole = value = None
            if node.eligible:
                chars = _chars(node.name)
                if chars <= NAME_BUDGET and node.items <= self.item_limit:
                    whole = _Shape(node.name, chars, node.items)
                point = node.point
                if not self.with_attrs and point is not None and point.described:
                    name = node.name + VALUE_MEMBER
                    if (chars := _chars(name)) <= NAME_BUDGET:
                        value = _Shape(name, chars, 1)
            reads = self._reads[node] = (whole, value)
        return reads

    def shapes(self, node: _Node) -> tuple[_Shape, ...]:
        """Every way of reading the node by one name."""
        shapes = self._shapes.get(node)
        if shapes is None:
            shapes = self._shapes[node] = tuple(
                shape for shape in self.reads(node) if shape is not None
            )
        return shapes

    def sizes(self, node: _Node) -> tuple[tuple[int, int], ...]:
        """Return the (characters, items) of every way of reading the node."""
        sizes = self._sizes.get(node)
        if sizes is None:
            sizes = self._sizes[node] = tuple(
                (shape.chars, shape.items) for shape in self.shapes(node)
            )
        return sizes

    def unit(self, node: _Node) -> _Unit:
        """Return the read of a node, in whatever shape, as a unit to pack."""
        unit = self._units.get(node)
        if unit is None:
            whole, value = self.reads(node)
            keys = frozenset(
                sub.point.key
                for sub in _subtree(node)
                if sub.point is not None and sub.point.key in self.polled
            )
            if whole is None:
                assert value is not None, "only readable nodes are read"
                unit = _Unit(node.order, keys, value)
            elif (
                value is not None
                and value.chars - whole.chars == _TURN_CHARS
                and whole.items - value.items == _TURN_ITEMS
            ):
                unit = _Unit(node.order, keys, whole, value)
            else:
                unit = _Unit(node.order, keys, whole)
            self._units[node] = unit
        return unit

    def splittable(self, node: _Node) -> bool:
        """Whether the node may be read through its parts instead of whole.

        A node that is a point itself is read whole, unless no read reaches it
        (then it is reported unreadable and its members are read without it).
        """
        if not node.children:
            return False  # mutate: equivalent — a leaf has no parts to be read by
        if node.point is not None and node.point.key not in self.unreadable:
            return False
        return not node.is_array or node.items > self.item_limit

    def _mark(self, polled: set[str]) -> set[str]:
        """Mark nodes holding polled points; return polled points no read reaches."""
        unreadable = {key for key in polled if key in self.unparsable}
        reachable: dict[_Node, bool] = {}
        for node in self.nodes:
            whole, value = self.reads(node)
            above = node.parent is not None and reachable[node.parent]
            reachable[node] = above or whole is not None
            point = node.point
            if point is None or point.key not in polled:
                continue
            if reachable[node] or value is not None:
                ancestor: _Node | None = node
                while ancestor is not None and not ancestor.required:
                    ancestor.required = True
                    ancestor = ancestor.parent
            else:
                unreadable.add(point.key)
        return unreadable


# --- the lower bound ----------------------------------------------------------


@dataclass(frozen=True, slots=True)
class _Pricing:
    """One weighing of reads under which no request weighs more than 1 (see above).

    ``share`` is ``λ``; ``density`` is ``r`` (None: plain weights only);
    ``capped`` chooses capped weights over the offset.
    """

    share: float
    density: float | None = None
    capped: bool = False

    def weight(self, chars: int, items: int, limit: int) -> float:
        """Return a read's share of one request."""
        share = self.share
        plain = share * chars / NAME_BUDGET + (1 - share) * items / limit
        if self.density is None:
            return plain
        if 2 * items > limit:
            left = limit - items
            room = min(NAME_BUDGET - chars, self.density * left)
            large = 1 - share * room / NAME_BUDGET - (1 - share) * left / limit
            return max(plain, large)
        if self.capped:
            capped = min(chars, self.density * items)
            return share * capped / NAME_BUDGET + (1 - share) * items / limit
        return plain

    def excess(self, chars: int, items: int, limit: int) -> float:
        """Return a read's characters beyond the density (what the offset counts)."""
        if self.density is None or self.capped or 2 * items > limit:
            return 0.0
        return max(0.0, chars - self.density * items)


def _pricings(tree: _Tree) -> list[_Pricing]:
    """Return the grid of pricings: shares, and densities the reads actually have."""
    limit = tree.item_limit
    densities = sorted(
        {
            shape.chars / shape.items
            for node in tree.required
            for shape in tree.shapes(node)
            if 0 < 2 * shape.items <= limit
        }
    )
    if len(densities) > _DENSITIES:
        last = len(densities) - 1
        densities = [
            densities[round(step * last / (_DENSITIES - 1))]
            for step in range(_DENSITIES)
        ]
    # Density 0, capped: a large read weighs its whole request at λ = 1 (at most
    # one per request), whatever the densities of the others, which then weigh
    # their items only. Without it reads all larger than half the limit had no
    # density at all, and the bound counted them as if two could share a request.
    large = any(
        2 * shape.items > limit for node in tree.required for shape in tree.shapes(node)
    )
    pricings = [_Pricing(0.0)]
    for step in range(1, _SHARES + 1):
        share = step / _SHARES
        pricings.append(_Pricing(share))
        for density in densities:
            pricings.append(_Pricing(share, density))
            pricings.append(_Pricing(share, density, capped=True))
        if large:
            pricings.append(_Pricing(share, 0.0, capped=True))
    return pricings


def _fractional_bounds(tree: _Tree, pricings: Sequence[_Pricing]) -> list[float]:
    """Return, per pricing, the least weight of a cover less the pricing's offset.

    One pass over the tree prices every node under all pricings at once; nodes
    read in the same shapes share their prices.
    """
    limit = tree.item_limit
    by_shapes: dict[tuple[tuple[int, int], ...], list[float]] = {}
    cost: dict[_Node, list[float] | None] = {}
    for node in tree.required:
        sizes = tree.sizes(node)
        own = by_shapes.get(sizes)
        if own is None and sizes:
            own = by_shapes[sizes] = [
                min(pricing.weight(chars, items, limit) for chars, items in sizes)
                for pricing in pricings
            ]
        parts: list[list[float] | None] = []
        if tree.splittable(node):
            parts = [cost[child] for child in node.children.values() if child.required]
        known = [part for part in parts if part is not None]
        if known and len(known) == len(parts):
            split = [sum(column) for column in zip(*known, strict=True)]
            own = split if own is None else list(map(min, own, split))
        cost[node] = own
    covers = [
        vector
        for root in tree.roots.values()
        if root.required and (vector := cost[root]) is not None
    ]
    totals = [sum(column) for column in zip(*covers, strict=True)]
    # Nodes read in the same shapes have the same excess: count them once.
    same = Counter(tree.sizes(node) for node in tree.required)
    excess: dict[float, float] = {}
    for pricing in pricings:
        if pricing.density is None or pricing.capped or pricing.density in excess:
            continue
        excess[pricing.density] = sum(
            count * max((pricing.excess(*size, limit) for size in sizes), default=0)
            for sizes, count in same.items()
        )
    return [
        total - pricing.share * excess.get(pricing.density or 0.0, 0.0) / NAME_BUDGET
        if pricing.density is not None and not pricing.capped
        else total
        for pricing, total in zip(pricings, totals, strict=True)
    ]


# --- covers -------------------------------------------------------------------


class _Cover:
    """The cheapest cover of the polled points under one pricing (a tree programme)."""

    def __init__(self, tree: _Tree, pricing: _Pricing) -> None:
        self.tree = tree
        limit = tree.item_limit
        self.cost: dict[_Node, float | None] = {}
        self.split: set[_Node] = set()
        weights: dict[tuple[tuple[int, int], ...], float | None] = {}
        for node in tree.required:
            sizes = tree.sizes(node)
            if sizes in weights:
                best = weights[sizes]
            else:
                best = weights[sizes] = min(
                    (pricing.weight(*size, limit) for size in sizes), default=None
                )
            if tree.splittable(node):
                parts = [
                    self.cost[child]
                    for child in node.children.values()
                    if child.required
                ]
                known = [part for part in parts if part is not None]
                if known and len(known) == len(parts):
                    total = sum(known)
                    if best is None or total < best:
                        best = total
                        self.split.add(node)
            self.cost[node] = best

    def reads(self, nodes: Iterable[_Node]) -> list[_Node]:
        """Return the nodes read to cover ``nodes``, in the PLC's order."""
        reads: list[_Node] = []
        stack = [node for node in reversed(list(nodes)) if node.required]
        while stack:
            node = stack.pop()
            if self.cost[node] is None:
                continue
            if node in self.split:
                stack.extend(
                    child
                    for child in reversed(node.children.values())
                    if child.required
                )
            else:
                reads.append(node)
        return reads

    def parts(self, node: _Node) -> list[_Node] | None:
        """Return the reads that cover a node read whole through its parts, if any."""
        if not self.tree.splittable(node) or node in self.split:
            return None
        children = [child for child in node.children.values() if child.required]
        if any(self.cost[child] is None for child in children):
            return None
        return self.reads(children)

    def units(self) -> list[_Unit]:
        """Return the reads of the cover."""
        return [self.tree.unit(node) for node in self.reads(self.tree.roots.values())]

    def mixed(self) -> list[_Unit]:
        """Return the cover with the parts read instead of some nodes read whole.

        A pricing weighs characters against items at one fixed rate, but the
        plan may need some nodes read whole and others of the same kind through
        their parts. Nodes are split one at a time, each time the one that most
        lowers the requests the cover fills by volume, while that still falls.
        """
        tree = self.tree
        limit = tree.item_limit
        units = {node: tree.unit(node) for node in self.reads(tree.roots.values())}
        totals = _Volume.of(units.values(), limit)
        options: dict[_Node, tuple[list[_Node], _Volume]] = {}

        def offer(node: _Node) -> None:
            if parts := self.parts(node):
                change = _Volume.of([tree.unit(part) for part in parts], limit)
                options[node] = (parts, change.less(units[node]))

        for node in list(units):
            offer(node)
        while options:
            best = min(
                options,
                key=lambda node: (totals.plus(options[node][1]).requests(), node.order),
            )
            parts, change = options.pop(best)
            if totals.plus(change).requests() >= totals.requests() - 1e-9:
                break
            totals = totals.plus(change)
            del units[best]
            for part in parts:
                units[part] = tree.unit(part)
                offer(part)
        return sorted(units.values(), key=lambda unit: unit.order)


@dataclass(frozen=True, slots=True)
class _Volume:
    """What some reads hold in total: characters, items, turnable and large reads."""

    limit: int
    chars: int = 0  # mutate: equivalent — never read: every _Volume gets all fields
    items: int = 0  # mutate: equivalent — never read: every _Volume gets all fields
    turnable: int = 0  # mutate: equivalent — never read: every _Volume gets all fields
    large: int = 0  # mutate: equivalent — never read: every _Volume gets all fields

    @classmethod
    def of(cls, units: Iterable[_Unit], limit: int) -> "_Volume":
        """Return the totals of some reads."""
        chars = items = turnable = large = 0
        for unit in units:
            chars += unit.shape.chars
            items += unit.shape.items
            turnable += unit.turned is not None
            large += 2 * unit.shape.items > limit
        return cls(limit, chars, items, turnable, large)

    def plus(self, other: "_Volume") -> "_Volume":
        """Return the sum of two totals."""
        return _Volume(
            self.limit,
            self.chars + other.chars,
            self.items + other.items,
            self.turnable + other.turnable,
            self.large + other.large,
        )

    def less(self, unit: _Unit) -> "_Volume":
        """Return the totals without one read."""
        other = _Volume.of([unit], self.limit)
        return _Volume(
            self.limit,
            self.chars - other.chars,
            self.items - other.items,
            self.turnable - other.turnable,
            self.large - other.large,
        )

    def requests(self) -> float:
        """Return the requests these totals fill, turning reads where that helps."""
        balance = (self.items * NAME_BUDGET - self.chars * self.limit) / (
            _TURN_CHARS * self.limit + _TURN_ITEMS * NAME_BUDGET
        )
        turns = min(max(balance, 0.0), float(self.turnable))
        return max(
            float(self.large),
            (self.chars + _TURN_CHARS * turns) / NAME_BUDGET,
            (self.items - _TURN_ITEMS * turns) / self.limit,
        )


def _candidate_covers(
    tree: _Tree, pricings: Sequence[_Pricing], fractional: Sequence[float]
) -> list[list[_Unit]]:
    """Return the covers worth packing, the most promising first.

    The covers of the pricings with the best bounds, mixed (see
    ``_Cover.mixed``) and as they are, and those of plain pricings across the
    shares, from reading as much as possible whole to as little; ranked by the
    requests they fill by volume.
    """
    ranked = sorted(range(len(pricings)), key=lambda index: (-fractional[index], index))
    chosen = [pricings[index] for index in ranked[:_BEST_PRICINGS]]
    chosen += [_Pricing(step / _SWEEP) for step in range(_SWEEP, -1, -1)]
    candidates: dict[frozenset[int], tuple[tuple[int, int], list[_Unit]]] = {}
    for rank, pricing in enumerate(chosen):
        cover = _Cover(tree, pricing)
        covers = [cover.units()]
        if rank < _BEST_PRICINGS:
            covers.insert(0, cover.mixed())
        for units in covers:
            key = frozenset(unit.order for unit in units)
            if key not in candidates:
                need = _Volume.of(units, tree.item_limit).requests()
                candidates[key] = ((math.ceil(need - 1e-9), rank), units)
    ordered = sorted(candidates.values(), key=lambda candidate: candidate[0])
    fewest = ordered[0][0][0]
    return [
        units for (need, _), units in ordered[:_PACKED_COVERS] if need <= fewest + 1
    ]


# --- packing ------------------------------------------------------------------


class _Table:
    """The packing programme's table: every (characters, items) a request can hold.

    Bit ``chars * stride + items`` of an integer is set when some choice of reads
    adds up to those characters and items (reads counted in their whole shape).
    Items may exceed the limit by ``_TURN_ITEMS`` for every ``_TURN_CHARS``
    characters left, since that many T_ApiObjects can turn into ``.value`` reads;
    each row is followed by a gap wide enough that no shift spills into the next,
    and rows start on whole bytes so they can be read from the integer's bytes.
    """

    def __init__(self, item_limit: int, turns: int) -> None:
        self.item_limit = item_limit
        self.turns = turns > 0
        self.width = item_limit + _TURN_ITEMS * turns
        self.row_bytes = (2 * (self.width + 1) + 7) // 8
        self.stride = 8 * self.row_bytes
        self.plain = (1 << (item_limit + 1)) - 1
        self.valid = 0
        for chars in range(NAME_BUDGET + 1):
            top = item_limit
            if turns:
                top += _TURN_ITEMS * min(turns, (NAME_BUDGET - chars) // _TURN_CHARS)
            self.valid |= ((1 << (top + 1)) - 1) << (chars * self.stride)

    def turns_needed(self, chars: int, items: int, turnable: int) -> int | None:
        """Return how many reads must turn into ``.value``, None if too few can."""
        over = items - self.item_limit
        needed = 0 if over <= 0 else -(-over // _TURN_ITEMS)
        if needed > turnable or chars + needed * _TURN_CHARS > NAME_BUDGET:
            return None
        return needed


@dataclass(slots=True)
class _Budget:
    """What the requests still to come may waste and still end at the target."""

    target: int
    chars: int
    items: int

    def waste(self, table: _Table, done: int) -> Callable[[int, int], float]:
        """Return the share of the affordable waste a request of (chars, items) uses.

        While the reads left hold more items than the remaining requests can, every
        request must shed items by turning reads, ``_TURN_CHARS`` characters per
        ``_TURN_ITEMS`` items: items and characters are then one currency, and a
        request wastes the characters it leaves unused less those it spends on
        shedding more than its own items. Otherwise the two are wasted apart, and
        a request is measured by the one it wastes more of.
        """
        limit = table.item_limit
        left = max(1, self.target - done)
        over = self.items - left * limit
        if table.turns and over > 0:
            rate = _TURN_CHARS / _TURN_ITEMS
            scale = max(1.0, left * NAME_BUDGET - self.chars - rate * over)
            return lambda chars, items: (
                (NAME_BUDGET - chars - rate * (items - limit)) / scale
            )
        chars_scale = max(1, left * NAME_BUDGET - self.chars)
        items_scale = max(1, -over)
        return lambda chars, items: max(
            (NAME_BUDGET - chars) / chars_scale, (limit - items) / items_scale
        )


def _complete_requests(
    units: Sequence[_Unit], item_limit: int, target: int
) -> list[list[_Unit]] | None:
    """Pack reads request by request, each completed by the exact programme.

    When the reads hold more items than ``target`` requests can, the turns that
    must happen anyway are made first, on the reads with the fewest characters;
    the other T_ApiObjects stay free to turn wherever their request needs it.
    Returns None when the table would be too wide (an item limit far above any
    real CPU's), for the caller to pack otherwise.
    """
    over = sum(unit.shape.items for unit in units) - target * item_limit
    if over > 0:
        turnable = sorted(
            (unit for unit in units if unit.turned is not None),
            key=lambda unit: (unit.shape.chars, unit.order),
        )
        early = {unit.order for unit in turnable[: -(-over // _TURN_ITEMS)]}
        units = [
            _Unit(unit.order, unit.keys, unit.turned)
            if unit.order in early and unit.turned is not None
            else unit
            for unit in units
        ]
    items = sum(unit.shape.items for unit in units)
    turning = [unit.shape.chars + _TURN_CHARS for unit in units if unit.turned]
    # A request turns at most as many reads as fit in its characters.
    turns = NAME_BUDGET // min(turning) if turning and items > item_limit else 0
    # No request holds more items than all reads together.
    limit = min(item_limit, items)
    if limit + _TURN_ITEMS * turns > _MAX_TABLE_ITEMS:
        return None
    table = _Table(limit, turns)
    pending: dict[_Kind, list[_Unit]] = {}
    for unit in sorted(units, key=lambda unit: unit.order, reverse=True):
        pending.setdefault(unit.kind, []).append(unit)
    budget = _Budget(target, sum(unit.shape.chars for unit in units), items)
    requests: list[list[_Unit]] = []
    while pending:
        first = max(
            pending,
            key=lambda kind: (max(kind[0] * item_limit, kind[1] * NAME_BUDGET), kind),
        )
        counts = _fill(table, pending, first, budget.waste(table, len(requests)))
        request: list[_Unit] = []
        for kind, count in counts.items():
            queue = pending[kind]
            request.extend(queue.pop() for _ in range(count))
            if not queue:
                del pending[kind]
        budget.chars -= sum(unit.shape.chars for unit in request)
        budget.items -= sum(unit.shape.items for unit in request)
        requests.append(request)
    return requests


def _fill(
    table: _Table,
    pending: dict[_Kind, list[_Unit]],
    first: _Kind,
    waste: Callable[[int, int], float],
) -> dict[_Kind, int]:
    """Return how many reads of each kind the next request takes (``first`` too).

    Each kind's count is split in powers of two, so the table takes any number of
    reads of a kind in a few shifts; the table before each step is kept to trace
    the chosen cell back to the steps that reached it.
    """
    stride, width = table.stride, table.width
    room_chars = NAME_BUDGET - first[0]
    room_items = width - first[1]
    steps: list[tuple[_Kind, int]] = []
    # Tracing back prefers the earlier steps: larger reads go first, keeping the
    # smaller ones, which fit anywhere, for the requests still to come.
    limit = table.item_limit
    for kind in sorted(
        pending,
        key=lambda kind: (-max(kind[0] * limit, kind[1] * NAME_BUDGET), kind),
    ):
        left = len(pending[kind]) - (kind == first)
        size = 1
        while left > 0:
            count = min(size, left)
            if kind[0] * count <= room_chars and kind[1] * count <= room_items:
                steps.append((kind, count))
            left -= count
            size *= 2
    reach = (1 << (first[0] * stride + first[1])) & table.valid
    history = [reach]
    for (chars, items, _), count in steps:
        reach = (reach | (reach << (count * (chars * stride + items)))) & table.valid
        history.append(reach)
    rows = reach.to_bytes(table.row_bytes * (NAME_BUDGET + 1), "little")
    cells: list[tuple[float, int, int]] = []
    for chars in range(NAME_BUDGET, -1, -1):
        offset = chars * table.row_bytes
        row = int.from_bytes(rows[offset : offset + table.row_bytes], "little")
        if not row:
            continue
        items = row.bit_length() - 1
        cells.append((waste(chars, items), -chars, items))
        if items > limit and (plain := row & table.plain):
            # Not every read can turn: keep a cell without turns to fall back on.
            items = plain.bit_length() - 1
            cells.append((waste(chars, items), -chars, items))
    cells.sort()
    misses = 0
    for _, negative_chars, items in cells:
        if items > limit and misses >= _MAX_MISSES:
            continue
        counts = {first: 1}
        position = -negative_chars * stride + items
        for index in range(len(steps) - 1, -1, -1):
            if (history[index] >> position) & 1:
                continue
            (kind, count) = steps[index]
            position -= count * (kind[0] * stride + kind[1])
            counts[kind] = counts.get(kind, 0) + count
        turnable = sum(count for kind, count in counts.items() if kind[2])
        if table.turns_needed(-negative_chars, items, turnable) is not None:
            return counts
        misses += 1
    raise AssertionError("the first read alone always fits")  # pragma: no cover


def _first_fit(units: Sequence[_Unit], item_limit: int) -> list[list[_Unit]]:
    """Pack reads first-fit, largest first (for item limits too wide for the table)."""
    requests: list[tuple[list[_Unit], list[int]]] = []
    for unit in sorted(
        units,
        key=lambda unit: (
            -max(unit.shape.chars * item_limit, unit.shape.items * NAME_BUDGET),
            unit.order,
        ),
    ):
        for request, load in requests:
            if (
                load[0] + unit.shape.chars <= NAME_BUDGET
                and load[1] + unit.shape.items <= item_limit
            ):
                request.append(unit)
                load[0] += unit.shape.chars
                load[1] += unit.shape.items
                break
        else:
            requests.append(([unit], [unit.shape.chars, unit.shape.items]))
    return [request for request, _ in requests]


def _planned(request: Sequence[_Unit], item_limit: int) -> PlannedRequest:
    """Make a request of its reads, turned to ``.value`` wherever characters allow."""
    placed = sorted(request, key=lambda unit: unit.order)
    chars = sum(unit.shape.chars for unit in placed)
    items = sum(unit.shape.items for unit in placed)
    turns = (NAME_BUDGET - chars) // _TURN_CHARS
    names: list[str] = []
    for unit in placed:
        if unit.turned is not None and turns > 0:
            names.append(unit.turned.name)
            turns -= 1
            items -= _TURN_ITEMS
        else:
            names.append(unit.shape.name)
    assert items <= item_limit, "packing keeps every request within the limit"
    return PlannedRequest(
        names=tuple(names),
        target=GET_OBJECT + "&".join(encode_name(name) for name in names),
        items=items,
        point_keys=frozenset().union(*(unit.keys for unit in placed)),
    )


def _best_packing(
    covers: Sequence[Sequence[_Unit]], item_limit: int, lower_bound: int
) -> list[list[_Unit]]:
    """Return the packing with the fewest requests (then items) of some covers.

    Each cover is packed aiming at the lower bound and, if that ends more than
    one request above it, aiming one higher (the budget of waste then differs);
    the search ends as soon as a packing is within one request of the bound
    (further covers then rarely save the last request: once in 120 generated
    programs, at twice the time).
    """
    best: tuple[tuple[int, int], list[list[_Unit]]] | None = None
    for units in covers:
        for target in (lower_bound, lower_bound + 1):
            requests = _complete_requests(units, item_limit, target)
            if requests is None:
                requests = _first_fit(units, item_limit)
            score = (
                len(requests),
                sum(unit.shape.items for request in requests for unit in request),
            )
            if best is None or score < best[0]:
                best = (score, requests)
            if len(requests) <= target + 1:
                break
        if best is not None and best[0][0] <= lower_bound + 1:
            break
    if best is None:
        return []
    if best[0][0] > lower_bound + 1:
        return _repack_loose(best[1], item_limit)
    return best[1]


def _waste(request: Sequence[_Unit], item_limit: int) -> float:
    """Return the share of a request's characters and items left unused."""
    chars = sum(unit.shape.chars for unit in request)
    items = sum(unit.shape.items for unit in request)
    turns = max(0, -(-(items - item_limit) // _TURN_ITEMS))
    return (NAME_BUDGET - chars - _TURN_CHARS * turns) / NAME_BUDGET + (
        item_limit - items + _TURN_ITEMS * turns
    ) / item_limit


def _repack_loose(requests: list[list[_Unit]], item_limit: int) -> list[list[_Unit]]:
    """Pack the loosest requests again, together, aiming at one request fewer.

    Packing request by request leaves its waste in the last requests and in
    those that found no good partner; their reads, with a few of the next
    loosest requests for room to move, often fit in one request fewer.
    """
    for _ in range(_REPACK_ROUNDS):
        waste = [_waste(request, item_limit) for request in requests]
        ranked = sorted(range(len(requests)), key=lambda index: (-waste[index], index))
        loose = sum(share > _LOOSE for share in waste)
        for extra in _REPACK_EXTRA:
            chosen = set(ranked[: loose + extra])
            if len(chosen) < 2:
                continue
            pool = [unit for index in sorted(chosen) for unit in requests[index]]
            repacked = _complete_requests(pool, item_limit, len(chosen) - 1)
            if repacked is not None and len(repacked) < len(chosen):
                kept = [r for index, r in enumerate(requests) if index not in chosen]
                requests = kept + repacked
                break
        else:
            break
    return requests


def plan_reads(
    points: Iterable[Point],
    *,
    item_limit: int,
    with_attrs: bool,
    catalogue: Catalogue | None = None,
) -> ReadPlan:
    """Plan the GetObject requests that poll ``points``.

    ``catalogue`` tells what else a struct or array holds (its leaves count
    toward the item limit even when not polled); without it the points given are
    taken to be everything there is. ``with_attrs`` asks for every T_ApiObject's
    ``attr`` too. The result lists the requests, the lower bound of the module
    docstring, and the polled points no request can reach within the limits.
    """
    if item_limit < 1:
        raise ValueError("item_limit must be at least 1")
    polled_points = {point.key: point for point in points}
    universe: dict[str, Point] = dict(catalogue.points) if catalogue else {}
    universe.update(
        (key, point) for key, point in polled_points.items() if key not in universe
    )
    polled = set(polled_points)
    tree = _Tree(universe.values(), polled, item_limit, with_attrs)

    lower_bound = 0
    best: list[list[_Unit]] = []
    if polled - tree.unreadable:
        pricings = _pricings(tree)
        fractional = _fractional_bounds(tree, pricings)
        lower_bound = max(0, *(math.ceil(value - 1e-9) for value in fractional))
        best = _best_packing(
            _candidate_covers(tree, pricings, fractional), item_limit, lower_bound
        )

    best.sort(key=lambda request: min(unit.order for unit in request))
    requests = tuple(_planned(request, item_limit) for request in best)
    # A point the rules reach but no cover does (a point with members of its
    # own, which no catalogue makes) is reported rather than silently dropped.
    read = frozenset().union(*(request.point_keys for request in requests))
    return ReadPlan(
        requests=requests,
        lower_bound=lower_bound,
        with_attrs=with_attrs,
        point_keys=frozenset(polled),
        item_limit=item_limit,
        unreadable=frozenset(polled - read),
    )
