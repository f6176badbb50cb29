"""The FP-I4C benchmark's deterministic counts, asserted (its timings: scripts/bench fpi4c).

For the benchmark's maps of 50, 300 and 1,000 points: a poll of every point
takes exactly the planner's bound of POSTs on the wire, far fewer than the
naive client's one POST a point, and the map's points all read.
"""

import aiohttp
import pytest

from custom_components.tecoapi.pyplc.panasonic import FpI4cClient, FpI4cSource
from tests.benchmarks.fpi4c import SIZES, bench_map
from tests.simulator.fpi4c import FpI4cSimulator


def test_the_maps_are_what_the_benchmark_says() -> None:
    point_map, stations = bench_map(300)
    assert len(point_map.points) == 300
    assert set(stations) == {1, 2, 3}
    types = {point.type.kind.value for point in point_map.points}
    assert types == {"bool", "integer", "real", "string"}
    assert bench_map(300)[0] == point_map, "seeded: the same map every run"


@pytest.mark.parametrize(("points", "posts"), zip(SIZES, (2, 3, 3), strict=True))
async def test_a_poll_of_every_point_takes_the_bound(
    points: int, posts: int, socket_enabled: None
) -> None:
    point_map, stations = bench_map(points)
    async with (
        FpI4cSimulator(stations, station=1) as gateway,
        aiohttp.ClientSession() as http,
    ):
        client = FpI4cClient(http, gateway.url)
        source = FpI4cSource(client, point_map, identity="bench")
        keys = frozenset((await source.poll(())).catalogue.points)
        snapshot = await source.poll(keys)
    plan = source.plan(keys)
    assert source.statistics.last_poll_requests == plan.lower_bound == len(plan.posts)
    assert set(snapshot.values) == keys
    assert snapshot.quality == {}
    # A POST or two a station: a tiny share of the naive client's one a point.
    assert plan.lower_bound == posts
    assert plan.requests <= 20 * posts
