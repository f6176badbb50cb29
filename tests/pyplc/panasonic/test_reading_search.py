"""A request that fails as a whole is halved until only its bad points fail.

The simulated PLC's DT area ends at DT32764 (as a real CPU's ends somewhere):
the gateway fails a request that covers DT32766 as a whole, so a map that
names DT32760 and DT32766 once lost both. Now the read halves the failed
request, DT32760 gets its value, DT32766 alone stays bad with the gateway's
code, and later plans keep them apart without searching again.
"""

import asyncio
from collections.abc import Iterable
import logging

import pytest

from custom_components.tecoapi.pyplc.core.pointmap import PointMap, load_csv
from custom_components.tecoapi.pyplc.core.source import Snapshot
from custom_components.tecoapi.pyplc.panasonic import FpI4cSource, check_point
from custom_components.tecoapi.pyplc.panasonic.address import WireType, parse_address
from custom_components.tecoapi.pyplc.panasonic.planner import (
    Target,
    covering,
    plan_reads,
)
from custom_components.tecoapi.pyplc.panasonic.reading import (
    CUT_POLLS,
    REJOIN_READS,
    SEARCH_POSTS,
)
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


def hundred(start: int = 32666) -> str:
    """The boiler and 100 INTs from DT``start`` on, at station 1."""
    rows = "".join(f"p{n},P{n},DT{start + n},INT,1\n" for n in range(100))
    return "".join(END.splitlines(keepends=True)[:2]) + rows


async def poll_counted(
    source: FpI4cSource, gateway: FpI4cSimulator, keys: Iterable[str]
) -> tuple[Snapshot, list[list[str]]]:
    """Poll some points; the snapshot and the requests of the poll's POSTs.

    Every poll keeps to the budget: its plan meets the planner's bound, and
    the search adds at most :data:`SEARCH_POSTS` POST (one station here).
    """
    posts = len(gateway.posts)
    snapshot = await source.poll(keys)
    requests = requests_of(gateway, posts)
    plan = source.read_plan
    assert plan is not None
    assert len(plan.posts) == plan.lower_bound
    assert len(requests) <= plan.lower_bound + SEARCH_POSTS
    return snapshot, requests


async def test_the_search_spends_one_post_a_poll_and_leaves_the_normal_plan(
    make_source: MakeSource, gateway: FpI4cSimulator, caplog: pytest.LogCaptureFixture
) -> None:
    """100 points in one request, the last past DT's end: 7 halvings, a poll each.

    Each poll costs its plan's POSTs (at the planner's bound) and one more
    while the search is under way; each halving gives the values of the half
    that reads. Once the bad point is alone, the plan is the planner's plan
    of the good points and one request for the bad one: nothing else stays
    split. Until a point fails in a request of its own, its failure is not
    its own: no code (no repair issue), no warning.
    """
    source = make_source(end_map(hundred()))
    gateway.set(1, "DT32700", "INT", 7)
    with caplog.at_level(logging.WARNING):
        snapshot, requests = await poll_counted(source, gateway, ())
        keys = snapshot.catalogue.points.keys()
        assert requests == [
            ["DT0 x1", "DT32666 x100"],
            ["DT32666 x50", "DT32716 x50"],
        ]
        assert len(snapshot.values) == 1 + 50
        assert snapshot.values["p34"] == 7
        assert {snapshot.quality[key].code for key in snapshot.missing} == {None}
        assert source.diagnostics()["failed_points"] == []
        searching = 1
        while len(requests) == 2:
            snapshot, requests = await poll_counted(source, gateway, keys)
            searching += 1
    assert (
        [
            record.getMessage()
            for record in caplog.records
            if record.name != "asyncio"  # its slow-callback notes on a busy machine
        ]
        == [
            FAILING.replace("typo", "p99")
            + f"DT32765: DT32765..DT32765 is past DT32764 "
            f"(err_code {DATA_ERROR})"
        ]
    )
    # The search's last POST found p99 (DT32765) alone; this poll was plain.
    assert searching - 1 == 7
    good = [Target("boiler", 1, parse_address("DT0"), WireType.INT)] + [
        Target(f"p{n}", 1, parse_address(f"DT{32666 + n}"), WireType.INT)
        for n in range(99)
    ]
    normal = plan_reads(good)
    assert requests == [["DT0 x1", "DT32666 x99", "DT32765 x1"]]
    assert len(requests[0]) == normal.requests + 1
    assert snapshot.missing == {"p99"}
    assert len(snapshot.values) == 100
    assert source.diagnostics()["read_apart"] == {"breaks": 0, "alone": ["p99"]}
    snapshot, again = await poll_counted(source, gateway, keys)
    assert again == requests
    assert snapshot.missing == {"p99"}


async def test_transient_item_errors_leave_the_normal_plan_again(
    make_source: MakeSource, gateway: FpI4cSimulator
) -> None:
    """Errors that come and go: the points read apart rejoin, the cuts expire.

    A lone point that reads :data:`REJOIN_READS` times in a row rejoins its
    neighbours; a cut where no point failed goes after :data:`CUT_POLLS`
    polls. After each burst of errors the plan comes back to the normal one,
    so what is read apart stays bounded however long the run.
    """
    gaps = "".join(f"g{n},G{n},DT{300 + 2 * n},INT,1\n" for n in range(10))
    source = make_source(end_map(hundred(100) + gaps))
    snapshot, normal = await poll_counted(source, gateway, ())
    keys = snapshot.catalogue.points.keys()
    assert normal == [["DT0 x1", "DT100 x100", "DT300 x19"]]
    # A point's own error for some polls (found alone, then it reads again),
    # some that go while the search is under way, and one at an address
    # between two points (DT305: both halves read, a cut between them).
    for address, polls in (
        ("DT105", 9),
        ("DT160", 2),
        ("DT305", 5),
        ("DT133", 8),
        ("DT199", 3),
    ):
        gateway.item_errors[1, address] = (61, "Data error")
        for _ in range(polls):
            snapshot, requests = await poll_counted(source, gateway, keys)
            assert len(requests[0]) <= len(normal[0]) + 2 * 7
        if address == "DT305":
            assert source.diagnostics()["read_apart"] == {"breaks": 1, "alone": []}
            assert requests == [["DT0 x1", "DT100 x100", "DT300 x5", "DT306 x13"]]
            assert snapshot.missing == set()
        gateway.item_errors.clear()
        for _ in range(CUT_POLLS + REJOIN_READS):
            snapshot, requests = await poll_counted(source, gateway, keys)
        assert requests == normal
        assert source.diagnostics()["read_apart"] == {"breaks": 0, "alone": []}
        assert snapshot.missing == set()
        assert len(snapshot.values) == 111


async def test_a_cut_is_tried_again_in_one_post_without_losing_a_value(
    make_source: MakeSource, gateway: FpI4cSimulator
) -> None:
    """A failing address between two points: the cut is tried every CUT_POLLS polls.

    The poll that drops the cut reads the points together again; the request
    fails, and its search splits it at the dropped cut first: both halves
    read in that one more POST, nothing is unavailable, and the cut is back.
    """
    gaps = "".join(f"g{n},G{n},DT{300 + 2 * n},INT,1\n" for n in range(10))
    source = make_source(end_map("".join(END.splitlines(keepends=True)[:2]) + gaps))
    gateway.item_errors[1, "DT305"] = (61, "Data error")
    snapshot, requests = await poll_counted(source, gateway, ())
    keys = snapshot.catalogue.points.keys()
    while len(requests) > 1:
        snapshot, requests = await poll_counted(source, gateway, keys)
    cut = [["DT0 x1", "DT300 x5", "DT306 x13"]]
    retried = [["DT0 x1", "DT300 x19"], ["DT300 x5", "DT306 x13"]]
    assert requests == cut
    seen = []
    for _ in range(2 * CUT_POLLS):
        snapshot, requests = await poll_counted(source, gateway, keys)
        assert snapshot.missing == set()
        seen.append(requests)
    assert [requests for requests in seen if requests != cut] == [retried, retried]


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
    # The integration's warnings: asyncio's debug mode adds one of its own when a
    # busy machine holds a step of the loop past 100 ms.
    warnings = [
        record.getMessage()
        for record in caplog.records
        if record.levelname == "WARNING"
        and record.name.startswith("custom_components.tecoapi")
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
    assert diagnostics["read_apart"] == {"breaks": 0, "alone": ["typo"]}
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
    assert [
        record.getMessage()
        for record in caplog.records
        if record.name != "asyncio"  # its slow-callback notes on a busy machine
    ] == [
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
    """Eleven failed requests: ten halved in one POST of 20, the last next poll.

    The poll that finds them spends one search POST; the next reads the ten
    found apart (two POSTs, its bound) and halves the eleventh in one more.
    """
    rows = "".join(
        f"a{n},A{n},DT{200 * n},INT,1\nb{n},B{n},DT{200 * n + 1},INT,1\n"
        for n in range(11)
    )
    for n in range(11):
        gateway.item_errors[1, f"DT{200 * n + 1}"] = (61, "Data error")
    source = make_source(
        end_map("".join(END.splitlines(keepends=True)[:1]) + rows + "y,Y,Y0,BOOL,1\n")
    )
    snapshot, requests = await poll_counted(source, gateway, ())
    assert [len(post) for post in requests] == [12, 20]
    assert snapshot.missing == {f"b{n}" for n in range(11)} | {"a10"}
    snapshot, requests = await poll_counted(
        source, gateway, snapshot.catalogue.points.keys()
    )
    assert [len(post) for post in requests] == [20, 2, 2]
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
