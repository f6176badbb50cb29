"""The one write path: a write is shown once, a refusal names its point.

Against the simulated PLC over HTTP (the demo program): the entities show what
the PLC acknowledged at once, and its read-back tells them nothing again when
it finds the same, so a command is one update of the coordinator and each
entity writes its state once; a read-back that finds otherwise is shown, one
that found nothing is followed by a poll. An error names the point of a batch
the source refused, by its key, path, address or a member within it.
"""

from collections.abc import Callable
from dataclasses import replace
from typing import Any, Final
from unittest.mock import patch

from homeassistant.core import HomeAssistant
from homeassistant.exceptions import ServiceValidationError
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.tecoapi.coordinator import PlcCoordinator
from custom_components.tecoapi.pyplc import DataType, Point, ValueKind
from custom_components.tecoapi.pyplc.core.appliances import Batch, MissingPointError
from custom_components.tecoapi.pyplc.core.source import Snapshot
from custom_components.tecoapi.writer import refused_key
from tests.components.tecoapi.conftest import StateWrites
from tests.components.tecoapi.typed import call, typed
from tests.simulator import Simulator

SETPOINT: Final = "number.heating_living_room_setpoint"
LIVING: Final = "heating.livingsetpoint"
WRITES: Final = frozenset({"SetObject", "PutObject"})


def _updates(coordinator: PlcCoordinator) -> list[None]:
    """Count the coordinator's updates its listeners hear from now on."""
    heard: list[None] = []
    coordinator.async_add_listener(lambda: heard.append(None))
    return heard


def _writes(simulator: Simulator) -> list[str]:
    return [r.service for r in simulator.requests if r.service in WRITES]


async def test_a_write_is_one_update_and_one_state_write(
    hass: HomeAssistant,
    simulator: Simulator,
    demo_entry: MockConfigEntry,
    state_writes: StateWrites,
) -> None:
    """The acknowledged value and the read-back reach the entity together."""
    heard = _updates(demo_entry.runtime_data)

    await call(hass, "number", "set_value", entity_id=SETPOINT, value=22.5)

    assert simulator.get_value("Heating.livingSetpoint.value") == 22.5
    assert hass.states.get(SETPOINT).state == "22.5"
    assert len(heard) == 1
    assert state_writes == {SETPOINT: 1}


async def test_a_command_is_one_update_and_one_state_write(
    hass: HomeAssistant, demo_entry: MockConfigEntry, state_writes: StateWrites
) -> None:
    """A light switched on at a brightness and a colour: one batch, one update."""
    light = typed(hass, "light", "gtsap1:light:kuchyne_linka")
    heard = _updates(demo_entry.runtime_data)

    await call(
        hass, "light", "turn_on", entity_id=light, brightness=51, rgb_color=(255, 0, 0)
    )

    assert hass.states.get(light).attributes["brightness"] == 51
    assert len(heard) == 1
    assert state_writes == {light: 1}


async def _write_reading_back(
    coordinator: PlcCoordinator,
    value: float,
    read_back: Callable[[Snapshot], Snapshot | None],
) -> None:
    """Write the living room's setpoint; the source reads back what ``read_back`` says."""
    source = coordinator.source
    write = source.write

    async def written(key: str, value: Any) -> Snapshot | None:
        confirmed = await write(key, value)
        assert confirmed is not None
        return read_back(confirmed)

    with patch.object(source, "write", written):
        await coordinator.async_write(LIVING, value)


async def test_a_read_back_that_finds_otherwise_is_shown_too(
    hass: HomeAssistant, demo_entry: MockConfigEntry, state_writes: StateWrites
) -> None:
    """The acknowledged value at once, then what the device holds: two updates."""
    coordinator: PlcCoordinator = demo_entry.runtime_data
    heard = _updates(coordinator)

    await _write_reading_back(
        coordinator,
        26.0,
        lambda confirmed: replace(confirmed, values={LIVING: 25.0}),
    )

    assert hass.states.get(SETPOINT).state == "25.0"
    assert len(heard) == 2
    assert state_writes == {SETPOINT: 2}


async def test_a_write_that_read_nothing_back_is_followed_by_a_poll(
    hass: HomeAssistant, demo_entry: MockConfigEntry
) -> None:
    coordinator: PlcCoordinator = demo_entry.runtime_data
    polls = coordinator.source.statistics.polls

    await _write_reading_back(coordinator, 23.0, lambda confirmed: None)
    await hass.async_block_till_done(wait_background_tasks=True)

    assert coordinator.source.statistics.polls == polls + 1
    assert hass.states.get(SETPOINT).state == "23.0"


async def test_a_key_that_is_no_point_is_a_variable_not_found(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    """The library refuses it before sending; the error names the key."""
    writer = demo_entry.runtime_data.writer
    simulator.clear_requests()

    for write in (
        writer.async_write("no.such.point", 1),
        writer.async_write_many({LIVING: 22.0, "no.such.point": 1}),
    ):
        with pytest.raises(ServiceValidationError) as raised:
            await write
        assert raised.value.translation_key == "variable_not_found"
        assert raised.value.translation_placeholders == {"path": "no.such.point"}

    assert _writes(simulator) == []
    assert simulator.get_value("Heating.livingSetpoint.value") == 21.5


async def test_a_point_the_library_does_not_have_is_a_variable_not_found(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    """Its own check may name the point it lacks by its key (``MissingPointError``)."""
    coordinator: PlcCoordinator = demo_entry.runtime_data

    async def lacking(values: Any) -> Snapshot | None:
        raise MissingPointError("heating.gone")

    with (
        patch.object(coordinator.source, "write_many", lacking),
        pytest.raises(ServiceValidationError) as raised,
    ):
        await coordinator.async_write_many({LIVING: 22.0, "heating.gone": 1})

    assert raised.value.translation_key == "variable_not_found"
    assert raised.value.translation_placeholders == {"path": "heating.gone"}


async def test_a_command_is_sent_and_returned(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    """What a command makes is written as one batch; an empty one sends nothing."""
    writer = demo_entry.runtime_data.writer
    simulator.clear_requests()

    assert await writer.async_send(dict) == {}
    assert _writes(simulator) == []
    assert await writer.async_send(lambda: {LIVING: 22.0}) == {LIVING: 22.0}
    assert simulator.get_value("Heating.livingSetpoint.value") == 22.0


async def test_a_command_needing_a_point_gone_sends_nothing(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    def gone() -> Batch:
        raise MissingPointError("heating.gone")

    simulator.clear_requests()
    with pytest.raises(ServiceValidationError) as raised:
        await demo_entry.runtime_data.writer.async_send(gone)

    assert raised.value.translation_key == "variable_not_found"
    assert raised.value.translation_placeholders == {"path": "heating.gone"}
    assert _writes(simulator) == []


async def test_the_actions_read_and_write_any_path(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    writer = demo_entry.runtime_data.writer

    await writer.async_write_variable("Heating.livingSetpoint.value", 20.5)

    assert await writer.async_read_variable("Heating.livingSetpoint.value") == 20.5
    assert hass.states.get(SETPOINT).state == "20.5"
    with pytest.raises(ServiceValidationError) as raised:
        await writer.async_read_variable("noSuchVariable")
    assert raised.value.translation_key == "variable_not_found"


REAL: Final = DataType(kind=ValueKind.REAL)
POINTS: Final = {
    "living": Point(key="living", path="Heating.Living", address="%R10", type=REAL),
    "bedroom": Point(key="bedroom", path="Heating.Bed", address="%R11", type=REAL),
    "bedside": Point(key="bedside", path="Heating.Bedside", address="", type=REAL),
}


@pytest.mark.parametrize(
    ("named", "refused"),
    [
        ("bedroom", "bedroom"),
        ("BEDROOM", "bedroom"),
        ("heating.bed", "bedroom"),
        ("%r11", "bedroom"),
        ("Heating.Bed.value", "bedroom"),
        ("Heating.Bedside.value", "bedside"),
        ("gone", "gone"),
        ("Heating.Other", "living"),
        (None, "living"),
    ],
)
def test_the_refused_point_is_named_by_key_path_address_or_member(
    named: str | None, refused: str
) -> None:
    """The longest path the name is within wins; nothing named: the first."""
    values = dict.fromkeys(["living", "bedroom", "bedside", "gone"], 1.0)
    assert refused_key(values, POINTS, named) == refused
