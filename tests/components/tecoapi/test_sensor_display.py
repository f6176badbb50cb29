"""A display without a known symbol: its unit variable's text, and its precision."""

from typing import Any

from homeassistant.const import ATTR_DEVICE_CLASS, ATTR_UNIT_OF_MEASUREMENT
from homeassistant.core import HomeAssistant
from homeassistant.helpers import entity_registry as er
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from tests.components.tecoapi.conftest import setup_entry
from tests.components.tecoapi.typed import typed
from tests.simulator import Program, Simulator

DISPLAY = "OBYVAK_GTSAP1_DISPLAY"


@pytest.mark.parametrize(
    ("unit", "precision", "shown_unit", "shown_precision"),
    [
        (" kWh ", 2, "kWh", 2),
        ("   ", 7, None, None),
        ("m³", 6, "m³", 6),
        ("", -1, None, None),
    ],
)
async def test_a_display_shows_its_unit_text_and_precision(
    hass: HomeAssistant,
    simulator: Simulator,
    config_entry: MockConfigEntry,
    *,
    unit: str,
    precision: int,
    shown_unit: str | None,
    shown_precision: int | None,
) -> None:
    """No symbol: the unit is the ``unit`` text, stripped; a precision of 0-6 is used."""
    source = simulator.program.to_mapping()
    variables: dict[str, Any] = source["variables"]
    variables.pop(f"{DISPLAY}_symbol")
    variables[f"{DISPLAY}_unit"] = {"type": "STRING[8]", "value": unit}
    variables[f"{DISPLAY}_precision"] = {"type": "SINT", "value": precision}
    variables[f"{DISPLAY}_value"] = {"type": "REAL", "value": 12.25}
    simulator.load_program(Program.from_mapping(source))

    await setup_entry(hass, config_entry)

    display = typed(hass, "sensor", "gtsap1:display:obyvak")
    state = hass.states.get(display)
    assert state is not None
    assert state.state == "12.25"
    assert ATTR_DEVICE_CLASS not in state.attributes
    assert state.attributes.get(ATTR_UNIT_OF_MEASUREMENT) == shown_unit
    entry = er.async_get(hass).async_get(display)
    assert entry is not None
    assert entry.options.get("sensor", {}).get("suggested_display_precision") == (
        shown_precision
    )
