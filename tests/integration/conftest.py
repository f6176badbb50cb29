"""Fixtures for the Home Assistant integration tests."""

from collections.abc import Generator
from typing import Any
from unittest.mock import AsyncMock, patch

import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.tecoapi.const import DOMAIN
from homeassistant.const import CONF_HOST, CONF_PASSWORD, CONF_USERNAME, CONF_VERIFY_SSL
from homeassistant.core import HomeAssistant
from tests.conftest import SIM_PASSWORD, SIM_USERNAME
from tests.simulator import Simulator


@pytest.fixture(autouse=True)
def auto_enable_custom_integrations(enable_custom_integrations: None) -> None:
    """Let Home Assistant load custom_components.tecoapi in every test here."""


def entry_data(sim: Simulator, **changes: Any) -> dict[str, Any]:
    """Config entry data for a simulator, as the config flow stores it."""
    return {
        CONF_HOST: sim.url,
        CONF_USERNAME: SIM_USERNAME,
        CONF_PASSWORD: SIM_PASSWORD,
        CONF_VERIFY_SSL: True,
        **changes,
    }


def make_entry(sim: Simulator, **options: Any) -> MockConfigEntry:
    """A config entry for a simulator, as the config flow creates it."""
    return MockConfigEntry(
        domain=DOMAIN,
        title=f"{sim.plc_type} · {sim.program.name}",
        unique_id=sim.serial_number,
        data=entry_data(sim),
        options=options,
    )


async def setup_entry(hass: HomeAssistant, entry: MockConfigEntry) -> MockConfigEntry:
    """Add an entry to Home Assistant and set it up."""
    entry.add_to_hass(hass)
    await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    return entry


@pytest.fixture
def mock_setup_entry() -> Generator[AsyncMock]:
    """Keep config-flow tests to the flow: entries are created, not set up."""
    with patch(
        "custom_components.tecoapi.async_setup_entry", return_value=True
    ) as mock:
        yield mock


@pytest.fixture
def config_entry(simulator: Simulator) -> MockConfigEntry:
    """A config entry for the demo simulator (not yet added to Home Assistant)."""
    return make_entry(simulator)


@pytest.fixture
def manual_entry(manual_simulator: Simulator) -> MockConfigEntry:
    """A config entry for the manual's program (not yet added)."""
    return make_entry(manual_simulator)
