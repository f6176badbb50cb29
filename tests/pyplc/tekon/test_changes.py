"""Every change between two polls, in its UpTime order, bounded (seed: NewSession alldata=1)."""

from datetime import datetime, timedelta

import aiohttp
import pytest

from custom_components.tecoapi.pyplc import (
    PointQuality,
    Quality,
    ResponseTooLargeError,
    Snapshot,
)
from custom_components.tecoapi.pyplc.core.models import Access, PointEvent
from custom_components.tecoapi.pyplc.tekon import TekonClient, TekonSource
from custom_components.tecoapi.pyplc.tekon.changes import (
    MOST_CHANGES,
    in_order,
    states,
)
from custom_components.tecoapi.pyplc.tekon.client import ItemUpdate
from tests.pyplc.conftest import Clock
from tests.pyplc.tekon.conftest import discovered, key
from tests.simulator.tekon import TekonGateway
from tests.simulator.tekon.building import CONTROLLER, LIFT

DOOR = f"{CONTROLLER}.Дверь подъезда"
FIRE = f"{CONTROLLER}.Пожарная сигнализация"
LIGHT = f"{CONTROLLER}.Освещение"
SETPOINT = f"{CONTROLLER}.Уставка"
INTERCOM = f"{CONTROLLER}.Переговорное устройство"
SHAFT_DOOR = f"{LIFT}.Дверь шахты"
CALL = key(INTERCOM) + "#call"
RING = key(INTERCOM) + "#ring"
START = datetime(2025, 3, 18, 12, 0, 0)  # noqa: DTZ001 (the gateway's local time)


def at(seconds: int) -> datetime:
    return START + timedelta(seconds=seconds)


def pushed_by(source: TekonSource) -> list[Snapshot]:
    """The snapshots the source pushes from now on."""
    heard: list[Snapshot] = []
    source.subscribe(heard.append)
    return heard


async def test_sessions_are_opened_for_every_change(
    gateway: TekonGateway, source: TekonSource
) -> None:
    await source.identify()
    (session,) = gateway.sessions.values()
    assert session.alldata
    assert source.diagnostics()["subscription"]["every_change"] is True


async def test_a_door_that_opened_and_closed_within_a_poll_is_shown_open_first(
    gateway: TekonGateway, source: TekonSource
) -> None:
    polled = frozenset({key(DOOR), key(FIRE)})
    await discovered(source, polled)
    heard = pushed_by(source)
    gateway.set_value(DOOR, "1", at=at(0))
    gateway.set_value(DOOR, "0", at=at(0))
    snapshot = await source.poll(polled)
    assert [pushed.values for pushed in heard] == [{key(DOOR): True}]
    assert snapshot.values == {key(DOOR): False}
    # A quiet poll after it is one request, and pushes nothing.
    gateway.clear_requests()
    quiet = await source.poll(polled)
    assert (gateway.requests, quiet.values, len(heard)) == (["GetUpdatesText"], {}, 1)


async def test_changes_are_taken_in_their_up_time_order(
    gateway: TekonGateway, source: TekonSource
) -> None:
    """A gateway that lists an answer's changes by item: the UpTimes put them in order."""
    gateway.updates_order = "items"
    polled = frozenset({key(DOOR), key(FIRE), key(LIGHT)})
    await discovered(source, polled)
    heard = pushed_by(source)
    gateway.set_value(DOOR, "1", at=at(0))
    gateway.set_value(FIRE, "1", at=at(1))
    gateway.set_value(DOOR, "0", at=at(2))
    gateway.set_value(FIRE, "0", at=at(3))
    # Listed door, door, fire, fire; it happened door, fire, door, fire.
    snapshot = await source.poll(polled)
    assert [pushed.values for pushed in heard] == [{key(DOOR): True, key(FIRE): True}]
    assert snapshot.values == {key(DOOR): False, key(FIRE): False}


async def test_changes_of_the_same_up_time_keep_the_answer_s_order(
    gateway: TekonGateway, source: TekonSource
) -> None:
    polled = frozenset({key(LIGHT)})
    await discovered(source, polled)
    heard = pushed_by(source)
    for value in ("0", "1", "0"):
        gateway.set_value(LIGHT, value, at=at(5))
    snapshot = await source.poll(polled)
    assert [pushed.values for pushed in heard] == [
        {key(LIGHT): False},
        {key(LIGHT): True},
    ]
    assert snapshot.values == {key(LIGHT): False}


async def test_each_state_carries_the_quality_and_health_of_its_moment(
    gateway: TekonGateway, source: TekonSource
) -> None:
    polled = frozenset({key(SETPOINT), key(SHAFT_DOOR)})
    await discovered(source, polled)
    heard = pushed_by(source)
    gateway.set_value(SETPOINT, "21", quality=0x44, at=at(0))
    gateway.set_value(f"{LIFT}.Status", "0", at=at(0))
    gateway.set_value(SETPOINT, "22", at=at(1))
    gateway.set_value(f"{LIFT}.Status", "10", at=at(1))
    snapshot = await source.poll(polled)
    (first,) = heard
    assert first.values == {key(SETPOINT): 21.0}
    assert first.quality == {
        key(SETPOINT): PointQuality(quality=Quality.UNCERTAIN, reason="last_usable")
    }
    assert first.offline == {key(LIFT): "no_data_exchange"}
    assert (snapshot.values, snapshot.quality, snapshot.offline) == (
        {key(SETPOINT): 22.0},
        {},
        {},
    )


async def test_a_chattering_item_is_bounded(
    gateway: TekonGateway, source: TekonSource
) -> None:
    """Thousands of changes of one item between two polls: at most MOST_CHANGES applied."""
    polled = frozenset({key(SETPOINT), key(DOOR)})
    await discovered(source, polled)
    heard = pushed_by(source)
    gateway.set_value(DOOR, "1", at=at(0))
    for value in range(5000):
        gateway.set_value(SETPOINT, str(value), at=at(value // 1000))
    gateway.clear_requests()
    snapshot = await source.poll(polled)
    assert gateway.requests == ["GetUpdatesText"]
    # The first fifteen, then the last: sixteen states, fifteen of them pushed.
    assert [pushed.values.get(key(SETPOINT)) for pushed in heard] == [
        float(value) for value in range(MOST_CHANGES - 1)
    ]
    assert heard[0].values[key(DOOR)] is True
    # The poll's snapshot: every point the answer changed, as it ended.
    assert snapshot.values == {key(SETPOINT): 4999.0, key(DOOR): True}
    assert source.collapsed_changes == 5000 - MOST_CHANGES
    assert source.diagnostics()["subscription"]["collapsed_changes"] == 4984


async def test_an_answer_too_large_is_skipped_and_the_values_of_now_read(
    gateway: TekonGateway, http: aiohttp.ClientSession, clock: Clock
) -> None:
    client = TekonClient(http, gateway.url)
    client.max_updates_bytes = 64 * 1024
    source = TekonSource(client, clock=clock)
    try:
        polled = frozenset({key(SETPOINT), key(DOOR)})
        await discovered(source, polled)
        gateway.set_value(DOOR, "1")
        for value in range(3000):
            gateway.set_value(SETPOINT, str(value))
        gateway.clear_requests()
        snapshot = await source.poll(polled)
        # The gateway took the answer: its rid is not asked again.
        assert gateway.requests == [
            "GetUpdatesText",
            "ReadAllItemsValues",
            "GetUpdatesText",
        ]
        assert snapshot.values == {key(SETPOINT): 2999.0, key(DOOR): True}
        assert source.skipped_answers == 1
        gateway.clear_requests()
        assert (await source.poll(polled)).values == {}
        assert gateway.requests == ["GetUpdatesText"]
    finally:
        await source.close()


@pytest.mark.parametrize("read_all", [True, False])
async def test_an_answer_too_large_is_never_asked_again(
    gateway: TekonGateway, http: aiohttp.ClientSession, clock: Clock, read_all: bool
) -> None:
    """The current values past the cap too: the poll fails; without them, none are read.

    Either way the next poll asks a new rid: the one answered too large is behind it.
    """
    client = TekonClient(http, gateway.url)
    source = TekonSource(client, clock=clock)
    try:
        gateway.read_all = read_all
        polled = frozenset({key(SETPOINT), key(DOOR)})
        await discovered(source, polled)
        client.max_updates_bytes = 150
        for value in range(10):
            gateway.set_value(SETPOINT, str(value))
        gateway.set_value(DOOR, "1")
        gateway.clear_requests()
        if read_all:
            with pytest.raises(ResponseTooLargeError):
                await source.poll(polled)
            assert source.skipped_answers == 2
        else:
            # A gateway without ReadAllItemsValues: the changes are lost.
            assert (await source.poll(polled)).values == {}
            assert source.skipped_answers == 1
        assert gateway.requests == [
            "GetUpdatesText",
            *(["ReadAllItemsValues"] if read_all else []),
            "GetUpdatesText",
        ]
        client.max_updates_bytes = 64 * 1024
        gateway.set_value(DOOR, "0")
        gateway.clear_requests()
        assert (await source.poll(polled)).values == {key(DOOR): False}
        assert gateway.requests == ["GetUpdatesText"]
    finally:
        await source.close()


async def test_an_intercom_s_call_state_and_calls_beside_its_button(
    gateway: TekonGateway, source: TekonSource
) -> None:
    """Channel 3001: its low bit says a call is on (seed); writing 1 calls."""
    snapshot = await source.poll(())
    points = snapshot.catalogue.points
    button, call, ring = points[key(INTERCOM)], points[CALL], points[RING]
    assert (button.attributes and button.attributes.access) is Access.WRITE
    assert (call.attributes and call.attributes.access) is Access.READ
    assert (ring.attributes and ring.attributes.access, ring.event) == (
        Access.READ,
        PointEvent.RING,
    )
    assert call.address == ring.address == button.address == INTERCOM
    polled = frozenset({CALL, RING})
    assert (await source.poll(polled)).values == {CALL: False, RING: False}
    heard = pushed_by(source)
    gateway.set_value(INTERCOM, "1", at=at(0))
    gateway.set_value(INTERCOM, "2", at=at(1))  # the low bit: no call
    changed = await source.poll(polled)
    assert [pushed.values for pushed in heard] == [{CALL: True, RING: True}]
    assert changed.values == {CALL: False, RING: False}
    # The button still calls.
    await source.write(key(INTERCOM), True)
    assert gateway.writes[-1] == (INTERCOM, "1")


def update(name: str, value: str, second: int | None) -> ItemUpdate:
    return ItemUpdate(
        name=name,
        item_id=None,
        value=value,
        quality=192,
        time=None if second is None else at(second),
    )


def test_an_entry_without_up_time_keeps_its_place_after_the_one_before() -> None:
    ordered = in_order(
        [
            update("B", "1", 5),
            update("A", "1", None),
            update("A", "0", 2),
            update("b", "0", 5),
        ]
    )
    assert [(u.name, u.value) for u in ordered.changes] == [
        ("A", "0"),
        ("B", "1"),
        ("A", "1"),
        ("b", "0"),
    ]
    assert [[u.value for u in state] for state in states(ordered.changes)] == [
        ["0", "1"],
        ["1", "0"],
    ]


def test_the_bound_keeps_the_first_and_the_last() -> None:
    chattering = [update("A", str(value), 0) for value in range(10)]
    ordered = in_order([*chattering, update("B", "x", 0)], most=4)
    assert [u.value for u in ordered.changes] == ["0", "1", "2", "9", "x"]
    assert ordered.collapsed == 6
    assert in_order(chattering, most=1).changes == [chattering[-1]]
