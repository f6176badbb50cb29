"""The read planner at its edges: a target of exactly 256 characters, a read of
exactly the item limit, a read of just over half of it, a ``.value`` read exactly
paid for by the characters left, and the weights of the lower bound exactly full.

TECOAPI.md: the whole GetObject target is at most 256 characters and a response
at most the CPU's item limit (a struct or array counts all its leaves, a
T_ApiObject 8). The planner's docstring defines the lower bound's weights.
"""

import math
from typing import Any

from hypothesis import given, settings, strategies as st
import pytest

from custom_components.tecoapi.pyplc import Point, ValueKind
from custom_components.tecoapi.pyplc.tecomat import ReadPlan, plan_reads
from custom_components.tecoapi.pyplc.tecomat.points import tecomat_point
from custom_components.tecoapi.pyplc.tecomat.tecoapi.catalogue import build_catalogue

# The weighing is private to the planner; its exactness is what is tested here.
from custom_components.tecoapi.pyplc.tecomat.tecoapi.planner import (
    NAME_BUDGET,
    _Pricing,
)
from tests.pyplc.tecomat.tecoapi.test_planner import api_object

PREFIX = "/TecoApi/GetObject?"


def _plan(tree: dict[str, Any], limit: int, *, with_attrs: bool = False) -> ReadPlan:
    catalogue = build_catalogue(list(tree), tree)
    return plan_reads(
        catalogue.points.values(),
        item_limit=limit,
        with_attrs=with_attrs,
        catalogue=catalogue,
    )


def _names(plan: ReadPlan) -> list[tuple[str, ...]]:
    return [request.names for request in plan.requests]


def _scalar(name: str) -> Point:
    return tecomat_point(name, ValueKind.BOOL)


# --- 256 characters -----------------------------------------------------------


def test_names_have_238_characters_with_their_separators() -> None:
    # /TecoApi/GetObject is 18 characters; each name brings its ? or &.
    assert NAME_BUDGET == 256 - len(PREFIX) + 1 == 238


def test_a_name_that_fills_the_target_to_256_is_read_and_one_longer_is_not() -> None:
    fits, too_long = "x" * (256 - len(PREFIX)), "y" * (257 - len(PREFIX))
    plan = plan_reads(
        [_scalar(fits), _scalar(too_long)], item_limit=1, with_attrs=False
    )
    assert [len(request.target) for request in plan.requests] == [256]
    assert plan.unreadable == {too_long}
    assert plan.lower_bound == 1


def test_two_names_share_a_request_when_the_target_is_exactly_256() -> None:
    # 19 + 118 + 1 + 118 = 256: one request; one character more makes two.
    plan = plan_reads(
        [_scalar("a" * 118), _scalar("b" * 118)], item_limit=128, with_attrs=False
    )
    assert _names(plan) == [("a" * 118, "b" * 118)]
    assert len(plan.requests[0].target) == 256
    assert plan.lower_bound == 1
    plan = plan_reads(
        [_scalar("a" * 119), _scalar("b" * 118)], item_limit=128, with_attrs=False
    )
    assert sorted(_names(plan)) == [("a" * 119,), ("b" * 118,)]
    assert plan.lower_bound == 2


# --- the item limit -------------------------------------------------------------


@pytest.mark.parametrize("limit", [1, 2, 7])
def test_every_read_of_one_item_each_takes_a_request_at_limit_one(limit: int) -> None:
    points = [_scalar(f"v{index}") for index in range(limit + 1)]
    plan = plan_reads(points, item_limit=limit, with_attrs=False)
    assert len(plan.requests) == plan.lower_bound == 2
    assert sorted(request.items for request in plan.requests) == [1, limit]


def test_a_struct_of_exactly_the_limit_is_read_whole_one_more_through_members() -> None:
    plan = _plan({"s": {f"m{index}": index for index in range(16)}}, 16)
    assert _names(plan) == [("s",)]
    assert plan.requests[0].items == 16
    plan = _plan({"s": {f"m{index}": index for index in range(17)}}, 16)
    names = [name for names in _names(plan) for name in names]
    assert "s" not in names
    assert sorted(names) == sorted(f"s.m{index}" for index in range(17))
    assert len(plan.requests) == plan.lower_bound == 2


def test_an_array_of_exactly_the_limit_is_read_whole_one_more_by_elements() -> None:
    plan = _plan({"a": list(range(16))}, 16)
    assert _names(plan) == [("a",)]
    assert plan.unreadable == frozenset()
    plan = _plan({"a": list(range(17))}, 16)
    names = sorted(name for names in _names(plan) for name in names)
    assert names == sorted(f"a[{index}]" for index in range(17))
    assert len(plan.requests) == plan.lower_bound == 2


def test_an_element_of_an_array_inside_a_too_large_array_is_read_through_it() -> None:
    # The outer array is too large, so its elements are read by index; each
    # element is an array of its own that fits, read whole, never by its index.
    plan = _plan({"a": [[1, 2], [3, 4], [5, 6]]}, 4)
    names = sorted(name for names in _names(plan) for name in names)
    assert names == ["a[0]", "a[1]", "a[2]"]
    assert plan.unreadable == frozenset()


# --- large reads: more than half the limit, one per request --------------------


@pytest.mark.parametrize(("members", "requests"), [(64, 3), (65, 5)])
def test_reads_of_more_than_half_the_limit_take_a_request_each(
    members: int, requests: int
) -> None:
    # Five arrays (read whole only): 64 items pair up, 65 items never do.
    plan = _plan({f"a{index}": list(range(members)) for index in range(5)}, 128)
    assert plan.lower_bound == requests
    assert len(plan.requests) == requests


def test_a_large_read_leaves_its_request_only_what_its_items_allow() -> None:
    # Four arrays of 100 items and eight scalars of 100 characters: an array
    # leaves 28 items and 234 characters, room for two scalars; nothing else packs.
    tree: dict[str, Any] = {f"a{index}": list(range(100)) for index in range(4)}
    tree |= {f"{'s' * 98}{index}": index for index in range(8)}
    plan = _plan(tree, 128)
    assert plan.lower_bound == len(plan.requests) == 4


# --- .value reads -----------------------------------------------------------


def test_a_value_read_is_made_when_exactly_its_six_characters_are_left() -> None:
    # "o" whole takes 2 characters and 8 items; "o.value" 8 characters, 1 item.
    filler = "f" * (NAME_BUDGET - 2 - 6 - 1)
    plan = _plan({filler: 1, "o": api_object()}, 128)
    assert _names(plan) == [(filler, "o.value")]
    assert plan.requests[0].items == 2
    assert len(plan.requests[0].target) == 256
    # One character less left: the object is read whole, its attributes with it.
    filler += "f"
    plan = _plan({filler: 1, "o": api_object()}, 128)
    assert _names(plan) == [(filler, "o")]
    assert plan.requests[0].items == 9


def test_a_value_read_that_fills_the_target_to_256_is_made() -> None:
    # A 230-character object: its .value read makes a target of exactly 256.
    name = "o" * (256 - len(PREFIX) - len(".value"))
    plan = _plan({name: api_object()}, 128)
    assert _names(plan) == [(name + ".value",)]
    assert len(plan.requests[0].target) == 256
    assert plan.requests[0].items == 1
    # One character longer: only the object whole fits, attributes and all.
    plan = _plan({name + "o": api_object()}, 128)
    assert _names(plan) == [(name + "o",)]
    assert plan.requests[0].items == 8


def test_objects_turn_to_value_reads_only_as_far_as_the_items_need() -> None:
    # Three objects in 17 items: two read whole (16), the third must turn.
    tree = {f"o{index}": api_object() for index in range(3)}
    plan = _plan(tree, 17)
    assert len(plan.requests) == plan.lower_bound == 1
    assert plan.requests[0].items <= 17
    # Without attributes every object turns while characters allow.
    assert plan.requests[0].names == ("o0.value", "o1.value", "o2.value")
    plan = _plan(tree, 17, with_attrs=True)
    assert len(plan.requests) == plan.lower_bound == 2


# --- the lower bound's weights are tight ---------------------------------------


@settings(max_examples=300, deadline=None, database=None)
@given(
    limit=st.integers(2, 300),
    share=st.integers(0, 8).map(lambda step: step / 8),
    data=st.data(),
)
def test_a_request_full_in_both_limits_weighs_exactly_one(
    limit: int, share: float, data: st.DataObject
) -> None:
    # Plain weights: B characters and L items in any split weigh exactly 1.
    cut_chars = data.draw(st.integers(1, NAME_BUDGET - 1))
    cut_items = data.draw(st.integers(0, limit))
    pricing = _Pricing(share)
    weight = pricing.weight(cut_chars, cut_items, limit) + pricing.weight(
        NAME_BUDGET - cut_chars, limit - cut_items, limit
    )
    assert weight == pytest.approx(1.0)


@settings(max_examples=300, deadline=None, database=None)
@given(
    limit=st.integers(4, 300),
    share=st.integers(0, 8).map(lambda step: step / 8),
    density=st.floats(0.05, 120.0),
    data=st.data(),
)
def test_a_large_read_and_capped_reads_filling_what_it_leaves_weigh_one(
    limit: int, share: float, density: float, data: st.DataObject
) -> None:
    items = data.draw(st.integers(limit // 2 + 1, limit - 1))
    chars = data.draw(st.integers(2, NAME_BUDGET - 2))
    left = limit - items
    room = min(NAME_BUDGET - chars, density * left)
    large = _Pricing(share, density, capped=True)
    weight = large.weight(chars, items, limit)
    plain = share * chars / NAME_BUDGET + (1 - share) * items / limit
    # The others: their items exactly what is left, their characters the room.
    filled = large.weight(math.ceil(room) + 1, left, limit)
    if weight > plain + 1e-9 and room == density * left:
        # Capped at density x items, the reads beside it weigh exactly the rest.
        assert weight + filled == pytest.approx(1.0)
    assert weight >= plain - 1e-12
    # Offset weights leave every read that is not large at its plain weight.
    offset = _Pricing(share, density)
    assert (
        offset.weight(chars, left, limit)
        == pytest.approx(_Pricing(share).weight(chars, left, limit))
        or 2 * left > limit
    )
    assert offset.excess(chars, left, limit) == pytest.approx(
        max(0.0, chars - density * left)
    )
    assert offset.excess(chars, items, limit) == 0.0
    assert large.excess(chars, left, limit) == 0.0


@settings(max_examples=80, deadline=None, database=None)
@given(
    limit=st.integers(1, 130),
    reads=st.lists(
        st.tuples(st.integers(1, 130), st.integers(1, 200)), min_size=1, max_size=12
    ),
)
def test_the_bound_of_fixed_reads_is_at_least_each_volume_bound(
    limit: int, reads: list[tuple[int, int]]
) -> None:
    # Arrays that fit are read whole only: the cover is fixed, and the bound must
    # see its characters, its items and its large reads (one per request).
    tree = {
        f"{'n' * min(length, 230)}{index}": list(range(min(size, limit)))
        for index, (size, length) in enumerate(reads)
    }
    chars = sum(len(name) + 1 for name in tree)
    items = sum(len(elements) for elements in tree.values())
    large = sum(2 * len(elements) > limit for elements in tree.values())
    plan = _plan(tree, limit)
    assert plan.lower_bound >= max(
        math.ceil(chars / NAME_BUDGET), math.ceil(items / limit), large
    )
    # (Not always within one request of it: 46-item arrays never join 62-item
    # ones at limit 107, which the bound's single density cannot see.)
    assert plan.lower_bound <= len(plan.requests)


# --- what is polled --------------------------------------------------------------


def test_only_the_roots_holding_polled_points_are_read() -> None:
    tree = {"a": {"x": 1, "y": 2}, "b": 3, "c": [4, 5]}
    catalogue = build_catalogue(list(tree), tree)
    wanted = [catalogue.points["a.y"], catalogue.points["b"]]
    plan = plan_reads(wanted, item_limit=128, with_attrs=False, catalogue=catalogue)
    assert _names(plan) == [("a", "b")]
    assert plan.requests[0].items == 3
    assert plan.requests[0].point_keys == {"a.y", "b"}
    assert plan.point_keys == {"a.y", "b"}


def test_a_polled_point_missing_from_the_catalogue_is_still_read() -> None:
    tree = {"a": 1}
    catalogue = build_catalogue(list(tree), tree)
    plan = plan_reads(
        [_scalar("late")], item_limit=128, with_attrs=False, catalogue=catalogue
    )
    assert _names(plan) == [("late",)]
    assert plan.unreadable == frozenset()


# --- T_ApiObjects against small limits ----------------------------------------


@pytest.mark.parametrize(
    ("limit", "without", "with_"),
    [
        (7, [("o.value", "p.value")], []),
        (8, [("o.value", "p.value")], [("o",), ("p",)]),
        (16, [("o.value", "p.value")], [("o", "p")]),
    ],
)
def test_an_object_is_read_whole_only_from_a_limit_of_its_eight_items(
    limit: int, without: list[tuple[str, ...]], with_: list[tuple[str, ...]]
) -> None:
    tree = {"o": api_object(), "p": api_object()}
    plan = _plan(tree, limit)
    assert _names(plan) == without
    assert plan.unreadable == frozenset()
    plan = _plan(tree, limit, with_attrs=True)
    assert _names(plan) == with_
    assert plan.unreadable == (frozenset() if with_ else {"o", "p"})
    assert plan.lower_bound == len(with_)


def test_a_point_with_members_of_its_own_is_read_whole_when_it_fits() -> None:
    # No catalogue makes one, but plan_reads takes any points: "a" read whole
    # answers both; where "a" cannot be read, its member is read alone.
    points = [_scalar("a"), _scalar("a.b")]
    plan = plan_reads(points, item_limit=2, with_attrs=False)
    assert _names(plan) == [("a",)]
    assert plan.requests[0].point_keys == {"a", "a.b"}
    plan = plan_reads(points, item_limit=1, with_attrs=False)
    assert _names(plan) == [("a.b",)]
    assert plan.unreadable == {"a"}
