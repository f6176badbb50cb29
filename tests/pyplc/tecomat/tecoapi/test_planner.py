"""The read planner: limits always kept, near its lower bound, checked by the PLC."""

from collections.abc import Callable, Iterator, Sequence
from functools import partial
import itertools
from typing import Any

import aiohttp
from hypothesis import HealthCheck, given, settings, strategies as st
import pytest

from custom_components.tecoapi.pyplc import Catalogue, Point, ValueKind
from custom_components.tecoapi.pyplc.tecomat import ReadPlan, plan_reads
from custom_components.tecoapi.pyplc.tecomat.points import tecomat_point, value_path
from custom_components.tecoapi.pyplc.tecomat.tecoapi.catalogue import build_catalogue
from custom_components.tecoapi.pyplc.tecomat.tecoapi.info import item_limit_for_type
from custom_components.tecoapi.pyplc.tecomat.tecoapi.paths import encode_name
from custom_components.tecoapi.pyplc.tecomat.tecoapi.planner import NAME_BUDGET
from tests.pyplc.conftest import StartSimulator, make_client
from tests.simulator import Program, generate_program, load_program
from tests.simulator.iec import leaf_count

ATTR = {
    "enable": True,
    "visibility": True,
    "readOnly": True,
    "title": "t",
    "minValue": 0.0,
    "maxValue": 0.0,
    "units": "",
}


def api_object(value: Any = 1.0) -> dict[str, Any]:
    """A T_ApiObject of the value, with attributes."""
    return {"value": value, "attr": dict(ATTR)}


def _catalogue_of(program: Program) -> Catalogue:
    """The catalogue discovery would build: every root read whole."""
    tree = {
        declaration.name: declaration.initial for declaration in program.declarations
    }
    return build_catalogue(list(tree), tree)


def _check_limits(plan: ReadPlan, points: Sequence[Point], limit: int) -> None:
    """Every request within both limits; every point read by exactly one request."""
    seen: list[str] = []
    for request in plan.requests:
        assert len(request.target) <= 256
        assert request.target.startswith("/TecoApi/GetObject?")
        assert 0 < request.items <= limit
        assert len(request.names) <= limit
        seen.extend(request.point_keys)
    assert sorted(seen) == sorted(
        point.key for point in points if point.key not in plan.unreadable
    )


PROGRAMS: dict[str, Callable[[], Program]] = {
    "manual": partial(load_program, "manual"),
    "demo": partial(load_program, "demo"),
    **{
        f"generated-{points}-{plc_type}-seed{seed}": partial(
            generate_program, points, seed=seed, plc_type=plc_type
        )
        for plc_type in ("CP-2080", "CP-1000")
        for points in (50, 300, 1000)
        for seed in range(5)
    },
}


# Per program, without and with attributes: (lower bound, requests, items) as
# measured when the planner was last tuned. The bound is a computed quantity and
# must stay exactly as it is; a plan may only get better (fewer requests, then
# fewer items): a change that loses a request or polls more on any of these fails.
MEASURED: dict[str, list[tuple[int, int, int]]] = {
    "manual": [(1, 1, 84), (1, 1, 105)],
    "demo": [(6, 6, 521), (6, 6, 521)],
    "generated-50-CP-2080-seed0": [(3, 3, 398), (3, 3, 405)],
    "generated-50-CP-2080-seed1": [(3, 3, 391), (3, 3, 405)],
    "generated-50-CP-2080-seed2": [(3, 3, 398), (3, 3, 405)],
    "generated-50-CP-2080-seed3": [(3, 3, 405), (3, 3, 405)],
    "generated-50-CP-2080-seed4": [(3, 3, 398), (3, 3, 405)],
    "generated-300-CP-2080-seed0": [(10, 10, 2363), (10, 10, 2405)],
    "generated-300-CP-2080-seed1": [(10, 10, 2286), (11, 11, 2405)],
    "generated-300-CP-2080-seed2": [(10, 10, 2307), (11, 11, 2405)],
    "generated-300-CP-2080-seed3": [(10, 10, 2300), (10, 10, 2405)],
    "generated-300-CP-2080-seed4": [(10, 10, 2328), (10, 10, 2405)],
    "generated-1000-CP-2080-seed0": [(32, 33, 7753), (35, 35, 8005)],
    "generated-1000-CP-2080-seed1": [(31, 32, 7865), (32, 32, 8005)],
    "generated-1000-CP-2080-seed2": [(31, 32, 7781), (34, 34, 8005)],
    "generated-1000-CP-2080-seed3": [(32, 33, 7795), (34, 34, 8005)],
    "generated-1000-CP-2080-seed4": [(32, 32, 7753), (34, 34, 8005)],
    "generated-50-CP-1000-seed0": [(3, 3, 349), (4, 4, 405)],
    "generated-50-CP-1000-seed1": [(3, 3, 335), (4, 4, 405)],
    "generated-50-CP-1000-seed2": [(3, 3, 349), (4, 4, 405)],
    "generated-50-CP-1000-seed3": [(3, 3, 363), (4, 4, 405)],
    "generated-50-CP-1000-seed4": [(3, 3, 335), (4, 4, 405)],
    "generated-300-CP-1000-seed0": [(14, 14, 1775), (19, 19, 2405)],
    "generated-300-CP-1000-seed1": [(14, 14, 1775), (19, 19, 2405)],
    "generated-300-CP-1000-seed2": [(14, 14, 1768), (19, 19, 2405)],
    "generated-300-CP-1000-seed3": [(13, 14, 1656), (19, 19, 2405)],
    "generated-300-CP-1000-seed4": [(14, 14, 1754), (19, 19, 2405)],
    "generated-1000-CP-1000-seed0": [(44, 45, 5625), (63, 63, 8005)],
    "generated-1000-CP-1000-seed1": [(43, 44, 5499), (63, 63, 8005)],
    "generated-1000-CP-1000-seed2": [(43, 44, 5499), (63, 63, 8005)],
    "generated-1000-CP-1000-seed3": [(45, 46, 5744), (63, 63, 8005)],
    "generated-1000-CP-1000-seed4": [(43, 44, 5604), (63, 63, 8005)],
}


@pytest.mark.parametrize("with_attrs", [False, True])
@pytest.mark.parametrize("name", list(PROGRAMS))
def test_plans_stay_within_one_request_of_the_lower_bound(
    name: str, with_attrs: bool
) -> None:
    program = PROGRAMS[name]()
    catalogue = _catalogue_of(program)
    limit = item_limit_for_type(program.plc.type)
    points = list(catalogue.points.values())
    plan = plan_reads(
        points, item_limit=limit, with_attrs=with_attrs, catalogue=catalogue
    )
    _check_limits(plan, points, limit)
    assert plan.unreadable == frozenset()
    assert plan.lower_bound >= 1
    assert plan.lower_bound <= len(plan.requests) <= plan.lower_bound + 1
    # Never an array element by index: these arrays all fit in one response.
    assert not any("[" in name for request in plan.requests for name in request.names)
    assert plan.with_attrs is with_attrs
    assert plan.item_limit == limit
    assert plan.point_keys == frozenset(catalogue.points)
    bound, requests, items = MEASURED[name][with_attrs]
    assert plan.lower_bound == bound
    assert len(plan.requests) <= requests
    if len(plan.requests) == requests:
        assert sum(request.items for request in plan.requests) <= items


def test_the_lower_bound_counts_characters_and_items() -> None:
    # 40 scalars with 30-character names: 31 characters each, 7 fit in 238.
    chars_bound = [
        tecomat_point(f"{'v' * 27}{index:03d}", ValueKind.BOOL) for index in range(40)
    ]
    plan = plan_reads(chars_bound, item_limit=256, with_attrs=False)
    assert plan.lower_bound == 6  # ceil(40 * 31 / 238)
    assert len(plan.requests) == 6
    # 10 structs of 60 items each with short names: items bind, two per request.
    tree = {
        f"s{index}": {f"m{member}": member for member in range(60)}
        for index in range(10)
    }
    catalogue = build_catalogue(list(tree), tree)
    plan = plan_reads(
        catalogue.points.values(), item_limit=128, with_attrs=False, catalogue=catalogue
    )
    assert plan.lower_bound == 5  # ceil(600 / 128)
    assert len(plan.requests) == 5
    assert all(len(request.names) == 2 for request in plan.requests)


def test_values_only_unless_whole_objects_cost_nothing_more() -> None:
    tree = {"Main": {f"obj{index}": api_object() for index in range(3)}}
    catalogue = build_catalogue(["Main"], tree)
    points = catalogue.points.values()
    plan = plan_reads(points, item_limit=128, with_attrs=False, catalogue=catalogue)
    assert plan.requests[0].names == (
        "Main.obj0.value",
        "Main.obj1.value",
        "Main.obj2.value",
    )
    assert plan.requests[0].items == 3
    plan = plan_reads(points, item_limit=128, with_attrs=True, catalogue=catalogue)
    assert plan.requests[0].names == ("Main",)
    assert plan.requests[0].items == 24
    # 30 objects with long names: reading them whole saves characters, so requests.
    tree = {f"{'o' * 25}{index:02d}": api_object() for index in range(30)}
    catalogue = build_catalogue(list(tree), tree)
    plan = plan_reads(
        catalogue.points.values(), item_limit=256, with_attrs=False, catalogue=catalogue
    )
    whole_reads = [
        name
        for request in plan.requests
        for name in request.names
        if not name.endswith(".value")
    ]
    assert whole_reads
    assert len(plan.requests) <= plan.lower_bound + 1


def test_arrays_are_read_through_their_array_or_parent() -> None:
    tree = {
        "house": {"rooms": [api_object(), api_object(), api_object()], "name": "home"},
        "arr1": ["a", "b"],
    }
    catalogue = build_catalogue(list(tree), tree)
    wanted = [catalogue.points["house.rooms[1]"], catalogue.points["arr1[0]"]]
    plan = plan_reads(wanted, item_limit=128, with_attrs=False, catalogue=catalogue)
    names = [name for request in plan.requests for name in request.names]
    assert all("[" not in name for name in names)
    assert set(names) <= {"house", "house.rooms", "arr1"}
    # The whole array counts toward the limit even if one element is polled.
    assert sum(request.items for request in plan.requests) >= 24 + 2


def test_an_array_larger_than_a_response_is_read_by_elements() -> None:
    tree = {"big": [[float(index), float(index)] for index in range(100)]}
    catalogue = build_catalogue(["big"], tree)
    points = list(catalogue.points.values())
    plan = plan_reads(points, item_limit=128, with_attrs=False, catalogue=catalogue)
    _check_limits(plan, points, 128)
    names = [name for request in plan.requests for name in request.names]
    assert "big" not in names
    assert all(name.startswith("big[") for name in names)
    assert len(plan.requests) <= plan.lower_bound + 1


def test_points_no_request_can_reach_are_reported() -> None:
    long_name = "x" * 240
    points = [
        tecomat_point(long_name, ValueKind.BOOL),
        tecomat_point("ok", ValueKind.BOOL),
        tecomat_point("bad..path", ValueKind.BOOL),
    ]
    plan = plan_reads(points, item_limit=128, with_attrs=False)
    assert plan.unreadable == {long_name, "bad..path"}
    assert [request.names for request in plan.requests] == [("ok",)]


@pytest.mark.parametrize("points_count", [300, 1000])
def test_item_limits_far_above_any_cpu_still_plan_near_the_bound(
    points_count: int,
) -> None:
    # Characters alone bind; 1000 points hold more items than the packing
    # table spans, so they are packed first-fit instead.
    catalogue = _catalogue_of(generate_program(points_count))
    points = list(catalogue.points.values())
    plan = plan_reads(points, item_limit=100_000, with_attrs=True, catalogue=catalogue)
    _check_limits(plan, points, 100_000)
    assert plan.lower_bound <= len(plan.requests) <= plan.lower_bound + 1


def test_nothing_to_poll_means_no_requests() -> None:
    plan = plan_reads([], item_limit=128, with_attrs=True)
    assert plan.requests == ()
    assert plan.lower_bound == 0
    with pytest.raises(ValueError, match="item_limit"):
        plan_reads([], item_limit=0, with_attrs=True)


def test_names_are_percent_encoded_in_targets() -> None:
    tree = {"a b": 1, "c&d": 2, "é": 3}
    catalogue = build_catalogue(list(tree), tree)
    plan = plan_reads(catalogue.points.values(), item_limit=128, with_attrs=False)
    (request,) = plan.requests
    assert request.target == "/TecoApi/GetObject?a%20b&c%26d&%C3%A9"


# --- the lower bound is a lower bound: brute force on small trees ------------


def _candidates(
    points: Sequence[Point], universe: Sequence[Point], with_attrs: bool
) -> dict[str, int]:
    """Every name that may read some polled point, with its items."""
    names: dict[str, int] = {}
    for point in points:
        parts = point.path.split(".")
        for depth in range(1, len(parts) + 1):
            name = ".".join(parts[:depth])
            names[name] = sum(
                8 if other.described else 1
                for other in universe
                if other.key == name.lower() or other.key.startswith(name.lower() + ".")
            )
        if point.described and not with_attrs:
            names[value_path(point)] = 1
    return names


def _covers(name: str, point: Point) -> bool:
    key = name.lower()
    return (
        point.key == key
        or point.key.startswith(key + ".")
        or key == point.key + ".value"
    )


def _partitions(items: list[str]) -> Iterator[list[list[str]]]:
    if not items:
        yield []
        return
    first, rest = items[0], items[1:]
    for partition in _partitions(rest):
        yield [[first], *partition]
        for index in range(len(partition)):
            yield [
                *partition[:index],
                [first, *partition[index]],
                *partition[index + 1 :],
            ]


def _optimum(
    points: Sequence[Point], universe: Sequence[Point], with_attrs: bool, limit: int
) -> int:
    names = _candidates(points, universe, with_attrs)
    usable = {
        name: items
        for name, items in names.items()
        if items <= limit and len(encode_name(name)) + 1 <= NAME_BUDGET
    }
    best = len(points) + 1
    for size in range(1, len(usable) + 1):
        for chosen in itertools.combinations(sorted(usable), size):
            if not all(
                any(_covers(name, point) for name in chosen) for point in points
            ):
                continue
            for partition in _partitions(list(chosen)):
                if len(partition) >= best:
                    continue
                if all(
                    sum(usable[name] for name in group) <= limit
                    and sum(len(encode_name(name)) + 1 for name in group) <= NAME_BUDGET
                    for group in partition
                ):
                    best = len(partition)
    return best


_member_names = st.text(alphabet="abcdefghij", min_size=1, max_size=70)
_leaf = st.one_of(st.integers(0, 9), st.just(api_object()))
_small_trees = st.dictionaries(
    _member_names,
    st.one_of(_leaf, st.dictionaries(_member_names, _leaf, min_size=1, max_size=3)),
    min_size=1,
    max_size=3,
)


@settings(
    max_examples=60,
    deadline=None,
    database=None,
    suppress_health_check=[HealthCheck.too_slow],
)
@given(
    tree=_small_trees,
    limit=st.integers(8, 24),
    with_attrs=st.booleans(),
    data=st.data(),
)
def test_lower_bound_never_exceeds_the_true_optimum(
    tree: dict[str, Any], limit: int, with_attrs: bool, data: st.DataObject
) -> None:
    catalogue = build_catalogue(list(tree), tree)
    universe = list(catalogue.points.values())
    points = data.draw(
        st.lists(
            st.sampled_from(universe), min_size=1, max_size=5, unique_by=lambda p: p.key
        )
    )
    plan = plan_reads(
        points, item_limit=limit, with_attrs=with_attrs, catalogue=catalogue
    )
    _check_limits(plan, points, limit)
    readable = [point for point in points if point.key not in plan.unreadable]
    if not readable:
        return
    optimum = _optimum(readable, universe, with_attrs, limit)
    assert plan.lower_bound <= optimum <= len(plan.requests)


# --- executed by the simulated PLC -------------------------------------------


@pytest.mark.parametrize("plc_type", ["CP-2080", "CP-1000"])
@pytest.mark.parametrize("points_count", [50, 300, 1000])
async def test_generated_plans_run_on_the_plc_without_limit_errors(
    start_simulator: StartSimulator,
    session: aiohttp.ClientSession,
    points_count: int,
    plc_type: str,
) -> None:
    sim = await start_simulator(generate_program(points_count, plc_type=plc_type))
    client = make_client(session, sim)
    await client.get_info()
    catalogue = await client.discover()
    # A root of more items than one response holds cannot be read, and GetList
    # does not tell its members: discovery reports it as skipped.
    program = sim.program
    too_big = tuple(
        declaration.name
        for declaration in program.declarations
        if leaf_count(declaration.type) > sim.item_limit
    )
    assert catalogue.skipped_groups == too_big
    unreachable = sum(
        len(declaration.initial)
        for declaration in program.declarations
        if declaration.name in too_big
    )
    assert (
        sum(point.described for point in catalogue.points.values())
        == points_count - unreachable
    )
    for with_attrs in (False, True):
        plan = client.plan(catalogue.points.values(), with_attrs=with_attrs)
        sim.clear_requests()
        before = client.request_count
        result = await client.read(plan, catalogue.points)
        # (How near the bound plans come is asserted on the whole generated
        # programs above; here the PLC checks the limits of every request.)
        assert client.request_count - before == len(plan.requests)
        assert [record.status for record in sim.requests] == [200] * len(plan.requests)
        assert all(record.items <= sim.item_limit for record in sim.requests)
        assert result.missing == frozenset()
        assert result.values == catalogue.values
        if with_attrs:
            assert set(result.attributes) == {
                key for key, point in catalogue.points.items() if point.described
            }
