"""The Mervis read planner at its limits: a body of exactly the bytes allowed, one more.

Each test pins an edge an off-by-one would move (scripts/mutate found them unpinned).
"""

import itertools
import json
import math

from hypothesis import given, settings, strategies as st

from custom_components.tecoapi.pyplc.mervis.ids import Address, IdStyle
from custom_components.tecoapi.pyplc.mervis.planner import (
    DEFAULT_MAX_REQUEST_SIZE,
    DEFAULT_MAX_VARIABLES,
    ReadPlan,
    plan_reads,
    request_body,
)
from tests.pyplc.mervis.test_planner import point

CREDENTIALS = {"u": "admin", "p": "0123456789abcdef"}


def _uniform(count: int) -> list[str]:
    """IDs of one width each: 5-digit CommUids, four bytes from 0."""
    return [f"{10000 + index}[0,4]" for index in range(count)]


def _body(count: int, credentials: dict[str, str] = CREDENTIALS) -> int:
    """Bytes of a body with the first `count` uniform IDs, as sent."""
    ids = [IdStyle.RELEASED.value + address for address in _uniform(count)]
    return len(request_body(credentials, ids))


def _plan(
    count: int,
    max_bytes: int,
    max_variables: int = 64,
    credentials: dict[str, str] = CREDENTIALS,
) -> ReadPlan:
    points = [point(f"p{i}", address) for i, address in enumerate(_uniform(count))]
    return plan_reads(
        points,
        max_variables=max_variables,
        max_bytes=max_bytes,
        style=IdStyle.RELEASED,
        credentials=credentials,
    )


def test_a_body_of_exactly_the_bytes_allowed_is_one_request() -> None:
    exact = _body(10)
    plan = _plan(10, exact)
    assert [len(r.reads) for r in plan.requests] == [10]
    assert plan.requests[0].body_bytes == exact
    assert plan.lower_bound == 1


def test_a_body_one_byte_too_big_is_two_requests_and_so_is_the_bound() -> None:
    plan = _plan(10, _body(10) - 1)
    assert [len(r.reads) for r in plan.requests] == [9, 1]
    assert [r.body_bytes for r in plan.requests] == [_body(9), _body(1)]
    assert plan.lower_bound == 2


@given(st.integers(1, 40), st.integers(0, 400))
def test_the_lower_bound_is_the_formula_of_the_module(count: int, spare: int) -> None:
    """max(⌈IDs / max_variables⌉, ⌈(ID bytes + commas + 1) / (room + 1)⌉)."""
    max_bytes = _body(1) + spare
    plan = _plan(count, max_bytes, max_variables=7)
    empty = len(request_body(CREDENTIALS, []))
    id_bytes = sum(
        len(json.dumps(IdStyle.RELEASED.value + address)) for address in _uniform(count)
    )
    room = max_bytes - empty
    assert plan.lower_bound == max(
        math.ceil(count / 7), math.ceil((id_bytes + count) / (room + 1))
    )
    assert plan.lower_bound <= len(plan.requests)
    for request in plan.requests:
        assert request.body_bytes <= max_bytes
        assert len(request.reads) <= 7


def test_the_default_limits_are_64_ids_and_4096_bytes() -> None:
    wide = 10**6
    assert [len(r.reads) for r in _plan(64, wide, DEFAULT_MAX_VARIABLES).requests] == [
        64
    ]
    assert [len(r.reads) for r in _plan(65, wide, DEFAULT_MAX_VARIABLES).requests] == [
        64,
        1,
    ]
    # ten IDs and a password that makes the body exactly 4096 bytes, then one more
    pad = 4096 - _body(10, {"u": "admin", "p": ""})
    for password, sizes in (("x" * pad, [10]), ("x" * (pad + 1), [9, 1])):
        credentials = {"u": "admin", "p": password}
        plan = _plan(10, DEFAULT_MAX_REQUEST_SIZE, wide, credentials)
        assert [len(r.reads) for r in plan.requests] == sizes
    assert _body(10, {"u": "admin", "p": "x" * pad}) == 4096


def test_no_limit_of_ids_is_one_id_a_request() -> None:
    plan = _plan(3, 10**6, max_variables=0)
    assert [len(r.reads) for r in plan.requests] == [1, 1, 1]
    assert plan.max_variables == 1
    assert plan.lower_bound == 3


def test_a_body_keeps_its_letters_as_utf8() -> None:
    """The controller gets (and the size counts) a name's UTF-8, not JSON escapes."""
    body = request_body({"u": "Žofie", "p": "x"}, ["svc://DefaultConnection/1[0,1]"])
    assert (
        body
        == (
            '{"ver":1,"c":{"u":"Žofie","p":"x"},"v":["svc://DefaultConnection/1[0,1]"]}'
        ).encode()
    )


@given(st.permutations(["b", "a", "c", "d"]))
def test_a_range_s_members_are_in_address_order_then_by_key(order: list[str]) -> None:
    """The same points make the same plan, whatever order they come in."""
    addresses = {"a": "7[8,4]", "b": "7[8,4]", "c": "7[0,2]", "d": "7[12,4]"}
    plan = plan_reads(
        [point(key, addresses[key]) for key in order],
        max_variables=64,
        max_bytes=4096,
        style=IdStyle.SEED,
    )
    (request,) = plan.requests
    (read,) = request.reads
    assert read.address == Address(7, 0, 16)
    assert [key for key, _ in read.members] == ["c", "a", "b", "d"]


def _fewest_requests(costs: list[int], empty: int, max_bytes: int, limit: int) -> int:
    """The fewest requests of ANY grouping of the IDs (not only in order), by brute force.

    A request holds at most `limit` IDs, in a body of at most `max_bytes`, unless it
    is one ID alone (an ID no body holds is sent alone, over the limit).
    """

    def fits(group: list[int]) -> bool:
        body = empty + sum(costs[i] for i in group) + len(group) - 1
        return len(group) <= limit and (body <= max_bytes or len(group) == 1)

    def best(rest: list[int]) -> int:
        if not rest:
            return 0
        first, *others = rest
        fewest = len(rest)
        for size in range(len(others) + 1):
            for together in itertools.combinations(others, size):
                if fits([first, *together]):
                    left = [i for i in others if i not in together]
                    fewest = min(fewest, 1 + best(left))
        return fewest

    return best(list(range(len(costs))))


@settings(max_examples=150, deadline=None)
@given(
    st.lists(st.integers(1, 10**9), min_size=1, max_size=6, unique=True),
    st.integers(0, 120),
    st.integers(1, 4),
    st.sampled_from([None, CREDENTIALS]),
)
def test_the_lower_bound_holds_for_any_max_bytes_even_below_an_empty_body(
    commuids: list[int],
    max_bytes: int,
    max_variables: int,
    credentials: dict[str, str] | None,
) -> None:
    """A body limit below the empty body's size, or below one ID's, still has a bound
    no plan beats: an ID no body holds is a request of its own, and the bound counts it
    so (it counted its bytes, and promised more requests than the plan made)."""
    points = [point(f"p{commuid}", f"{commuid}[0,4]") for commuid in commuids]
    plan = plan_reads(
        points,
        max_variables=max_variables,
        max_bytes=max_bytes,
        style=IdStyle.RELEASED,
        credentials=credentials,
    )
    assert plan.lower_bound <= len(plan.requests)
    for request in plan.requests:
        assert len(request.reads) <= max_variables
        assert request.body_bytes <= max_bytes or len(request.reads) == 1
    empty = len(request_body(credentials, []))
    costs = [
        len(json.dumps(IdStyle.RELEASED.value + f"{commuid}[0,4]"))
        for commuid in sorted(commuids)
    ]
    fewest = _fewest_requests(costs, empty, max_bytes, max_variables)
    assert plan.lower_bound <= fewest <= len(plan.requests)
    if all(empty + cost > max_bytes for cost in costs):
        # no ID fits any body: one request each, and the bound says so
        assert len(plan.requests) == plan.lower_bound == len(commuids)


def test_an_id_no_body_holds_is_one_request_and_the_others_count_by_bytes() -> None:
    """A body holds the short ID exactly and the long one not at all: two requests,
    bound 2 (counting the long ID's bytes against the room said 3)."""
    empty = len(request_body(None, []))
    short_cost = len(json.dumps(IdStyle.RELEASED.value + "1[0,4]"))
    max_bytes = empty + short_cost
    points = [point("short", "1[0,4]"), point("long", f"{10**9}[0,4]")]
    plan = plan_reads(
        points, max_variables=64, max_bytes=max_bytes, style=IdStyle.RELEASED
    )
    assert [len(r.reads) for r in plan.requests] == [1, 1]
    assert [r.body_bytes for r in plan.requests] == [max_bytes, max_bytes + 9]
    assert plan.lower_bound == 2
