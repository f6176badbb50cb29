"""A Mervis controller (Unipi) added in the UI with its ``.vlist``, for the tests that need one.

The ``mervis`` fixture (conftest.py) is the simulated house with credentials
(tests/simulator/mervis/); ``add_house`` adds it through the config flow with a
real file upload, as the frontend posts it.
"""

from typing import Any

from homeassistant.config_entries import SOURCE_USER, ConfigEntry
from homeassistant.const import CONF_HOST, CONF_PASSWORD, CONF_USERNAME, CONF_VERIFY_SSL
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
from homeassistant.helpers import entity_registry as er
from pytest_homeassistant_custom_component.typing import ClientSessionGenerator

from custom_components.tecoapi.const import DOMAIN
from custom_components.tecoapi.pyplc.core.descriptor import CONF_POINT_MAP
from tests.components.tecoapi.file_upload import upload
from tests.simulator.mervis import MervisSimulator

USER = "panel"


PASSWORD = "Heslo-123"


async def start_flow(hass: HomeAssistant) -> dict[str, Any]:
    """Open the config flow and choose Mervis from its menu."""
    result = await hass.config_entries.flow.async_init(
        DOMAIN, context={"source": SOURCE_USER}
    )
    assert "mervis" in result["menu_options"]
    return await hass.config_entries.flow.async_configure(
        result["flow_id"], {"next_step_id": "mervis"}
    )


def form(sim: MervisSimulator, file_id: str, **changes: Any) -> dict[str, Any]:
    """The connection form as a user fills it."""
    return {
        CONF_HOST: sim.host,
        CONF_USERNAME: USER,
        CONF_PASSWORD: PASSWORD,
        CONF_VERIFY_SSL: True,
        CONF_POINT_MAP: file_id,
        **changes,
    }


async def add(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    sim: MervisSimulator,
    vlist: str | None = None,
    name: str = "house.vlist",
    **changes: Any,
) -> dict[str, Any]:
    """Add the controller through the config flow with its .vlist."""
    result = await start_flow(hass)
    file_id = await upload(hass, hass_client, name, vlist or sim.project.vlist())
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], form(sim, file_id, **changes)
    )
    await hass.async_block_till_done()
    return result


async def add_house(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, sim: MervisSimulator
) -> ConfigEntry:
    """Add the house through the config flow; its entry."""
    result = await add(hass, hass_client, sim)
    assert result["type"] is FlowResultType.CREATE_ENTRY
    entry: ConfigEntry = result["result"]
    return entry


def identity(hass: HomeAssistant) -> str:
    """The identity of the one entry: its project, at the address it was added at."""
    (entry,) = hass.config_entries.async_entries(DOMAIN)
    return str(entry.unique_id)


def entity(hass: HomeAssistant, domain: str, key: str) -> str:
    """The entity ID of a point's entity on a platform."""
    entity_id = er.async_get(hass).async_get_entity_id(
        domain, DOMAIN, f"{identity(hass)}_{key}"
    )
    assert entity_id is not None, (domain, key)
    return entity_id


def keys(hass: HomeAssistant, entry: ConfigEntry) -> dict[str, str]:
    """The entry's entities by point key."""
    return {
        item.unique_id.removeprefix(f"{entry.unique_id}_"): item.entity_id
        for item in er.async_entries_for_config_entry(
            er.async_get(hass), entry.entry_id
        )
    }


async def open_upload(hass: HomeAssistant, entry: ConfigEntry) -> dict[str, Any]:
    """Open the entry's options at the upload of a newer file."""
    result = await hass.config_entries.options.async_init(entry.entry_id)
    return await hass.config_entries.options.async_configure(
        result["flow_id"], {"next_step_id": "upload"}
    )


async def upload_newer(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    entry: ConfigEntry,
    vlist: str,
    name: str = "house.vlist",
    **fields: Any,
) -> dict[str, Any]:
    """Upload a newer file in the entry's options (with the form's other fields)."""
    result = await open_upload(hass, entry)
    file_id = await upload(hass, hass_client, name, vlist)
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {CONF_POINT_MAP: file_id, **fields}
    )
    await hass.async_block_till_done()
    return result
