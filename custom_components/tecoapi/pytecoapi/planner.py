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
chosen names into requests is a two-dimensional bin packing. For a weight
``λ`` in ``[0, 1]`` every request satisfies ``λ·C/238 + (1-λ)·I/L ≤ 1`` (``C`` its
characters of names incl. one separator each, ``I`` its items), so any plan
following the rules needs at least ``ceil(min over covers of λ·C/238 + (1-λ)·I/L)``
requests. That minimum is an exact tree dynamic programme; its maximum over a
grid of ``λ`` is the reported ``lower_bound`` (at ``λ = 1`` it is the character
bound, at ``λ = 0`` the item bound). Each ``λ`` also yields a cover, which is
packed first-fit and best-fit decreasing; the plan with the fewest requests wins,
then the one reading fewer items. Finally a whole T_ApiObject is narrowed to its
``.value`` wherever its request has room for the longer name, so attributes are
only polled when that costs no request.
"""

from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass, field
from typing import Final

from .catalogue import API_OBJECT_ITEMS
from .models import Catalogue, PlannedRequest, Point, ReadPlan
from .paths import GET_OBJECT, MAX_TARGET_LENGTH, encode_name, join_path, split_path

NAME_BUDGET: Final = MAX_TARGET_LENGTH - len(GET_OBJECT) + 1
"""Characters for names in one request, counting one separator (``?``/``&``) each."""

_GRID: Final = 24


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
class _Read:
    """One name to put in a request."""

    name: str
    chars: int
    items: int
    order: int
    keys: frozenset[str]
    narrower: "_Read | None" = None


@dataclass(slots=True)
class _Bin:
    """A request being filled."""

    reads: list[_Read] = field(default_factory=list)
    chars: int = 0
    items: int = 0


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

    def whole(self, node: _Node) -> _Read | None:
        """Return the read of the whole node, if the rules and limits allow it."""
        chars = _chars(node.name)
        if not node.eligible or chars > NAME_BUDGET or node.items > self.item_limit:
            return None
        return _Read(node.name, chars, node.items, node.order, frozenset())

    def value(self, node: _Node) -> _Read | None:
        """Return the read of a T_ApiObject's ``.value`` alone, if allowed."""
        if self.with_attrs or node.point is None or not node.point.is_api_object:
            return None
        name = f"{node.name}.value"
        if not node.eligible or _chars(name) > NAME_BUDGET:
            return None
        return _Read(name, _chars(name), 1, node.order, frozenset())

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


class _Cover:
    """The cheapest cover of the polled points for one weight of chars vs items."""

    def __init__(self, tree: _Tree, weight: int) -> None:
        self.tree = tree
        self.char_weight = weight * tree.item_limit
        self.item_weight = (_GRID - weight) * NAME_BUDGET
        # Per node: (weighted cost, items) of its cheapest cover, None if it has none.
        self.cost: dict[_Node, tuple[int, int] | None] = {}
        self.choice: dict[_Node, _Read | None] = {}
        for node in reversed(tree.nodes):
            if node.required:
                self._solve(node)

    def _solve(self, node: _Node) -> None:
        """Pick the cheapest way to read a node (its children are solved)."""
        options: list[tuple[tuple[int, int], _Read | None]] = [
            (
                (
                    read.chars * self.char_weight + read.items * self.item_weight,
                    read.items,
                ),
                read,
            )
            for read in (self.tree.value(node), self.tree.whole(node))
            if read is not None
        ]
        if self.tree.splittable(node):
            parts = [
                self.cost[child] for child in node.children.values() if child.required
            ]
            if all(part is not None for part in parts):
                cost = sum(part[0] for part in parts if part is not None)
                items = sum(part[1] for part in parts if part is not None)
                options.append(((cost, items), None))
        best = min(options, key=lambda option: option[0], default=None)
        self.cost[node] = None if best is None else best[0]
        self.choice[node] = None if best is None else best[1]

    @property
    def total(self) -> int:
        """The weighted cost of the whole cover."""
        total = 0
        for root in self.tree.roots.values():
            if root.required:
                cost = self.cost[root]
                assert cost is not None, "every required root has a cover"
                total += cost[0]
        return total

    def reads(self, polled: set[str]) -> list[_Read]:
        """Return the names of the cover, each with the polled points it answers for."""
        reads: list[_Read] = []
        stack = [root for root in reversed(self.tree.roots.values()) if root.required]
        while stack:
            node = stack.pop()
            read = self.choice[node]
            if read is None:
                stack.extend(
                    child
                    for child in reversed(node.children.values())
                    if child.required
                )
                continue
            keys = frozenset(
                sub.point.key
                for sub in _subtree(node)
                if sub.point is not None and sub.point.key in polled
            )
            narrower = self.tree.value(node) if read.items > 1 else None
            reads.append(
                _Read(read.name, read.chars, read.items, read.order, keys, narrower)
            )
        return reads


def _subtree(node: _Node) -> Iterator[_Node]:
    """Yield the node and everything under it."""
    stack = [node]
    while stack:
        current = stack.pop()
        yield current
        stack.extend(current.children.values())


def _pack(reads: Sequence[_Read], item_limit: int, best_fit: bool) -> list[_Bin]:
    """Pack reads into requests, largest first (by the tighter of the two limits)."""
    ordered = sorted(
        reads,
        key=lambda read: (
            -max(read.chars * item_limit, read.items * NAME_BUDGET),
            read.order,
        ),
    )
    bins: list[_Bin] = []
    for read in ordered:
        fitting = [
            candidate
            for candidate in bins
            if candidate.chars + read.chars <= NAME_BUDGET
            and candidate.items + read.items <= item_limit
        ]
        if not fitting:
            target = _Bin()
            bins.append(target)
        elif best_fit:
            target = max(
                fitting,
                key=lambda candidate: max(
                    candidate.chars * item_limit, candidate.items * NAME_BUDGET
                ),
            )
        else:
            target = fitting[0]
        target.reads.append(read)
        target.chars += read.chars
        target.items += read.items
    return bins


def _narrow(bins: list[_Bin]) -> None:
    """Read a T_ApiObject's ``.value`` instead of all of it where the request has room."""
    for request in bins:
        for index, read in enumerate(request.reads):
            narrower = read.narrower
            if narrower is None:
                continue
            extra = narrower.chars - read.chars
            if request.chars + extra <= NAME_BUDGET:
                request.reads[index] = _Read(
                    narrower.name, narrower.chars, 1, read.order, read.keys
                )
                request.chars += extra
                request.items -= read.items - 1


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
    best: tuple[tuple[int, int], list[_Bin]] | None = None
    tried: set[tuple[str, ...]] = set()
    if readable:
        for weight in range(_GRID + 1):
            cover = _Cover(tree, weight)
            bound = -(-cover.total // (_GRID * item_limit * NAME_BUDGET))
            lower_bound = max(lower_bound, bound)
            reads = cover.reads(readable)
            signature = tuple(sorted(read.name for read in reads))
            if signature in tried:
                continue
            tried.add(signature)
            for best_fit in (False, True):
                bins = _pack(reads, item_limit, best_fit)
                if not with_attrs:
                    _narrow(bins)
                score = (len(bins), sum(request.items for request in bins))
                if best is None or score < best[0]:
                    best = (score, bins)

    requests = [] if best is None else best[1]
    planned = []
    for request in sorted(requests, key=lambda r: min(read.order for read in r.reads)):
        reads = sorted(request.reads, key=lambda read: read.order)
        names = tuple(read.name for read in reads)
        planned.append(
            PlannedRequest(
                names=names,
                target=GET_OBJECT + "&".join(encode_name(name) for name in names),
                items=request.items,
                point_keys=frozenset().union(*(read.keys for read in reads)),
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
