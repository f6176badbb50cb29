"""The read planner's decisions that mutation testing found no test pinning.

Each test names the rule it checks: the weights and volumes of the module
docstring, the packing programme's table and its exact completion of a request
(checked against brute force on small sets of reads), the fallback to first-fit
for tables too wide, and the repacking of loose requests.
"""

from collections.abc import Callable
import itertools
import math
from typing import Any, Final

from hypothesis import HealthCheck, given, settings, strategies as st
import pytest

from custom_components.tecoapi.pyplc import Point, ValueKind
from custom_components.tecoapi.pyplc.tecomat import plan_reads
from custom_components.tecoapi.pyplc.tecomat.points import tecomat_point
from custom_components.tecoapi.pyplc.tecomat.tecoapi.catalogue import build_catalogue

# The planner's parts are private; what they compute is what is tested here.
from custom_components.tecoapi.pyplc.tecomat.tecoapi.planner import (
    _BEST_PRICINGS,
    _DENSITIES,
    _PACKED_COVERS,
    _SHARES,
    _SWEEP,
    NAME_BUDGET,
    _best_packing,
    _Budget,
    _candidate_covers,
    _complete_requests,
    _Cover,
    _fill,
    _first_fit,
    _fractional_bounds,
    _Kind,
    _Node,
    _Pricing,
    _pricings,
    _repack_loose,
    _Shape,
    _Table,
    _Tree,
    _Unit,
    _Volume,
    _waste,
)
from tests.pyplc.tecomat.tecoapi.test_planner import api_object
from tests.simulator import generate_program

B = NAME_BUDGET
TURN_CHARS, TURN_ITEMS = 6, 7  # ".value": 6 characters more, 7 items fewer


def _scalar(name: str) -> Point:
    return tecomat_point(name, ValueKind.BOOL)


def _unit(order: int, chars: int, items: int, *, turns: bool = False) -> _Unit:
    shape = _Shape(f"n{order}", chars, items)
    turned = _Shape(f"n{order}.value", chars + 6, items - 7) if turns else None
    return _Unit(order, frozenset({f"n{order}"}), shape, turned)


# --- the weights of the module docstring -----------------------------------------


def _docstring_weight(pricing: _Pricing, c: int, i: int, limit: int) -> float:
    share, density = pricing.share, pricing.density
    plain = share * c / B + (1 - share) * i / limit
    if density is None:
        return plain
    if i > limit / 2:  # large: at most one per request
        left = limit - i
        room = min(B - c, density * left)
        return max(plain, 1 - share * room / B - (1 - share) * left / limit)
    if pricing.capped:
        return share * min(c, density * i) / B + (1 - share) * i / limit
    return plain


@settings(max_examples=200, deadline=None, database=None)
@given(
    limit=st.integers(1, 300),
    share=st.integers(0, 8).map(lambda step: step / 8),
    density=st.one_of(st.none(), st.floats(0.0, 120.0)),
    capped=st.booleans(),
    data=st.data(),
)
def test_weights_and_excess_are_those_of_the_docstring(
    limit: int, share: float, density: float | None, capped: bool, data: st.DataObject
) -> None:
    chars = data.draw(st.integers(2, B))
    items = data.draw(st.integers(1, limit))
    pricing = _Pricing(share, density, capped)
    assert pricing.weight(chars, items, limit) == pytest.approx(
        _docstring_weight(pricing, chars, items, limit), abs=1e-12
    )
    offset = density is not None and not capped and 2 * items <= limit
    expected = max(0.0, chars - density * items) if offset else 0.0  # type: ignore[operator]
    assert pricing.excess(chars, items, limit) == pytest.approx(expected, abs=1e-12)


def test_weights_at_exactly_half_the_limit_and_just_over() -> None:
    # 64 of 128 items is not large (two fit a request); 65 is.
    pricing = _Pricing(0.5, 1.0, capped=True)
    assert pricing.weight(100, 64, 128) == pytest.approx(0.5 * 64 / B + 0.5 * 0.5)
    left = 128 - 65
    large = 1 - 0.5 * min(B - 100, 1.0 * left) / B - 0.5 * left / 128
    assert pricing.weight(100, 65, 128) == pytest.approx(large)
    # The offset pricing counts the excess of the first, none of the second.
    offset = _Pricing(0.5, 1.0)
    assert offset.excess(100, 64, 128) == 36.0
    assert offset.excess(100, 65, 128) == 0.0
    assert offset.excess(50, 64, 128) == 0.0


# --- volumes ----------------------------------------------------------------


@settings(max_examples=150, deadline=None, database=None)
@given(
    limit=st.integers(1, 300),
    reads=st.lists(
        st.tuples(st.integers(2, B), st.integers(1, 300), st.booleans()),
        min_size=1,
        max_size=8,
    ),
)
def test_volume_requests_are_the_fewest_over_any_number_of_turns(
    limit: int, reads: list[tuple[int, int, bool]]
) -> None:
    units = [
        _unit(order, chars, max(items, 8) if turns else items, turns=turns)
        for order, (chars, items, turns) in enumerate(reads)
    ]
    volume = _Volume.of(units, limit)
    chars = sum(unit.shape.chars for unit in units)
    items = sum(unit.shape.items for unit in units)
    turnable = sum(unit.turned is not None for unit in units)
    large = sum(2 * unit.shape.items > limit for unit in units)
    assert (volume.chars, volume.items) == (chars, items)
    assert (volume.turnable, volume.large) == (turnable, large)
    # Sums and differences of totals.
    one = _Volume.of(units[:1], limit)
    rest = _Volume.of(units[1:], limit)
    assert one.plus(rest) == volume
    assert volume.less(units[0]) == rest

    def filled(turns: float) -> float:
        return max(
            float(large),
            (chars + TURN_CHARS * turns) / B,
            (items - TURN_ITEMS * turns) / limit,
        )

    # Any share of the turnable reads may turn (a volume, not a packing).
    steps = 2000
    grid = min(filled(turnable * step / steps) for step in range(steps + 1))
    slack = (turnable / steps) * max(TURN_CHARS / B, TURN_ITEMS / limit)
    assert grid - slack - 1e-9 <= volume.requests() <= grid + 1e-9


def test_a_read_of_exactly_half_the_limit_is_not_large() -> None:
    assert _Volume.of([_unit(0, 10, 64)], 128).large == 0
    assert _Volume.of([_unit(0, 10, 65)], 128).large == 1
    # Two reads over half the limit fill two requests, whatever their size.
    assert _Volume.of([_unit(0, 3, 65), _unit(1, 3, 65)], 128).requests() == 2.0


# --- the packing programme's table -----------------------------------------------


@settings(max_examples=60, deadline=None, database=None)
@given(limit=st.integers(1, 130), turns=st.integers(0, 40))
def test_the_table_holds_every_cell_a_request_can_reach_and_no_other(
    limit: int, turns: int
) -> None:
    table = _Table(limit, turns)
    assert table.item_limit == limit
    assert table.turns is (turns > 0)
    assert table.width == limit + TURN_ITEMS * turns
    # Rows on whole bytes, with room for a row shifted by a whole row.
    assert table.stride == 8 * table.row_bytes
    assert table.stride >= 2 * (table.width + 1)
    assert table.plain == (1 << (limit + 1)) - 1
    rows = table.valid.to_bytes(table.row_bytes * (B + 1), "little")
    assert table.valid >> (table.stride * (B + 1)) == 0
    for chars in range(B + 1):
        row = int.from_bytes(
            rows[chars * table.row_bytes : (chars + 1) * table.row_bytes], "little"
        )
        # Items up to the limit, and 7 more for each ".value" the characters pay.
        top = limit + TURN_ITEMS * min(turns, (B - chars) // TURN_CHARS)
        assert row == (1 << (top + 1)) - 1, chars


@pytest.mark.parametrize(
    ("chars", "items", "turnable", "needed"),
    [
        (10, 128, 0, 0),  # exactly the limit: nothing turns
        (10, 129, 1, 1),  # one item over: one turn
        (10, 135, 1, 1),  # seven over: still one
        (10, 136, 1, None),  # eight over: two needed, one can
        (10, 136, 2, 2),
        (B - 6, 129, 1, 1),  # the turn's six characters exactly left
        (B - 5, 129, 1, None),  # one character short
        (B - 12, 136, 2, 2),
        (B - 11, 136, 2, None),
        (B, 50, 0, 0),
    ],
)
def test_turns_needed_to_bring_a_request_within_the_limit(
    chars: int, items: int, turnable: int, needed: int | None
) -> None:
    assert _Table(128, 3).turns_needed(chars, items, turnable) == needed


# --- the budget of waste ----------------------------------------------------------


def test_waste_is_measured_against_what_the_requests_to_come_may_waste() -> None:
    table = _Table(100, 0)
    # 3 requests aimed at, 1 done: 2 left, which may leave 2*238-300 characters
    # and 2*100-150 items unused.
    waste = _Budget(3, 300, 150).waste(table, 1)
    assert waste(200, 80) == pytest.approx(max(38 / 176, 20 / 50))
    assert waste(100, 95) == pytest.approx(max(138 / 176, 5 / 50))
    # Past the target, the last request counts as the only one left.
    waste = _Budget(3, 100, 40).waste(table, 5)
    assert waste(200, 80) == pytest.approx(max(38 / 138, 20 / 60))
    # Nothing to spare: each scale is one, no more.
    waste = _Budget(1, B, 100).waste(table, 0)
    assert waste(B - 2, 97) == pytest.approx(3.0)
    assert waste(B - 4, 99) == pytest.approx(4.0)
    waste = _Budget(1, B - 1, 99).waste(table, 0)  # one character, one item
    assert waste(B - 4, 99) == pytest.approx(4.0)
    assert waste(B - 1, 96) == pytest.approx(4.0)


def test_waste_in_turns_when_the_items_need_turning() -> None:
    table = _Table(100, 4)
    # 2 left, 230 items: 30 over, shed at 6/7 of a character each.
    rate = TURN_CHARS / TURN_ITEMS
    waste = _Budget(2, 300, 230).waste(table, 0)
    scale = 2 * B - 300 - rate * 30
    assert waste(200, 110) == pytest.approx((B - 200 - rate * 10) / scale)
    assert waste(150, 90) == pytest.approx((B - 150 + rate * 10) / scale)
    # Without turnable reads the items are wasted apart.
    waste = _Budget(2, 300, 230).waste(_Table(100, 0), 0)
    assert waste(200, 90) == pytest.approx(max(38 / 176, 10 / 1))
    # Exactly at the items the requests hold: wasted apart too.
    waste = _Budget(2, 300, 200).waste(table, 0)
    assert waste(200, 90) == pytest.approx(max(38 / 176, 10 / 1))


# --- completing a request exactly --------------------------------------------------


def _request_waste(
    waste: Callable[[int, int], float], counts: dict[_Kind, int]
) -> float:
    chars = sum(kind[0] * count for kind, count in counts.items())
    items = sum(kind[1] * count for kind, count in counts.items())
    return waste(chars, items)


_kinds = st.lists(
    st.tuples(
        st.integers(2, 120), st.integers(1, 40), st.booleans(), st.integers(1, 3)
    ),
    min_size=1,
    max_size=4,
    unique_by=lambda kind: kind[:3],
)


@settings(max_examples=150, deadline=None, database=None)
@given(kinds=_kinds, limit=st.integers(8, 60), chars_left=st.integers(0, 600))
def test_a_request_is_completed_with_the_least_waste_of_any_choice(
    kinds: list[tuple[int, int, bool, int]], limit: int, chars_left: int
) -> None:
    kinds = [
        # A T_ApiObject read whole fits the limit (else it is read as .value only).
        (chars, min(max(items, 8), limit) if turns else min(items, limit), turns, count)
        for chars, items, turns, count in kinds
    ]
    pending: dict[_Kind, list[_Unit]] = {}
    order = 0
    for chars, items, turns, count in kinds:
        for _ in range(count):
            pending.setdefault((chars, items, turns), []).append(
                _unit(order, chars, items, turns=turns)
            )
            order += 1
    turning = [kind[0] + TURN_CHARS for kind in pending if kind[2]]
    table = _Table(limit, B // min(turning) if turning else 0)
    first = max(pending, key=lambda kind: (max(kind[0] * limit, kind[1] * B), kind))
    if table.turns_needed(first[0], first[1], int(first[2])) is None:
        return  # the planner never starts a request with a read that cannot fit
    total_chars = sum(kind[0] * len(units) for kind, units in pending.items())
    total_items = sum(kind[1] * len(units) for kind, units in pending.items())
    budget = _Budget(2, total_chars + chars_left, total_items)
    waste = budget.waste(table, 0)
    counts = _fill(table, pending, first, waste)
    assert counts[first] >= 1
    assert all(0 < counts[kind] <= len(pending[kind]) for kind in counts)
    chars = sum(kind[0] * count for kind, count in counts.items())
    items = sum(kind[1] * count for kind, count in counts.items())
    turnable = sum(count for kind, count in counts.items() if kind[2])
    assert table.turns_needed(chars, items, turnable) is not None
    # Brute force over every choice of the other reads.
    ranges = [
        range(len(units) + 1) if kind != first else range(1, len(units) + 1)
        for kind, units in pending.items()
    ]
    best_plain = best_any = math.inf
    for choice in itertools.product(*ranges):
        chosen = dict(zip(pending, choice, strict=True))
        c = sum(kind[0] * n for kind, n in chosen.items())
        i = sum(kind[1] * n for kind, n in chosen.items())
        t = sum(n for kind, n in chosen.items() if kind[2])
        if c > B:
            continue
        if i <= limit:
            best_plain = min(best_plain, waste(c, i))
        if table.turns_needed(c, i, t) is not None:
            best_any = min(best_any, waste(c, i))
    got = _request_waste(waste, counts)
    assert best_any - 1e-9 <= got <= best_plain + 1e-9
    if not turning:
        assert got == pytest.approx(best_any)


def _fits(request: list[_Unit], limit: int) -> bool:
    chars = sum(unit.shape.chars for unit in request)
    items = sum(unit.shape.items for unit in request)
    turnable = sum(unit.turned is not None for unit in request)
    return _Table(limit, 0).turns_needed(chars, items, turnable) is not None


@settings(max_examples=150, deadline=None, database=None)
@given(
    limit=st.integers(8, 64),
    reads=st.lists(
        st.tuples(st.integers(2, 120), st.integers(1, 64), st.booleans()),
        min_size=1,
        max_size=10,
    ),
    target=st.integers(1, 6),
)
def test_completed_requests_hold_every_read_once_within_both_limits(
    limit: int, reads: list[tuple[int, int, bool]], target: int
) -> None:
    units = [
        _unit(
            order,
            chars,
            min(max(items, 8), limit) if turns else min(items, limit),
            turns=turns,
        )
        for order, (chars, items, turns) in enumerate(reads)
    ]
    requests = _complete_requests(units, limit, target)
    assert requests is not None
    packed = sorted(unit.order for request in requests for unit in request)
    assert packed == sorted(unit.order for unit in units)
    for request in requests:
        assert request
        assert _fits(request, limit)


@pytest.mark.parametrize("limit", [17, 23])
def test_reads_that_must_turn_anyway_are_the_shortest(limit: int) -> None:
    # Three objects of 8 items in one request: 7 (or 1) items over the limit, so
    # one must turn; the one of fewest characters turns before packing.
    units = [_unit(0, 30, 8, turns=True), _unit(1, 10, 8, turns=True)]
    units.append(_unit(2, 20, 8, turns=True))
    requests = _complete_requests(units, limit, 1)
    assert requests is not None
    (request,) = requests
    turned = [unit.order for unit in request if unit.shape.items == 1]
    assert turned == [1]
    assert sorted(unit.shape.chars for unit in request) == [16, 20, 30]


def test_reads_of_one_kind_are_packed_in_the_plcs_order() -> None:
    # Two of these fit a request: the first two go together, the third alone.
    units = [_unit(order, 101, 1) for order in range(3)]
    requests = _complete_requests(units, 128, 2)
    assert requests is not None
    assert sorted(sorted(unit.order for unit in request) for request in requests) == [
        [0, 1],
        [2],
    ]


def test_each_request_starts_with_the_largest_read_left() -> None:
    # 210 of 238 characters outweighs 60 of 128 items: it starts the first
    # request, where nothing else fits; the two item-heavy reads share the next.
    units = [_unit(0, 210, 1), _unit(1, 30, 60), _unit(2, 30, 60)]
    requests = _complete_requests(units, 128, 2)
    assert requests is not None
    assert [sorted(unit.order for unit in request) for request in requests] == [
        [0],
        [1, 2],
    ]


def test_the_programme_spans_4096_items_and_first_fit_takes_wider_tables() -> None:
    # Two reads of 2100 items: the limit bounds the table's item axis.
    units = [_unit(0, 10, 2100), _unit(1, 10, 2100)]
    requests = _complete_requests(units, 4096, 2)
    assert requests is not None
    assert sorted(len(request) for request in requests) == [1, 1]
    assert _complete_requests(units, 4097, 2) is None
    # All the reads hold fewer items than the limit: that is the axis.
    units = [_unit(0, 10, 2000), _unit(1, 10, 2096)]
    assert _complete_requests(units, 10_000, 1) is not None
    units = [_unit(0, 10, 2000), _unit(1, 10, 2097)]
    assert _complete_requests(units, 10_000, 1) is None
    # Reads that may turn widen it by 7 items for each turn a request can make:
    # two of 113+6 characters fit in 238.
    units = [_unit(0, 113, 2050, turns=True), _unit(1, 113, 2050, turns=True)]
    requests = _complete_requests(units, 4082, 2)
    assert requests is not None
    assert sorted(unit.order for request in requests for unit in request) == [0, 1]
    assert _complete_requests(units, 4083, 2) is None
    # Reads of exactly the limit in all need no turn: no room is made for one.
    units = [_unit(0, 113, 2045, turns=True), _unit(1, 113, 2045, turns=True)]
    requests = _complete_requests(units, 4090, 1)
    assert requests is not None
    assert [len(request) for request in requests] == [2]


# --- first-fit ---------------------------------------------------------------------


def test_first_fit_takes_the_largest_reads_first_each_into_the_first_that_fits() -> (
    None
):
    limit = 10_000
    units = [
        _unit(0, 100, 10),
        _unit(1, 200, 10),  # largest by characters
        _unit(2, 30, 9000),  # largest by items: 9000/10000 > 200/238
        _unit(3, 8, 990),  # fills the first exactly
        _unit(4, 138, 10),
        _unit(5, 10, 1001),
    ]
    requests = _first_fit(units, limit)
    assert [[unit.order for unit in request] for request in requests] == [
        [2, 1, 3],
        [4, 0],
        [5],
    ]
    # Exactly full in both limits still fits.
    requests = _first_fit([_unit(0, 119, 5000), _unit(1, 119, 5000)], limit)
    assert len(requests) == 1
    requests = _first_fit([_unit(0, 120, 10), _unit(1, 119, 10)], limit)
    assert len(requests) == 2
    requests = _first_fit([_unit(0, 10, 5001), _unit(1, 10, 5000)], limit)
    assert len(requests) == 2
    # A request's items add up: 6000 + 3000 leaves no room for 1500 more.
    units = [_unit(0, 10, 6000), _unit(1, 10, 3000), _unit(2, 10, 1500)]
    requests = _first_fit(units, limit)
    assert [[unit.order for unit in request] for request in requests] == [[0, 1], [2]]


# --- loose requests ----------------------------------------------------------------


def test_waste_of_a_request_is_its_unused_share_of_both_limits() -> None:
    assert _waste([_unit(0, 119, 64)], 128) == pytest.approx(0.5 + 0.5)
    assert _waste([_unit(0, B, 128)], 128) == pytest.approx(0.0)
    # 9 items over 8 sheds them by two turns: 12 characters and 14 items.
    request = [_unit(0, 100, 8, turns=True), _unit(1, 100, 9, turns=True)]
    assert _waste(request, 8) == pytest.approx((B - 212) / B + (8 - 17 + 14) / 8)


def test_the_loosest_requests_are_packed_again_in_one_fewer() -> None:
    # Five requests each a fifth full: packed again, they fit in one.
    requests = [[_unit(order, 40, 20)] for order in range(5)]
    repacked = _repack_loose(requests, 128)
    assert len(repacked) == 1
    assert sorted(unit.order for unit in repacked[0]) == list(range(5))


# --- covers and the fractional bound: against every cover ------------------------


def _tree(
    catalogue_tree: dict[str, Any], limit: int, with_attrs: bool, share: float = 1.0
) -> _Tree:
    catalogue = build_catalogue(list(catalogue_tree), catalogue_tree)
    points = list(catalogue.points.values())
    polled = {point.key for index, point in enumerate(points) if index % 3 != 1}
    return _Tree(points, polled or {points[0].key}, limit, with_attrs)


def _every_cover(tree: _Tree, node: _Node) -> list[list[_Node]]:
    """Every set of reads covering a node's polled points (none: no cover)."""
    options: list[list[_Node]] = [[node]] if tree.shapes(node) else []
    if tree.splittable(node):
        parts = [
            _every_cover(tree, child)
            for child in node.children.values()
            if child.required
        ]
        if parts and all(parts):
            options += [
                list(itertools.chain(*combo)) for combo in itertools.product(*parts)
            ]
    return options


def _cover_weights(
    tree: _Tree, pricing: _Pricing
) -> tuple[list[float], list[list[_Node]]]:
    roots = [
        covers
        for root in tree.roots.values()
        if root.required and (covers := _every_cover(tree, root))
    ]
    limit = tree.item_limit
    covers = [list(itertools.chain(*combo)) for combo in itertools.product(*roots)]
    weights = [
        sum(
            min(
                pricing.weight(chars, items, limit) for chars, items in tree.sizes(node)
            )
            for node in cover
        )
        for cover in covers
    ]
    return weights, covers


_names = st.text(alphabet="abcdefgh", min_size=1, max_size=60)
_leaf = st.one_of(st.integers(0, 9), st.builds(api_object))
_struct = st.dictionaries(_names, _leaf, min_size=1, max_size=4)
_catalogues = st.dictionaries(
    _names,
    st.one_of(
        _leaf,
        _struct,
        st.lists(_leaf, min_size=1, max_size=12),
        st.dictionaries(_names, st.one_of(_leaf, _struct), min_size=1, max_size=3),
    ),
    min_size=1,
    max_size=4,
)


_SLOW_CATALOGUES: Final = settings(
    deadline=None, database=None, suppress_health_check=[HealthCheck.too_slow]
)
"""Generated catalogues are planned whole: no deadline, no example database."""


def _priced(
    catalogue: dict[str, Any], limit: int, with_attrs: bool
) -> tuple[_Tree, list[_Pricing], list[float]] | None:
    """A catalogue's tree, its pricings and their fractional bounds (None: nothing to read)."""
    tree = _tree(catalogue, limit, with_attrs)
    if not tree.required or tree.polled <= tree.unreadable:
        return None
    pricings = _pricings(tree)
    return tree, pricings, _fractional_bounds(tree, pricings)


@settings(_SLOW_CATALOGUES, max_examples=60)
@given(catalogue=_catalogues, limit=st.integers(2, 40), with_attrs=st.booleans())
def test_the_bound_and_the_covers_are_the_least_weight_of_any_cover(
    catalogue: dict[str, Any], limit: int, with_attrs: bool
) -> None:
    if (priced := _priced(catalogue, limit, with_attrs)) is None:
        return
    tree, pricings, fractional = priced
    # What the offset pricings take off: each required node's largest excess.
    for pricing, bound in itertools.islice(
        zip(pricings, fractional, strict=True), 0, None, 7
    ):
        weights, covers = _cover_weights(tree, pricing)
        excess = 0.0
        if pricing.density is not None and not pricing.capped:
            excess = sum(
                max(
                    (pricing.excess(c, i, limit) for c, i in tree.sizes(node)),
                    default=0.0,
                )
                for node in tree.required
            )
        least = min(weights, default=0.0)
        assert bound == pytest.approx(least - pricing.share * excess / NAME_BUDGET)
        # The cover of the pricing is one of the lightest, in the PLC's order.
        cover = _Cover(tree, pricing)
        units = cover.units()
        assert [unit.order for unit in units] == sorted(unit.order for unit in units)
        chosen = sorted(unit.order for unit in units)
        assert chosen in [sorted(node.order for node in c) for c in covers]
        nodes = {node.order: node for node in tree.nodes}
        assert sum(
            min(pricing.weight(c, i, limit) for c, i in tree.sizes(nodes[order]))
            for order in chosen
        ) == pytest.approx(least)
        # Mixing never fills more requests by volume, and is a cover too.
        mixed = cover.mixed()
        assert (
            _Volume.of(mixed, limit).requests()
            <= _Volume.of(units, limit).requests() + 1e-9
        )
        assert sorted(unit.order for unit in mixed) in [
            sorted(node.order for node in c) for c in covers
        ]


def _whole_tree(catalogue_tree: dict[str, Any], limit: int) -> _Tree:
    catalogue = build_catalogue(list(catalogue_tree), catalogue_tree)
    points = list(catalogue.points.values())
    return _Tree(points, {point.key for point in points}, limit, False)


def test_a_node_whose_parts_weigh_as_much_is_read_whole() -> None:
    # Items only: "s" whole weighs 2 items, its two members 1 each: a tie.
    tree = _whole_tree({"s": {"x": 1, "y": 2}}, 128)
    units = _Cover(tree, _Pricing(0.0)).units()
    assert [unit.shape.name for unit in units] == ["s"]
    # Characters only: the members' names cost more, so too.
    units = _Cover(tree, _Pricing(1.0)).units()
    assert [unit.shape.name for unit in units] == ["s"]


def test_mixing_splits_a_node_only_where_that_lowers_the_volume() -> None:
    # A 100-item array fills its request anyway: splitting "s" lowers nothing.
    tree = _whole_tree({"a": list(range(100)), "s": {"x": 1, "y": 2}}, 128)
    cover = _Cover(tree, _Pricing(1.0))
    assert [unit.shape.name for unit in cover.units()] == ["a", "s"]
    assert [unit.shape.name for unit in cover.mixed()] == ["a", "s"]
    # Two structs of 70 items are large, a request each; one read through its
    # members (420 characters) leaves 1.9 requests by volume: split the first.
    tree = _whole_tree(
        {"p": {f"m{i}": i for i in range(70)}, "q": {f"m{i}": i for i in range(70)}},
        128,
    )
    cover = _Cover(tree, _Pricing(1.0))
    assert [unit.shape.name for unit in cover.units()] == ["p", "q"]
    mixed = [unit.shape.name for unit in cover.mixed()]
    assert mixed == [*(f"p.m{i}" for i in range(70)), "q"]


def test_the_grid_spreads_its_densities_over_those_the_reads_have() -> None:
    # Scalars of 2 to 40 characters, one item each: 39 densities, 16 chosen.
    tree = _Tree(
        [_scalar("v" * length) for length in range(1, 40)],
        {"v" * length for length in range(1, 40)},
        128,
        False,
    )
    pricings = _pricings(tree)
    assert pricings[0] == _Pricing(0.0)
    densities = sorted({p.density for p in pricings if p.density is not None})
    assert len(densities) == _DENSITIES
    assert densities[0] == 2.0
    assert densities[-1] == 40.0
    # Evenly: the chosen ones' places among all 39 differ by 2 or 3.
    places = [int(density) - 2 for density in densities]
    assert {b - a for a, b in itertools.pairwise(places)} <= {2, 3}
    # Per share (1/8 .. 1): plain, then offset and capped at each density.
    assert len(pricings) == 1 + _SHARES * (1 + 2 * _DENSITIES)
    assert [p.share for p in pricings if p.density is None] == [
        step / _SHARES for step in range(_SHARES + 1)
    ]
    assert pricings[1:4] == [
        _Pricing(1 / _SHARES),
        _Pricing(1 / _SHARES, 2.0),
        _Pricing(1 / _SHARES, 2.0, capped=True),
    ]


def test_the_grid_prices_large_reads_at_density_zero_and_excludes_them() -> None:
    # An array of 65 of 128 items is large; one of 64 is not.
    for size, large in ((64, False), (65, True)):
        catalogue = build_catalogue(["a", "s"], {"a": list(range(size)), "s": 1})
        points = list(catalogue.points.values())
        tree = _Tree(points, {point.key for point in points}, 128, False)
        pricings = _pricings(tree)
        densities = {p.density for p in pricings if p.density is not None}
        assert (0.0 in densities) is large
        expected = {2 / 1} | (set() if large else {2 / size})
        assert densities - {0.0} == expected
        assert (_Pricing(1.0, 0.0, capped=True) in pricings) is large


# --- the covers worth packing -----------------------------------------------------


@settings(_SLOW_CATALOGUES, max_examples=40)
@given(catalogue=_catalogues, limit=st.integers(8, 40), with_attrs=st.booleans())
def test_candidate_covers_are_the_fewest_by_volume_of_those_tried(
    catalogue: dict[str, Any], limit: int, with_attrs: bool
) -> None:
    if (priced := _priced(catalogue, limit, with_attrs)) is None:
        return
    tree, pricings, fractional = priced
    candidates = _candidate_covers(tree, pricings, fractional)
    assert 1 <= len(candidates) <= _PACKED_COVERS
    needs = [
        math.ceil(_Volume.of(units, limit).requests() - 1e-9) for units in candidates
    ]
    assert needs == sorted(needs)
    assert needs[-1] <= needs[0] + 1
    assert len({frozenset(u.order for u in units) for units in candidates}) == len(
        candidates
    )
    # No cover of the sweep of plain pricings, nor of the best ones, needs fewer.
    ranked = sorted(range(len(pricings)), key=lambda k: (-fractional[k], k))
    tried = [pricings[k] for k in ranked[:_BEST_PRICINGS]]
    tried += [_Pricing(step / _SWEEP) for step in range(_SWEEP + 1)]
    every: dict[frozenset[int], int] = {}
    for rank, pricing in enumerate(tried):
        cover = _Cover(tree, pricing)
        mixed = [cover.mixed()] if rank < _BEST_PRICINGS else []
        for units in [cover.units(), *mixed]:
            need = math.ceil(_Volume.of(units, limit).requests() - 1e-9)
            assert needs[0] <= need
            every[frozenset(unit.order for unit in units)] = need
    # As many as there are within one request of the fewest, up to the most packed.
    near = sum(need <= needs[0] + 1 for need in every.values())
    assert len(candidates) == min(_PACKED_COVERS, near)


# --- the best packing -----------------------------------------------------------


def test_the_best_packing_has_the_fewest_requests_then_items() -> None:
    full = [_unit(order, B, 5) for order in range(3)]  # a request each
    light = [_unit(10 + order, B, 3) for order in range(3)]
    same = [_unit(20 + order, B, 3) for order in range(3)]
    best = _best_packing([full, light, same], 128, 1)
    assert sorted(unit.order for request in best for unit in request) == [10, 11, 12]
    # Within one request of the bound: no other cover is tried.
    fewer = [_unit(30 + order, 100, 3) for order in range(4)]  # two requests
    best = _best_packing([full, fewer], 128, 2)
    assert len(best) == 3
    assert best[0][0].order in range(3)
    best = _best_packing([full, fewer], 128, 1)
    assert len(best) == 2
    assert _best_packing([], 128, 1) == []


# --- what is polled and what the catalogue says ---------------------------------


def test_the_catalogue_describes_a_polled_point_it_holds() -> None:
    # The catalogue's "o" is a T_ApiObject (8 items); the point polled under the
    # same key without attributes does not replace it.
    tree = {"o": api_object(), "p": 1}
    catalogue = build_catalogue(list(tree), tree)
    plan = plan_reads(
        [_scalar("o"), _scalar("p")],
        item_limit=128,
        with_attrs=True,
        catalogue=catalogue,
    )
    assert plan.requests[0].names == ("o", "p")
    assert plan.requests[0].items == 9


# --- plans at their lower bound ---------------------------------------------------


# (points, seed, CPU) of generate_program, an item limit, with attributes or not,
# and the requests of the plan, which its lower bound proves the fewest.
AT_THE_BOUND: list[tuple[tuple[int, int, str], int, bool, int]] = [
    # The sweep of plain pricings (17 shares) finds the cover packed here.
    ((80, 659, "CP-1000"), 64, False, 7),
]


@pytest.mark.parametrize(("program", "limit", "with_attrs", "requests"), AT_THE_BOUND)
def test_generated_programs_planned_at_their_lower_bound(
    program: tuple[int, int, str], limit: int, with_attrs: bool, requests: int
) -> None:
    points, seed, plc_type = program
    generated = generate_program(points, seed=seed, plc_type=plc_type)
    tree = {
        declaration.name: declaration.initial for declaration in generated.declarations
    }
    catalogue = build_catalogue(list(tree), tree)
    plan = plan_reads(
        catalogue.points.values(),
        item_limit=limit,
        with_attrs=with_attrs,
        catalogue=catalogue,
    )
    assert plan.unreadable == frozenset()
    assert len(plan.requests) == plan.lower_bound == requests


def test_two_loose_requests_are_packed_again_into_one() -> None:
    requests = [[_unit(0, 40, 20)], [_unit(1, 40, 20)]]
    repacked = _repack_loose(requests, 128)
    assert [sorted(unit.order for unit in request) for request in repacked] == [[0, 1]]
    # Full requests are left as they are: nothing is loose.
    full = [[_unit(0, B, 128)], [_unit(1, B, 128)]]
    assert _repack_loose(full, 128) == full
    # A loose request beside full ones: packing it again saves nothing.
    mixed = [[_unit(0, B, 128)], [_unit(1, 40, 20)]]
    assert _repack_loose(mixed, 128) == mixed


def test_a_struct_is_read_whole_when_one_of_its_parts_has_no_read() -> None:
    # "s.<240 characters>" is too long to name, and its elements are read only
    # through it: "s" whole is the only read that reaches them.
    long = "y" * 240
    tree = {"s": {"x": 1, long: [1, 2]}}
    catalogue = build_catalogue(list(tree), tree)
    plan = plan_reads(
        catalogue.points.values(), item_limit=128, with_attrs=False, catalogue=catalogue
    )
    assert [request.names for request in plan.requests] == [("s",)]
    assert plan.unreadable == frozenset()
    assert plan.requests[0].point_keys == frozenset(catalogue.points)
