"""The planner's bound is sound and met: no plan has fewer POSTs, and none of its are more.

For random small maps (small request and POST limits, so that limits bind),
the fewest requests of each chain are found by brute force -- every set of
windows, smallest first -- and the fewest POSTs from them; the planner's
``lower_bound`` must equal that, and its plan must have exactly that many
POSTs, each following the gateway's rules and reading every point where it
is.
"""

from collections import defaultdict
from collections.abc import Sequence
import itertools
import math

from hypothesis import given, settings, strategies as st

from custom_components.tecoapi.pyplc.panasonic.address import Address, Area, WireType
from custom_components.tecoapi.pyplc.panasonic.planner import (
    ReadPlan,
    Target,
    plan_reads,
    values_per_request,
)

REGISTER_TYPES = [
    WireType.INT,
    WireType.UINT,
    WireType.DINT,
    WireType.UDINT,
    WireType.REAL,
    WireType.STRING,
]


@st.composite
def targets(draw: st.DrawFn) -> list[Target]:
    """A small map: a few stations, areas and types, addresses close together."""
    found: list[Target] = []
    for number in range(draw(st.integers(1, 14))):
        station = draw(st.sampled_from([None, 1, 2]))
        area = draw(st.sampled_from([Area.DT, Area.LD, Area.R, Area.Y]))
        if area.bits:
            address = Address(area, draw(st.integers(0, 3)), draw(st.integers(0, 15)))
            wire = WireType.BOOL
        else:
            address = Address(area, draw(st.integers(0, 40)))
            wire = draw(st.sampled_from(REGISTER_TYPES))
        found.append(Target(f"p{number}", station, address, wire))
    return found


def _position(target: Target) -> int:
    return target.address.index


def _fewest_windows(slots: Sequence[int], width: int) -> int:
    """The fewest windows of ``width`` values covering every slot (brute force)."""
    points = sorted(set(slots))
    for count in range(1, len(points) + 1):
        for starts in itertools.combinations(points, count):
            if all(any(s <= p < s + width for s in starts) for p in points):
                return count
    return 0


def _fewest_posts(found: list[Target], max_requests: int, max_registers: int) -> int:
    chains: dict[int | None, dict[tuple[Area, WireType, int], list[int]]] = defaultdict(
        lambda: defaultdict(list)
    )
    for target in found:
        wire = target.type
        if wire.registers == 2:
            parity = target.address.word % 2
            chains[target.station][target.address.area, wire, parity].append(
                target.address.word // 2
            )
        else:
            chains[target.station][target.address.area, wire, 0].append(
                _position(target)
            )
    posts = 0
    for by_chain in chains.values():
        requests = 0
        for (_, wire, _), slots in by_chain.items():
            width = (
                1
                if wire is WireType.STRING
                else values_per_request(wire, max_registers)
            )
            requests += _fewest_windows(slots, width)
        posts += math.ceil(requests / max_requests)
    return posts


def _check_rules(
    plan: ReadPlan, found: list[Target], max_requests: int, max_registers: int
) -> None:
    """Every POST and request follows the gateway's rules; every point is read."""
    by_key = {target.key: target for target in found}
    read: set[str] = set()
    for post in plan.posts:
        assert 1 <= len(post.requests) <= max_requests
        for request in post.requests:
            width = max(request.type.registers, 1)
            if request.type is WireType.STRING:
                assert request.count is None
            else:
                assert request.count is not None
                assert request.count * width <= max_registers
            for key, index in request.points:
                target = by_key[key]
                assert target.station == post.station
                assert (target.address.area, target.type) == (
                    request.area,
                    request.type,
                )
                assert request.start + index * width == target.address.index
                if request.count is not None:
                    assert index < request.count
                read.add(key)
    assert read == set(by_key)
    assert plan.point_keys == frozenset(by_key)


@settings(max_examples=300, deadline=None, database=None)
@given(
    found=targets(),
    max_requests=st.integers(1, 4),
    max_registers=st.sampled_from([2, 4, 6, 10]),
    split_gaps=st.booleans(),
)
def test_every_plan_meets_the_bound_and_no_plan_beats_it(
    found: list[Target], max_requests: int, max_registers: int, split_gaps: bool
) -> None:
    plan = plan_reads(
        found,
        max_requests=max_requests,
        max_registers=max_registers,
        split_gaps=split_gaps,
    )
    _check_rules(plan, found, max_requests, max_registers)
    fewest = _fewest_posts(found, max_requests, max_registers)
    assert plan.lower_bound == fewest
    assert len(plan.posts) == plan.lower_bound
    if not split_gaps:
        assert plan.requests == plan.minimal_requests


@settings(max_examples=100, deadline=None, database=None)
@given(
    words=st.lists(st.integers(0, 5000), min_size=1, max_size=400, unique=True),
    bits=st.lists(st.integers(0, 3000), max_size=300, unique=True),
)
def test_large_maps_meet_the_bound_at_the_gateways_limits(
    words: list[int], bits: list[int]
) -> None:
    found = [
        Target(f"w{word}", 1, Address(Area.DT, word), WireType.INT) for word in words
    ] + [
        Target(f"b{bit}", 1, Address(Area.R, *divmod(bit, 16)), WireType.BOOL)
        for bit in bits
    ]
    plan = plan_reads(found)
    _check_rules(plan, found, 20, 100)
    assert len(plan.posts) == plan.lower_bound == math.ceil(plan.minimal_requests / 20)
    assert plan.minimal_requests <= plan.requests <= 20 * len(plan.posts)
