"""TecoApi's batches against the simulated PLC over HTTP.

SetObject carries ``name1=val1&name2=val2`` within 256 characters and PutObject
``{"name": value, ...}`` (the manual): consecutive writes of one form share a
request, in the order given; one GetObject plan reads the batch back. Every
value is validated with the latest attributes before anything is sent, and a
refusal of the PLC names the variable it named.
"""

from collections.abc import Callable
from datetime import timedelta
from typing import Any

import aiohttp
import pytest

from custom_components.tecoapi.pyplc import (
    OutOfRangeError,
    ReadOnlyError,
    Snapshot,
    ValueRejectedError,
)
from custom_components.tecoapi.pyplc.tecomat import TecoApiSession
from custom_components.tecoapi.pyplc.tecomat.tecoapi.paths import MAX_TARGET_LENGTH
from tests.pyplc.conftest import Clock, make_client
from tests.simulator import Simulator

LIVING = "heating.livingsetpoint"
BEDROOM = "heating.bedroomsetpoint"
BOILER = "heating.boileron"
MESSAGE = "displaymessage"
ALARM = "alarmarmed"
NOTE = "installernote"
LIGHT_NAME = "obyvak_strop_gtsap1_light_name"
POLLED = frozenset({LIVING, BEDROOM})


@pytest.fixture
def demo_session(
    session: aiohttp.ClientSession, simulator: Simulator
) -> TecoApiSession:
    """A session of the demo simulator, planning on the event loop (no executor)."""
    return TecoApiSession(
        make_client(session, simulator),
        metadata_interval=timedelta(seconds=60),
        clock=Clock(),
        run_blocking=_at_once,
    )


async def _at_once(job: Callable[[], Any]) -> Any:
    return job()


def _services(simulator: Simulator) -> list[str]:
    return [request.service for request in simulator.requests if request.authorized]


async def test_members_go_in_one_setobject_and_come_back_in_one_getobject(
    demo_session: TecoApiSession, simulator: Simulator
) -> None:
    await demo_session.poll(POLLED)
    pushed: list[Snapshot] = []
    demo_session.subscribe(pushed.append)
    simulator.clear_requests()

    confirmed = await demo_session.write_many(
        {LIVING: 22.5, BEDROOM: 20.0, BOILER: False}
    )

    assert _services(simulator) == ["SetObject", "GetObject"]
    assert simulator.requests[-2].query.count("&") == 2
    assert simulator.get_value("Heating.livingSetpoint.value") == 22.5
    assert simulator.get_value("Heating.bedroomSetpoint.value") == 20.0
    assert simulator.get_value("Heating.boilerOn.value") is False
    assert [snapshot.values for snapshot in pushed] == [
        {LIVING: 22.5, BEDROOM: 20.0, BOILER: False}
    ]
    assert confirmed is not None
    assert confirmed.values == {LIVING: 22.5, BEDROOM: 20.0, BOILER: False}
    assert demo_session.statistics.writes == 3


async def test_top_level_variables_share_one_putobject_and_forms_keep_their_order(
    demo_session: TecoApiSession, simulator: Simulator
) -> None:
    await demo_session.poll(POLLED)
    simulator.clear_requests()

    await demo_session.write_many({ALARM: True, NOTE: "Serviced today"})
    assert _services(simulator) == ["PutObject", "GetObject"]
    assert simulator.get_value("alarmArmed") is True
    assert simulator.get_value("installerNote") == "Serviced today"

    simulator.clear_requests()
    await demo_session.write_many({LIVING: 23.0, ALARM: False, BEDROOM: 18.0})
    assert _services(simulator) == ["SetObject", "PutObject", "SetObject", "GetObject"]
    assert simulator.get_value("alarmArmed") is False
    assert simulator.get_value("Heating.bedroomSetpoint.value") == 18.0


async def test_a_setobject_stays_within_256_characters(
    demo_session: TecoApiSession, simulator: Simulator
) -> None:
    await demo_session.poll(POLLED)
    simulator.clear_requests()
    spaced = " " * 60  # each space is %20 in the query

    await demo_session.write_many({MESSAGE: spaced, LIVING: 24.0, BEDROOM: 21.0})

    assert _services(simulator) == ["SetObject", "SetObject", "GetObject"]
    first, second = simulator.requests[0], simulator.requests[1]
    assert first.query.count("&") == 0
    assert second.query.count("&") == 1
    for request in (first, second):
        assert len(f"/TecoApi/SetObject?{request.query}") <= MAX_TARGET_LENGTH
    assert simulator.get_value("displayMessage.value") == spaced
    assert simulator.get_value("Heating.bedroomSetpoint.value") == 21.0


async def test_the_plc_refusing_one_of_a_putobject_names_that_variable(
    demo_session: TecoApiSession, simulator: Simulator
) -> None:
    await demo_session.poll(POLLED)
    held = simulator.get_value("alarmArmed")

    with pytest.raises(ValueRejectedError) as raised:
        # The light's name is a STRING[32]: the PLC refuses 40 characters.
        await demo_session.write_many({ALARM: not held, LIGHT_NAME: "x" * 40})

    assert raised.value.path == "OBYVAK_STROP_GTSAP1_LIGHT_name"
    assert "at most 32 characters" in str(raised.value)
    # The simulated PLC writes a request's variables all or none.
    assert simulator.get_value("alarmArmed") == held


async def test_a_batch_is_validated_with_the_latest_attributes_before_sending(
    session: aiohttp.ClientSession, simulator: Simulator
) -> None:
    clock = Clock()
    source = TecoApiSession(
        make_client(session, simulator),
        metadata_interval=timedelta(seconds=60),
        clock=clock,
        run_blocking=_at_once,
    )
    await source.poll(POLLED)
    simulator.set_value("Heating.bedroomSetpoint.attr.readOnly", True)
    simulator.set_value("Heating.livingSetpoint.attr.maxValue", 22.0)
    clock.tick(60)
    await source.poll(POLLED)
    simulator.clear_requests()

    with pytest.raises(ReadOnlyError):
        await source.write_many({LIVING: 21.0, BEDROOM: 20.0})
    with pytest.raises(OutOfRangeError):
        await source.write_many({ALARM: True, LIVING: 25.0})

    assert simulator.requests == []
    assert source.statistics.writes == 0
