"""Flows that change a set-up entry: one reload, by the entry's update listener.

Home Assistant 2026.12 stops accepting a flow that reloads an entry which has an
update listener (it logs "has an update listener" until then). A loaded entry is
only updated by its flows and reloaded by its listener; an entry whose setup failed
has no listener and is reloaded by the flow.
"""

from homeassistant.config_entries import ConfigEntryState
from homeassistant.const import CONF_HOST, CONF_PASSWORD, CONF_USERNAME, CONF_VERIFY_SSL
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
import pytest

from custom_components.tecoapi.const import DOMAIN
from tests.components.tecoapi.conftest import (
    add_tecoapi,
    entry_data,
    make_entry,
    setup_entry,
)
from tests.conftest import SIM_PASSWORD, SIM_USERNAME
from tests.simulator import Simulator

DEPRECATION = "has an update listener"


async def move_the_plc(simulator: Simulator) -> None:
    """The PLC gets another address (here: another port)."""
    port = simulator.port
    await simulator.stop()
    await simulator.start()
    assert simulator.port != port


async def test_reconfigure_a_loaded_entry_keeps_the_password(
    hass: HomeAssistant,
    simulator: Simulator,
    caplog: pytest.LogCaptureFixture,
) -> None:
    """Only the address changes: no password asked, one reload, no warning."""
    entry = await setup_entry(hass, make_entry(simulator))
    coordinator = entry.runtime_data
    await move_the_plc(simulator)

    result = await entry.start_reconfigure_flow(hass)
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"],
        {CONF_HOST: simulator.host, CONF_USERNAME: SIM_USERNAME, CONF_VERIFY_SSL: True},
    )
    await hass.async_block_till_done()

    assert result["type"] is FlowResultType.ABORT
    assert result["reason"] == "tecoapi_reconfigured"
    assert entry.data == entry_data(simulator)
    assert entry.data[CONF_PASSWORD] == SIM_PASSWORD
    assert entry.state is ConfigEntryState.LOADED
    assert entry.runtime_data is not coordinator
    assert hass.states.get("sensor.tecomat_cp_2080_outside_temperature").state == (
        "4.5"
    )
    assert DEPRECATION not in caplog.text


async def test_reconfigure_with_a_new_password(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    """A password typed in the reconfigure form replaces the stored one."""
    entry = await setup_entry(hass, make_entry(simulator))
    simulator.password = "n3w-Pa55"

    result = await entry.start_reconfigure_flow(hass)
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"],
        {
            CONF_HOST: simulator.host,
            CONF_USERNAME: SIM_USERNAME,
            CONF_PASSWORD: "n3w-Pa55",
            CONF_VERIFY_SSL: True,
        },
    )
    await hass.async_block_till_done()

    assert result["reason"] == "tecoapi_reconfigured"
    assert entry.data[CONF_PASSWORD] == "n3w-Pa55"
    assert entry.state is ConfigEntryState.LOADED


async def test_reauth_of_a_loaded_entry_reloads_it_once(
    hass: HomeAssistant, simulator: Simulator, caplog: pytest.LogCaptureFixture
) -> None:
    """Revoked while running: the new credentials are stored and used, no warning."""
    entry = await setup_entry(hass, make_entry(simulator))
    coordinator = entry.runtime_data
    simulator.password = "n3w-Pa55"

    result = await entry.start_reauth_flow(hass)
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {CONF_USERNAME: SIM_USERNAME, CONF_PASSWORD: "n3w-Pa55"}
    )
    await hass.async_block_till_done()

    assert result["reason"] == "reauth_successful"
    assert entry.state is ConfigEntryState.LOADED
    assert entry.runtime_data is not coordinator
    assert entry.runtime_data.last_update_success
    assert DEPRECATION not in caplog.text


async def test_reauth_after_a_failed_setup_sets_the_entry_up(
    hass: HomeAssistant, simulator: Simulator, caplog: pytest.LogCaptureFixture
) -> None:
    """Rejected at start (no update listener yet): the flow reloads the entry itself."""
    entry = make_entry(simulator)
    entry.add_to_hass(hass)
    hass.config_entries.async_update_entry(
        entry, data=entry_data(simulator, password="wrong")
    )
    await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    assert entry.state is ConfigEntryState.SETUP_ERROR

    flows = hass.config_entries.flow.async_progress_by_handler(DOMAIN)
    result = await hass.config_entries.flow.async_configure(
        flows[0]["flow_id"], {CONF_USERNAME: SIM_USERNAME, CONF_PASSWORD: SIM_PASSWORD}
    )
    await hass.async_block_till_done()

    assert result["reason"] == "reauth_successful"
    assert entry.state is ConfigEntryState.LOADED
    assert DEPRECATION not in caplog.text


async def test_adding_a_loaded_plc_again_at_a_new_address(
    hass: HomeAssistant, simulator: Simulator, caplog: pytest.LogCaptureFixture
) -> None:
    """The user adds a known PLC under its new address: it is stored and used."""
    entry = await setup_entry(hass, make_entry(simulator))
    coordinator = entry.runtime_data
    await move_the_plc(simulator)

    result = await add_tecoapi(hass, simulator.host)
    await hass.async_block_till_done()

    assert result["reason"] == "tecoapi_already_configured"
    assert entry.data[CONF_HOST] == simulator.url
    assert entry.state is ConfigEntryState.LOADED
    assert entry.runtime_data is not coordinator
    assert DEPRECATION not in caplog.text


async def test_a_new_title_alone_does_not_reload(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    entry = await setup_entry(hass, make_entry(simulator))
    coordinator = entry.runtime_data

    hass.config_entries.async_update_entry(entry, title="Our house")
    await hass.async_block_till_done()

    assert entry.runtime_data is coordinator
