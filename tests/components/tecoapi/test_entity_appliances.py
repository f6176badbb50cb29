"""A typed device's command is one batch of writes, checked whole before anything is sent.

The typed devices' entities (lights, covers, thermostats, switches) hold the
library's appliances and send each command through the coordinator's writer
(``writer.PlcWriter.async_send``), one ``write_many`` of the source: a light
switched on at a brightness and a
colour is one batch, not three writes; a value the PLC would refuse leaves the
PLC and the entity as they were, with a translated error. A state write asks
the appliance for its state once, however many properties show it.
"""

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, cast
from unittest.mock import patch

from homeassistant.core import HomeAssistant
from homeassistant.exceptions import ServiceValidationError
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.tecoapi.const import DOMAIN
from custom_components.tecoapi.pyplc.core.appliances import (
    Appliance,
    Batch,
    Cover,
    Light,
    MissingPointError,
    Thermostat,
)
from tests.components.tecoapi.conftest import StateWrites
from tests.components.tecoapi.flows.test_subentry import compose, composed_entity
from tests.components.tecoapi.typed import call, typed
from tests.simulator import Simulator

if TYPE_CHECKING:
    from custom_components.tecoapi.climate import PlcClimate
    from custom_components.tecoapi.coordinator import PlcCoordinator

RGB = "KUCHYNE_LINKA_GTSAP1_LIGHT"
WRITES = frozenset({"SetObject", "PutObject"})


def _writes(simulator: Simulator) -> list[Any]:
    return [r for r in simulator.requests if r.service in WRITES]


async def test_brightness_and_colour_are_one_batch(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    """A light switched on at a brightness and a colour: one write_many, in order."""
    coordinator: PlcCoordinator = demo_entry.runtime_data
    source = coordinator.source
    light = typed(hass, "light", "gtsap1:light:kuchyne_linka")
    assert hass.states.get(light).state == "off"
    simulator.clear_requests()

    with (
        patch.object(source, "write_many", wraps=source.write_many) as write_many,
        patch.object(source, "write", wraps=source.write) as write,
    ):
        await call(
            hass,
            "light",
            "turn_on",
            entity_id=light,
            brightness=51,
            rgb_color=(255, 128, 1),
        )

    write_many.assert_awaited_once()
    (batch,) = write_many.await_args.args
    prefix = RGB.lower()
    assert list(batch.items()) == [
        (f"{prefix}_rgb", 255 + 128 * 256 + 65536),
        (f"{prefix}_dimlevel", 20.0),
        (f"{prefix}_onoff", True),
    ]
    # Nothing written besides the batch: TecoApi's native batch sends its three
    # top-level variables in one PutObject, no write of its own.
    assert write.await_count == 0
    assert [request.service for request in _writes(simulator)] == ["PutObject"]
    assert simulator.get_value(f"{RGB}_rgb") == 255 + 128 * 256 + 65536
    assert simulator.get_value(f"{RGB}_dimlevel") == 20.0
    assert simulator.get_value(f"{RGB}_onoff") is True
    state = hass.states.get(light)
    assert state.state == "on"
    assert state.attributes["rgb_color"] == (255, 128, 1)
    assert state.attributes["brightness"] == 51


async def test_a_refused_value_leaves_the_plc_and_the_light_as_they_were(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    """The level beyond its point's range: nothing sent, the colour before it neither.

    A contrived lamp: its colour temperature is a setpoint of 15 to 28 (so its
    kelvin range), its level a fan speed of 0 to 3 (full brightness, 100, is
    refused). Written one by one, the colour temperature would have changed.
    """
    await compose(
        hass,
        demo_entry,
        "light",
        {
            "name": "Odd lamp",
            "onoff": "lights[3]",
            "level": "ventilation.fanspeed",
            "color_temp": "heating.livingsetpoint",
        },
    )
    light = composed_entity(hass, "light", demo_entry)
    shown = hass.states.get(light)
    assert shown.state == "off"
    assert shown.attributes["max_color_temp_kelvin"] == 28
    variables = ("lights[3].value", "ventilation.fanSpeed.value")
    variables += ("Heating.livingSetpoint.value",)
    held = [simulator.get_value(variable) for variable in variables]
    assert held[2] != 20
    simulator.clear_requests()

    with pytest.raises(ServiceValidationError) as raised:
        await call(
            hass,
            "light",
            "turn_on",
            entity_id=light,
            brightness=255,
            color_temp_kelvin=20,
        )

    assert raised.value.translation_domain == DOMAIN
    assert raised.value.translation_key == "out_of_range"
    assert _writes(simulator) == []
    assert [simulator.get_value(variable) for variable in variables] == held
    after = hass.states.get(light)
    assert (after.state, after.attributes) == (shown.state, shown.attributes)


async def test_a_role_point_gone_from_the_catalogue_is_a_translated_error(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    """A command that cannot encode a value for a missing point sends nothing."""
    climate = typed(hass, "climate", "gtsap1:thermostat:termostaty.obyvak")
    entity = cast("PlcClimate", hass.data["climate"].get_entity(climate))
    simulator.clear_requests()

    def gone() -> Batch:
        raise MissingPointError("obyvak_gtsap1_thermostat_setpoint")

    with pytest.raises(ServiceValidationError) as raised:
        await entity.async_send(gone)

    assert raised.value.translation_key == "variable_not_found"
    assert raised.value.translation_placeholders == {
        "path": "obyvak_gtsap1_thermostat_setpoint"
    }
    assert _writes(simulator) == []


async def test_a_thermostat_switched_off_and_on_is_one_batch_of_its_flags(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    """Off: every mode flag off together; on: its first mode (heat), cooling off."""
    coordinator: PlcCoordinator = demo_entry.runtime_data
    source = coordinator.source
    climate = typed(hass, "climate", "gtsap1:thermostat:termostaty.obyvak")
    base = "Termostaty.OBYVAK_GTSAP1_THERMOSTAT"
    prefix = base.lower()
    simulator.set_value(f"{base}_coolmode", True)
    entity = cast("PlcClimate", hass.data["climate"].get_entity(climate))

    with patch.object(source, "write_many", wraps=source.write_many) as write_many:
        await call(hass, "climate", "turn_off", entity_id=climate)
        await call(hass, "climate", "turn_on", entity_id=climate)
        # A temperature range alone (not this thermostat's): no setpoint written.
        await entity.async_set_temperature()

    assert [awaited.args[0] for awaited in write_many.await_args_list] == [
        {f"{prefix}_coolmode": False, f"{prefix}_heatmode": False},
        {f"{prefix}_coolmode": False, f"{prefix}_heatmode": True},
    ]
    assert simulator.get_value(f"{base}_heatmode") is True
    assert simulator.get_value(f"{base}_coolmode") is False
    assert hass.states.get(climate).state == "heat"


async def test_a_typed_switch_is_switched_by_a_batch_of_its_onoff(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    """A socket's on and off: each one batch of its ``onoff``, no write of its own."""
    coordinator: PlcCoordinator = demo_entry.runtime_data
    source = coordinator.source
    socket = typed(hass, "switch", "gtsap1:socket:terasa")
    key = "terasa_gtsap1_socket_onoff"

    with (
        patch.object(source, "write_many", wraps=source.write_many) as write_many,
        patch.object(source, "write", wraps=source.write) as write,
    ):
        await call(hass, "switch", "turn_on", entity_id=socket)
        assert hass.states.get(socket).state == "on"
        await call(hass, "switch", "turn_off", entity_id=socket)

    assert [awaited.args[0] for awaited in write_many.await_args_list] == [
        {key: True},
        {key: False},
    ]
    assert write.await_count == 0
    assert simulator.get_value("TERASA_GTSAP1_SOCKET_onoff") is False
    assert hass.states.get(socket).state == "off"


@dataclass(frozen=True, slots=True)
class Reading:
    """A typed entity, a change of one of its points, what its appliance reads."""

    domain: str
    key: str
    variable: str
    value: Any
    appliance: type[Appliance]


@pytest.mark.parametrize(
    "reading",
    [
        Reading(
            "light",
            "gtsap1:light:kuchyne_linka",
            "KUCHYNE_LINKA_GTSAP1_LIGHT_dimlevel",
            40.0,
            Light,
        ),
        Reading(
            "cover",
            "gtsap1:opener:stineni.obyvak_zaluzie",
            "Stineni.OBYVAK_ZALUZIE_GTSAP1_OPENER_current",
            55,
            Cover,
        ),
        Reading(
            "climate",
            "gtsap1:thermostat:termostaty.loznice",
            "Termostaty.LOZNICE_GTSAP1_THERMOSTAT_meastemp",
            21.5,
            Thermostat,
        ),
    ],
    ids=lambda reading: reading.domain,
)
async def test_a_state_write_computes_the_appliance_state_once(
    hass: HomeAssistant,
    simulator: Simulator,
    demo_entry: MockConfigEntry,
    state_writes: StateWrites,
    reading: Reading,
) -> None:
    """However many properties the state shows, the appliance reads its values once.

    A light's on, brightness, colour and white are one state of its appliance,
    a cover's position, closed, opening and closing too, a thermostat's
    temperatures, mode and action too.
    """
    entity = typed(hass, reading.domain, reading.key)
    simulator.set_value(reading.variable, reading.value)
    appliance = reading.appliance
    read = getattr(appliance, "state")  # noqa: B009 (each kind has its own)
    with patch.object(appliance, "state", autospec=True, side_effect=read) as state:
        await demo_entry.runtime_data.async_refresh()

    assert state_writes == {entity: 1}
    assert state.call_count == 1
