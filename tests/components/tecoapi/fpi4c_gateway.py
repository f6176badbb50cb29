"""An FP-I4C gateway added in the UI with its register map, for the tests that need one.

The ``gateway`` fixture (conftest.py) is the simulated gateway
(tests/simulator/fpi4c/); ``add_gateway`` adds it through the config
flow with a real file upload, ``options_step`` opens a step of its options.
"""

from typing import Any

from homeassistant.config_entries import SOURCE_USER, ConfigEntry
from homeassistant.const import CONF_HOST
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
from homeassistant.helpers import entity_registry as er
from pytest_homeassistant_custom_component.typing import ClientSessionGenerator

from custom_components.tecoapi.const import DOMAIN
from custom_components.tecoapi.pyplc.core.descriptor import CONF_POINT_MAP
from tests.components.tecoapi.memory_house import upload
from tests.simulator.fpi4c import EXAMPLE_CSV, FpI4cSimulator

EXAMPLE = EXAMPLE_CSV.read_text(encoding="utf-8")


async def start_flow(hass: HomeAssistant) -> dict[str, Any]:
    """Open the config flow and choose the FP-I4C from its menu."""
    result = await hass.config_entries.flow.async_init(
        DOMAIN, context={"source": SOURCE_USER}
    )
    assert "fpi4c" in result["menu_options"]
    return dict(
        await hass.config_entries.flow.async_configure(
            result["flow_id"], {"next_step_id": "fpi4c"}
        )
    )


async def submit(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    result: dict[str, Any],
    form: dict[str, Any],
    csv: str = EXAMPLE,
) -> dict[str, Any]:
    """Submit the form with a fresh upload of a map."""
    file_id = await upload(hass, hass_client, "map.csv", csv)
    submitted = await hass.config_entries.flow.async_configure(
        result["flow_id"], {**form, CONF_POINT_MAP: file_id}
    )
    await hass.async_block_till_done()
    return dict(submitted)


async def add_gateway(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    gateway: FpI4cSimulator,
    csv: str = EXAMPLE,
) -> ConfigEntry:
    """Add the gateway through the config flow with its map."""
    result = await submit(
        hass, hass_client, await start_flow(hass), {CONF_HOST: gateway.url}, csv
    )
    assert result["type"] is FlowResultType.CREATE_ENTRY, result
    entry: ConfigEntry = result["result"]
    return entry


def entity_ids(hass: HomeAssistant, entry: ConfigEntry) -> dict[str, str]:
    """The entry's entity IDs by point key."""
    prefix = f"{entry.unique_id}_"
    return {
        item.unique_id.removeprefix(prefix): item.entity_id
        for item in er.async_entries_for_config_entry(
            er.async_get(hass), entry.entry_id
        )
    }


def state(hass: HomeAssistant, entity_id: str) -> str:
    """An entity's state, which must be there."""
    found = hass.states.get(entity_id)
    assert found is not None, entity_id
    return found.state


async def options_step(hass: HomeAssistant, entry: ConfigEntry, step: str) -> Any:
    """Open the entry's options and choose a step of the menu."""
    result = await hass.config_entries.options.async_init(entry.entry_id)
    assert result["type"] is FlowResultType.MENU
    return await hass.config_entries.options.async_configure(
        result["flow_id"], {"next_step_id": step}
    )
