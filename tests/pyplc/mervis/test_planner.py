"""The read planner: one range per CommUid, requests packed under both limits."""

import math

from hypothesis import given, settings, strategies as st
import pytest

from custom_components.tecoapi.pyplc.core.models import DataType, Point, ValueKind
from custom_components.tecoapi.pyplc.mervis.ids import Address, IdStyle
from custom_components.tecoapi.pyplc.mervis.planner import (
    plan_reads,
    ranges,
    request_body,
)

REAL = DataType(kind=ValueKind.REAL, bits=32)


def point(key: str, address: str) -> Point:
    return Point(key=key, path=key, address=address, type=REAL)


def test_members_of_a_variable_are_one_range_sliced_locally() -> None:
    plan = plan_reads(
        [
            point("fb.b", "7001[8,4]"),
            point("fb.a", "7001[4,4]"),
            point("fb.c", "7001[20,4]"),
            point("other", "7002[0,4]"),
        ],
        max_variables=64,
        max_bytes=4096,
        style=IdStyle.RELEASED,
    )
    (request,) = plan.requests
    block, other = request.reads
    assert block.address == Address(7001, 4, 20)
    assert [key for key, _ in block.members] == ["fb.a", "fb.b", "fb.c"]
    raw = bytes(range(20))
    assert block.slice(raw, Address(7001, 8, 4)) == bytes([4, 5, 6, 7])
    assert other.address == Address(7002, 0, 4)
    assert plan.ids == 2
    assert plan.lower_bound == 1


def test_breaks_begin_ranges_and_a_lone_member_is_read_apart() -> None:
    """What a search learned: its cuts begin ranges, a refused point stands alone.

    A lone member does not cut its neighbours: their range spans its bytes.
    """
    points = [
        point("fb.a", "7001[0,4]"),
        point("fb.b", "7001[4,4]"),
        point("fb.x", "7001[8,40]"),
        point("fb.c", "7001[12,4]"),
        point("fb.d", "7001[16,4]"),
        point("fb.e", "7001[20,4]"),
        point("x", "7002[0,4]"),
    ]
    reads, unreadable = ranges(points, breaks={"fb.d", "x"}, alone={"fb.x"})
    assert [
        (str(read.address), [key for key, _ in read.members]) for read in reads
    ] == [
        ("7001[0,16]", ["fb.a", "fb.b", "fb.c"]),
        ("7001[8,40]", ["fb.x"]),
        ("7001[16,8]", ["fb.d", "fb.e"]),
        ("7002[0,4]", ["x"]),
    ]
    assert unreadable == frozenset()


def test_variables_of_another_connection_are_their_own() -> None:
    """The same CommUid through another connection is another variable."""
    points = [
        point("local", "7001[0,4]"),
        point("remote.a", "svc:Other/7001[0,4]"),
        point("remote.b", "svc://other/7001[4,4]"),
    ]
    reads, _ = ranges(points)
    assert [read.address.variable_id(IdStyle.SEED) for read in reads] == [
        "svc:defaultConnection/7001[0,4]",
        "svc:Other/7001[0,8]",
    ]


def test_requests_hold_at_most_the_variables_allowed() -> None:
    points = [point(f"p{index}", f"{index}[0,4]") for index in range(11)]
    plan = plan_reads(points, max_variables=5, max_bytes=10**6, style=IdStyle.SEED)
    assert [len(request.reads) for request in plan.requests] == [5, 5, 1]
    assert plan.lower_bound == 3


def test_a_body_is_measured_as_it_is_sent_credentials_included() -> None:
    points = [point(f"p{index}", f"{1000 + index}[0,4]") for index in range(40)]
    credentials = {"u": "admin", "p": "0123456789abcdef0123456789abcdef"}
    plan = plan_reads(
        points,
        max_variables=64,
        max_bytes=600,
        style=IdStyle.RELEASED,
        credentials=credentials,
    )
    for request in plan.requests:
        ids = [read.address.variable_id(IdStyle.RELEASED) for read in request.reads]
        body = request_body(credentials, ids)
        assert len(body) == request.body_bytes <= 600
    assert len(plan.requests) == plan.lower_bound


def test_points_without_an_address_are_not_read() -> None:
    plan = plan_reads(
        [point("a", "1[0,4]"), point("b", "nowhere")],
        max_variables=5,
        max_bytes=1500,
        style=IdStyle.RELEASED,
    )
    assert plan.unreadable == frozenset({"b"})
    assert plan.point_keys == frozenset({"a", "b"})
    assert plan.ids == 1


def test_nothing_to_read_is_no_request() -> None:
    plan = plan_reads([], max_variables=5, max_bytes=1500, style=IdStyle.RELEASED)
    assert (plan.requests, plan.lower_bound) == ((), 0)


@settings(max_examples=80, deadline=None)
@given(
    st.lists(
        st.tuples(
            st.integers(1, 60000), st.integers(0, 64), st.sampled_from([1, 4, 8])
        ),
        min_size=1,
        max_size=300,
    ),
    st.integers(1, 80),
    st.integers(120, 5000),
)
def test_every_point_is_read_once_within_both_limits(
    addresses: list[tuple[int, int, int]], max_variables: int, max_bytes: int
) -> None:
    points = [
        point(f"p{index}", f"{commuid}[{offset},{length}]")
        for index, (commuid, offset, length) in enumerate(addresses)
    ]
    plan = plan_reads(
        points, max_variables=max_variables, max_bytes=max_bytes, style=IdStyle.RELEASED
    )
    seen = [
        key
        for request in plan.requests
        for read in request.reads
        for key, _ in read.members
    ]
    assert sorted(seen) == sorted(item.key for item in points)
    variables = {commuid for commuid, _, _ in addresses}
    assert plan.ids == len(variables)
    for request in plan.requests:
        assert len(request.reads) <= max_variables
        assert request.body_bytes <= max_bytes or len(request.reads) == 1
        for read in request.reads:
            for _, member in read.members:
                assert read.address.offset <= member.offset
                assert member.end <= read.address.end
    assert plan.lower_bound <= len(plan.requests)
    assert len(plan.requests) >= math.ceil(len(variables) / max_variables)


@pytest.mark.parametrize("count", [50, 300, 1000])
def test_uniform_ids_are_packed_at_the_lower_bound(count: int) -> None:
    points = [point(f"p{index}", f"{10000 + index}[0,4]") for index in range(count)]
    plan = plan_reads(points, max_variables=64, max_bytes=1500, style=IdStyle.RELEASED)
    assert len(plan.requests) == plan.lower_bound
