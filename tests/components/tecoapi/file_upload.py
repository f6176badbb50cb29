"""Uploading a file as the frontend does (a point map, a ``.vlist``), for the flows' tests."""

from http import HTTPStatus

import aiohttp
from homeassistant.core import HomeAssistant
from homeassistant.setup import async_setup_component
from pytest_homeassistant_custom_component.typing import ClientSessionGenerator


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
