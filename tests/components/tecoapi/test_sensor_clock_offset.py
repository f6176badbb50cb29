"""The PLC's clock, shown as its offset from Home Assistant's clock.

The offset stays the same while both clocks run in step, so the sensor writes no
state (no logbook entry, no recorder row) when GetInfo reports a later PLC time.
"""

from collections.abc import Iterator
from datetime import UTC, datetime, timedelta
from typing import Any
from unittest.mock import patch

from freezegun.api import FrozenDateTimeFactory
from homeassistant.components.logbook.helpers import is_sensor_continuous
from homeassistant.components.sensor import SensorDeviceClass, SensorStateClass
from homeassistant.const import (
    ATTR_DEVICE_CLASS,
    ATTR_UNIT_OF_MEASUREMENT,
    EVENT_STATE_CHANGED,
    EntityCategory,
)
from homeassistant.core import Event, HomeAssistant
from homeassistant.helpers import entity_registry as er
import pytest
from pytest_homeassistant_custom_component.common import (
    MockConfigEntry,
    async_capture_events,
)

from custom_components.tecoapi.const import DOMAIN
from custom_components.tecoapi.data import shown_clock_offset
from custom_components.tecoapi.pyplc.tecomat.tecoapi.info import parse_plc_info
from tests.components.tecoapi.conftest import (
    FROZEN_TIME,
    StateWrites,
    poll,
    setup_entry,
)
from tests.simulator import Simulator, services

CLOCK_OFFSET = "sensor.tecomat_cp_2080_clock_offset"


class PlcClock:
    """How far the simulated PLC's clock runs ahead of the real time."""

    def __init__(self) -> None:
        self.ahead = timedelta()


@pytest.fixture
def plc_clock() -> Iterator[PlcClock]:
    """Set the simulated PLC's clock: GetInfo prints the real time plus ``ahead``."""
    clock = PlcClock()
    print_time = services.plc_time

    def plc_time(moment: datetime) -> str:
        return print_time(moment + clock.ahead)

    with patch.object(services, "plc_time", plc_time):
        yield clock


def offset_state_changes(events: list[Event[Any]]) -> list[str]:
    """The clock offset's new states among state changes (what logbook and recorder get)."""
    return [
        event.data["new_state"].state
        for event in events
        if event.data["entity_id"] == CLOCK_OFFSET
    ]


async def set_up_at_frozen_time(
    hass: HomeAssistant,
    config_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """Set the demo entry up with Home Assistant's clock frozen."""
    freezer.move_to(FROZEN_TIME)
    await setup_entry(hass, config_entry)


@pytest.mark.usefixtures("demo_entry")
async def test_clock_offset_is_a_diagnostic_duration(hass: HomeAssistant) -> None:
    """Seconds, a measurement, diagnostic, enabled; the logbook leaves it out."""
    registry = er.async_get(hass)
    state = hass.states.get(CLOCK_OFFSET)

    assert state.state == "0"
    assert state.name == "Tecomat CP-2080 Clock offset"
    assert state.attributes[ATTR_UNIT_OF_MEASUREMENT] == "s"
    assert state.attributes[ATTR_DEVICE_CLASS] == SensorDeviceClass.DURATION
    assert state.attributes["state_class"] == SensorStateClass.MEASUREMENT
    entry = registry.async_get(CLOCK_OFFSET)
    assert entry is not None
    assert entry.entity_category is EntityCategory.DIAGNOSTIC
    assert entry.disabled_by is None
    assert entry.unique_id == "SD 2080_plc-clock-offset"
    assert is_sensor_continuous(hass, registry, CLOCK_OFFSET)


@pytest.mark.usefixtures("demo_entry")
async def test_clock_in_step_writes_no_state(
    hass: HomeAssistant,
    simulator: Simulator,
    freezer: FrozenDateTimeFactory,
    state_writes: StateWrites,
) -> None:
    """Two GetInfos a minute apart, the PLC's time a minute later: nothing written."""
    events = async_capture_events(hass, EVENT_STATE_CHANGED)
    simulator.clear_requests()

    await poll(hass, freezer, 60)
    await poll(hass, freezer, 60)

    assert [request.service for request in simulator.requests].count("GetInfo") == 2
    assert hass.states.get(CLOCK_OFFSET).state == "0"
    assert state_writes[CLOCK_OFFSET] == 0
    assert offset_state_changes(events) == []


async def test_a_wrong_plc_clock_shows_its_offset(
    hass: HomeAssistant,
    config_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
    plc_clock: PlcClock,
) -> None:
    """90 s ahead shows 90; setting the PLC's clock shows the new offset once.

    The simulated program changes no value, so every poll is quiet and reads
    GetInfo (it checks the PLC's mode): the new offset shows on the next poll.
    """
    plc_clock.ahead = timedelta(seconds=90)
    await set_up_at_frozen_time(hass, config_entry, freezer)
    assert hass.states.get(CLOCK_OFFSET).state == "90"
    events = async_capture_events(hass, EVENT_STATE_CHANGED)

    plc_clock.ahead = timedelta(seconds=-42)
    await poll(hass, freezer, 5)
    assert hass.states.get(CLOCK_OFFSET).state == "-42"
    await poll(hass, freezer, 55)
    await poll(hass, freezer, 60)

    assert hass.states.get(CLOCK_OFFSET).state == "-42"
    assert offset_state_changes(events) == ["-42"]


async def test_an_offset_on_the_edge_of_a_second_does_not_flip(
    hass: HomeAssistant,
    config_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
    plc_clock: PlcClock,
) -> None:
    """Measurements around half a second keep the offset shown until it moves by one."""
    plc_clock.ahead = timedelta(seconds=0.45)
    await set_up_at_frozen_time(hass, config_entry, freezer)
    assert hass.states.get(CLOCK_OFFSET).state == "0"
    events = async_capture_events(hass, EVENT_STATE_CHANGED)

    for ahead in (0.55, 0.45, 0.55, 0.95):
        plc_clock.ahead = timedelta(seconds=ahead)
        await poll(hass, freezer, 60)
    assert offset_state_changes(events) == []

    plc_clock.ahead = timedelta(seconds=1.2)
    await poll(hass, freezer, 60)
    assert offset_state_changes(events) == ["1"]


async def test_the_former_plc_clock_sensor_is_removed(
    hass: HomeAssistant,
    simulator: Simulator,
    config_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """The timestamp sensor of earlier versions leaves no orphaned registry entry."""
    registry = er.async_get(hass)
    config_entry.add_to_hass(hass)
    former = registry.async_get_or_create(
        "sensor",
        DOMAIN,
        f"{simulator.serial_number}_plc-clock",
        config_entry=config_entry,
        suggested_object_id="tecomat_cp_2080_plc_clock",
    )
    freezer.move_to(FROZEN_TIME)

    await hass.config_entries.async_setup(config_entry.entry_id)
    await hass.async_block_till_done()

    assert registry.async_get(former.entity_id) is None
    assert hass.states.get(CLOCK_OFFSET).state == "0"


def plc_info_at(time: str | None) -> Any:
    """GetInfo as parsed, with the PLC's time as printed (None: no time)."""
    body: dict[str, Any] = {"plc": {"serialNumber": "SD 2080", "mode": "RUN"}}
    if time is not None:
        body["plc"]["time"] = time
    return parse_plc_info(body)


RECEIVED = datetime(2026, 3, 14, 10, 0, 0, tzinfo=UTC)


@pytest.mark.parametrize(
    ("plc_time", "shown", "expected"),
    [
        ("2026-03-14T10:00:00.400Z", None, 0),
        ("2026-03-14T10:00:00.600Z", None, 1),
        ("2026-03-14T09:59:59.400Z", None, -1),
        ("2026-03-14T10:01:30.000Z", None, 90),
        ("2026-03-14T10:00:00.990Z", 0, 0),
        ("2026-03-14T09:59:59.010Z", 0, 0),
        ("2026-03-14T10:00:01.000Z", 0, 1),
        ("2026-03-14T10:00:00.200Z", 1, 1),
        ("2026-03-14T09:59:59.900Z", 1, 0),
        ("2026-03-14T10:01:30.000Z", 1, 90),
        (None, 3, None),
    ],
)
def test_shown_offset_moves_by_whole_seconds(
    plc_time: str | None, shown: int | None, expected: int | None
) -> None:
    """Rounded to whole seconds; a measurement within a second keeps what is shown."""
    assert shown_clock_offset(plc_info_at(plc_time), RECEIVED, shown) == expected
