"""A request that fails as a whole is halved until only its bad points fail.

The simulated PLC's DT area ends at DT32764 (as a real CPU's ends somewhere):
the gateway fails a request that covers DT32766 as a whole, so a map that
names DT32760 and DT32766 once lost both. Now the read halves the failed
request, DT32760 gets its value, DT32766 alone stays bad with the gateway's
code, and later plans keep them apart without searching again.
"""

import asyncio
import logging

import pytest

from custom_components.tecoapi.pyplc.core.pointmap import PointMap, load_csv
from custom_components.tecoapi.pyplc.panasonic import check_point
from custom_components.tecoapi.pyplc.panasonic.address import WireType, parse_address
from custom_components.tecoapi.pyplc.panasonic.planner import (
    MAX_REQUESTS,
    Target,
    covering,
    plan_reads,
)
from custom_components.tecoapi.pyplc.panasonic.source import SEARCH_ROUNDS
from tests.pyplc.panasonic.conftest import MakeSource
from tests.simulator.fpi4c import FpI4cSimulator
from tests.simulator.fpi4c.memory import DATA_ERROR

END = """\
id,name,address,type,device
boiler,Boiler,DT0,INT,1
near_end,Near the end,DT32760,INT,1
typo,A typo,DT32766,INT,1
"""
"""The heating plant's boiler, a register near DT's end, and one past it."""
FAILING = "typo cannot be read, its entity is unavailable: "


def end_map(text: str = END) -> PointMap:
    return load_csv(text, check_point)


def requests_of(gateway: FpI4cSimulator, posts: int) -> list[list[str]]:
    """The requests of the POSTs since ``posts`` as ``DT32760 x7``."""
    return [
        [
            f"{item['area']}{item['start']} x{item.get('count', 1)}"
            for item in body["req"]
        ]
        for body in gateway.posts[posts:]
    ]


async def test_a_bad_address_costs_only_its_own_point(
    make_source: MakeSource, gateway: FpI4cSimulator
) -> None:
    gateway.set(1, "DT32760", "INT", 42)
    source = make_source(end_map())
    snapshot = await source.poll(())
    # The plan reads DT32760..DT32766 in one request; it fails as a whole,
    # and one POST of its two halves finds the bad one.
    assert requests_of(gateway, 0) == [
        ["DT0 x1", "DT32760 x7"],
        ["DT32760 x1", "DT32766 x1"],
    ]
    assert snapshot.values["near_end"] == 42
    assert snapshot.values["boiler"] == 652
    assert snapshot.missing == {"typo"}
    assert snapshot.quality["typo"].reason.startswith(f"err_code {DATA_ERROR}: ")
    assert snapshot.offline == {}
    # The split stays: each poll reads them apart, at its bound, and searches
    # nothing again.
    for _ in range(3):
        posts = len(gateway.posts)
        snapshot = await source.poll({"boiler", "near_end", "typo"})
        assert requests_of(gateway, posts) == [["DT0 x1", "DT32760 x1", "DT32766 x1"]]
        assert snapshot.values == {"boiler": 652, "near_end": 42}
        assert snapshot.missing == {"typo"}
    plan = source.read_plan
    assert plan is not None
    assert len(plan.posts) == plan.lower_bound == 1
    # A read of some points between polls keeps the bad one apart too.
    posts = len(gateway.posts)
    snapshot = await source.read_points(["near_end", "typo"])
    assert snapshot is not None
    assert snapshot.values == {"near_end": 42}
    assert requests_of(gateway, posts) == [["DT32760 x1", "DT32766 x1"]]


async def test_a_new_map_is_read_without_the_old_split(
    make_source: MakeSource, gateway: FpI4cSimulator
) -> None:
    """A map change is a new source: what the old one learned is gone."""
    source = make_source(end_map())
    await source.poll(())
    fixed = END.replace("DT32766", "DT32763")
    source = make_source(end_map(fixed))
    posts = len(gateway.posts)
    snapshot = await source.poll(())
    assert requests_of(gateway, posts) == [["DT0 x1", "DT32760 x4"]]
    assert snapshot.quality == {}
    assert source.diagnostics()["read_apart"] == {"breaks": 0, "alone": []}


async def test_the_search_costs_one_post_a_round_and_a_request_a_halving(
    make_source: MakeSource, gateway: FpI4cSimulator
) -> None:
    """100 points in one request, the last past DT's end: 7 halvings, 7 POSTs.

    The search's cost in the read that finds the failure: one POST per round
    and station (the two halves of each failed request), at most
    :data:`SEARCH_ROUNDS` rounds. After it, the plan reads the points in the
    windows the halvings left, one more request per halving, in the same
    single POST as before.
    """
    rows = "".join(f"p{n},P{n},DT{32666 + n},INT,1\n" for n in range(100))
    source = make_source(end_map("".join(END.splitlines(keepends=True)[:2]) + rows))
    gateway.set(1, "DT32700", "INT", 7)
    snapshot = await source.poll(())
    requests = requests_of(gateway, 0)
    assert requests[0] == ["DT0 x1", "DT32666 x100"]
    assert requests[1] == ["DT32666 x50", "DT32716 x50"]
    assert requests[-1] == ["DT32764 x1", "DT32765 x1"]
    assert len(requests) == 1 + SEARCH_ROUNDS == 8
    assert all(len(post) == 2 for post in requests[1:])
    assert snapshot.missing == {"p99"}
    assert snapshot.values["p34"] == 7
    assert len(snapshot.values) == 100
    assert source.diagnostics()["read_apart"] == {"breaks": 7, "alone": ["p99"]}
    posts = len(gateway.posts)
    snapshot = await source.poll(snapshot.catalogue.points.keys())
    (poll,) = requests_of(gateway, posts)
    assert len(poll) == 1 + 1 + 7 <= MAX_REQUESTS
    assert snapshot.missing == {"p99"}
    assert len(snapshot.values) == 100


async def test_a_station_whose_every_item_fails_is_not_searched(
    make_source: MakeSource, gateway: FpI4cSimulator
) -> None:
    """A PLC that does not answer is offline: nothing is halved."""
    source = make_source(end_map())
    await source.poll(())
    gateway.silent.add(1)
    posts = len(gateway.posts)
    snapshot = await source.poll({"boiler", "near_end", "typo"})
    assert len(gateway.posts) == posts + 1
    assert set(snapshot.offline) == {"station_1"}
    assert source.diagnostics()["failed_points"] == []


async def test_the_code_and_its_meaning_are_in_the_diagnostics_and_logged_once(
    make_source: MakeSource, gateway: FpI4cSimulator, caplog: pytest.LogCaptureFixture
) -> None:
    source = make_source(end_map())
    with caplog.at_level(logging.INFO):
        await source.poll(())
        await source.poll({"boiler", "near_end", "typo"})
    warnings = [
        record.getMessage()
        for record in caplog.records
        if record.levelname == "WARNING"
    ]
    assert warnings == [
        FAILING + f"DT32766: DT32766..DT32766 is past DT32764 (err_code {DATA_ERROR})"
    ]
    diagnostics = source.diagnostics()
    assert diagnostics["failed_points"] == [
        {
            "key": "typo",
            "request": "DT32766",
            "err_code": str(DATA_ERROR),
            "meaning": "DT32766..DT32766 is past DT32764",
        }
    ]
    assert diagnostics["read_apart"] == {"breaks": 1, "alone": ["typo"]}
    # Another code is a new fault (logged); the point reading again is said once.
    gateway.item_errors[1, "DT32766"] = (66, "Address error")
    caplog.clear()
    with caplog.at_level(logging.INFO):
        await source.poll({"boiler", "typo"})
        await source.poll({"boiler", "typo"})
        gateway.item_errors.clear()
        gateway.stations[1].sizes = {**gateway.stations[1].sizes, "DT": 32_767}
        await source.poll({"boiler", "typo"})
        await source.poll({"boiler", "typo"})
    assert [record.getMessage() for record in caplog.records] == [
        FAILING + "DT32766: Address error (err_code 66)",
        "typo reads again",
    ]
    assert source.diagnostics()["failed_points"] == []


def _target(key: str, address: str, wire: WireType = WireType.INT) -> Target:
    return Target(key, None, parse_address(address), wire)


def test_the_planner_reads_breaks_and_lone_points_apart() -> None:
    """A break begins a request; a lone point is read in one of its own."""
    targets = [
        _target("a", "DT10"),
        _target("b", "DT12"),
        _target("c", "DT14"),
        _target("d", "DT16"),
    ]
    (together,) = plan_reads(targets, split_gaps=False).posts
    assert [request.name for request in together.requests] == ["DT10"]
    (post,) = plan_reads(targets, split_gaps=False, breaks={"c"}).posts
    assert [(r.name, r.count) for r in post.requests] == [("DT10", 3), ("DT14", 3)]
    (post,) = plan_reads(targets, split_gaps=False, alone={"b"}).posts
    assert [(r.name, r.count) for r in post.requests] == [
        ("DT10", 1),
        ("DT12", 1),
        ("DT14", 3),
    ]
    plan = plan_reads(targets, split_gaps=False, alone={"b"})
    assert plan.lower_bound == len(plan.posts) == 1
    assert plan.minimal_requests == 3


def test_covering_reads_exactly_some_points_of_one_chain() -> None:
    request = covering([_target("b", "DT12"), _target("a", "DT10")])
    assert (request.name, request.count, request.points) == (
        "DT10",
        3,
        (("a", 0), ("b", 2)),
    )
    real = covering([_target("r", "DT21", WireType.REAL)])
    assert (real.start, real.count, real.points) == (21, 1, (("r", 0),))
    with pytest.raises(ValueError, match="one chain"):
        covering([_target("a", "DT10"), _target("y", "Y0", WireType.BOOL)])
    with pytest.raises(ValueError, match="one chain"):
        covering([])
    with pytest.raises(ValueError, match="do not fit"):
        covering([_target("a", "DT10"), _target("z", "DT110")])


async def test_a_round_halves_at_most_ten_failed_requests_of_a_station(
    make_source: MakeSource, gateway: FpI4cSimulator
) -> None:
    """Eleven failed requests: ten halved in one POST of 20, the last in the next."""
    rows = "".join(
        f"a{n},A{n},DT{200 * n},INT,1\nb{n},B{n},DT{200 * n + 1},INT,1\n"
        for n in range(11)
    )
    for n in range(11):
        gateway.item_errors[1, f"DT{200 * n + 1}"] = (61, "Data error")
    source = make_source(
        end_map("".join(END.splitlines(keepends=True)[:1]) + rows + "y,Y,Y0,BOOL,1\n")
    )
    snapshot = await source.poll(())
    assert [len(post) for post in requests_of(gateway, 0)] == [12, 20, 2]
    assert snapshot.missing == {f"b{n}" for n in range(11)}
    assert {f"a{n}" for n in range(11)} <= set(snapshot.values)


async def test_a_search_whose_post_is_lost_leaves_the_first_read_s_failures(
    make_source: MakeSource, gateway: FpI4cSimulator
) -> None:
    """The halves' POST unanswered: the points stay bad; the next poll goes on."""
    gateway.set(1, "DT32760", "INT", 42)
    source = make_source(end_map())
    async with gateway.hold() as hold:
        polled = asyncio.create_task(source.poll(()))
        await hold.reached()
        gateway.dropped.add(1)
    snapshot = await polled
    assert snapshot.missing == {"near_end", "typo"}
    assert snapshot.values == {"boiler": 652}
    gateway.dropped.clear()
    snapshot = await source.poll({"boiler", "near_end", "typo"})
    assert snapshot.missing == {"typo"}
    assert snapshot.values == {"boiler": 652, "near_end": 42}
