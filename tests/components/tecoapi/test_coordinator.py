"""The coordinator: discovery, polling, per-entity updates, attribute refresh, failures."""

from aiohttp import web
from freezegun.api import FrozenDateTimeFactory
from homeassistant.const import STATE_UNAVAILABLE
from homeassistant.core import HomeAssistant
from homeassistant.helpers.update_coordinator import UpdateFailed
import pytest
from pytest_homeassistant_custom_component.common import (
    MockConfigEntry,
)

from custom_components.tecoapi.const import (
    CONF_INCLUDE,
    CONF_PLAIN_VARIABLES,
    PlainVariables,
)
from tests.components.tecoapi.conftest import (
    StateWrites,
    make_entry,
    poll,
    setup_entry,
)
from tests.simulator import Simulator

OUTSIDE = "sensor.tecomat_cp_2080_outside_temperature"
LIVING = "sensor.rooms_living_room_temperature"
CLOCK_OFFSET = "sensor.tecomat_cp_2080_clock_offset"
MODE = "sensor.tecomat_cp_2080_mode"
PROBLEM = "binary_sensor.tecomat_cp_2080_running_problem"


async def test_discovery_is_the_first_poll(
    hass: HomeAssistant, simulator: Simulator, config_entry: MockConfigEntry
) -> None:
    """Setup reads GetInfo, GetList and the roots; no extra poll follows at once."""
    await setup_entry(hass, config_entry)

    services = [request.service for request in simulator.requests]
    assert services[:3] == ["GetInfo", "GetInfo", "GetList"]
    assert set(services[3:]) == {"GetObject"}
    assert not simulator.requests[0].authorized
    assert all(request.authorized for request in simulator.requests[1:])
    assert hass.states.get(OUTSIDE).state == "4.5"


@pytest.mark.usefixtures("demo_entry")
async def test_unchanged_poll_writes_no_state(
    hass: HomeAssistant,
    simulator: Simulator,
    freezer: FrozenDateTimeFactory,
    state_writes: StateWrites,
) -> None:
    """A poll that finds every value as it was writes no state at all.

    Such a quiet poll also reads GetInfo: a stopped program changes nothing.
    """
    simulator.clear_requests()

    await poll(hass, freezer)
    await poll(hass, freezer)

    assert simulator.requests
    assert {request.service for request in simulator.requests} == {
        "GetObject",
        "GetInfo",
    }
    assert state_writes.total == 0


async def test_one_changed_value_writes_one_state(
    hass: HomeAssistant,
    simulator: Simulator,
    demo_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
    state_writes: StateWrites,
) -> None:
    """A value changed in the PLC: its entity, and only it, writes its state."""
    simulator.set_value("outsideTemp.value", -2.5)

    await demo_entry.runtime_data.async_refresh()

    assert state_writes == {OUTSIDE: 1}
    assert hass.states.get(OUTSIDE).state == "-2.5"


async def test_poll_takes_one_round_trip_per_planned_request(
    hass: HomeAssistant,
    simulator: Simulator,
    demo_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """Each planned GetObject is one authorised request: no challenge per poll."""
    coordinator = demo_entry.runtime_data
    simulator.clear_requests()
    # A value changed: the poll is not quiet, so it reads no GetInfo either.
    simulator.set_value("outsideTemp.value", -2.5)

    await poll(hass, freezer)

    plan = coordinator.source.read_plan
    assert plan is not None
    assert plan.point_keys == coordinator.polled_keys
    assert len(simulator.requests) == len(plan.requests)
    assert len(plan.requests) <= plan.lower_bound + 1
    assert all(request.authorized for request in simulator.requests)


@pytest.mark.usefixtures("demo_entry")
async def test_disabled_entities_are_not_polled(
    hass: HomeAssistant, simulator: Simulator, freezer: FrozenDateTimeFactory
) -> None:
    """Plain variables are disabled by default, so a poll does not read them."""
    simulator.clear_requests()

    await poll(hass, freezer)

    queries = " ".join(request.query for request in simulator.requests)
    assert "outsideTemp" in queries
    assert "doorbellCount" not in queries


async def test_enabled_plain_variables_are_polled(
    hass: HomeAssistant, simulator: Simulator, freezer: FrozenDateTimeFactory
) -> None:
    """With plain variables enabled they are shown and polled, named by their path."""
    freezer.move_to("2026-03-14T10:00:00+00:00")
    entry = make_entry(simulator, **{CONF_PLAIN_VARIABLES: PlainVariables.ENABLED})
    await setup_entry(hass, entry)
    simulator.set_value("doorbellCount", 1288)

    await poll(hass, freezer)

    state = hass.states.get("sensor.tecomat_cp_2080_doorbellcount")
    assert state.state == "1288"
    assert state.name == "Tecomat CP-2080 doorbellCount"


async def test_attributes_and_status_follow_the_slow_cadence(
    hass: HomeAssistant,
    simulator: Simulator,
    freezer: FrozenDateTimeFactory,
    state_writes: StateWrites,
) -> None:
    """Titles, enable flags and the PLC status are read every attribute interval.

    A T_ApiObject the plan reads whole anyway shows attribute changes sooner;
    this entry polls the family house's heating and rooms only, whose plan reads
    the outside temperature by its ``.value``.
    """
    freezer.move_to("2026-03-14T10:00:00+00:00")
    entry = make_entry(
        simulator, **{CONF_INCLUDE: ["outsidetemp", "rooms.*", "heating.*"]}
    )
    await setup_entry(hass, entry)
    await poll(hass, freezer, 5)
    plan = entry.runtime_data.source.read_plan
    assert plan is not None
    assert "outsideTemp.value" in {
        name for request in plan.requests for name in request.names
    }
    state_writes.clear()
    simulator.set_value("outsideTemp.attr.title", "Outdoor temperature")
    simulator.set_value("outsideTemp.attr.enable", False)

    await poll(hass, freezer, 5)

    assert hass.states.get(OUTSIDE).name == "Tecomat CP-2080 Outside temperature"
    assert state_writes.total == 0

    simulator.clear_requests()
    await poll(hass, freezer, 50)

    assert simulator.requests[0].service == "GetInfo"
    outside = hass.states.get(OUTSIDE)
    assert outside.state == STATE_UNAVAILABLE
    assert outside.name == "Tecomat CP-2080 Outdoor temperature"
    assert hass.states.get(MODE).state == "run"
    assert hass.states.get(PROBLEM).state == "off"
    # The PLC's clock moved on with Home Assistant's: its offset did not change.
    assert hass.states.get(CLOCK_OFFSET).state == "0"
    assert set(state_writes) == {OUTSIDE}


@pytest.mark.usefixtures("demo_entry")
async def test_failed_poll_makes_entities_unavailable_until_the_next_good_one(
    hass: HomeAssistant,
    simulator: Simulator,
    freezer: FrozenDateTimeFactory,
) -> None:
    """A broken answer makes every entity unavailable; the next good poll restores them."""
    simulator.faults.malformed_json = True

    await poll(hass, freezer)

    assert hass.states.get(OUTSIDE).state == STATE_UNAVAILABLE
    assert hass.states.get(MODE).state == STATE_UNAVAILABLE

    simulator.faults.clear()
    simulator.set_value("outsideTemp.value", 7.0)
    await poll(hass, freezer)

    assert hass.states.get(OUTSIDE).state == "7.0"
    assert hass.states.get(MODE).state == "run"


@pytest.mark.usefixtures("demo_entry")
async def test_unreachable_plc_while_running(
    hass: HomeAssistant, simulator: Simulator, freezer: FrozenDateTimeFactory
) -> None:
    """A dropped connection makes the entities unavailable; they return with the PLC."""
    simulator.faults.drop_connection = True

    await poll(hass, freezer)

    assert hass.states.get(OUTSIDE).state == STATE_UNAVAILABLE

    simulator.faults.clear()
    await poll(hass, freezer)

    assert hass.states.get(OUTSIDE).state == "4.5"


async def test_missing_variable_makes_only_its_entity_unavailable(
    hass: HomeAssistant,
    simulator: Simulator,
    demo_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """A root the PLC stops serving (400.005) takes only its entities down."""
    simulator.faults.rejected_by_object = {"outsideTemp"}

    await poll(hass, freezer)

    assert hass.states.get(OUTSIDE).state == STATE_UNAVAILABLE
    assert hass.states.get(LIVING).state == "21.8"

    simulator.faults.clear()
    await poll(hass, freezer)

    assert hass.states.get(OUTSIDE).state == "4.5"


async def test_another_web_server_at_the_address(
    hass: HomeAssistant,
    simulator: Simulator,
    demo_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """The PLC's address now serves some other web site: the poll fails as unknown."""
    port = simulator.port
    await simulator.stop()

    async def not_found(request: web.Request) -> web.Response:
        return web.Response(status=404, text="No such page")

    app = web.Application()
    app.router.add_get("/{tail:.*}", not_found)
    runner = web.AppRunner(app, access_log=None)
    await runner.setup()
    await web.TCPSite(runner, "127.0.0.1", port, reuse_address=True).start()
    try:
        await poll(hass, freezer)
    finally:
        await runner.cleanup()

    error = demo_entry.runtime_data.last_exception
    assert isinstance(error, UpdateFailed)
    assert error.translation_key == "unknown_error"
    assert hass.states.get(OUTSIDE).state == STATE_UNAVAILABLE
