"""Push through Home Assistant: PLCComS beside TecoApi, and PLCComS alone.

Both are set up as a user sets them up: push from a TecoApi entry's options (a
PLCComS host and port), PLCComS alone from the config flow's second choice. The
PLCComS server is the simulator's, over real TCP on 127.0.0.1, serving the same
PLC memory as the TecoApi simulator; it scans for changes when a test says so.

The clock runs here (a burst of pushed values is handed on after its 10 ms window,
and waits time out); polls are asked for with `refresh()` rather than waited for.
"""

import asyncio
from collections.abc import AsyncIterator
from datetime import UTC, datetime
import json
import logging
from typing import Any
from unittest.mock import PropertyMock, patch

from homeassistant.components.diagnostics import REDACTED
from homeassistant.config_entries import SOURCE_USER, ConfigEntryState
from homeassistant.const import (
    CONF_HOST,
    CONF_PORT,
    CONF_SCAN_INTERVAL,
    EVENT_STATE_CHANGED,
    STATE_UNAVAILABLE,
)
from homeassistant.core import Event, HomeAssistant, callback
from homeassistant.data_entry_flow import FlowResultType
from homeassistant.helpers import entity_registry as er
from homeassistant.helpers.update_coordinator import UpdateFailed
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry
from pytest_homeassistant_custom_component.components.diagnostics import (
    get_diagnostics_for_config_entry,
)
from pytest_homeassistant_custom_component.typing import ClientSessionGenerator

from custom_components.tecoapi.const import CONF_PUSH, CONF_TRANSPORT, DOMAIN
from custom_components.tecoapi.options import PlcOptions
from custom_components.tecoapi.pyplc import PlcResponseError
from custom_components.tecoapi.pyplc.core.source import RecentError
from custom_components.tecoapi.pyplc.tecomat import (
    PlcComsSource,
    PushedTecoApiSession,
    TecoApiSession,
)
from custom_components.tecoapi.pyplc.tecomat.points import value_path
from tests.components.tecoapi.conftest import make_entry, open_settings, setup_entry
from tests.simulator import Program, Simulator
from tests.simulator.plccoms import PlcComsServer
from tests.waits import connected

OUTSIDE = "sensor.tecomat_cp_2080_outside_temperature"
LIGHT = "switch.lights_kitchen_light"
MODE = "sensor.tecomat_cp_2080_mode"
IDENTITY = "EPSNET 127.0.0.1:61682"
"""A PLC's identity through PLCComS: its EPSNET address as the server reaches it."""
WAIT = 5.0


@pytest.fixture
async def coms(simulator: Simulator) -> AsyncIterator[PlcComsServer]:
    """The demo PLC's PLCComS server, scanning when a test says so."""
    async with PlcComsServer(simulator, scan_interval=None) as server:
        yield server


def push_options(coms: PlcComsServer) -> dict[str, Any]:
    """A TecoApi entry's options with push switched on, as the options flow stores."""
    return PlcOptions(push={CONF_HOST: "127.0.0.1", CONF_PORT: coms.port}).as_dict()


def plccoms_entry(coms: PlcComsServer, **options: Any) -> MockConfigEntry:
    """A PLCComS-only entry, as the config flow creates it (and ``options``)."""
    return MockConfigEntry(
        domain=DOMAIN,
        title="CP-2080 · FAMILY_HOUSE v1.3 · PLCComS",
        unique_id=IDENTITY,
        data={CONF_TRANSPORT: "plccoms", CONF_HOST: "127.0.0.1", CONF_PORT: coms.port},
        options=options,
    )


async def refresh(hass: HomeAssistant, entry: MockConfigEntry) -> None:
    """Poll the entry's PLC now, as its interval would."""
    await entry.runtime_data.async_refresh()
    await hass.async_block_till_done()


async def state_of(hass: HomeAssistant, entity_id: str, state: str) -> None:
    """Wait until an entity shows a state (already, or by a state change)."""
    if (current := hass.states.get(entity_id)) is not None and current.state == state:
        return
    shown = asyncio.get_running_loop().create_future()

    @callback
    def changed(event: Event[Any]) -> None:
        new = event.data["new_state"]
        if (
            event.data["entity_id"] == entity_id
            and new is not None
            and new.state == state
            and not shown.done()
        ):
            shown.set_result(None)

    unsubscribe = hass.bus.async_listen(EVENT_STATE_CHANGED, changed)
    try:
        async with asyncio.timeout(WAIT):
            await shown
    finally:
        unsubscribe()


# --- TecoApi with push -------------------------------------------------------------


async def pushed_entry(
    hass: HomeAssistant, simulator: Simulator, coms: PlcComsServer
) -> MockConfigEntry:
    """A TecoApi entry with push on, PLCComS connected and one poll done.

    The poll enables the polled points on PLCComS and reads TecoApi once.
    """
    entry = await setup_entry(hass, make_entry(simulator, **push_options(coms)))
    source = entry.runtime_data.source
    assert isinstance(source, PushedTecoApiSession)
    await connected(source.coms, WAIT)
    await refresh(hass, entry)
    return entry


async def test_push_is_off_unless_the_user_switches_it_on(
    hass: HomeAssistant, simulator: Simulator, coms: PlcComsServer
) -> None:
    """A PLCComS server on the network is never used by itself."""
    entry = await setup_entry(hass, make_entry(simulator))
    assert type(entry.runtime_data.source) is TecoApiSession
    assert coms.connections == 0


async def test_diagnostics_never_name_the_push_server_s_host(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    simulator: Simulator,
    coms: PlcComsServer,
) -> None:
    """Its settings show with the host redacted; a message naming it is scrubbed."""
    push = {CONF_HOST: "localhost", CONF_PORT: coms.port}
    entry = make_entry(simulator, **PlcOptions(push=push).as_dict())
    await setup_entry(hass, entry)
    source = entry.runtime_data.source
    assert isinstance(source, PushedTecoApiSession)
    await connected(source.coms, WAIT)
    failure = RecentError(
        time=datetime(2026, 3, 14, tzinfo=UTC),
        operation="push",
        error="PlcConnectionError",
        message=f"PLCComS at localhost:{coms.port} closed the connection",
    )
    with patch.object(
        PushedTecoApiSession,
        "recent_errors",
        new_callable=PropertyMock,
        return_value=(failure,),
    ):
        diagnostics: dict[str, Any] = await get_diagnostics_for_config_entry(
            hass, hass_client, entry
        )

    assert "localhost" not in json.dumps(diagnostics)
    shown = {CONF_HOST: REDACTED, CONF_PORT: coms.port}
    assert diagnostics["entry"]["options"][CONF_PUSH] == shown
    assert diagnostics["options"][CONF_PUSH] == shown
    assert diagnostics["recent_errors"][0]["message"] == (
        f"PLCComS at {REDACTED}:{coms.port} closed the connection"
    )


@pytest.mark.usefixtures("entity_registry_enabled_by_default")
async def test_pushed_values_and_modes_reach_the_entities_at_once(
    hass: HomeAssistant,
    simulator: Simulator,
    coms: PlcComsServer,
) -> None:
    """Push on in the options: values and HALT arrive without a TecoApi value poll."""
    entry = await pushed_entry(hass, simulator, coms)
    simulator.clear_requests()

    simulator.set_value("outsideTemp.value", -4.0)
    simulator.set_value("lights[1].value", False)
    await coms.scan()
    await state_of(hass, OUTSIDE, "-4.0")
    await state_of(hass, LIGHT, "off")
    await refresh(hass, entry)  # a poll while PLCComS is healthy asks TecoApi nothing
    await refresh(hass, entry)

    simulator.mode = "HALT"
    await coms.scan()
    await state_of(hass, MODE, "halt")

    # Values came by push, the mode by one GetInfo: no value poll of TecoApi.
    assert [r.service for r in simulator.requests if r.authorized] == ["GetInfo"]


@pytest.mark.parametrize("transport", ["tecoapi", "plccoms"])
async def test_values_are_pushed_from_the_setup_on(
    hass: HomeAssistant,
    simulator: Simulator,
    coms: PlcComsServer,
    transport: str,
) -> None:
    """Polled every 5 minutes: a change is pushed at once, before any poll.

    The setup enables the polled points on PLCComS as soon as the entities
    listen, instead of at the first scheduled poll (up to an interval later),
    and reads no poll for it.
    """
    if transport == "tecoapi":
        entry = make_entry(simulator, **{**push_options(coms), CONF_SCAN_INTERVAL: 300})
        serial_number = simulator.serial_number
    else:
        entry = plccoms_entry(coms, **{CONF_SCAN_INTERVAL: 300})
        serial_number = IDENTITY
    await setup_entry(hass, entry)
    await hass.async_block_till_done(wait_background_tasks=True)
    source = entry.runtime_data.source
    simulator.clear_requests()

    simulator.set_value("outsideTemp.value", -9.5)
    await coms.scan()

    outside = er.async_get(hass).async_get_entity_id(
        "sensor", DOMAIN, f"{serial_number}_outsidetemp"
    )
    assert outside is not None
    await state_of(hass, outside, "-9.5")
    assert source.statistics.polls == 0
    assert simulator.requests == []


async def test_polling_takes_over_when_plccoms_drops(
    hass: HomeAssistant,
    simulator: Simulator,
    coms: PlcComsServer,
) -> None:
    """PLCComS gone: every poll reads TecoApi again, and values keep coming."""
    entry = await pushed_entry(hass, simulator, coms)

    await coms.stop()
    simulator.set_value("outsideTemp.value", 12.5)
    simulator.clear_requests()
    await refresh(hass, entry)

    assert "GetObject" in {r.service for r in simulator.requests}
    assert hass.states.get(OUTSIDE).state == "12.5"


# --- PLCComS alone -----------------------------------------------------------------


@pytest.mark.usefixtures("entity_registry_enabled_by_default")
async def test_plccoms_alone_gives_the_entities_tecoapi_gives(
    hass: HomeAssistant,
    simulator: Simulator,
    coms: PlcComsServer,
) -> None:
    """The same entities (names from T_ApiObject titles), keyed by the PLCComS identity."""
    tecoapi = await setup_entry(hass, make_entry(simulator))
    registry = er.async_get(hass)
    expected = {
        entry.unique_id.removeprefix(f"{simulator.serial_number}_"): entry.original_name
        for entry in er.async_entries_for_config_entry(registry, tecoapi.entry_id)
    }
    await hass.config_entries.async_remove(tecoapi.entry_id)
    await hass.async_block_till_done()

    alone = await setup_entry(hass, plccoms_entry(coms))
    points = {
        entry.unique_id.removeprefix(f"{IDENTITY}_"): entry.original_name
        for entry in er.async_entries_for_config_entry(registry, alone.entry_id)
    }

    # Status entities' keys hold a dash, point keys never do.
    def point_entities(names: dict[str, str | None]) -> dict[str, str | None]:
        return {key: name for key, name in names.items() if "-" not in key}

    assert point_entities(points) == point_entities(expected)

    source = alone.runtime_data.source
    assert isinstance(source, PlcComsSource)
    await refresh(hass, alone)  # enables the polled points
    simulator.set_value("outsideTemp.value", 8.5)
    await coms.scan()
    outside = registry.async_get_entity_id("sensor", DOMAIN, f"{IDENTITY}_outsidetemp")
    assert outside is not None
    await state_of(hass, outside, "8.5")


async def submit_plccoms(hass: HomeAssistant, port: int) -> Any:
    """Add a PLC through PLCComS on 127.0.0.1:``port``, as a user: the flow's answer."""
    result = await hass.config_entries.flow.async_init(
        DOMAIN, context={"source": SOURCE_USER}
    )
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {"next_step_id": "plccoms"}
    )
    return await hass.config_entries.flow.async_configure(
        result["flow_id"], {CONF_HOST: "127.0.0.1", CONF_PORT: port}
    )


async def test_config_flow_adds_a_plc_through_plccoms(
    hass: HomeAssistant, simulator: Simulator, coms: PlcComsServer
) -> None:
    """The second choice: a PLCComS host and port, checked, then the entry."""
    result = await hass.config_entries.flow.async_init(
        DOMAIN, context={"source": SOURCE_USER}
    )
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {"next_step_id": "plccoms"}
    )
    assert result["step_id"] == "plccoms"
    flow_id = result["flow_id"]

    for host, port, error in (
        ("http://127.0.0.1", coms.port, {CONF_HOST: "invalid_plccoms_host"}),
        ("127.0.0.1", 1, {"base": "plccoms_cannot_connect"}),
    ):
        result = await hass.config_entries.flow.async_configure(
            flow_id, {CONF_HOST: host, CONF_PORT: port}
        )
        assert result["type"] is FlowResultType.FORM
        assert result["errors"] == error

    with patch("custom_components.tecoapi.async_setup_entry", return_value=True):
        result = await hass.config_entries.flow.async_configure(
            flow_id, {CONF_HOST: " 127.0.0.1 ", CONF_PORT: coms.port}
        )
    assert result["type"] is FlowResultType.CREATE_ENTRY
    # Its TecoApi entry's title, and the way in: the two can be told apart.
    assert result["title"] == "CP-2080 · FAMILY_HOUSE v1.3 · PLCComS"
    assert result["data"] == {
        CONF_TRANSPORT: "plccoms",
        CONF_HOST: "127.0.0.1",
        CONF_PORT: coms.port,
    }
    assert result["result"].unique_id == IDENTITY
    # No credentials asked, none stored; and nothing switched on beyond the entry.
    assert not result["result"].options

    # The same PLC again: already configured.
    result = await submit_plccoms(hass, coms.port)
    assert result["type"] is FlowResultType.ABORT
    assert result["reason"] == "plccoms_already_configured"


async def test_config_flow_plccoms_without_variables(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    """A PLCComS server that lists nothing of the PLC is not taken."""
    empty = simulator.program.to_mapping()
    empty["variables"] = {}
    empty["links"] = []
    simulator.load_program(Program.from_mapping(empty))
    async with PlcComsServer(simulator, scan_interval=None) as coms:
        result = await submit_plccoms(hass, coms.port)
    assert result["errors"] == {"base": "plccoms_no_variables"}


async def test_reconfigure_moves_a_plccoms_entry_to_another_server(
    hass: HomeAssistant, simulator: Simulator, coms: PlcComsServer
) -> None:
    """The same PLC through another PLCComS server (or port): the entry follows."""
    entry = await setup_entry(hass, plccoms_entry(coms))
    result = await entry.start_reconfigure_flow(hass)
    assert result["step_id"] == "reconfigure_plccoms"

    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {CONF_HOST: "127.0.0.1", CONF_PORT: 1}
    )
    assert result["errors"] == {"base": "plccoms_cannot_connect"}

    # A scheme is no host name: refused on the field, nothing tried.
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {CONF_HOST: "http://127.0.0.1", CONF_PORT: coms.port}
    )
    assert result["step_id"] == "reconfigure_plccoms"
    assert result["errors"] == {CONF_HOST: "invalid_plccoms_host"}

    async with PlcComsServer(simulator, scan_interval=None) as moved:
        result = await hass.config_entries.flow.async_configure(
            result["flow_id"], {CONF_HOST: "127.0.0.1", CONF_PORT: moved.port}
        )
        await hass.async_block_till_done()
        assert result["type"] is FlowResultType.ABORT
        assert result["reason"] == "plccoms_reconfigured"
        assert entry.data[CONF_PORT] == moved.port
        assert entry.state is ConfigEntryState.LOADED
        source = entry.runtime_data.source
        assert isinstance(source, PlcComsSource)
        assert source.client.port == moved.port


# --- switching push on in the options ------------------------------------------------


async def open_push_options(hass: HomeAssistant, entry: MockConfigEntry) -> str:
    """Open the options; return the flow ID."""
    result = await open_settings(hass, entry.entry_id)
    assert result["type"] is FlowResultType.FORM
    return str(result["flow_id"])


def options_input(host: str, port: int) -> dict[str, Any]:
    """The options form as the frontend submits it, push in its section."""
    return {**PlcOptions().as_dict(), CONF_PUSH: {CONF_HOST: host, CONF_PORT: port}}


async def refused_push(hass: HomeAssistant, entry: MockConfigEntry, port: int) -> Any:
    """Submit push on 127.0.0.1:``port`` in the options; the form's errors.

    The server is refused: push stays off.
    """
    flow_id = await open_push_options(hass, entry)
    result = await hass.config_entries.options.async_configure(
        flow_id, options_input("127.0.0.1", port)
    )
    assert entry.options.get(CONF_PUSH, {}).get(CONF_HOST, "") == ""
    return result["errors"]


async def test_switching_push_on_checks_the_server_and_swaps_the_source(
    hass: HomeAssistant, simulator: Simulator, coms: PlcComsServer
) -> None:
    """Errors for a wrong host or port, then push on: the entry's source is swapped.

    The errors are the Push section's: the frontend shows them right above it,
    by the Submit button (an error of a field inside a section it does not show).
    """
    entry = await setup_entry(hass, make_entry(simulator))
    flow_id = await open_push_options(hass, entry)

    for host, port, error in (
        ("127.0.0.1/x", coms.port, {CONF_PUSH: "invalid_plccoms_host"}),
        ("127.0.0.1", 1, {CONF_PUSH: "plccoms_cannot_connect"}),
    ):
        result = await hass.config_entries.options.async_configure(
            flow_id, options_input(host, port)
        )
        assert result["type"] is FlowResultType.FORM
        assert result["errors"] == error
        # The form keeps what was typed, push unfolded.
        push = result["data_schema"].schema[CONF_PUSH]
        assert push.options == {"collapsed": False}
        assert {
            str(key): (key.description or {}).get("suggested_value")
            for key in push.schema.schema
        } == {CONF_HOST: host, CONF_PORT: port}

    result = await hass.config_entries.options.async_configure(
        flow_id, options_input("127.0.0.1", coms.port)
    )
    await hass.async_block_till_done()
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert entry.options[CONF_PUSH] == {CONF_HOST: "127.0.0.1", CONF_PORT: coms.port}
    assert entry.state is ConfigEntryState.LOADED
    assert isinstance(entry.runtime_data.source, PushedTecoApiSession)

    # Shown unfolded next time; emptying the host switches push off again.
    result = await open_settings(hass, entry.entry_id)
    assert result["data_schema"].schema[CONF_PUSH].options == {"collapsed": False}
    flow_id = result["flow_id"]
    result = await hass.config_entries.options.async_configure(
        flow_id, options_input("", coms.port)
    )
    await hass.async_block_till_done()
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert type(entry.runtime_data.source) is TecoApiSession


async def test_push_switched_on_in_the_options_is_pushed_at_once(
    hass: HomeAssistant, simulator: Simulator, coms: PlcComsServer
) -> None:
    """Polled every 5 minutes, push switched on in the options: pushed at once.

    The options apply in place (no reload) and swap the source; the swapped
    source enables the polled points on PLCComS as soon as the options flow is
    done, not at the next scheduled poll up to an interval later, and a change
    is then pushed before any poll.
    """
    entry = await setup_entry(hass, make_entry(simulator, **{CONF_SCAN_INTERVAL: 300}))
    coordinator = entry.runtime_data
    flow_id = await open_push_options(hass, entry)
    result = await hass.config_entries.options.async_configure(
        flow_id,
        {**options_input("127.0.0.1", coms.port), CONF_SCAN_INTERVAL: 300},
    )
    assert result["type"] is FlowResultType.CREATE_ENTRY
    await hass.async_block_till_done(wait_background_tasks=True)
    source = coordinator.source
    assert isinstance(source, PushedTecoApiSession)
    assert entry.runtime_data is coordinator

    # Every polled point is enabled on PLCComS already.
    polled = {
        value_path(coordinator.data.catalogue.points[key]).lower()
        for key in coordinator.polled_keys
    }
    assert "outsidetemp.value" in polled
    (enabled,) = coms.enabled()
    assert polled <= enabled

    simulator.clear_requests()
    simulator.set_value("outsideTemp.value", -9.5)
    await coms.scan()
    await state_of(hass, OUTSIDE, "-9.5")
    assert source.statistics.polls == 0
    assert simulator.requests == []


async def test_a_plccoms_server_of_another_plc_is_refused(
    hass: HomeAssistant, simulator: Simulator, manual_simulator: Simulator
) -> None:
    """PLCComS of another PLC (none of this program's variables) is not taken."""
    entry = await setup_entry(hass, make_entry(simulator))
    async with PlcComsServer(manual_simulator, scan_interval=None) as other:
        errors = await refused_push(hass, entry, other.port)
    assert errors == {CONF_PUSH: "plccoms_other_plc"}


async def test_a_plccoms_server_listing_nothing_is_refused(
    hass: HomeAssistant, simulator: Simulator, manual_simulator: Simulator
) -> None:
    """PLCComS that lists no variable (no public variables exported) is not taken."""
    entry = await setup_entry(hass, make_entry(simulator))
    empty = manual_simulator.program.to_mapping()
    empty["variables"] = {}
    manual_simulator.load_program(Program.from_mapping(empty))
    async with PlcComsServer(manual_simulator, scan_interval=None) as other:
        errors = await refused_push(hass, entry, other.port)
    assert errors == {CONF_PUSH: "plccoms_no_variables"}


async def test_a_plccoms_check_that_fails_otherwise_says_so(
    hass: HomeAssistant,
    simulator: Simulator,
    coms: PlcComsServer,
    caplog: pytest.LogCaptureFixture,
) -> None:
    """An error answer to the check: a translated error, the details in the log."""
    entry = await setup_entry(hass, make_entry(simulator))
    flow_id = await open_push_options(hass, entry)
    with patch.object(
        PlcComsSource, "identify", side_effect=PlcResponseError("ERROR: busy")
    ):
        result = await hass.config_entries.options.async_configure(
            flow_id, options_input("127.0.0.1", coms.port)
        )
    assert result["errors"] == {CONF_PUSH: "unknown"}
    assert "ERROR: busy" in caplog.text


async def test_a_plccoms_entry_has_no_push_section(
    hass: HomeAssistant, simulator: Simulator, coms: PlcComsServer
) -> None:
    """PLCComS alone pushes already: its options are the polling and entity ones."""
    entry = await setup_entry(hass, plccoms_entry(coms))
    result = await open_settings(hass, entry.entry_id)
    assert CONF_PUSH not in result["data_schema"].schema
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], PlcOptions().as_dict()
    )
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert CONF_PUSH not in entry.options


# --- a PLCComS server that cannot reach its PLC ----------------------------------------------


async def test_config_flow_says_plccoms_cannot_reach_its_plc(
    hass: HomeAssistant,
    coms: PlcComsServer,
    caplog: pytest.LogCaptureFixture,
) -> None:
    """ERROR:10 to LIST: (Teco's server 6.1 so): a translated error, no traceback."""
    coms.faults.plc_unreachable = True
    result = await submit_plccoms(hass, coms.port)

    assert result["type"] is FlowResultType.FORM
    assert result["errors"] == {"base": "plccoms_plc_unreachable"}
    assert not [r for r in caplog.records if r.levelno >= logging.ERROR]


async def test_push_options_say_plccoms_cannot_reach_its_plc(
    hass: HomeAssistant, simulator: Simulator, coms: PlcComsServer
) -> None:
    """The Push section's check tells the same, and push stays off."""
    entry = await setup_entry(hass, make_entry(simulator))
    coms.faults.plc_unreachable = True

    errors = await refused_push(hass, entry, coms.port)

    assert errors == {CONF_PUSH: "plccoms_plc_unreachable"}


async def test_entities_show_the_plc_out_of_plccoms_reach_and_come_back(
    hass: HomeAssistant, simulator: Simulator, coms: PlcComsServer
) -> None:
    """Unavailable with the reason while the PLC is out of reach; back without a reload."""
    entry = await setup_entry(hass, plccoms_entry(coms))
    source = entry.runtime_data.source
    assert isinstance(source, PlcComsSource)
    registry = er.async_get(hass)
    outside = registry.async_get_entity_id("sensor", DOMAIN, f"{IDENTITY}_outsidetemp")
    assert outside is not None
    await refresh(hass, entry)
    assert hass.states.get(outside).state == "4.5"
    accepted = coms.connections_accepted

    coms.faults.plc_unreachable = True
    await refresh(hass, entry)

    assert hass.states.get(outside).state == STATE_UNAVAILABLE
    failure = entry.runtime_data.last_exception
    assert isinstance(failure, UpdateFailed)
    assert failure.translation_key == "plc_unreachable"
    assert "cannot reach the PLC (the device says: ERROR:10 " in str(failure)
    # The client keeps trying by itself; the PLC comes back, changed meanwhile.
    await coms.wait_for_connections(accepted + 1)
    simulator.set_value("outsideTemp.value", -2.5)
    coms.faults.plc_unreachable = False
    await connected(source.client, WAIT)
    await refresh(hass, entry)

    assert hass.states.get(outside).state == "-2.5"
    assert entry.state is ConfigEntryState.LOADED
