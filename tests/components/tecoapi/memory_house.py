"""The memory house: every platform, driven by the in-memory source (no network).

The memory source (``tests/fake_source.py``) serves a small house from a CSV
map: plain points of every kind, and GTSAP1 families the library types as a
light, a blind, a thermostat and a button. The ``house`` fixture (conftest.py)
sets it up; these helpers find its entities and drive them. The ``memory``
fixture (conftest.py) offers the source in the config flow, where ``add_house``
adds the house as a user would.
"""

from typing import Any

from homeassistant.config_entries import SOURCE_USER
from homeassistant.const import ATTR_ENTITY_ID, CONF_HOST
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
from homeassistant.helpers import entity_registry as er
from pytest_homeassistant_custom_component.typing import ClientSessionGenerator

from custom_components.tecoapi.const import DOMAIN
from custom_components.tecoapi.pyplc.core.descriptor import CONF_POINT_MAP
from tests.components.tecoapi import file_upload
from tests.fake_source import HOUSE_CSV, NAME, house_device

IDENTITY = "MEM-0001"


def entity(hass: HomeAssistant, domain: str, key: str) -> str:
    """The entity ID of a point or typed device of the house."""
    entity_id = er.async_get(hass).async_get_entity_id(
        domain, DOMAIN, f"{IDENTITY}_{key}"
    )
    assert entity_id is not None, key
    return entity_id


def state(hass: HomeAssistant, domain: str, key: str) -> Any:
    """The state of a point or typed device of the house."""
    found = hass.states.get(entity(hass, domain, key))
    assert found is not None
    return found


async def call(
    hass: HomeAssistant, domain: str, service: str, key: str, **data: Any
) -> None:
    """Call an action on a point or typed device of the house and wait for it."""
    await hass.services.async_call(
        domain,
        service,
        {ATTR_ENTITY_ID: entity(hass, domain, key), **data},
        blocking=True,
    )


async def upload(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, name: str, text: str
) -> str:
    """Upload a point map (CSV) as the frontend does; return its ID."""
    return await file_upload.upload(hass, hass_client, name, text, "text/csv")


async def start_memory_flow(hass: HomeAssistant) -> dict[str, Any]:
    """Open the config flow and choose the memory source from its menu."""
    result = await hass.config_entries.flow.async_init(
        DOMAIN, context={"source": SOURCE_USER}
    )
    assert result["type"] is FlowResultType.MENU
    assert NAME in result["menu_options"]
    return await hass.config_entries.flow.async_configure(
        result["flow_id"], {"next_step_id": NAME}
    )


async def add_house(
    hass: HomeAssistant, hass_client: ClientSessionGenerator
) -> dict[str, Any]:
    """Add the memory house through the config flow, as a user would."""
    house_device()
    result = await start_memory_flow(hass)
    file_id = await upload(hass, hass_client, "house.csv", HOUSE_CSV)
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {CONF_HOST: "MEM-0001", CONF_POINT_MAP: file_id}
    )
    await hass.async_block_till_done()
    return result


def entity_ids(hass: HomeAssistant, entry_id: str) -> dict[str, str]:
    """The entry's entity IDs by point key (unique ID without the identity)."""
    registry = er.async_get(hass)
    return {
        entity.unique_id.removeprefix("MEM-0001_"): entity.entity_id
        for entity in er.async_entries_for_config_entry(registry, entry_id)
    }


async def open_options(hass: HomeAssistant, entry_id: str) -> dict[str, Any]:
    """Open the options of an entry of the memory source: its menu."""
    result = await hass.config_entries.options.async_init(entry_id)
    assert result["type"] is FlowResultType.MENU
    assert result["menu_options"] == [
        "settings",
        "upload",
        "add_point",
        "edit_point",
        "remove_point",
    ]
    return result


async def choose(hass: HomeAssistant, result: dict[str, Any], step: str) -> Any:
    """Choose a step of the options menu."""
    return await hass.config_entries.options.async_configure(
        result["flow_id"], {"next_step_id": step}
    )
