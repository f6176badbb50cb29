"""Setting up, unloading and reconfiguring a TecoApi entry."""

from datetime import timedelta
import logging

from freezegun.api import FrozenDateTimeFactory
from homeassistant.config_entries import SOURCE_REAUTH, ConfigEntryState
from homeassistant.core import HomeAssistant
from homeassistant.exceptions import HomeAssistantError
from homeassistant.helpers import (
    entity_registry as er,
)
import pytest
from pytest_homeassistant_custom_component.common import (
    MockConfigEntry,
    async_fire_time_changed,
)

from custom_components.tecoapi.const import (
    CONF_PLAIN_VARIABLES,
    DOMAIN,
    PlainVariables,
)
from tests.components.tecoapi.conftest import (
    entry_data,
    make_entry,
    setup_entry,
)
from tests.conftest import SIM_PASSWORD
from tests.simulator import Simulator


async def test_setup_and_unload(
    hass: HomeAssistant, simulator: Simulator, config_entry: MockConfigEntry
) -> None:
    """The entry loads with its coordinator, and unloads without leftovers."""
    await setup_entry(hass, config_entry)

    assert config_entry.state is ConfigEntryState.LOADED
    coordinator = config_entry.runtime_data
    assert coordinator.data.info.serial_number == simulator.serial_number
    assert hass.states.get("sensor.tecomat_cp_2080_outside_temperature") is not None

    assert await hass.config_entries.async_unload(config_entry.entry_id)
    await hass.async_block_till_done()

    assert config_entry.state is ConfigEntryState.NOT_LOADED
    assert hass.states.get("sensor.tecomat_cp_2080_outside_temperature").state == (
        "unavailable"
    )


async def test_home_assistant_s_loggers_are_left_as_they_are(
    hass: HomeAssistant, config_entry: MockConfigEntry
) -> None:
    """No filter of ours sits on another component's logger (Home Assistant's own).

    How Home Assistant logs what happens in it (the websocket API's line for a
    refused call among them) is its decision; only the integration's own
    loggers (``custom_components.tecoapi.*``) are ours to shape.
    """
    await setup_entry(hass, config_entry)
    ours = "custom_components.tecoapi"

    foreign = {
        name: [repr(known) for known in logger.filters]
        for name, logger in logging.Logger.manager.loggerDict.items()
        if isinstance(logger, logging.Logger)
        and name != ours
        and not name.startswith(f"{ours}.")
        # A filter is an object or a function: its __module__ says whose.
        and any(
            str(getattr(known, "__module__", "")).startswith(ours)
            for known in logger.filters
        )
    }
    assert foreign == {}


async def test_unreachable_plc_retries_setup(
    hass: HomeAssistant, simulator: Simulator, closed_port: str
) -> None:
    """A PLC that does not answer at start: setup is retried (ConfigEntryNotReady)."""
    entry = MockConfigEntry(
        domain=DOMAIN,
        unique_id=simulator.serial_number,
        data=entry_data(simulator, host=f"http://{closed_port}"),
    )

    await setup_entry(hass, entry)

    assert entry.state is ConfigEntryState.SETUP_RETRY
    assert entry.reason is not None
    assert "Cannot reach the device" in entry.reason


async def test_rejected_credentials_start_reauth(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    """Credentials the PLC rejects at start fail setup and open a reauth flow."""
    entry = make_entry(simulator)
    entry.add_to_hass(hass)
    hass.config_entries.async_update_entry(
        entry, data=entry_data(simulator, password="wrong")
    )

    await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()

    assert entry.state is ConfigEntryState.SETUP_ERROR
    flows = hass.config_entries.flow.async_progress_by_handler(DOMAIN)
    assert [flow["context"]["source"] for flow in flows] == [SOURCE_REAUTH]
    assert flows[0]["context"]["entry_id"] == entry.entry_id


async def test_ignored_plain_variables_are_not_created(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    """With plain variables ignored, only T_ApiObjects and the status remain."""
    entry = make_entry(simulator, **{CONF_PLAIN_VARIABLES: PlainVariables.IGNORED})

    await setup_entry(hass, entry)

    points = entry.runtime_data.data.points.values()
    assert points
    assert all(point.described for point in points)
    registry = er.async_get(hass)
    assert (
        registry.async_get_entity_id("sensor", DOMAIN, "SD 2080_doorbellcount") is None
    )


async def test_point_moving_platform_leaves_no_orphan(
    hass: HomeAssistant, simulator: Simulator, config_entry: MockConfigEntry
) -> None:
    """A setpoint made read-only in the PLC becomes a sensor; the number is removed."""
    await setup_entry(hass, config_entry)
    registry = er.async_get(hass)
    unique_id = "SD 2080_heating.livingsetpoint"
    assert registry.async_get_entity_id("number", DOMAIN, unique_id) is not None

    simulator.set_value("Heating.livingSetpoint.attr.readOnly", True)
    await hass.config_entries.async_reload(config_entry.entry_id)
    await hass.async_block_till_done()

    assert registry.async_get_entity_id("number", DOMAIN, unique_id) is None
    assert registry.async_get_entity_id("sensor", DOMAIN, unique_id) is not None


async def test_credentials_never_logged(
    hass: HomeAssistant,
    simulator: Simulator,
    config_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
    caplog: pytest.LogCaptureFixture,
) -> None:
    """Setup, polls, a failed write and revoked credentials at DEBUG: no password."""
    caplog.set_level(logging.DEBUG)
    await setup_entry(hass, config_entry)
    freezer.tick(timedelta(seconds=5))
    async_fire_time_changed(hass)
    await hass.async_block_till_done(wait_background_tasks=True)
    simulator.faults.http_500 = True
    with pytest.raises(HomeAssistantError):
        await config_entry.runtime_data.async_write("lights[0]", True)
    simulator.faults.clear()
    simulator.password = "n3w-secret"
    freezer.tick(timedelta(seconds=5))
    async_fire_time_changed(hass)
    await hass.async_block_till_done(wait_background_tasks=True)

    assert "rejected the stored credentials" in caplog.text
    assert SIM_PASSWORD not in caplog.text
    assert "n3w-secret" not in caplog.text
