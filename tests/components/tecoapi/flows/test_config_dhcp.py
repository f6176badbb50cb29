"""DHCP discovery: confirm a TecoApi PLC, ask only for credentials, follow a move.

A discovered PLC is probed on port 80; the simulator listens on a free port, so
the tests point the probe at it (``pyplc.tecomat.descriptor.HTTP_PORT``).
"""

from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import replace
from typing import Final
from unittest.mock import patch

from homeassistant.config_entries import SOURCE_DHCP, SOURCE_IGNORE
from homeassistant.const import CONF_HOST, CONF_PASSWORD, CONF_USERNAME, CONF_VERIFY_SSL
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
from homeassistant.helpers import device_registry as dr
from homeassistant.helpers.service_info.dhcp import DhcpServiceInfo
from homeassistant.loader import async_get_dhcp
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.tecoapi.const import CONF_TRANSPORT, DOMAIN
from custom_components.tecoapi.pyplc.core import registry
from tests.components.tecoapi.conftest import entry_data, make_entry
from tests.conftest import SIM_PASSWORD, SIM_USERNAME
from tests.fake_source import DEVICES, MEMORY, MemorySource, house_device, house_map
from tests.simulator import Simulator

pytestmark = pytest.mark.usefixtures("mock_setup_entry")

TECO_MAC: Final = "000a142c8017"  # the demo PLC's MAC, Teco a.s. prefix
VARISCITE_MAC: Final = "f8dc7a11f4dc"  # the manual's example PLC


def dhcp(mac: str, ip: str = "127.0.0.1") -> DhcpServiceInfo:
    """What Home Assistant's DHCP watcher reports."""
    return DhcpServiceInfo(ip=ip, hostname="foxtrot", macaddress=mac)


@contextmanager
def probe_port(port: int) -> Iterator[None]:
    """Point discovery's probe at a test server's port instead of 80."""
    with patch("custom_components.tecoapi.pyplc.tecomat.descriptor.HTTP_PORT", port):
        yield


@pytest.fixture
def plc_port(simulator: Simulator) -> Iterator[None]:
    """Discovery finds the demo simulator."""
    with probe_port(simulator.port):
        yield


async def discover(hass: HomeAssistant, info: DhcpServiceInfo) -> dict[str, object]:
    """Start a DHCP discovery flow."""
    result: dict[str, object] = await hass.config_entries.flow.async_init(
        DOMAIN, context={"source": SOURCE_DHCP}, data=info
    )
    return result


def known_plc(hass: HomeAssistant, simulator: Simulator, host: str) -> MockConfigEntry:
    """A configured PLC whose device carries the demo PLC's MAC."""
    entry = make_entry(simulator)
    entry.add_to_hass(hass)
    hass.config_entries.async_update_entry(entry, data=entry_data(simulator, host=host))
    dr.async_get(hass).async_get_or_create(
        config_entry_id=entry.entry_id,
        identifiers={(DOMAIN, simulator.serial_number)},
        connections={(dr.CONNECTION_NETWORK_MAC, "00:0a:14:2c:80:17")},
    )
    return entry


@pytest.mark.usefixtures("plc_port")
@pytest.mark.parametrize("mac", [TECO_MAC, VARISCITE_MAC])
async def test_discovered_plc_asks_only_for_credentials(
    hass: HomeAssistant, simulator: Simulator, mac: str
) -> None:
    """A TecoApi PLC is offered; a wrong password is shown, then it is added."""
    result = await discover(hass, dhcp(mac))

    assert result["type"] is FlowResultType.FORM
    assert result["step_id"] == "dhcp_confirm"
    assert result["description_placeholders"] == {
        "public_api": "{PUBLIC_API}",
        "host": simulator.url,
    }
    flows = hass.config_entries.flow.async_progress_by_handler(DOMAIN)
    assert flows[0]["context"]["title_placeholders"] == {"name": "127.0.0.1"}
    flow_id = str(result["flow_id"])

    result = await hass.config_entries.flow.async_configure(
        flow_id, {CONF_USERNAME: SIM_USERNAME, CONF_PASSWORD: "wrong"}
    )
    assert result["type"] is FlowResultType.FORM
    assert result["errors"] == {"base": "invalid_auth"}

    result = await hass.config_entries.flow.async_configure(
        flow_id, {CONF_USERNAME: SIM_USERNAME, CONF_PASSWORD: SIM_PASSWORD}
    )
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert result["title"] == "CP-2080 · FAMILY_HOUSE v1.3"
    assert result["data"] == {
        CONF_HOST: simulator.url,
        CONF_USERNAME: SIM_USERNAME,
        CONF_PASSWORD: SIM_PASSWORD,
        CONF_VERIFY_SSL: True,
    }
    assert result["result"].unique_id == simulator.serial_number


async def test_device_that_is_no_tecoapi_server_is_not_offered(
    hass: HomeAssistant, web_server: str
) -> None:
    """A Variscite module answering HTTP, but not as TecoApi: nothing is offered."""
    host, _, port = web_server.partition(":")
    with probe_port(int(port)):
        result = await discover(hass, dhcp(VARISCITE_MAC, host))

    assert result["type"] is FlowResultType.ABORT
    assert result["reason"] == "not_tecoapi"


async def test_device_without_a_web_server_is_not_offered(
    hass: HomeAssistant, closed_port: str
) -> None:
    """Nothing answers on the port: nothing is offered."""
    with probe_port(int(closed_port.partition(":")[2])):
        result = await discover(hass, dhcp(TECO_MAC))

    assert result["type"] is FlowResultType.ABORT
    assert result["reason"] == "cannot_connect"


@pytest.mark.parametrize(
    ("stored", "updated"),
    [
        ("http://10.0.0.7", "http://127.0.0.1"),
        ("https://10.0.0.7:8443", "https://127.0.0.1:8443"),
        ("http://127.0.0.1", "http://127.0.0.1"),
        ("http://plc.local", "http://plc.local"),
    ],
)
async def test_known_plc_follows_its_new_address(
    hass: HomeAssistant, simulator: Simulator, stored: str, updated: str
) -> None:
    """A configured PLC seen at a new IP: its address moves (scheme, port kept).

    One configured by name keeps its name. Either way nothing new is offered.
    """
    entry = known_plc(hass, simulator, stored)

    result = await discover(hass, dhcp(TECO_MAC, "127.0.0.1"))

    assert result["type"] is FlowResultType.ABORT
    assert result["reason"] == "tecoapi_already_configured"
    assert entry.data[CONF_HOST] == updated


async def test_ignored_discovery_stays_ignored(hass: HomeAssistant) -> None:
    """The user ignored this PLC before: it is not offered again."""
    MockConfigEntry(
        domain=DOMAIN, source=SOURCE_IGNORE, unique_id="00:0a:14:2c:80:17"
    ).add_to_hass(hass)

    result = await discover(hass, dhcp(TECO_MAC))

    assert result["type"] is FlowResultType.ABORT
    assert result["reason"] == "already_configured"


@pytest.mark.usefixtures("plc_port")
async def test_one_flow_per_discovered_plc(hass: HomeAssistant) -> None:
    """The same PLC reported twice: one flow."""
    first = await discover(hass, dhcp(TECO_MAC))
    second = await discover(hass, dhcp(TECO_MAC))

    assert first["type"] is FlowResultType.FORM
    assert second["type"] is FlowResultType.ABORT
    assert second["reason"] == "already_in_progress"


@pytest.mark.usefixtures("plc_port")
async def test_confirmed_plc_that_is_configured_already(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    """Configured, but never set up (no device yet): confirming updates its address."""
    entry = make_entry(simulator)
    entry.add_to_hass(hass)
    hass.config_entries.async_update_entry(
        entry, data=entry_data(simulator, host="http://10.0.0.7")
    )
    result = await discover(hass, dhcp(TECO_MAC))

    result = await hass.config_entries.flow.async_configure(
        str(result["flow_id"]),
        {CONF_USERNAME: SIM_USERNAME, CONF_PASSWORD: SIM_PASSWORD},
    )

    assert result["type"] is FlowResultType.ABORT
    assert result["reason"] == "tecoapi_already_configured"
    assert entry.data[CONF_HOST] == simulator.url


@pytest.mark.usefixtures("plc_port")
async def test_same_mac_on_another_integrations_device(hass: HomeAssistant) -> None:
    """A device of another integration with this MAC is not our PLC: offered."""
    other = MockConfigEntry(domain="other_integration")
    other.add_to_hass(hass)
    dr.async_get(hass).async_get_or_create(
        config_entry_id=other.entry_id,
        connections={(dr.CONNECTION_NETWORK_MAC, "00:0a:14:2c:80:17")},
    )

    result = await discover(hass, dhcp(TECO_MAC))

    assert result["type"] is FlowResultType.FORM
    assert result["step_id"] == "dhcp_confirm"


async def test_manifest_registers_the_dhcp_matchers(hass: HomeAssistant) -> None:
    """Home Assistant's DHCP watcher learns our MAC prefixes from manifest.json."""
    matchers = [
        matcher for matcher in await async_get_dhcp(hass) if matcher["domain"] == DOMAIN
    ]

    assert {m.get("macaddress") for m in matchers} >= {"000A14*", "F8DC7A*"}
    assert any(m.get("registered_devices") for m in matchers)


async def test_a_discovered_device_of_a_source_that_stores_its_name(
    hass: HomeAssistant, closed_port: str
) -> None:
    """A source found by its own probe stores its name with the entry it adds."""

    async def probe(session: object, ip: str) -> tuple[str | None, str]:
        return None, "MEM-0001"

    descriptor = replace(
        MEMORY,
        probe=probe,
        create=lambda context, data, options: MemorySource(
            DEVICES[data[CONF_HOST]], house_map()
        ),
    )
    house_device()
    unregister = registry.register(descriptor)
    try:
        with probe_port(int(closed_port.rpartition(":")[2])):
            result = await discover(hass, dhcp(TECO_MAC))
        assert result["step_id"] == "dhcp_confirm"
        result = await hass.config_entries.flow.async_configure(
            str(result["flow_id"]), {}
        )
    finally:
        unregister()
        DEVICES.clear()
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert result["data"] == {CONF_HOST: "MEM-0001", CONF_TRANSPORT: MEMORY.name}
