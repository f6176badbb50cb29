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

Choosing what to read is a tree problem (whole node or its parts) and packing the
chosen names into requests is a two-dimensional bin packing.

Lower bound. For a weight ``λ`` in ``[0, 1]`` every request satisfies
``λ·C/238 + (1-λ)·I/L ≤ 1`` (``C`` its characters of names incl. one separator
each, ``I`` its items, ``L`` the item limit), so any plan following the rules
needs at least ``ceil(min over covers of Σ λ·c/238 + (1-λ)·i/L)`` requests; the
minimum is an exact tree dynamic programme. A refinement prices a read of more
than ``L/2`` items -- at most one per request -- as the request it nearly fills:
next to it fit at most ``density`` characters per item left, apart from reads denser
than ``density``, whose characters are subtracted once. ``lower_bound`` is the maximum
over a grid of ``λ`` and ``density``; ``λ = 1`` alone is the character bound, ``λ = 0``
the item bound.

Plan. Each priced cover is packed three ways -- first-fit and best-fit
decreasing, and a balanced packer that fills each request with the mix of
characters and items of what is left -- then nearly empty requests are emptied
into the room of the others (turning T_ApiObjects between their whole and
``.value`` shapes, or trading reads between requests, to make room). The plan with
the fewest requests wins, then the one reading fewer items. Finally each
T_ApiObject is narrowed to its ``.value`` wherever its request has room for the
longer name, so attributes are only polled when that costs no request.
"""

from collections import deque
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass, field
import math
from typing import Final

from .catalogue import API_OBJECT_ITEMS
from .models import Catalogue, PlannedRequest, Point, ReadPlan
from .paths import GET_OBJECT, MAX_TARGET_LENGTH, encode_name, join_path, split_path

NAME_BUDGET: Final = MAX_TARGET_LENGTH - len(GET_OBJECT) + 1
"""Characters for names in one request, counting one separator (``?``/``&``) each."""

_SHARES: Final = 8
_LEVELS: Final = 5
_VICTIMS: Final = 4


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
    """Something to read in one request: the cover's shape first, then alternatives.

    A T_ApiObject may be read whole or as its ``.value`` (when attributes are not
    wanted); the packer picks whichever its request has room for.
    """

    order: int
    keys: frozenset[str]
    shapes: tuple[_Shape, ...]
    flexible: bool = True

    @property
    def choices(self) -> tuple[_Shape, ...]:
        """The shapes the packer may use (narrowing comes later in any case)."""
        return self.shapes if self.flexible else self.shapes[:1]


@dataclass(slots=True)
class _Request:
    """A request being filled."""

    placed: list[tuple[_Unit, _Shape]] = field(default_factory=list)
    chars: int = 0
    items: int = 0

    def shape_for(self, unit: _Unit, item_limit: int) -> _Shape | None:
        """Return the unit's shape to add here: the one sparing the scarcer resource."""
        fitting = [
            shape
            for shape in unit.choices
            if self.chars + shape.chars <= NAME_BUDGET
            and self.items + shape.items <= item_limit
        ]
        if not fitting:
            return None
        chars_scarcer = (NAME_BUDGET - self.chars) * item_limit < (
            item_limit - self.items
        ) * NAME_BUDGET
        if chars_scarcer:
            return min(fitting, key=lambda shape: (shape.chars, shape.items))
        return min(fitting, key=lambda shape: (shape.items, shape.chars))

    def add(self, unit: _Unit, shape: _Shape) -> None:
        """Put a unit in this request."""
        self.placed.append((unit, shape))
        self.chars += shape.chars
        self.items += shape.items

    def fullness(self, item_limit: int) -> int:
        """How full the request is in its fuller dimension (scaled to integers)."""
        return max(self.chars * item_limit, self.items * NAME_BUDGET)


def _chars(name: str) -> int:
    """Characters a name takes in a target, with its separator."""
    return len(encode_name(name)) + 1


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
        self._shapes: dict[_Node, tuple[_Shape, ...]] = {}
        self._keys: dict[_Node, frozenset[str]] = {}
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

    def _add(self, point: Point) -> None:
        """Add a point's path, counting its leaves in every ancestor."""
        try:
            segments = split_path(point.path)
        except ValueError:
            self.unparsable.add(point.key)
            return
        leaves = API_OBJECT_ITEMS if point.is_api_object else 1
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

    def whole(self, node: _Node) -> _Shape | None:
        """Return the read of the whole node, if the rules and limits allow it."""
        chars = _chars(node.name)
        if not node.eligible or chars > NAME_BUDGET or node.items > self.item_limit:
            return None
        return _Shape(node.name, chars, node.items)

    def value(self, node: _Node) -> _Shape | None:
        """Return the read of a T_ApiObject's ``.value`` alone, if allowed."""
        if self.with_attrs or node.point is None or not node.point.is_api_object:
            return None
        name = f"{node.name}.value"
        if not node.eligible or _chars(name) > NAME_BUDGET:
            return None
        return _Shape(name, _chars(name), 1)

    def shapes(self, node: _Node) -> tuple[_Shape, ...]:
        """Every way of reading the node by one name."""
        shapes = self._shapes.get(node)
        if shapes is None:
            shapes = tuple(
                shape
                for shape in (self.value(node), self.whole(node))
                if shape is not None
            )
            self._shapes[node] = shapes
        return shapes

    def keys_under(self, node: _Node, polled: set[str]) -> frozenset[str]:
        """Return the polled points a read of the node answers for."""
        keys = self._keys.get(node)
        if keys is None:
            keys = frozenset(
                sub.point.key
                for sub in _subtree(node)
                if sub.point is not None and sub.point.key in polled
            )
            self._keys[node] = keys
        return keys

    def splittable(self, node: _Node) -> bool:
        """Whether the node may be read through its parts instead of whole."""
        if not node.children or node.point is not None:
            return False
        return not node.is_array or node.items > self.item_limit

    def _mark(self, polled: set[str]) -> set[str]:
        """Mark nodes holding polled points; return polled points no read reaches."""
        unreadable = {key for key in polled if key in self.unparsable}
        reachable: dict[_Node, bool] = {}
        for node in self.nodes:
            above = node.parent is not None and reachable[node.parent]
            reachable[node] = above or self.whole(node) is not None
            point = node.point
            if point is None or point.key not in polled:
                continue
            if reachable[node] or self.value(node) is not None:
                ancestor: _Node | None = node
                while ancestor is not None and not ancestor.required:
                    ancestor.required = True
                    ancestor = ancestor.parent
            else:
                unreadable.add(point.key)
        return unreadable


@dataclass(frozen=True, slots=True)
class _Pricing:
    """One valid inequality ``sum of weights ≤ requests`` used to price covers.

    ``share`` weighs characters against items (the ``λ``). With a ``density``,
    a read of more than half the item limit (at most one per request) is priced
    as the part of a request it leaves unusable: next to it fit at most
    ``density`` characters per item left, apart from the reads denser than that,
    whose characters (``dense_chars``) are taken off the bound once.
    """

    share: float
    item_limit: int
    density: float | None = None
    dense_chars: int = 0

    def weight(self, shape: _Shape) -> float:
        """Return the shape's share of one request."""
        chars = shape.chars / NAME_BUDGET
        if self.density is not None and 2 * shape.items > self.item_limit:
            left = self.item_limit - shape.items
            chars = max(chars, 1 - self.density * left / NAME_BUDGET)
        return self.share * chars + (1 - self.share) * shape.items / self.item_limit

    @property
    def offset(self) -> float:
        """What the denser reads take off the bound."""
        return self.share * self.dense_chars / NAME_BUDGET


class _Cover:
    """The cheapest cover of the polled points under one pricing."""

    def __init__(self, tree: _Tree, pricing: _Pricing, *, values: bool) -> None:
        self.tree = tree
        self.pricing = pricing
        self.values = values
        # Per node: (price, items) of its cheapest cover, None if it has none.
        self.cost: dict[_Node, tuple[float, int] | None] = {}
        self.choice: dict[_Node, _Shape | None] = {}
        for node in reversed(tree.nodes):
            if node.required:
                self._solve(node)

    def _solve(self, node: _Node) -> None:
        """Pick the cheapest way to read a node (its children are solved)."""
        options: list[tuple[tuple[float, int], _Shape | None]] = [
            ((self.pricing.weight(shape), shape.items), shape)
            for shape in self.tree.shapes(node)
            if self.values or shape.name == node.name
        ]
        if self.tree.splittable(node):
            parts = [
                self.cost[child] for child in node.children.values() if child.required
            ]
            if all(part is not None for part in parts):
                price = sum(part[0] for part in parts if part is not None)
                items = sum(part[1] for part in parts if part is not None)
                options.append(((price, items), None))
        best = min(options, key=lambda option: option[0], default=None)
        self.cost[node] = None if best is None else best[0]
        self.choice[node] = None if best is None else best[1]

    @property
    def bound(self) -> int:
        """The fewest requests this pricing proves necessary."""
        total = -self.pricing.offset
        for root in self.tree.roots.values():
            if root.required:
                cost = self.cost[root]
                assert cost is not None, "every required root has a cover"
                total += cost[0]
        return max(0, math.ceil(total - 1e-9))

    def units(self, polled: set[str]) -> list[_Unit]:
        """Return the reads of the cover, each with the polled points it answers for."""
        units: list[_Unit] = []
        stack = [root for root in reversed(self.tree.roots.values()) if root.required]
        while stack:
            node = stack.pop()
            shape = self.choice[node]
            if shape is None:
                stack.extend(
                    child
                    for child in reversed(node.children.values())
                    if child.required
                )
                continue
            keys = self.tree.keys_under(node, polled)
            others = tuple(other for other in self.tree.shapes(node) if other != shape)
            units.append(_Unit(node.order, keys, (shape, *others)))
        return units


def _subtree(node: _Node) -> Iterator[_Node]:
    """Yield the node and everything under it."""
    stack = [node]
    while stack:
        current = stack.pop()
        yield current
        stack.extend(current.children.values())


def _pricings(tree: _Tree) -> list[_Pricing]:
    """Return the inequalities to try: a grid of ``λ``, plain and with densities."""
    limit = tree.item_limit
    small = sorted(
        (
            shape
            for node in tree.nodes
            if node.required
            for shape in tree.shapes(node)
            if 2 * shape.items < limit
        ),
        key=lambda shape: -shape.chars / shape.items,
    )
    # Densities below which only a few requests' worth of characters remain.
    budgets = [0, *(NAME_BUDGET * 2**power // 4 for power in range(_LEVELS))]
    levels: list[tuple[float, int]] = []
    dense_chars = 0
    for shape in small:
        while budgets and dense_chars + shape.chars > budgets[0]:
            budgets.pop(0)
            levels.append((shape.chars / shape.items, dense_chars))
        dense_chars += shape.chars
    pricings = []
    for step in range(_SHARES + 1):
        share = step / _SHARES
        pricings.append(_Pricing(share, limit))
        pricings.extend(
            _Pricing(share, limit, density, chars) for density, chars in levels
        )
    return pricings


def _pack(units: Sequence[_Unit], item_limit: int, best_fit: bool) -> list[_Request]:
    """Pack units into requests, largest first (by the tighter of the two limits)."""
    ordered = sorted(
        units,
        key=lambda unit: (
            -max(unit.shapes[0].chars * item_limit, unit.shapes[0].items * NAME_BUDGET),
            unit.order,
        ),
    )
    requests: list[_Request] = []
    for unit in ordered:
        candidates = (
            sorted(requests, key=lambda request: -request.fullness(item_limit))
            if best_fit
            else requests
        )
        for request in candidates:
            if (shape := request.shape_for(unit, item_limit)) is not None:
                request.add(unit, shape)
                break
        else:
            request = _Request()
            request.add(unit, unit.shapes[0])
            requests.append(request)
    return requests


def _pack_balanced(units: Sequence[_Unit], item_limit: int) -> list[_Request]:
    """Pack units request by request, each mixing characters and items like the rest.

    Keeping each request's mix near the mix of everything left means neither
    limit fills up alone. Each request starts with the largest unit left; then, while anything fits, it
    takes the unit (of the largest kind that fits) heavy in whichever resource
    the request uses less of than the units left do.
    """
    kinds: dict[tuple[tuple[int, int], ...], deque[_Unit]] = {}
    for unit in sorted(units, key=lambda unit: unit.order):
        sizes = tuple((shape.chars, shape.items) for shape in unit.choices)
        kinds.setdefault(sizes, deque()).append(unit)
    chars_left = sum(unit.shapes[0].chars for unit in units)
    items_left = sum(unit.shapes[0].items for unit in units)
    requests: list[_Request] = []
    while kinds:
        request = _Request()
        while True:
            # Characters lag behind items when the request's chars/items ratio is
            # below that of what is left.
            want_chars = request.chars * items_left <= request.items * chars_left
            best: tuple[tuple[int, int], _Shape, tuple[tuple[int, int], ...]] | None = (
                None
            )
            for sizes, queue in kinds.items():
                shape = request.shape_for(queue[0], item_limit)
                if shape is None:
                    continue
                if not request.placed:
                    score = (
                        max(shape.chars * item_limit, shape.items * NAME_BUDGET),
                        -queue[0].order,
                    )
                elif want_chars:
                    score = (shape.chars, -shape.items)
                else:
                    score = (shape.items, -shape.chars)
                if best is None or score > best[0]:
                    best = (score, shape, sizes)
            if best is None:
                break
            _, shape, sizes = best
            unit = kinds[sizes].popleft()
            if not kinds[sizes]:
                del kinds[sizes]
            request.add(unit, shape)
            chars_left -= unit.shapes[0].chars
            items_left -= unit.shapes[0].items
        requests.append(request)
    return requests


def _eliminate(requests: list[_Request], item_limit: int) -> None:
    """Empty whole requests into the room the others have left, while one can be.

    The emptiest requests are tried first; each unit of the victim goes where it
    fits tightest, if need be after turning one T_ApiObject of that request into
    its other shape to make room. A victim that cannot be emptied is restored.
    """
    progress = True
    while progress and len(requests) > 1:
        progress = False
        victims = sorted(
            requests,
            key=lambda request: (
                request.chars * item_limit + request.items * NAME_BUDGET
            ),
        )
        for victim in victims[:_VICTIMS]:
            others = [request for request in requests if request is not victim]
            if len(victim.placed) == 1:
                # A request of one read: trade reads between the others to make
                # room (no undo needed: a trade keeps both within the limits).
                ((unit, _),) = victim.placed
                if (
                    _room_for(unit, others, item_limit) is not None
                    or _swap_for(unit, others, item_limit) is not None
                ):
                    requests.remove(victim)
                    progress = True
                    break
                continue
            undo: list[tuple[_Request, int, _Unit, _Shape, _Shape | None]] = []
            for unit, _ in sorted(
                victim.placed,
                key=lambda pair: (
                    -max(pair[1].chars * item_limit, pair[1].items * NAME_BUDGET)
                ),
            ):
                move = _room_for(unit, others, item_limit)
                if move is None:
                    break
                undo.append(move)
            else:
                requests.remove(victim)
                progress = True
                break
            for target, index, unit, shape, previous in reversed(undo):
                target.placed.remove((unit, shape))
                target.chars -= shape.chars
                target.items -= shape.items
                if previous is not None:
                    neighbour, changed = target.placed[index]
                    target.placed[index] = (neighbour, previous)
                    target.chars += previous.chars - changed.chars
                    target.items += previous.items - changed.items


def _room_for(
    unit: _Unit, requests: Sequence[_Request], item_limit: int
) -> tuple[_Request, int, _Unit, _Shape, _Shape | None] | None:
    """Put a unit into the request where it fits tightest; return how to undo it.

    The undo record is the request, the index of a neighbour whose shape was
    changed to make room (-1 if none), the unit, its shape, and the neighbour's
    previous shape.
    """
    best: tuple[int, _Request, _Shape] | None = None
    for request in requests:
        shape = request.shape_for(unit, item_limit)
        if shape is not None:
            left = min(
                (NAME_BUDGET - request.chars - shape.chars) * item_limit,
                (item_limit - request.items - shape.items) * NAME_BUDGET,
            )
            if best is None or left < best[0]:
                best = (left, request, shape)
    if best is not None:
        best[1].add(unit, best[2])
        return best[1], -1, unit, best[2], None
    for request in requests:
        for index, (neighbour, current) in enumerate(request.placed):
            for other in neighbour.choices:
                chars = request.chars - current.chars + other.chars
                items = request.items - current.items + other.items
                if other == current or chars > NAME_BUDGET or items > item_limit:
                    continue
                fitting = [
                    shape
                    for shape in unit.choices
                    if chars + shape.chars <= NAME_BUDGET
                    and items + shape.items <= item_limit
                ]
                if fitting:
                    request.placed[index] = (neighbour, other)
                    request.chars, request.items = chars, items
                    request.add(unit, fitting[0])
                    return request, index, unit, fitting[0], current
    return None


def _swap_for(
    unit: _Unit, requests: Sequence[_Request], item_limit: int
) -> tuple[_Request, _Shape] | None:
    """Make room for a unit by trading a neighbour for a smaller one elsewhere.

    A request with items to spare but too few characters gives one of its reads
    to another request in exchange for a read with fewer characters; the unit
    then goes into the freed room. Both requests stay within the limits.
    """
    for target in requests:
        for shape in unit.choices:
            if target.items + shape.items > item_limit:
                continue
            for out_index, (leaving, out_shape) in enumerate(target.placed):
                for donor in requests:
                    if donor is target:
                        continue
                    for in_index, (coming, in_shape) in enumerate(donor.placed):
                        chars = target.chars - out_shape.chars + in_shape.chars
                        items = target.items - out_shape.items + in_shape.items
                        if (
                            chars + shape.chars > NAME_BUDGET
                            or items + shape.items > item_limit
                            or donor.chars - in_shape.chars + out_shape.chars
                            > NAME_BUDGET
                            or donor.items - in_shape.items + out_shape.items
                            > item_limit
                        ):
                            continue
                        target.placed[out_index] = (coming, in_shape)
                        donor.placed[in_index] = (leaving, out_shape)
                        target.chars, target.items = chars, items
                        donor.chars += out_shape.chars - in_shape.chars
                        donor.items += out_shape.items - in_shape.items
                        target.add(unit, shape)
                        return target, shape
    return None


def _narrow(requests: list[_Request]) -> None:
    """Swap each read for its fewest-items shape its request has room for."""
    for request in requests:
        for index, (unit, shape) in enumerate(request.placed):
            room = NAME_BUDGET - request.chars + shape.chars
            better = min(
                (other for other in unit.shapes if other.chars <= room),
                key=lambda other: (other.items, other.chars),
            )
            if better.items < shape.items:
                request.placed[index] = (unit, better)
                request.chars += better.chars - shape.chars
                request.items += better.items - shape.items


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
    readable = polled - tree.unreadable

    lower_bound = 0
    best: tuple[tuple[int, int], list[_Request]] | None = None
    if readable:
        pricings = _pricings(tree)
        covers = [_Cover(tree, pricing, values=True) for pricing in pricings]
        lower_bound = max(cover.bound for cover in covers)
        if not with_attrs:
            # Whole T_ApiObjects pack differently; the packer may still narrow them.
            covers += [_Cover(tree, pricing, values=False) for pricing in pricings]
        distinct: dict[tuple[_Shape | None, ...], _Cover] = {}
        for cover in covers:
            distinct.setdefault(tuple(cover.choice.values()), cover)
        candidates: list[list[_Unit]] = []
        for cover in distinct.values():
            units = cover.units(readable)
            candidates.append(units)
            if not with_attrs:
                # Packed in their chosen shapes, narrowed to ``.value`` afterwards.
                candidates.append(
                    [
                        _Unit(unit.order, unit.keys, unit.shapes, flexible=False)
                        for unit in units
                    ]
                )
        for units in candidates:
            for requests in (
                _pack(units, item_limit, best_fit=False),
                _pack(units, item_limit, best_fit=True),
                _pack_balanced(units, item_limit),
            ):
                _eliminate(requests, item_limit)
                _narrow(requests)
                score = (len(requests), sum(request.items for request in requests))
                if best is None or score < best[0]:
                    best = (score, requests)

    planned = []
    chosen = [] if best is None else best[1]
    for request in sorted(chosen, key=lambda r: min(u.order for u, _ in r.placed)):
        placed = sorted(request.placed, key=lambda pair: pair[0].order)
        names = tuple(shape.name for _, shape in placed)
        planned.append(
            PlannedRequest(
                names=names,
                target=GET_OBJECT + "&".join(encode_name(name) for name in names),
                items=request.items,
                point_keys=frozenset().union(*(unit.keys for unit, _ in placed)),
            )
        )
    return ReadPlan(
        requests=tuple(planned),
        lower_bound=lower_bound,
        with_attrs=with_attrs,
        point_keys=frozenset(polled),
        item_limit=item_limit,
        unreadable=frozenset(tree.unreadable),
    )
