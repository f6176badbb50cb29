"""Helpers of the tests of the demo's typed entities (lights, blinds, thermostats...)."""

from typing import Any

from homeassistant.core import HomeAssistant

from tests.components.tecoapi.conftest import entity_id_of

SERIAL = "SD 2080"


def typed(hass: HomeAssistant, domain: str, key: str) -> str:
    """The entity ID of a typed device of the demo."""
    return entity_id_of(hass, domain, f"{SERIAL}_{key}")


async def call(hass: HomeAssistant, domain: str, service: str, **data: Any) -> None:
    """Call an action and wait for it."""
    await hass.services.async_call(domain, service, data, blocking=True)
