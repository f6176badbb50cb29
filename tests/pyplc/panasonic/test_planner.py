"""The read planner's plans, case by case (its bound: test_planner_bound.py)."""

import pytest

from custom_components.tecoapi.pyplc.panasonic.address import (
    Address,
    Area,
    WireType,
    bit_start,
    parse_address,
)
from custom_components.tecoapi.pyplc.panasonic.planner import (
    MAX_REGISTERS,
    REQUEST_BYTES,
    VALUE_BYTES,
    Target,
    covering,
    plan_reads,
)


def target(key: str, address: str, wire: WireType, station: int | None = 1) -> Target:
    return Target(key, station, parse_address(address), wire)


def bodies(targets: list[Target], **options: int) -> list[list[dict[str, object]]]:
    plan = plan_reads(targets, **options)
    return [[request.body() for request in post.requests] for post in plan.posts]


def test_contiguous_registers_of_a_type_are_one_request() -> None:
    found = [target(f"t{n}", f"DT{n}", WireType.INT) for n in (0, 1, 2, 5)]
    assert bodies(found) == [
        [{"area": "DT", "type": "INT", "start": 0, "count": 6}],
    ]


def test_station_area_and_type_each_need_their_requests() -> None:
    found = [
        target("a", "DT0", WireType.INT),
        target("b", "DT1", WireType.UINT),
        target("c", "LD1", WireType.INT),
        target("d", "DT2", WireType.INT, station=2),
        target("e", "DT3", WireType.INT, station=None),
    ]
    plan = plan_reads(found)
    assert [post.station for post in plan.posts] == [None, 1, 2]
    assert [len(post.requests) for post in plan.posts] == [1, 3, 1]
    assert plan.lower_bound == 3


def test_bits_are_bool_ranges_started_by_their_address() -> None:
    found = [
        target("yf", "YF", WireType.BOOL),
        target("y18", "Y18", WireType.BOOL),
        target("r1a", "R1A", WireType.BOOL),
    ]
    plan = plan_reads(found)
    (post,) = plan.posts
    assert [request.body() for request in post.requests] == [
        {"area": "R", "type": "BOOL", "start": "1A", "count": 1},
        {"area": "Y", "type": "BOOL", "start": "F", "count": 10},
    ]
    # YF is the first value, Y18 the tenth (YF, Y10 ... Y18).
    assert dict(post.requests[1].points) == {"yf": 0, "y18": 9}
    assert post.requests[1].name == "YF"


def test_a_request_reads_at_most_100_registers() -> None:
    found = [target(f"t{n}", f"DT{n}", WireType.INT) for n in range(250)]
    plan = plan_reads(found)
    assert [request.count for request in plan.posts[0].requests] == [100, 100, 50]
    assert plan.lower_bound == 1
    assert MAX_REGISTERS == 100


def test_a_double_word_takes_two_registers_and_its_parity() -> None:
    found = [target(f"e{n}", f"DT{2 * n}", WireType.DINT) for n in range(60)]
    found.append(target("odd", "DT1", WireType.DINT))
    plan = plan_reads(found)
    requests = plan.posts[0].requests
    # 50 double words a request (100 registers); DT1 is at no even offset from
    # DT0: a request of its own.
    assert [(request.start, request.count) for request in requests] == [
        (0, 50),
        (1, 1),
        (100, 10),
    ]
    assert dict(requests[0].points)["e3"] == 3


def test_strings_are_read_one_by_one() -> None:
    found = [
        target("s1", "DT300", WireType.STRING),
        target("s2", "DT301", WireType.STRING),
        target("same", "DT300", WireType.STRING),
    ]
    plan = plan_reads(found)
    assert [request.body() for request in plan.posts[0].requests] == [
        {"area": "DT", "type": "STRING", "start": 300},
        {"area": "DT", "type": "STRING", "start": 301},
    ]
    assert dict(plan.posts[0].requests[0].points) == {"s1": 0, "same": 0}
    # a string request reads its one string: no value of it is unused
    assert [request.unused for request in plan.posts[0].requests] == [0, 0]
    assert plan.unused_values == 0


def test_a_post_carries_20_requests_of_one_station() -> None:
    found = [target(f"s{n}", f"DT{n}", WireType.STRING) for n in range(45)]
    plan = plan_reads(found)
    assert [len(post.requests) for post in plan.posts] == [20, 20, 5]
    assert plan.lower_bound == 3


def test_large_gaps_are_split_in_the_posts_spare_slots_small_ones_bridged() -> None:
    # A gap of 40 INTs costs more than a request; one of 3 does not.
    assert (
        40 * VALUE_BYTES[WireType.INT] > REQUEST_BYTES > 3 * VALUE_BYTES[WireType.INT]
    )
    found = [target(f"t{n}", f"DT{n}", WireType.INT) for n in (0, 1, 5, 45, 46, 90, 99)]
    split = plan_reads(found)
    assert [(r.start, r.count) for r in split.posts[0].requests] == [
        (0, 6),
        (45, 2),
        (90, 10),
    ]
    assert split.requests == 3
    assert split.minimal_requests == 1
    assert split.unused_values == 3 + 8
    bridged = plan_reads(found, split_gaps=False)
    assert [(r.start, r.count) for r in bridged.posts[0].requests] == [(0, 100)]
    assert bridged.unused_values == 100 - 7


def test_splitting_never_costs_a_post() -> None:
    # 20 windows fill a POST: no spare slot, every gap stays bridged.
    found = [
        target(f"t{n}-{m}", f"DT{n * 1000 + m}", WireType.INT)
        for n in range(20)
        for m in (0, 60)
    ]
    plan = plan_reads(found)
    assert len(plan.posts) == 1
    assert plan.requests == 20
    assert all(request.count == 61 for request in plan.posts[0].requests)
    # One window fewer leaves a slot: the costliest gap is split.
    plan = plan_reads(found[2:])
    assert plan.requests == 20
    assert sorted(request.count for request in plan.posts[0].requests)[:2] == [1, 1]


def test_a_plan_names_its_points_and_is_stable() -> None:
    found = [target("b", "DT5", WireType.INT), target("a", "R0", WireType.BOOL)]
    assert plan_reads(found) == plan_reads(list(reversed(found)))
    assert plan_reads(found).point_keys == {"a", "b"}
    assert plan_reads([]).posts == ()
    assert Address(Area.DT, 1).start == 1


# The fewest unused values between two points that a spare slot splits, by type: their
# bytes must exceed a request's 150 (BOOL 2 bytes a value, INT 7, UINT 6, DINT 12,
# UDINT 11, REAL 14). One fewer stays bridged.
SPLIT_FROM = {
    WireType.BOOL: 76,  # 76 · 2 = 152; 75 · 2 = 150 is no saving
    WireType.INT: 22,  # 154; 21 · 7 = 147
    WireType.UINT: 26,  # 156; 25 · 6 = 150
    WireType.DINT: 13,  # 156; 12 · 12 = 144
    WireType.UDINT: 14,  # 154; 13 · 11 = 143
    WireType.REAL: 11,  # 154; 10 · 14 = 140
}


def _pair(wire: WireType, unused: int) -> list[Target]:
    """Two points of a type with `unused` values between them."""
    if wire is WireType.BOOL:
        return [target("a", "R0", wire), target("b", f"R{bit_start(unused + 1)}", wire)]
    step = 2 if wire.registers == 2 else 1
    return [target("a", "DT0", wire), target("b", f"DT{step * (unused + 1)}", wire)]


def test_a_gap_is_split_from_the_values_whose_bytes_exceed_a_request() -> None:
    for wire, first in SPLIT_FROM.items():
        for unused, requests in ((first - 1, 1), (first, 2)):
            plan = plan_reads(_pair(wire, unused))
            assert (wire, unused, plan.requests) == (wire, unused, requests)
            assert plan.unused_values == (unused if requests == 1 else 0)
            assert (plan.minimal_requests, plan.lower_bound) == (1, 1)


def test_covering_takes_the_points_of_exactly_one_chain() -> None:
    """A double word's parity is a chain of its own: DT10 and DT11 as DINTs are two."""
    one = covering(
        [target("b", "DT14", WireType.DINT), target("a", "DT10", WireType.DINT)]
    )
    assert (one.start, one.count, one.points) == (10, 3, (("a", 0), ("b", 2)))
    for several in (
        [target("a", "DT10", WireType.DINT), target("b", "DT11", WireType.DINT)],
        [target("a", "DT10", WireType.INT), target("b", "DT10", WireType.UINT)],
        [target("a", "DT10", WireType.INT), target("b", "LD10", WireType.INT)],
        [target(f"k{n}", f"DT{n}", WireType.DINT) for n in range(3)],
        [],
    ):
        with pytest.raises(ValueError, match="one chain"):
            covering(several)


def test_the_one_spare_slot_splits_the_costliest_gap_not_a_later_one() -> None:
    """Two windows, three requests a POST: one spare slot. The first window's gap of
    60 INTs saves 270 bytes, the second's (at its third point) of 30 saves 60: the
    first is split, whatever the windows' order or the gaps' places."""
    found = [
        target("a0", "DT0", WireType.INT),
        target("a61", "DT61", WireType.INT),
        *(target(f"b{n}", f"DT{n}", WireType.INT) for n in (1000, 1001, 1002, 1033)),
    ]
    plan = plan_reads(found, max_requests=3)
    assert [(r.start, r.count) for r in plan.posts[0].requests] == [
        (0, 1),
        (61, 1),
        (1000, 34),
    ]
    assert (plan.minimal_requests, plan.lower_bound, plan.unused_values) == (2, 1, 30)


def test_of_two_gaps_saving_the_same_the_first_window_s_is_split() -> None:
    """Gaps of 40 INTs in two windows save the same: the spare slot goes to the first
    window's (at its third point), not to the one at the lower position."""
    found = [
        *(target(f"a{n}", f"DT{n}", WireType.INT) for n in (0, 1, 2, 43)),
        target("b0", "DT1000", WireType.INT),
        target("b41", "DT1041", WireType.INT),
    ]
    plan = plan_reads(found, max_requests=3)
    assert [(r.start, r.count) for r in plan.posts[0].requests] == [
        (0, 3),
        (43, 1),
        (1000, 42),
    ]


def test_the_gateway_s_own_station_comes_before_station_0() -> None:
    """Stations are numbered from 0; the gateway's own (None) is planned first."""
    found = [
        target("zero", "DT1", WireType.INT, station=0),
        target("own", "DT2", WireType.INT, station=None),
    ]
    assert [post.station for post in plan_reads(found).posts] == [None, 0]
