"""The FP-I4C's batches against the simulated gateway over HTTP.

``/plcpost`` carries up to 20 requests, writes and reads mixed, one station's
(the seed): a batch goes as a station's writes in the order given, then their
read-backs and DT0, nine writes a POST. Every value is checked first (the
codec, a REAL's range: nothing is sent when one is refused); a value the PLC
refuses stops the batch after its POST, and what that POST wrote is pushed.
"""

import aiohttp
import pytest

from custom_components.tecoapi.pyplc import (
    InvalidValueError,
    OutOfRangeError,
    Snapshot,
    ValueRejectedError,
)
from custom_components.tecoapi.pyplc.core.pointmap import load_csv
from custom_components.tecoapi.pyplc.panasonic import (
    FpI4cClient,
    FpI4cSource,
    check_point,
)
from custom_components.tecoapi.pyplc.panasonic.source import WRITES_PER_POST
from tests.pyplc.panasonic.conftest import MakeSource, example_map
from tests.simulator.fpi4c import FpI4cSimulator

PROBE = {"area": "DT", "type": "INT", "start": 0, "count": 1}


async def test_a_stations_writes_and_read_backs_go_in_one_post(
    make_source: MakeSource, gateway: FpI4cSimulator
) -> None:
    source = make_source()
    await source.poll(())
    told: list[Snapshot] = []
    source.subscribe(told.append)
    posts = len(gateway.posts)

    confirmed = await source.write_many(
        {"room_setpoint": 22.0, "dhw_setpoint": 60, "door_target": 55}
    )

    # Station 1's two writes in one POST, station 2's in another.
    assert len(gateway.posts) == posts + 2
    first, second = gateway.posts[-2]["req"], gateway.posts[-1]["req"]
    assert [(item["start"], item.get("value")) for item in first] == [
        (101, 220),
        (102, 600),
        (101, None),
        (102, None),
        (0, None),
    ]
    assert first[-1] == PROBE
    assert [(item["start"], item.get("value")) for item in second] == [
        (11, 55),
        (11, None),
        (0, None),
    ]
    assert gateway.get(1, "DT101", "INT") == 220
    assert gateway.get(1, "DT102", "INT") == 600
    assert gateway.get(2, "DT11", "INT") == 55
    assert [snapshot.values for snapshot in told] == [
        {"room_setpoint": 22.0, "dhw_setpoint": 60.0},
        {"door_target": 55},
    ]
    assert confirmed is not None
    assert confirmed.values == {
        "room_setpoint": 22.0,
        "dhw_setpoint": 60.0,
        "door_target": 55,
    }
    assert source.statistics.writes == 3


async def test_more_writes_than_a_post_carries_take_more_posts(
    gateway: FpI4cSimulator, http: aiohttp.ClientSession
) -> None:
    count = WRITES_PER_POST + 1
    rows = "".join(f"W{index},DT{600 + index},INT,yes\n" for index in range(count))
    point_map = load_csv("name,address,type,writable\n" + rows, check_point)
    source = FpI4cSource(
        FpI4cClient(http, gateway.url), point_map, identity="g", station=1
    )
    await source.poll(())
    posts = len(gateway.posts)

    confirmed = await source.write_many({f"w{index}": index for index in range(count)})

    assert len(gateway.posts) == posts + 2
    assert [len(post["req"]) for post in gateway.posts[-2:]] == [
        2 * WRITES_PER_POST + 1,
        3,
    ]
    assert all(len(post["req"]) <= 20 for post in gateway.posts)
    assert [gateway.get(1, f"DT{600 + index}", "INT") for index in range(count)] == [
        *range(count)
    ]
    assert confirmed is not None
    assert confirmed.values == {f"w{index}": index for index in range(count)}


@pytest.mark.parametrize(
    ("refused", "error"),
    [
        (("room_setpoint", 30.0), OutOfRangeError),
        (("ratio", 1e39), InvalidValueError),  # the source's own check: a REAL's range
    ],
)
async def test_a_batch_with_one_refused_value_sends_nothing(
    gateway: FpI4cSimulator,
    http: aiohttp.ClientSession,
    refused: tuple[str, float],
    error: type[Exception],
) -> None:
    point_map = example_map().with_new_point(
        load_csv(
            "name,address,type,writable,device\nRatio,DT410,REAL,yes,1\n", check_point
        ).points[0]
    )
    source = FpI4cSource(FpI4cClient(http, gateway.url), point_map, identity="g")
    await source.poll(())
    posts = len(gateway.posts)
    key, value = refused

    with pytest.raises(error):
        await source.write_many({"door_target": 55, key: value})
    with pytest.raises(error):
        source.check_write(key, value)

    assert len(gateway.posts) == posts
    assert gateway.get(2, "DT11", "INT") == 0


async def test_a_value_the_plc_refuses_stops_the_batch_after_its_post(
    make_source: MakeSource, gateway: FpI4cSimulator
) -> None:
    source = make_source()
    await source.poll(())
    told: list[Snapshot] = []
    source.subscribe(told.append)
    gateway.write_errors[1, "DT101"] = (65, "Protect error")
    posts = len(gateway.posts)

    with pytest.raises(ValueRejectedError) as raised:
        await source.write_many(
            {"dhw_setpoint": 60, "room_setpoint": 22.0, "door_target": 55}
        )

    assert (raised.value.code, raised.value.path) == ("65", "room_setpoint")
    # One failed item does not fail the others (the seed): DT102 was written.
    assert gateway.get(1, "DT102", "INT") == 600
    assert gateway.get(1, "DT101", "INT") == 215
    assert [snapshot.values for snapshot in told] == [{"dhw_setpoint": 60.0}]
    # Station 2's POST was not sent.
    assert len(gateway.posts) == posts + 1
    assert gateway.get(2, "DT11", "INT") == 0
    assert source.statistics.failed_writes == 0
