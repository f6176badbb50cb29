"""Buttons: a press writes true to a flag, 1 to an integer, and nothing is read.

The demo's buttons are a gateway's (an intercom's call, ``test_init_tekon``);
here the platform's entity is made of a writable point of the simulated PLC.
"""

from typing import TYPE_CHECKING

from homeassistant.core import HomeAssistant
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.tecoapi.button import PlcButton
from tests.simulator import Simulator

if TYPE_CHECKING:
    from custom_components.tecoapi.coordinator import PlcCoordinator


async def test_a_press_writes_true_or_one(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    coordinator: PlcCoordinator = demo_entry.runtime_data
    descriptions = coordinator.data.descriptions
    assert simulator.get_value("lights[3].value") is False
    simulator.set_value("ventilation.fanSpeed.value", 0)

    for key in ("lights[3]", "ventilation.fanspeed"):
        await PlcButton(coordinator, descriptions[key]).async_press()

    assert simulator.get_value("lights[3].value") is True
    assert simulator.get_value("ventilation.fanSpeed.value") == 1
