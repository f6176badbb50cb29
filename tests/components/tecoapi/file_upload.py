"""Uploading a file as the frontend does (a point map, a ``.vlist``), for the flows' tests."""

from collections.abc import Mapping
from http import HTTPStatus
from typing import Any

import aiohttp
from homeassistant.core import HomeAssistant
from homeassistant.setup import async_setup_component
from pytest_homeassistant_custom_component.typing import ClientSessionGenerator

from custom_components.tecoapi.compat import vol
from custom_components.tecoapi.pyplc.core.descriptor import CONF_POINT_MAP


async def upload(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    name: str,
    text: str,
    content_type: str | None = None,
) -> str:
    """Upload a file through Home Assistant's ``file_upload``; return its ID."""
    assert await async_setup_component(hass, "file_upload", {})
    client = await hass_client()
    form = aiohttp.FormData()
    form.add_field("file", text.encode(), filename=name, content_type=content_type)
    response = await client.post("/api/file_upload", data=form)
    assert response.status == HTTPStatus.OK
    file_id: str = (await response.json())["file_id"]
    return file_id


def map_field(result: Mapping[str, Any]) -> tuple[type[vol.Marker], Any]:
    """Whether a form's map file is required (or optional), and what it suggests."""
    (key,) = (key for key in result["data_schema"].schema if key == CONF_POINT_MAP)
    return type(key), (key.description or {}).get("suggested_value")
