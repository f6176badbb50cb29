"""The options flow: its form's defaults, what it stores, and the intervals it refuses."""

from homeassistant.const import CONF_HOST, CONF_PORT, CONF_SCAN_INTERVAL
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType, InvalidData
import pytest

from custom_components.tecoapi.const import (
    CONF_ATTRIBUTE_INTERVAL,
    CONF_DEVICES,
    CONF_EXCLUDE,
    CONF_INCLUDE,
    CONF_PLAIN_VARIABLES,
    CONF_PUSH,
)
from tests.components.tecoapi.conftest import make_entry, open_settings
from tests.simulator import Simulator

pytestmark = pytest.mark.usefixtures("mock_setup_entry")


async def test_options_flow_defaults_and_save(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    """Options show their defaults and store what the user chose."""
    entry = make_entry(simulator)
    entry.add_to_hass(hass)

    result = await open_settings(hass, entry.entry_id)
    assert result["type"] is FlowResultType.FORM
    assert result["step_id"] == "tecoapi"
    suggested = {
        str(key): (key.description or {}).get("suggested_value")
        for key in result["data_schema"].schema
    }
    assert suggested == {
        CONF_SCAN_INTERVAL: 5,
        CONF_ATTRIBUTE_INTERVAL: 60,
        CONF_PLAIN_VARIABLES: "disabled",
        CONF_INCLUDE: [],
        CONF_EXCLUDE: [],
        CONF_DEVICES: "groups_and_areas",
        CONF_PUSH: None,
    }
    push = result["data_schema"].schema[CONF_PUSH]
    assert push.options == {"collapsed": True}  # push is off: folded away
    assert {
        str(key): (key.description or {}).get("suggested_value")
        for key in push.schema.schema
    } == {CONF_HOST: "", CONF_PORT: 5010}

    result = await hass.config_entries.options.async_configure(
        result["flow_id"],
        {
            CONF_SCAN_INTERVAL: 2.0,
            CONF_ATTRIBUTE_INTERVAL: 30.0,
            CONF_PLAIN_VARIABLES: "ignored",
            CONF_INCLUDE: ["Heating.*", "  ", "Rooms.*"],
            CONF_EXCLUDE: ["*Debug*"],
            CONF_DEVICES: "single",
            CONF_PUSH: {CONF_PORT: 5010},
        },
    )

    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert entry.options == {
        CONF_SCAN_INTERVAL: 2,
        CONF_ATTRIBUTE_INTERVAL: 30,
        CONF_PLAIN_VARIABLES: "ignored",
        CONF_INCLUDE: ["heating.*", "rooms.*"],
        CONF_EXCLUDE: ["*debug*"],
        CONF_DEVICES: "single",
        CONF_PUSH: {CONF_HOST: "", CONF_PORT: 5010},
        # Where the release before reads push (off), in step (test_init_upgrade).
        "plccoms_host": "",
        "plccoms_port": 5010,
    }


@pytest.mark.parametrize(
    ("field", "value"),
    [(CONF_SCAN_INTERVAL, 0), (CONF_SCAN_INTERVAL, 301), (CONF_ATTRIBUTE_INTERVAL, 1)],
)
async def test_options_flow_refuses_intervals_out_of_range(
    hass: HomeAssistant, simulator: Simulator, field: str, value: int
) -> None:
    """Polling 1 to 300 s; attribute refresh at least 5 s; nothing stored otherwise."""
    entry = make_entry(simulator)
    entry.add_to_hass(hass)
    result = await open_settings(hass, entry.entry_id)
    options = {
        CONF_SCAN_INTERVAL: 5,
        CONF_ATTRIBUTE_INTERVAL: 60,
        CONF_PLAIN_VARIABLES: "disabled",
        field: value,
    }

    with pytest.raises(InvalidData):
        await hass.config_entries.options.async_configure(result["flow_id"], options)

    assert entry.options == {}
