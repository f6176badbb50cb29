"""What a user sets moving: shown on its way at once, and followed there every second.

The demo's blinds move 20 % a second (the simulator's links move them over time,
on the frozen clock), as real blinds do: a blind written a new target is closing
or opening from the write on, its points alone are read every second until it
arrives, and the steady poll (60 s here, so that no poll falls in between) keeps
its interval. Counts and states are exact: time passes only when a test says so.
"""

from collections.abc import Awaitable
from typing import Any
from unittest.mock import patch

from freezegun.api import FrozenDateTimeFactory
from homeassistant.components.cover import ATTR_CURRENT_POSITION
from homeassistant.const import CONF_SCAN_INTERVAL
from homeassistant.core import HomeAssistant
from homeassistant.util import dt as dt_util
import pytest
from pytest_homeassistant_custom_component.common import (
    MockConfigEntry,
    async_fire_time_changed,
)

from custom_components.tecoapi.motion import MOTION_READS
from tests.components.tecoapi.conftest import (
    FROZEN_TIME,
    entity_id_of,
    make_entry,
    poll,
    setup_entry,
)
from tests.simulator import Simulator

SERIAL = "SD 2080"
BASE = "Stineni.OBYVAK_ZALUZIE_GTSAP1_OPENER"
BLIND_POINTS = {f"{BASE}_{prop}" for prop in ("current", "target", "moving")}
RATE = 20.0
"""The blinds' speed: % a second."""


async def set_up_moving(
    hass: HomeAssistant,
    simulator: Simulator,
    freezer: FrozenDateTimeFactory,
    scan_interval: int = 60,
) -> MockConfigEntry:
    """The demo, polled every ``scan_interval`` s, its blinds moving on the frozen clock."""
    freezer.move_to(FROZEN_TIME)
    simulator.link_motion.rate = RATE
    simulator.link_motion.clock = lambda: dt_util.utcnow().timestamp()
    return await setup_entry(
        hass, make_entry(simulator, **{CONF_SCAN_INTERVAL: scan_interval})
    )


@pytest.fixture
async def moving_entry(
    hass: HomeAssistant, simulator: Simulator, freezer: FrozenDateTimeFactory
) -> MockConfigEntry:
    """The demo, polled every minute, its blinds moving on the frozen clock."""
    return await set_up_moving(hass, simulator, freezer)


def blind(hass: HomeAssistant) -> str:
    """The living room blind (open, 100 %)."""
    return entity_id_of(hass, "cover", f"{SERIAL}_gtsap1:opener:stineni.obyvak_zaluzie")


async def call(hass: HomeAssistant, service: str, **data: Any) -> None:
    """Call a cover action and wait for it."""
    await hass.services.async_call("cover", service, data, blocking=True)


def shown(hass: HomeAssistant, entity_id: str) -> tuple[str, int]:
    """A cover's state and position."""
    state = hass.states.get(entity_id)
    assert state is not None
    return state.state, state.attributes[ATTR_CURRENT_POSITION]


def blind_reads(simulator: Simulator) -> int:
    """How many requests since the last clear were one GetObject of the blind alone.

    One request, whichever names the planner finds cheapest (the blinds' group,
    ``Stineni``, holds them in fewer items than a poll reads), and not a poll.
    """

    def reads_the_blind(query: str) -> bool:
        names = query.split("&")
        return len(names) <= len(BLIND_POINTS) and all(
            any(point == name or point.startswith(f"{name}.") for name in names)
            for point in BLIND_POINTS
        )

    return sum(
        request.service == "GetObject" and reads_the_blind(request.query)
        for request in simulator.requests
    )


@pytest.mark.parametrize(
    ("service", "data", "start", "path"),
    [
        ("close_cover", {}, 100, [80, 60, 40, 20, 0]),
        ("set_cover_position", {"position": 60}, 0, [20, 40, 60]),
    ],
    ids=["closing", "opening"],
)
async def test_a_blind_is_on_its_way_at_once_and_followed_every_second(
    hass: HomeAssistant,
    simulator: Simulator,
    moving_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
    *,
    service: str,
    data: dict[str, Any],
    start: int,
    path: list[int],
) -> None:
    """Closing (opening) from the click; one read of its points a second; then none."""
    entity_id = blind(hass)
    if start != 100:
        simulator.set_value(f"{BASE}_target", start)
        simulator.set_value(f"{BASE}_current", start)
        await poll(hass, freezer, 60)
    direction = "closing" if path[-1] < start else "opening"

    await call(hass, service, entity_id=entity_id, **data)

    # The PLC has not moved it yet: on its way all the same.
    assert shown(hass, entity_id) == (direction, start)
    simulator.clear_requests()
    seen = []
    for _ in path:
        await poll(hass, freezer, 1)
        seen.append(shown(hass, entity_id))
    expected_end = "closed" if path[-1] == 0 else "open"
    assert seen == [
        *((direction, position) for position in path[:-1]),
        (expected_end, path[-1]),
    ]
    # Its own points only, once a second: no poll, no GetInfo.
    assert blind_reads(simulator) == len(simulator.requests) == len(path)

    # There: nothing more is read until the next poll.
    simulator.clear_requests()
    for _ in range(5):
        await poll(hass, freezer, 1)
    assert simulator.requests == []


async def test_a_blind_stopped_on_its_way_is_no_longer_followed(
    hass: HomeAssistant,
    simulator: Simulator,
    moving_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """Stop writes where it is as its target: it is there, nothing is read."""
    entity_id = blind(hass)
    await call(hass, "close_cover", entity_id=entity_id)
    await poll(hass, freezer, 1)
    await poll(hass, freezer, 1)
    assert shown(hass, entity_id) == ("closing", 60)

    await call(hass, "stop_cover", entity_id=entity_id)

    assert simulator.get_value(f"{BASE}_target") == 60
    assert shown(hass, entity_id) == ("open", 60)
    simulator.clear_requests()
    for _ in range(5):
        await poll(hass, freezer, 1)
    assert simulator.requests == []
    assert simulator.get_value(f"{BASE}_current") == 60


async def test_a_blind_that_never_arrives_is_followed_for_two_minutes(
    hass: HomeAssistant,
    simulator: Simulator,
    moving_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """A blind far slower than expected: MOTION_READS reads, then the polls alone."""
    simulator.link_motion.rate = 0.1
    entity_id = blind(hass)
    await call(hass, "close_cover", entity_id=entity_id)
    simulator.clear_requests()

    for _ in range(MOTION_READS + 5):
        await poll(hass, freezer, 1)

    # The blind's reads, and the two minutes' polls.
    assert blind_reads(simulator) == MOTION_READS
    assert len(simulator.requests) > MOTION_READS
    assert shown(hass, entity_id)[0] == "closing"
    simulator.clear_requests()
    await poll(hass, freezer, 1)
    assert simulator.requests == []


async def test_a_failed_read_leaves_the_blind_to_the_polls(
    hass: HomeAssistant,
    simulator: Simulator,
    moving_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """The PLC does not answer the read: no more reads; the polls tell the rest."""
    entity_id = blind(hass)
    await call(hass, "close_cover", entity_id=entity_id)
    simulator.faults.http_500 = True
    simulator.clear_requests()

    await poll(hass, freezer, 1)
    failed = len(simulator.requests)
    simulator.faults.clear()
    for _ in range(3):
        await poll(hass, freezer, 1)

    assert failed >= 1
    assert len(simulator.requests) == failed
    assert shown(hass, entity_id)[0] == "closing"


async def test_following_stops_when_the_entry_unloads(
    hass: HomeAssistant,
    simulator: Simulator,
    moving_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """No read after the entry is unloaded (and no timer left behind)."""
    await call(hass, "close_cover", entity_id=blind(hass))
    await poll(hass, freezer, 1)

    assert await hass.config_entries.async_unload(moving_entry.entry_id)
    simulator.clear_requests()
    for _ in range(3):
        await poll(hass, freezer, 1)

    assert simulator.requests == []


async def test_a_read_of_what_moves_and_a_poll_take_turns(
    hass: HomeAssistant, simulator: Simulator, freezer: FrozenDateTimeFactory
) -> None:
    """While a read of the blind is under way, neither another one nor a poll starts.

    Each shows what it read in the order it read it: nothing is lost or shown
    older than it is. (Polled every 2 s: the hung read must not time out.)
    """
    entry = await set_up_moving(hass, simulator, freezer, scan_interval=2)
    entity_id = blind(hass)
    coordinator = entry.runtime_data
    source = coordinator.source
    await call(hass, "close_cover", entity_id=entity_id)
    simulator.faults.hang = True
    simulator.clear_requests()
    freezer.tick(1)
    async_fire_time_changed(hass)
    await simulator.wait_for_hung_requests(1)  # the blind's read, under way

    polled: list[object] = []
    started = hass.loop.create_future()
    update = coordinator._async_update_data  # its own, spied on below
    poll_source = source.poll

    async def starting_update() -> Any:
        if not started.done():
            started.set_result(None)
        return await update()

    def recording_poll(keys: Any) -> Awaitable[Any]:
        polled.append(keys)
        return poll_source(keys)

    with (
        # Home Assistant's hook of a refresh (tests/test_seam.py allows it).
        patch.object(coordinator, "_async_update_data", starting_update),
        patch.object(source, "poll", recording_poll),
    ):
        # A second more: no second read of the blind, and the poll is due: it
        # starts, and waits for the read.
        freezer.tick(1)
        async_fire_time_changed(hass)
        await started
        assert polled == []
        assert len(simulator.requests) == 1

        simulator.faults.hang = False
        await hass.async_block_till_done(wait_background_tasks=True)

    assert len(polled) == 1
    assert blind_reads(simulator) >= 1
    assert shown(hass, entity_id) == ("closing", simulator.get_value(f"{BASE}_current"))
