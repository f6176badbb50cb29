"""DHCP discovery of a source that stores its name: the entry says which source it is.

TecoApi, the only built-in source with a probe, stores no name (its entries
never had one); a registered source that probes and stores its name gets it in
the entry a discovery makes.
"""

from collections.abc import Iterator
from dataclasses import replace
from unittest.mock import patch

import aiohttp
from homeassistant.config_entries import SOURCE_DHCP
from homeassistant.const import CONF_HOST, CONF_PASSWORD, CONF_USERNAME
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
from homeassistant.helpers.service_info.dhcp import DhcpServiceInfo
import pytest

from custom_components.tecoapi.const import CONF_TRANSPORT, DOMAIN
from custom_components.tecoapi.pyplc.core import registry
from custom_components.tecoapi.pyplc.core.descriptor import Form
from custom_components.tecoapi.pyplc.tecomat.descriptor import TECOAPI
from tests.conftest import SIM_PASSWORD, SIM_USERNAME
from tests.simulator import Simulator

pytestmark = pytest.mark.usefixtures("mock_setup_entry")

NAME = "probing"


@pytest.fixture
def probing(simulator: Simulator) -> Iterator[None]:
    """A source whose probe finds the simulator wherever DHCP saw a device."""

    async def probe(session: aiohttp.ClientSession, ip: str) -> tuple[None, str]:
        return None, simulator.url

    descriptor = replace(
        TECOAPI,
        name=NAME,
        connect=Form(step_id=NAME, fields=TECOAPI.connect.fields),
        reconfigure=Form(step_id=f"reconfigure_{NAME}", fields=()),
        probe=probe,
        stores_name=True,
    )
    unregister = registry.register(descriptor)
    try:
        yield
    finally:
        unregister()


@pytest.mark.usefixtures("probing")
async def test_a_discovered_device_of_a_named_source_stores_its_name(
    hass: HomeAssistant, simulator: Simulator, closed_port: str
) -> None:
    # TecoApi's own probe (port 80 of the address) finds nothing there.
    with patch(
        "custom_components.tecoapi.pyplc.tecomat.descriptor.HTTP_PORT",
        int(closed_port.rpartition(":")[2]),
    ):
        result = await hass.config_entries.flow.async_init(
            DOMAIN,
            context={"source": SOURCE_DHCP},
            data=DhcpServiceInfo(
                ip="127.0.0.1", hostname="plc", macaddress="000a14000001"
            ),
        )
    assert result["step_id"] == "dhcp_confirm"
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {CONF_USERNAME: SIM_USERNAME, CONF_PASSWORD: SIM_PASSWORD}
    )
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert result["data"][CONF_TRANSPORT] == NAME
    assert result["data"][CONF_HOST] == simulator.url
