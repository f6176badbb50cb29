"""The one write path: a write is shown once, a refusal names its point.

Against the simulated PLC over HTTP (the demo program): a write's push of what
the PLC acknowledged and its read-back reach the entities in one update of the
coordinator, so each entity writes its state once per command; a snapshot
shown while a write is under way waits for it. An error names the point of a
batch the source refused, by its key, path, address or a member within it.
"""

from typing import Any, Final
from unittest.mock import patch

from homeassistant.core import HomeAssistant
from homeassistant.exceptions import HomeAssistantError, ServiceValidationError
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.tecoapi.coordinator import PlcCoordinator
from custom_components.tecoapi.pyplc import DataType, Point, ValueKind
from custom_components.tecoapi.pyplc.core.appliances import Batch, MissingPointError
from custom_components.tecoapi.writer import refused_key
from tests.components.tecoapi.conftest import StateWrites
from tests.components.tecoapi.typed import call, typed
from tests.simulator import Simulator

SETPOINT: Final = "number.heating_living_room_setpoint"
OUTSIDE: Final = "sensor.tecomat_cp_2080_outside_temperature"
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


async def test_what_is_shown_during_a_write_waits_for_it(
    hass: HomeAssistant,
    simulator: Simulator,
    demo_entry: MockConfigEntry,
    state_writes: StateWrites,
) -> None:
    """A snapshot shown while a write is under way is shown with its read-back."""
    coordinator: PlcCoordinator = demo_entry.runtime_data
    source = coordinator.source
    simulator.set_value("outsideTemp.value", -3.5)
    write = source.write
    seen: list[str] = []

    async def write_and_hear_a_change(key: str, value: Any) -> Any:
        read = await source.read_points(["outsidetemp"])
        assert read is not None
        coordinator.async_show(read)
        seen.append(hass.states.get(OUTSIDE).state)
        return await write(key, value)

    heard = _updates(coordinator)
    assert not coordinator.writer.holds(frozenset({"outsidetemp"}))
    with patch.object(source, "write", write_and_hear_a_change):
        await coordinator.async_write(LIVING, 23.0)

    assert seen == ["4.5"]
    assert hass.states.get(OUTSIDE).state == "-3.5"
    assert hass.states.get(SETPOINT).state == "23.0"
    assert len(heard) == 1
    assert state_writes == {OUTSIDE: 1, SETPOINT: 1}


async def test_a_failed_write_shows_what_was_heard_meanwhile(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    """A write the PLC refuses still lets a change heard during it show."""
    coordinator: PlcCoordinator = demo_entry.runtime_data
    source = coordinator.source
    simulator.set_value("outsideTemp.value", -3.5)
    write = source.write

    async def hear_then_fail(key: str, value: Any) -> Any:
        read = await source.read_points(["outsidetemp"])
        assert read is not None
        coordinator.async_show(read)
        simulator.faults.http_500 = True
        return await write(key, value)

    with (
        patch.object(source, "write", hear_then_fail),
        pytest.raises(HomeAssistantError) as raised,
    ):
        await coordinator.async_write(LIVING, 23.0)

    assert raised.value.translation_key == "write_failed"
    assert hass.states.get(OUTSIDE).state == "-3.5"
    assert hass.states.get(SETPOINT).state == "21.5"


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
