"""Adding a Tekon gateway in the UI: its URL checked on the gateway, its errors, its URL changed."""

from collections.abc import AsyncIterator
from dataclasses import replace
from typing import Any

from homeassistant.config_entries import (
    SOURCE_DHCP,
    SOURCE_RECONFIGURE,
    SOURCE_USER,
    ConfigEntry,
)
from homeassistant.const import CONF_HOST, CONF_VERIFY_SSL
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
from homeassistant.helpers.service_info.dhcp import DhcpServiceInfo
import pytest

from custom_components.tecoapi.const import CONF_TRANSPORT, DOMAIN
from custom_components.tecoapi.pyplc.core import registry
from custom_components.tecoapi.pyplc.tekon.descriptor import TEKON
from tests.components.tecoapi.conftest import open_settings
from tests.simulator.tekon import TekonGateway, large_building

TITLE = "ASUD.SCADA OPC-HTTP"


@pytest.fixture
async def gateway(socket_enabled: None) -> AsyncIterator[TekonGateway]:
    async with TekonGateway() as running:
        yield running


async def reconfigure(hass: HomeAssistant, entry: ConfigEntry) -> dict[str, Any]:
    """Open an entry's reconfigure flow."""
    return await hass.config_entries.flow.async_init(
        DOMAIN, context={"source": SOURCE_RECONFIGURE, "entry_id": entry.entry_id}
    )


async def tekon_form(hass: HomeAssistant) -> dict[str, Any]:
    """Open the config flow and choose the Tekon gateway."""
    result = await hass.config_entries.flow.async_init(
        DOMAIN, context={"source": SOURCE_USER}
    )
    assert "tekon" in result["menu_options"]
    return await hass.config_entries.flow.async_configure(
        result["flow_id"], {"next_step_id": "tekon"}
    )


async def add_gateway(hass: HomeAssistant, url: str, **form: Any) -> dict[str, Any]:
    """Add a gateway through the config flow, as a user would."""
    result = await tekon_form(hass)
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {CONF_HOST: url, CONF_VERIFY_SSL: True, **form}
    )
    await hass.async_block_till_done()
    return result


async def test_a_gateway_is_added_by_its_url(
    hass: HomeAssistant, gateway: TekonGateway, mock_setup_entry: Any
) -> None:
    result = await tekon_form(hass)
    assert result["type"] is FlowResultType.FORM
    assert result["step_id"] == "tekon"
    assert {str(key) for key in result["data_schema"].schema} == {
        CONF_HOST,
        CONF_VERIFY_SSL,
    }
    # Without a scheme: http, as typed.
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"],
        {CONF_HOST: gateway.url.removeprefix("http://"), CONF_VERIFY_SSL: True},
    )
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert result["title"] == TITLE
    assert result["data"] == {
        CONF_HOST: gateway.url,
        CONF_VERIFY_SSL: True,
        CONF_TRANSPORT: "tekon",
    }
    assert result["result"].unique_id.startswith("OPC-")
    # The check left no session open.
    assert gateway.sessions == {}
    assert gateway.requests[:4] == [
        "ServerInformation",
        "NewSession",
        "GetAddressSpaceHash",
        "GetAddressSpace",
    ]


@pytest.mark.parametrize(
    ("arrange", "error"),
    [
        ("closed", {"base": "tekon_cannot_connect"}),
        ("web_server", {"base": "not_tekon"}),
        ("forbidden", {"base": "tekon_forbidden"}),
        ("opc_down", {"base": "tekon_opc_unavailable"}),
        ("path", {CONF_HOST: "invalid_host"}),
    ],
)
async def test_errors_then_a_gateway_that_answers(  # noqa: PLR0917 (fixtures)
    hass: HomeAssistant,
    gateway: TekonGateway,
    mock_setup_entry: Any,
    closed_port: str,
    web_server: str,
    arrange: str,
    error: dict[str, str],
) -> None:
    url = gateway.url
    if arrange == "closed":
        url = closed_port
    elif arrange == "web_server":
        url = web_server
    elif arrange == "forbidden":
        gateway.allowed = frozenset({"192.0.2.1"})
    elif arrange == "opc_down":
        gateway.opc_available = False
    elif arrange == "path":
        url = f"{gateway.url}/GetAddressSpace"
    result = await tekon_form(hass)
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {CONF_HOST: url, CONF_VERIFY_SSL: True}
    )
    assert result["type"] is FlowResultType.FORM
    assert result["errors"] == error
    gateway.allowed = None
    gateway.opc_available = True
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {CONF_HOST: gateway.url, CONF_VERIFY_SSL: True}
    )
    assert result["type"] is FlowResultType.CREATE_ENTRY


async def test_the_same_gateway_twice_is_refused(
    hass: HomeAssistant, gateway: TekonGateway, mock_setup_entry: Any
) -> None:
    first = await add_gateway(hass, gateway.url)
    assert first["type"] is FlowResultType.CREATE_ENTRY
    # The same gateway (its address space) at another address: refused, and the
    # entry takes the address.
    async with TekonGateway() as same:
        second = await add_gateway(hass, same.url)
    assert second["type"] is FlowResultType.ABORT
    assert second["reason"] == "tekon_already_configured"
    assert len(hass.config_entries.async_entries(DOMAIN)) == 1
    assert first["result"].data[CONF_HOST] == same.url


async def test_reconfigure_changes_the_url_of_the_same_gateway(
    hass: HomeAssistant, gateway: TekonGateway, mock_setup_entry: Any
) -> None:
    entry = (await add_gateway(hass, gateway.url))["result"]
    result = await reconfigure(hass, entry)
    assert result["step_id"] == "reconfigure_tekon"
    async with TekonGateway() as moved:
        result = await hass.config_entries.flow.async_configure(
            result["flow_id"], {CONF_HOST: moved.url, CONF_VERIFY_SSL: False}
        )
        assert result["type"] is FlowResultType.ABORT
        assert result["reason"] == "tekon_reconfigured"
        assert entry.data == {
            CONF_HOST: moved.url,
            CONF_VERIFY_SSL: False,
            CONF_TRANSPORT: "tekon",
        }
    async with TekonGateway(large_building(100)) as other:
        result = await reconfigure(hass, entry)
        result = await hass.config_entries.flow.async_configure(
            result["flow_id"], {CONF_HOST: other.url, CONF_VERIFY_SSL: True}
        )
        assert result["type"] is FlowResultType.ABORT
        assert result["reason"] == "tekon_wrong_device"
    result = await reconfigure(hass, entry)
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {CONF_HOST: "http://a/b", CONF_VERIFY_SSL: True}
    )
    assert result["errors"] == {CONF_HOST: "invalid_host"}


async def test_an_entry_without_options_polls_every_second(
    hass: HomeAssistant, gateway: TekonGateway
) -> None:
    """The source's own default interval (the TecoApi entries' stays 5 s)."""
    entry = (await add_gateway(hass, gateway.url))["result"]
    assert entry.runtime_data.update_interval.total_seconds() == 1
    result = await open_settings(hass, entry.entry_id)
    suggested = {
        str(key): (key.description or {}).get("suggested_value")
        for key in result["data_schema"].schema
    }
    assert suggested["scan_interval"] == 1
    # Only what a gateway uses: no attribute cadence, no plain variables.
    assert set(suggested) == {"scan_interval", "include", "exclude", "devices"}
    await hass.config_entries.async_unload(entry.entry_id)


async def test_a_discovered_device_of_a_source_that_stores_its_name(
    hass: HomeAssistant, gateway: TekonGateway, mock_setup_entry: Any
) -> None:
    """A probe's find is confirmed and stored under its source's name (``transport``).

    No gateway is found by DHCP (a Windows server tells no vendor); this one's
    probe is the test's, to follow the generic path of a source that stores its name.
    """

    async def probe(session: Any, ip: str) -> tuple[str | None, str]:
        return None, gateway.url

    probing = replace(
        TEKON,
        name="tekon_probing",
        connect=replace(TEKON.connect, step_id="tekon_probing"),
        reconfigure=replace(TEKON.reconfigure, step_id="reconfigure_tekon_probing"),
        probe=probe,
    )
    unregister = registry.register(probing)
    try:
        result = await hass.config_entries.flow.async_init(
            DOMAIN,
            context={"source": SOURCE_DHCP},
            data=DhcpServiceInfo(
                ip="127.0.0.1", hostname="gw", macaddress="02aabbccddee"
            ),
        )
        assert result["step_id"] == "dhcp_confirm"
        result = await hass.config_entries.flow.async_configure(result["flow_id"], {})
    finally:
        unregister()
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert result["data"] == {
        CONF_HOST: gateway.url,
        CONF_VERIFY_SSL: True,
        CONF_TRANSPORT: "tekon_probing",
    }
