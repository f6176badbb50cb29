"""Config flow: user step, errors and their recovery, duplicates, reauth, reconfigure."""

from collections.abc import Callable
import dataclasses
from typing import Any
from unittest.mock import AsyncMock, patch

from homeassistant.config_entries import SOURCE_USER
from homeassistant.const import (
    CONF_HOST,
    CONF_PASSWORD,
    CONF_USERNAME,
    CONF_VERIFY_SSL,
)
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.tecoapi.const import (
    DOMAIN,
)
from tests.components.tecoapi.conftest import entry_data, make_entry
from tests.conftest import SIM_PASSWORD, SIM_USERNAME
from tests.simulator import Simulator

pytestmark = pytest.mark.usefixtures("mock_setup_entry")


def user_input(sim: Simulator, **changes: Any) -> dict[str, Any]:
    """What a user types for a simulator: host:port as shown, its credentials."""
    return {
        CONF_HOST: sim.host,
        CONF_USERNAME: SIM_USERNAME,
        CONF_PASSWORD: SIM_PASSWORD,
        CONF_VERIFY_SSL: True,
        **changes,
    }


async def start_user_flow(hass: HomeAssistant, way: str = "tecoapi") -> str:
    """Open the user step and choose how to reach the PLC; return the flow ID."""
    result = await hass.config_entries.flow.async_init(
        DOMAIN, context={"source": SOURCE_USER}
    )
    assert result["type"] is FlowResultType.MENU
    assert result["step_id"] == "user"
    assert result["menu_options"] == ["tecoapi", "plccoms", "mervis", "fpi4c", "tekon"]
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {"next_step_id": way}
    )
    assert result["type"] is FlowResultType.FORM
    assert result["step_id"] == way
    assert result["errors"] == {}
    return result["flow_id"]


async def test_user_flow_creates_entry(
    hass: HomeAssistant, simulator: Simulator, mock_setup_entry: AsyncMock
) -> None:
    """Host, credentials, verify SSL: the PLC is checked and the entry created."""
    flow_id = await start_user_flow(hass)

    result = await hass.config_entries.flow.async_configure(
        flow_id, user_input(simulator)
    )

    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert result["title"] == "CP-2080 · FAMILY_HOUSE v1.3"
    assert result["data"] == {
        CONF_HOST: simulator.url,
        CONF_USERNAME: SIM_USERNAME,
        CONF_PASSWORD: SIM_PASSWORD,
        CONF_VERIFY_SSL: True,
    }
    assert result["result"].unique_id == simulator.serial_number == "SD 2080"
    assert mock_setup_entry.call_count == 1
    services = [request.service for request in simulator.requests]
    assert services[-2:] == ["GetInfo", "GetList"]


async def test_user_form_describes_every_field(hass: HomeAssistant) -> None:
    """The form asks for host, username, password and verify SSL (on by default)."""
    result = await hass.config_entries.flow.async_init(
        DOMAIN, context={"source": SOURCE_USER}
    )
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {"next_step_id": "tecoapi"}
    )

    schema = result["data_schema"].schema
    assert [str(key) for key in schema] == [
        CONF_HOST,
        CONF_USERNAME,
        CONF_PASSWORD,
        CONF_VERIFY_SSL,
    ]
    defaults = {str(key): key.default() for key in schema if callable(key.default)}
    assert defaults == {CONF_VERIFY_SSL: True}
    assert result["description_placeholders"] == {"public_api": "{PUBLIC_API}"}


@dataclasses.dataclass(frozen=True)
class Breakage:
    """How a user's first attempt fails, and how they fix it."""

    error: dict[str, str]
    first_attempt: Callable[[Simulator, str, str], dict[str, Any]]
    break_plc: Callable[[Simulator], None] = lambda sim: None
    repair_plc: Callable[[Simulator], None] = lambda sim: None


def _hide_every_root(sim: Simulator) -> None:
    sim.faults.hidden_from_list = {d.name for d in sim.program.declarations}


def _drop_public_file(sim: Simulator) -> None:
    sim.load_program(dataclasses.replace(sim.program, public_file="missing"))


def _public_file(state: str) -> Callable[[Simulator], None]:
    """Load the program with its public file ``too_big`` or ``unreadable``."""

    def load(sim: Simulator) -> None:
        sim.load_program(dataclasses.replace(sim.program, public_file=state))

    return load


def _restore_demo(sim: Simulator) -> None:
    sim.load_program("demo")


def _malformed_json(sim: Simulator) -> None:
    sim.faults.malformed_json = True


def _clear_faults(sim: Simulator) -> None:
    sim.faults.clear()


BREAKAGES = {
    "unreachable": Breakage(
        {"base": "cannot_connect"},
        lambda sim, closed, web: user_input(sim, host=closed),
    ),
    "path in host": Breakage(
        {CONF_HOST: "invalid_host"},
        lambda sim, closed, web: user_input(sim, host=f"{sim.host}/TecoApi"),
    ),
    "not a PLC": Breakage(
        {"base": "not_tecoapi"},
        lambda sim, closed, web: user_input(sim, host=web),
    ),
    "empty GetList": Breakage(
        {"base": "no_public_variables"},
        lambda sim, closed, web: user_input(sim),
        _hide_every_root,
        _clear_faults,
    ),
    "no public file": Breakage(
        {"base": "no_public_variables"},
        lambda sim, closed, web: user_input(sim),
        _drop_public_file,
        _restore_demo,
    ),
    # The manual's 500.011 and 500.012 are not "no variables": each says its cure.
    "public file too big": Breakage(
        {"base": "public_file_too_big"},
        lambda sim, closed, web: user_input(sim),
        _public_file("too_big"),
        _restore_demo,
    ),
    "public file unreadable": Breakage(
        {"base": "public_file_unreadable"},
        lambda sim, closed, web: user_input(sim),
        _public_file("unreadable"),
        _restore_demo,
    ),
    "malformed answer": Breakage(
        {"base": "unknown"},
        lambda sim, closed, web: user_input(sim),
        _malformed_json,
        _clear_faults,
    ),
}


@pytest.mark.parametrize("breakage", BREAKAGES.values(), ids=BREAKAGES.keys())
async def test_user_flow_error_and_recovery(
    hass: HomeAssistant,
    simulator: Simulator,
    closed_port: str,
    web_server: str,
    breakage: Breakage,
) -> None:
    """Each failure shows its error on the form; fixing it creates the entry."""
    flow_id = await start_user_flow(hass)
    breakage.break_plc(simulator)

    result = await hass.config_entries.flow.async_configure(
        flow_id, breakage.first_attempt(simulator, closed_port, web_server)
    )

    assert result["type"] is FlowResultType.FORM
    assert result["errors"] == breakage.error
    assert not hass.config_entries.async_entries(DOMAIN)

    breakage.repair_plc(simulator)
    result = await hass.config_entries.flow.async_configure(
        flow_id, user_input(simulator)
    )

    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert result["result"].unique_id == simulator.serial_number


async def test_user_flow_form_keeps_input_but_not_password(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    """After an error the form suggests what was typed, except the password."""
    flow_id = await start_user_flow(hass)

    result = await hass.config_entries.flow.async_configure(
        flow_id, user_input(simulator, password="wrong", username="operator")
    )

    suggested = {
        str(key): (key.description or {}).get("suggested_value")
        for key in result["data_schema"].schema
    }
    assert suggested == {
        CONF_HOST: simulator.host,
        CONF_USERNAME: "operator",
        CONF_PASSWORD: None,
        CONF_VERIFY_SSL: True,
    }


async def test_user_flow_form_keeps_the_password_unless_it_was_refused(
    hass: HomeAssistant, simulator: Simulator, closed_port: str
) -> None:
    """A wrong port is not a wrong password: the form still holds the one typed."""
    flow_id = await start_user_flow(hass)

    result = await hass.config_entries.flow.async_configure(
        flow_id, user_input(simulator, host=closed_port)
    )

    assert result["errors"] == {"base": "cannot_connect"}
    suggested = {
        str(key): (key.description or {}).get("suggested_value")
        for key in result["data_schema"].schema
    }
    assert suggested[CONF_HOST] == closed_port
    assert suggested[CONF_PASSWORD] == SIM_PASSWORD
    # Refused next: the password is not shown again.
    result = await hass.config_entries.flow.async_configure(
        flow_id, user_input(simulator, password="wrong")
    )
    assert result["errors"] == {"base": "invalid_auth"}
    assert all(
        (key.description or {}).get("suggested_value") is None
        for key in result["data_schema"].schema
        if str(key) == CONF_PASSWORD
    )


async def test_user_flow_unexpected_error(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    """A bug (not a TecoApi error) shows "unknown"; the next attempt succeeds."""
    flow_id = await start_user_flow(hass)

    with patch(
        "custom_components.tecoapi.pyplc.tecomat.tecoapi.source.TecoApiSession.identify",
        side_effect=RuntimeError("boom"),
    ):
        result = await hass.config_entries.flow.async_configure(
            flow_id, user_input(simulator)
        )
    assert result["errors"] == {"base": "unknown"}

    result = await hass.config_entries.flow.async_configure(
        flow_id, user_input(simulator)
    )
    assert result["type"] is FlowResultType.CREATE_ENTRY


async def test_user_flow_untrusted_certificate(
    hass: HomeAssistant, tls_simulator: Simulator
) -> None:
    """A self-signed certificate fails verification; turning it off succeeds."""
    flow_id = await start_user_flow(hass)

    result = await hass.config_entries.flow.async_configure(
        flow_id, user_input(tls_simulator, host=tls_simulator.url)
    )
    assert result["errors"] == {"base": "tls_not_trusted"}

    result = await hass.config_entries.flow.async_configure(
        flow_id, user_input(tls_simulator, host=tls_simulator.url, verify_ssl=False)
    )
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert result["data"][CONF_HOST] == tls_simulator.url.lower()
    assert result["data"][CONF_VERIFY_SSL] is False


async def test_user_flow_already_configured_updates_host(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    """The same PLC (same serial) again: abort, and remember its new address."""
    existing = MockConfigEntry(
        domain=DOMAIN,
        unique_id=simulator.serial_number,
        data=entry_data(simulator, host="http://192.0.2.10"),
    )
    existing.add_to_hass(hass)
    flow_id = await start_user_flow(hass)

    result = await hass.config_entries.flow.async_configure(
        flow_id, user_input(simulator)
    )

    assert result["type"] is FlowResultType.ABORT
    assert result["reason"] == "tecoapi_already_configured"
    assert existing.data[CONF_HOST] == simulator.url
    assert len(hass.config_entries.async_entries(DOMAIN)) == 1


async def test_reauth_with_new_password(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    """The password changed on the PLC: a wrong one errors, the right one is stored."""
    entry = make_entry(simulator)
    entry.add_to_hass(hass)
    simulator.password = "n3w-Pa55"

    result = await entry.start_reauth_flow(hass)
    assert result["type"] is FlowResultType.FORM
    assert result["step_id"] == "reauth_tecoapi"
    assert result["description_placeholders"][CONF_HOST] == simulator.url

    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {CONF_USERNAME: SIM_USERNAME, CONF_PASSWORD: SIM_PASSWORD}
    )
    assert result["errors"] == {"base": "invalid_auth"}

    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {CONF_USERNAME: SIM_USERNAME, CONF_PASSWORD: "n3w-Pa55"}
    )
    assert result["type"] is FlowResultType.ABORT
    assert result["reason"] == "reauth_successful"
    assert entry.data[CONF_PASSWORD] == "n3w-Pa55"
    assert entry.data[CONF_HOST] == simulator.url


async def test_reauth_against_another_plc(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    """Credentials accepted by a different PLC at the address do not update the entry."""
    entry = make_entry(simulator)
    entry.add_to_hass(hass)
    simulator.serial_number = "OTHER 1"

    result = await entry.start_reauth_flow(hass)
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {CONF_USERNAME: SIM_USERNAME, CONF_PASSWORD: SIM_PASSWORD}
    )

    assert result["type"] is FlowResultType.ABORT
    assert result["reason"] == "tecoapi_wrong_device"
    assert entry.data == entry_data(simulator)


async def test_reconfigure_moves_to_new_address(
    hass: HomeAssistant, simulator: Simulator, closed_port: str
) -> None:
    """A new address: an unreachable one errors, the PLC's real one is stored."""
    entry = MockConfigEntry(
        domain=DOMAIN,
        unique_id=simulator.serial_number,
        data=entry_data(simulator, host="http://192.0.2.10"),
    )
    entry.add_to_hass(hass)

    result = await entry.start_reconfigure_flow(hass)
    assert result["type"] is FlowResultType.FORM
    assert result["step_id"] == "reconfigure"
    suggested = {
        str(key): (key.description or {}).get("suggested_value")
        for key in result["data_schema"].schema
    }
    assert suggested[CONF_HOST] == "http://192.0.2.10"
    assert suggested[CONF_PASSWORD] is None

    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], user_input(simulator, host=closed_port)
    )
    assert result["errors"] == {"base": "cannot_connect"}

    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], user_input(simulator, username=SIM_USERNAME)
    )
    assert result["type"] is FlowResultType.ABORT
    assert result["reason"] == "tecoapi_reconfigured"
    assert entry.data == entry_data(simulator)


async def test_reconfigure_to_another_plc(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    """An address where a different PLC answers aborts with wrong_device."""
    entry = MockConfigEntry(
        domain=DOMAIN,
        unique_id="PP 0004",
        data=entry_data(simulator, host="http://192.0.2.10"),
    )
    entry.add_to_hass(hass)

    result = await entry.start_reconfigure_flow(hass)
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], user_input(simulator)
    )

    assert result["type"] is FlowResultType.ABORT
    assert result["reason"] == "tecoapi_wrong_device"
    assert entry.data[CONF_HOST] == "http://192.0.2.10"
