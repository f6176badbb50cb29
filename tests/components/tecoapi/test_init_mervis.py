"""Mervis (Unipi) in Home Assistant, over real HTTP against the simulated controller.

The config flow uploads the project's ``.vlist`` (Home Assistant's
``file_upload``, as the frontend posts it), logs in and reads a few of its
variables; the entry's variables become entities by their type, ``hw.*`` left
out but for the inputs' and outputs' states; the options mark a variable
writable (a newer file and the point form: flows/test_point_map.py); a write
shows at once; one bad item costs its entity only; reauthentication follows a changed
password; diagnostics redact the credentials.
"""

from collections.abc import AsyncIterator, Mapping
from datetime import UTC, datetime, timedelta
import logging
from typing import Any, Final

from freezegun.api import FrozenDateTimeFactory
from homeassistant.config_entries import ConfigEntry, ConfigEntryState
from homeassistant.const import (
    ATTR_ENTITY_ID,
    CONF_HOST,
    CONF_PASSWORD,
    CONF_USERNAME,
    CONF_VERIFY_SSL,
    STATE_UNAVAILABLE,
    EntityCategory,
)
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
from homeassistant.exceptions import ServiceValidationError
from homeassistant.helpers import (
    device_registry as dr,
    entity_registry as er,
    issue_registry as ir,
)
import pytest
from pytest_homeassistant_custom_component.typing import ClientSessionGenerator
import yaml

from custom_components.tecoapi.compat import AREA_IN_ENTITY_ID, vol
from custom_components.tecoapi.const import CONF_EXCLUDE, CONF_TRANSPORT, DOMAIN
from custom_components.tecoapi.diagnostics import async_get_config_entry_diagnostics
from custom_components.tecoapi.flows.point_class import CLASS_STEP
from custom_components.tecoapi.flows.point_map import form_values
from custom_components.tecoapi.options import PlcOptions
from custom_components.tecoapi.pyplc import NoPublicVariablesError
from custom_components.tecoapi.pyplc.core.descriptor import (
    CONF_POINT_MAP,
    SourceContext,
    SourceOptions,
)
from custom_components.tecoapi.pyplc.core.pointmap import MapPoint, data_type
from custom_components.tecoapi.pyplc.mervis.descriptor import (
    DEFAULT_EXCLUDE,
    MERVIS,
    check_address,
)
from custom_components.tecoapi.pyplc.mervis.vlist import PROJECT
from tests.components.tecoapi.conftest import poll
from tests.components.tecoapi.file_upload import map_field
from tests.components.tecoapi.mervis_house import (
    PASSWORD,
    USER,
    add,
    add_house,
    entity,
    form,
    keys,
    start_flow,
    upload,
    upload_newer,
)
from tests.e2e.configuration import DEMO_DASHBOARD
from tests.e2e.provision import MERVIS_DEMO_POINTS, demo_vlist
from tests.simulator.mervis import (
    HOUSE_NAME,
    MervisSimulator,
    Switches,
    generated,
    house,
)

HOUSE_POINTS = 64
HOUSE_ENTITIES = 41
"""The house's points but the 23 hw settings, counters and registers."""


# --- adding a controller ----------------------------------------------------------------


async def test_a_controller_is_added_with_its_vlist(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, mervis: MervisSimulator
) -> None:
    result = await start_flow(hass)
    assert result["step_id"] == "mervis"
    assert {str(key) for key in result["data_schema"].schema} == {
        CONF_HOST,
        CONF_USERNAME,
        CONF_PASSWORD,
        CONF_VERIFY_SSL,
        CONF_POINT_MAP,
        PROJECT,
    }
    file_id = await upload(hass, hass_client, "house.vlist", mervis.project.vlist())
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], form(mervis, file_id)
    )
    await hass.async_block_till_done()

    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert result["title"] == f"Mervis · {HOUSE_NAME} · {mervis.host}"
    # It tells how many variables the file holds, and how many become entities.
    assert result["description"] == "point_map"
    assert result["description_placeholders"] == {
        "points": str(HOUSE_POINTS),
        "entities": str(HOUSE_ENTITIES),
        "skipped": "0",
    }
    entry = result["result"]
    assert entry.unique_id == f"Mervis {HOUSE_NAME} @ {mervis.host}"
    assert entry.data[CONF_TRANSPORT] == "mervis"
    assert entry.data[CONF_HOST] == mervis.url
    assert PROJECT not in entry.data  # the map's, not the connection's
    assert entry.options == {CONF_EXCLUDE: list(DEFAULT_EXCLUDE)}
    assert entry.state is ConfigEntryState.LOADED
    # The flow logged in and read a few of the file's variables.
    assert [record.service for record in mervis.requests[:2]] == ["login", "values"]
    assert len(keys(hass, entry)) == HOUSE_ENTITIES


async def test_variables_become_entities_by_their_type(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, mervis: MervisSimulator
) -> None:
    entry = await add_house(hass, hass_client, mervis)
    found = keys(hass, entry)
    # hw.*: the inputs' and outputs' states only.
    assert "hw.neuron_l203_di_1.02" in found
    assert "hw.neuron_l203_ro_2.08" in found
    assert "hw.neuron_l203_ai_1.01" in found
    assert "hw.neuron_l203_di_1.01_counter" not in found
    assert "hw.neuron_l203_fw_version" not in found
    di = hass.states.get(entity(hass, "binary_sensor", "hw.neuron_l203_di_1.02"))
    assert di.state == "on"
    temperature = hass.states.get(entity(hass, "sensor", "koupelna.temperature"))
    assert temperature.state == "21.5"
    # The controller's clock changes every poll: a diagnostic, disabled (no state,
    # so no logbook entry and no recorder row a poll) until the user enables it.
    clock = er.async_get(hass).async_get(entity(hass, "sensor", "clock"))
    assert clock is not None
    assert clock.entity_category is EntityCategory.DIAGNOSTIC
    assert clock.disabled_by is er.RegistryEntryDisabler.INTEGRATION
    assert hass.states.get(clock.entity_id) is None
    runtime = hass.states.get(entity(hass, "sensor", "kotel.runtime"))
    assert runtime.attributes["device_class"] == "duration"
    assert float(runtime.state) == pytest.approx(813 + 20 / 60, abs=0.01)
    assert hass.states.get(entity(hass, "sensor", "koupelna.mode")).state == "1"
    assert hass.states.get(entity(hass, "sensor", "energie.total")).state == "15234.25"


async def test_reals_and_durations_are_shown_with_few_decimals(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, mervis: MervisSimulator
) -> None:
    """A suggested display precision: two decimals of a real, of a duration's hour.

    An LREAL a program computes (hours: 3.69083333333333) showed every digit.
    An enumeration is its number (a .vlist names no labels), a counter whole.
    """
    await add_house(hass, hass_client, mervis)
    registry = er.async_get(hass)

    def precision(key: str) -> object:
        item = registry.async_get(entity(hass, "sensor", key))
        assert item is not None
        return item.options.get("sensor", {}).get("suggested_display_precision")

    assert {
        key: precision(key)
        for key in (
            "energie.total",
            "energie.power",
            "outside_temp",
            "kotel.runtime",
            "kotel.starts",
            "koupelna.mode",
        )
    } == {
        "energie.total": 2,
        "energie.power": 2,
        "outside_temp": 2,
        "kotel.runtime": 2,
        "kotel.starts": None,
        "koupelna.mode": None,
    }


async def test_names_are_readable_and_blocks_are_devices(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, mervis: MervisSimulator
) -> None:
    entry = await add_house(hass, hass_client, mervis)
    registry = dr.async_get(hass)
    devices = {
        device.name: device
        for device in dr.async_entries_for_config_entry(registry, entry.entry_id)
    }
    controller = devices[HOUSE_NAME]
    assert (controller.manufacturer, controller.model) == ("Unipi Technology", "Mervis")
    assert controller.configuration_url == mervis.url
    for name in ("Kotel", "Energie", "Neuron L203"):
        assert devices[name].via_device_id == controller.id
    # The board is its own model, not the project (the blocks are the project's).
    assert devices["Neuron L203"].model == "Neuron L203"
    assert devices["Kotel"].model == HOUSE_NAME
    # The hw namespace is the board its points name, which they do not say
    # again; Unipi's abbreviations stay in capitals.
    relay = hass.states.get("binary_sensor.neuron_l203_ro_2_01")
    assert relay.name == "Neuron L203 RO 2.01"
    di = hass.states.get(entity(hass, "binary_sensor", "hw.neuron_l203_di_1.02"))
    assert di.name == "Neuron L203 DI 1.02"
    analog = hass.states.get(entity(hass, "sensor", "hw.neuron_l203_ai_1.01"))
    assert analog.name == "Neuron L203 AI 1.01"
    assert entity(hass, "binary_sensor", "hw.neuron_l203_ro_2.01") == relay.entity_id
    water = er.async_get(hass).async_get(entity(hass, "sensor", "kotel.water_temp"))
    assert water is not None
    assert registry.async_get(water.device_id).name == "Kotel"  # type: ignore[union-attr]
    state = hass.states.get(water.entity_id)
    assert state.attributes["friendly_name"] == "Kotel Water temp"
    assert "$" not in state.attributes["friendly_name"]


@pytest.mark.parametrize(
    ("changes", "error", "field"),
    [
        ({CONF_PASSWORD: "wrong"}, "mervis_invalid_auth", "base"),
        ({CONF_USERNAME: "", CONF_PASSWORD: ""}, "mervis_invalid_auth", "base"),
        ({CONF_HOST: "http://127.0.0.1:1/path"}, "invalid_host", CONF_HOST),
    ],
)
async def test_what_the_form_refuses(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    mervis: MervisSimulator,
    *,
    changes: dict[str, Any],
    error: str,
    field: str,
) -> None:
    result = await add(hass, hass_client, mervis, **changes)
    assert result["type"] is FlowResultType.FORM
    assert result["errors"] == {field: error}
    assert hass.config_entries.async_entries(DOMAIN) == []


async def test_the_upload_outlives_a_wrong_password_and_a_wrong_port(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    mervis: MervisSimulator,
    closed_port: str,
) -> None:
    """The file read before an error is kept: the form, shown again, needs none.

    It does not suggest the file (issue 39: Home Assistant's file selector
    names only a file it uploaded itself, another is an "Unknown file"): the
    field is empty and optional, and left empty the map read before is used.
    """
    result = await start_flow(hass)
    file_id = await upload(hass, hass_client, "house.vlist", mervis.project.vlist())
    flow_id = result["flow_id"]
    assert map_field(result) == (vol.Required, None)
    result = await hass.config_entries.flow.async_configure(
        flow_id, form(mervis, file_id, **{CONF_PASSWORD: "wrong"})
    )
    assert result["errors"] == {"base": "mervis_invalid_auth"}
    assert map_field(result) == (vol.Optional, None)
    assert suggested(result)[CONF_PASSWORD] is None
    without_file = {
        key: value for key, value in form(mervis, "").items() if key != CONF_POINT_MAP
    }
    result = await hass.config_entries.flow.async_configure(
        flow_id, {**without_file, CONF_HOST: closed_port}
    )
    assert result["errors"] == {"base": "mervis_cannot_connect"}
    # Not about the password: it stays; the file is kept, not shown.
    assert map_field(result) == (vol.Optional, None)
    assert suggested(result)[CONF_PASSWORD] == PASSWORD
    result = await hass.config_entries.flow.async_configure(flow_id, without_file)
    await hass.async_block_till_done()
    assert result["type"] is FlowResultType.CREATE_ENTRY, result.get("errors")
    assert len(result["result"].runtime_data.point_map.points) == HOUSE_POINTS


def suggested(result: Mapping[str, Any]) -> dict[str, Any]:
    """What a form suggests in each field."""
    return {
        str(key): (key.description or {}).get("suggested_value")
        for key in result["data_schema"].schema
    }


async def test_nothing_answering(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    mervis: MervisSimulator,
    closed_port: str,
) -> None:
    result = await add(hass, hass_client, mervis, **{CONF_HOST: closed_port})
    assert result["errors"] == {"base": "mervis_cannot_connect"}


async def test_not_a_mervis_web_panel(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    mervis: MervisSimulator,
    web_server: str,
) -> None:
    result = await add(hass, hass_client, mervis, **{CONF_HOST: web_server})
    assert result["errors"] == {"base": "not_mervis"}


async def test_a_file_of_another_project_is_refused(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, mervis: MervisSimulator
) -> None:
    result = await add(hass, hass_client, mervis, generated(60, seed=5).vlist())
    assert result["errors"] == {"base": "vlist_unknown"}


@pytest.mark.parametrize(
    ("name", "text", "message"),
    [
        ("house.csv", "name,address,type\na,1[0,1],BOOL\n", "not a .vlist file"),
        ("house.vlist", "name,address,type\n", "no #ver: line"),
        (
            "house.vlist",
            "#ver:1.0\nProject;Name;Type;CommUid;Offset;Length\nP;$a$;$real$;1;0;3\n",
            "the file holds no variable",
        ),
    ],
)
async def test_a_file_that_is_no_vlist_is_refused(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    mervis: MervisSimulator,
    *,
    name: str,
    text: str,
    message: str,
) -> None:
    result = await add(hass, hass_client, mervis, text, name=name)
    assert result["errors"] == {CONF_POINT_MAP: "point_map_invalid"}
    assert message in result["description_placeholders"]["error"]


async def test_a_project_without_credentials(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, mervis: MervisSimulator
) -> None:
    mervis.username = None
    result = await add(
        hass, hass_client, mervis, **{CONF_USERNAME: "", CONF_PASSWORD: ""}
    )
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert CONF_USERNAME not in result["data"]
    assert CONF_PASSWORD not in result["data"]
    assert {record.service for record in mervis.requests} == {"values"}


async def test_the_same_controller_twice_is_configured_already(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, mervis: MervisSimulator
) -> None:
    await add_house(hass, hass_client, mervis)
    result = await add(hass, hass_client, mervis)
    assert (result["type"], result["reason"]) == (
        FlowResultType.ABORT,
        "mervis_already_configured",
    )


@pytest.fixture
async def unit(socket_enabled: None) -> AsyncIterator[MervisSimulator]:
    """A second controller running a copy of the same project (another house)."""
    async with MervisSimulator(house(), username=USER, password=PASSWORD) as sim:
        yield sim


async def reconfigure(
    hass: HomeAssistant, entry: ConfigEntry, sim: MervisSimulator
) -> dict[str, Any]:
    """Reconfigure an entry to a controller's address (the password kept)."""
    result = await hass.config_entries.flow.async_init(
        DOMAIN, context={"source": "reconfigure", "entry_id": entry.entry_id}
    )
    return await hass.config_entries.flow.async_configure(
        result["flow_id"],
        {CONF_HOST: sim.host, CONF_USERNAME: USER, CONF_VERIFY_SSL: True},
    )


async def test_two_units_of_one_project_are_both_added(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    mervis: MervisSimulator,
    unit: MervisSimulator,
) -> None:
    """Installers deploy one project to several units: each is an entry of its own.

    The second was refused as configured already, and the first entry was
    pointed at it.
    """
    first = await add_house(hass, hass_client, mervis)
    stored = (first.unique_id, dict(first.data))
    second = await add_house(hass, hass_client, unit)
    assert (first.unique_id, dict(first.data)) == stored
    assert second.unique_id == f"Mervis {HOUSE_NAME} @ {unit.host}"
    assert second.data[CONF_HOST] == unit.url
    assert first.state is second.state is ConfigEntryState.LOADED
    assert len(keys(hass, second)) == len(keys(hass, first)) == HOUSE_ENTITIES
    # Each shows its own house.
    unit.project.set("outside_temp", -7.5)
    await hass.config_entries.async_reload(second.entry_id)
    await hass.async_block_till_done()
    assert hass.states.get(keys(hass, first)["outside_temp"]).state == "4.5"
    assert hass.states.get(keys(hass, second)["outside_temp"]).state == "-7.5"


async def test_a_reconfigure_never_moves_an_entry_to_another_entry_s_unit(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    mervis: MervisSimulator,
    unit: MervisSimulator,
) -> None:
    first = await add_house(hass, hass_client, mervis)
    second = await add_house(hass, hass_client, unit)
    stored = dict(first.data)
    result = await reconfigure(hass, first, unit)
    assert (result["type"], result["reason"]) == (
        FlowResultType.ABORT,
        "device_of_another_entry",
    )
    assert result["description_placeholders"] == {"title": second.title}
    assert dict(first.data) == stored
    # Its own address again (a new password, say) is no other entry's.
    result = await reconfigure(hass, first, mervis)
    assert result["reason"] == "mervis_reconfigured"


async def test_a_unit_added_where_an_entry_was_added_is_a_new_entry(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    mervis: MervisSimulator,
    unit: MervisSimulator,
) -> None:
    """The entry moved away (a DHCP change); a unit now at its first address is another.

    Its identity named that address, the moved entry's unique ID: it aborted as
    configured already, for good (the test asserted that abort). Its unique ID
    is numbered now; the entry stays where its user moved it.
    """
    entry = await add_house(hass, hass_client, mervis)
    assert (await reconfigure(hass, entry, unit))["reason"] == ("mervis_reconfigured")
    await hass.async_block_till_done()
    added = await add_house(hass, hass_client, mervis)
    assert entry.unique_id == f"Mervis {HOUSE_NAME} @ {mervis.host}"
    assert added.unique_id == f"Mervis {HOUSE_NAME} @ {mervis.host} (2)"
    assert (entry.data[CONF_HOST], added.data[CONF_HOST]) == (unit.url, mervis.url)
    assert entry.state is added.state is ConfigEntryState.LOADED
    assert len(keys(hass, added)) == len(keys(hass, entry)) == HOUSE_ENTITIES
    # Each address is one entry's now.
    for sim in (mervis, unit):
        result = await add(hass, hass_client, sim)
        assert (result["type"], result["reason"]) == (
            FlowResultType.ABORT,
            "mervis_already_configured",
        )
    assert len(hass.config_entries.async_entries(DOMAIN)) == 2


async def test_a_unit_of_a_project_is_not_added_twice_at_its_address(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    mervis: MervisSimulator,
) -> None:
    """An entry added before the address was part of the identity is found by its address."""
    entry = await add_house(hass, hass_client, mervis)
    hass.config_entries.async_update_entry(entry, unique_id=f"Mervis {HOUSE_NAME}")
    result = await add(hass, hass_client, mervis)
    assert (result["type"], result["reason"]) == (
        FlowResultType.ABORT,
        "mervis_already_configured",
    )
    assert len(hass.config_entries.async_entries(DOMAIN)) == 1


def refusals(sim: MervisSimulator) -> int:
    """How many requests the controller refused."""
    return sum(1 for record in sim.requests if record.code not in ("ok", ""))


async def test_a_restart_reads_at_the_limits_learned_refusing_nothing(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, uploads: None
) -> None:
    """The seed's uPLC limits, told nothing: learned once, kept in the entry's store.

    A refusal of the limits was met by signing in again (three requests for
    one), and every setup learned the limits again from nothing.
    """
    switches = Switches(max_variables=5, max_request_size=1500)
    async with MervisSimulator(
        house(), username=USER, password=PASSWORD, switches=switches
    ) as sim:
        entry = await add_house(hass, hass_client, sim)
        # The form's check and the setup each sign in once; no refusal signs in.
        assert (sim.count("login"), refusals(sim), len(sim.requests)) == (2, 3, 20)
        assert await hass.config_entries.async_unload(entry.entry_id)
        sim.clear_requests()
        assert await hass.config_entries.async_setup(entry.entry_id)
        await hass.async_block_till_done()
        assert entry.state is ConfigEntryState.LOADED
        # Sign in, the sample of 8 variables in 2, every variable in 10.
        assert (sim.count("login"), refusals(sim), len(sim.requests)) == (1, 0, 13)
        assert max(record.variables for record in sim.requests) == 5
        await hass.config_entries.async_unload(entry.entry_id)


# --- reading and writing -----------------------------------------------------------------


async def test_a_bad_item_makes_its_entity_unavailable_and_it_comes_back(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    mervis: MervisSimulator,
    freezer: FrozenDateTimeFactory,
) -> None:
    await add_house(hass, hass_client, mervis)
    outside = entity(hass, "sensor", "outside_temp")
    water = entity(hass, "sensor", "kotel.water_temp")
    mervis.switches.item_errors.add(mervis.project.row("outside_temp").commuid)
    mervis.switches.qualities[mervis.project.row("kotel.water_temp").commuid] = "B"
    mervis.project.set("koupelna.temperature", 22.75)
    await poll(hass, freezer)
    assert hass.states.get(outside).state == STATE_UNAVAILABLE
    assert hass.states.get(water).state == STATE_UNAVAILABLE
    temperature = entity(hass, "sensor", "koupelna.temperature")
    assert hass.states.get(temperature).state == "22.75"
    mervis.switches.item_errors.clear()
    mervis.switches.qualities.clear()
    await poll(hass, freezer)
    assert hass.states.get(outside).state == "4.5"
    assert hass.states.get(water).state == "58.5"


BAD_MEMBER: Final = f"{HOUSE_NAME};$kotel$.$test$;$bool$;6003;60;1;fb;\n"
"""A point past the end of the Kotel block (21 bytes), as a typo puts one."""


def refused(hass: HomeAssistant, entry: ConfigEntry) -> list[str] | None:
    """The points the entry's "refuses some points" repair lists (None: no repair)."""
    issue = ir.async_get(hass).async_get_issue(
        DOMAIN, f"points_refused_{entry.entry_id}"
    )
    if issue is None:
        return None
    assert issue.translation_placeholders is not None
    assert issue.translation_placeholders["name"] == entry.title
    return issue.translation_placeholders["points"].split("\n")


async def test_a_bad_member_of_a_block_costs_its_own_entity_only(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    caplog: pytest.LogCaptureFixture,
    mervis: MervisSimulator,
    freezer: FrozenDateTimeFactory,
) -> None:
    """Issue 39: Burner, Water temp, Return temp, Starts and Runtime stay.

    They were all unavailable, blamed in the diagnostics ("unknown variable"),
    with no log line and no repair. The controller refuses the block's range:
    its members are read apart in one more request, once; then the block is
    one ID again and the bad point one of its own, logged once and listed in
    Repairs until a newer file leaves it out.
    """
    entry = await add_house(hass, hass_client, mervis)
    mervis.clear_requests()
    caplog.clear()
    result = await upload_newer(
        hass, hass_client, entry, mervis.project.vlist() + BAD_MEMBER
    )
    assert result["type"] is FlowResultType.CREATE_ENTRY
    # The check (sign-in, sample), then the new map read: every point, the
    # block's six members apart.
    assert [(r.service, r.variables) for r in mervis.requests] == [
        ("login", 0),
        ("values", 8),
        ("login", 0),
        ("values", 8),
        ("values", 50),
        ("values", 6),
    ]
    for key in ("kotel.burner", "kotel.water_temp", "kotel.starts", "kotel.runtime"):
        domain = "binary_sensor" if key == "kotel.burner" else "sensor"
        assert hass.states.get(entity(hass, domain, key)).state != STATE_UNAVAILABLE
    bad = entity(hass, "binary_sensor", "kotel.test")
    assert hass.states.get(bad).state == STATE_UNAVAILABLE
    assert refused(hass, entry) == [
        "- Kotel test (kotel.test), 6003[60,1]: the device says: error: unknown variable"
    ]
    mervis.clear_requests()
    for _ in range(3):
        await poll(hass, freezer)
    # The 40 polled entities' 26 IDs, and the bad point's own.
    assert [r.variables for r in mervis.requests] == [27, 27, 27]
    assert hass.states.get(entity(hass, "sensor", "kotel.water_temp")).state == "58.5"
    warnings = [
        record.getMessage()
        for record in caplog.records
        if record.name.startswith("custom_components.tecoapi")
        and record.levelno >= logging.WARNING
    ]
    assert warnings == [
        (
            f"kotel.test of the controller {mervis.url} cannot be read, its entity "
            "is unavailable: error: unknown variable"
        )
    ]
    diagnostics = await async_get_config_entry_diagnostics(hass, entry)
    assert diagnostics["read_plans"]["bad_points"] == {
        "kotel.test": "error: unknown variable"
    }
    # A newer file without it: the repair goes.
    await upload_newer(hass, hass_client, entry, mervis.project.vlist())
    assert refused(hass, entry) is None
    assert "kotel.test" not in keys(hass, entry)


async def test_a_poll_reads_each_block_once(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    mervis: MervisSimulator,
    freezer: FrozenDateTimeFactory,
) -> None:
    """The 40 enabled entities' points: 26 variables (blocks read whole), one request.

    (The 41st, the controller's clock, is disabled: not read.)
    """
    entry = await add_house(hass, hass_client, mervis)
    mervis.clear_requests()
    await poll(hass, freezer)
    assert [record.service for record in mervis.requests] == ["values"]
    assert mervis.requests[0].variables == 26
    assert entry.runtime_data.source.statistics.last_poll_requests == 1


async def test_a_variable_marked_writable_is_written_and_shown_at_once(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, mervis: MervisSimulator
) -> None:
    """A bool becomes a switch, a time a number of seconds, a dt a date and time."""
    entry = await add_house(hass, hass_client, mervis)
    await mark_writable(hass, entry, "hw.neuron_l203_ro_2.01")
    await mark_writable(hass, entry, "boost", low=0, high=7200)
    await mark_writable(hass, entry, "clock")
    relay = entity(hass, "switch", "hw.neuron_l203_ro_2.01")
    boost = entity(hass, "number", "boost")
    clock = entity(hass, "datetime", "clock")

    mervis.clear_requests()
    await hass.services.async_call(
        "switch", "turn_on", {ATTR_ENTITY_ID: relay}, blocking=True
    )
    assert hass.states.get(relay).state == "on"
    assert mervis.project.get("hw.neuron_l203_ro_2.01") is True
    assert [record.service for record in mervis.requests] == ["command", "values"]
    await hass.services.async_call(
        "number", "set_value", {ATTR_ENTITY_ID: boost, "value": 5400}, blocking=True
    )
    assert float(hass.states.get(boost).state) == 5400
    assert mervis.project.get("boost") == timedelta(minutes=90)
    await hass.services.async_call(
        "datetime",
        "set_value",
        {ATTR_ENTITY_ID: clock, "datetime": "2026-12-24T18:00:00+00:00"},
        blocking=True,
    )
    assert mervis.project.get("clock") == datetime(2026, 12, 24, 18, tzinfo=UTC)

    mervis.clear_requests()
    with pytest.raises(ServiceValidationError) as refused:
        await hass.services.async_call(
            "number", "set_value", {ATTR_ENTITY_ID: boost, "value": 9000}, blocking=True
        )
    assert refused.value.translation_key is not None
    assert mervis.requests == []
    assert mervis.project.get("boost") == timedelta(minutes=90)


async def test_a_block_of_a_temperature_and_a_setpoint_is_a_thermostat(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, mervis: MervisSimulator
) -> None:
    """As TecoApi structs in our convention: its setpoint marked writable."""
    entry = await add_house(hass, hass_client, mervis)
    await mark_writable(hass, entry, "koupelna.setpoint", unit="°C", low=15, high=28)
    climate = er.async_get(hass).async_get_entity_id(
        "climate", DOMAIN, f"{entry.unique_id}_struct:climate:koupelna"
    )
    assert climate is not None
    state = hass.states.get(climate)
    assert (
        state.attributes["current_temperature"],
        state.attributes["temperature"],
    ) == (
        21.5,
        22.0,
    )
    await hass.services.async_call(
        "climate",
        "set_temperature",
        {ATTR_ENTITY_ID: climate, "temperature": 23.5},
        blocking=True,
    )
    assert hass.states.get(climate).attributes["temperature"] == 23.5
    assert mervis.project.get("koupelna.setpoint") == 23.5


async def mark_writable(
    hass: HomeAssistant,
    entry: ConfigEntry,
    key: str,
    *,
    unit: str = "",
    low: float | None = None,
    high: float | None = None,
) -> None:
    """Mark a variable writable in the options, as a user does (its point's form)."""
    result = await hass.config_entries.options.async_init(entry.entry_id)
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {"next_step_id": "edit_point"}
    )
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {"point": [key]}
    )
    assert result["step_id"] == "mervis_point"
    point = entry.runtime_data.point_map.by_key()[key]
    changed = {**form_values(point), "writable": True}
    if unit:
        changed["unit"] = unit
    if low is not None and high is not None:
        changed |= {"min": low, "max": high}
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], changed
    )
    if result.get("step_id") == CLASS_STEP:  # a number with a unit: its class
        result = await hass.config_entries.options.async_configure(
            result["flow_id"], {}
        )
    assert result["type"] is FlowResultType.CREATE_ENTRY, result.get("errors")
    await hass.async_block_till_done()


async def test_the_default_leaves_hw_out_and_the_options_bring_it_back(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, mervis: MervisSimulator
) -> None:
    entry = await add_house(hass, hass_client, mervis)
    result = await hass.config_entries.options.async_init(entry.entry_id)
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {"next_step_id": "settings"}
    )
    assert {str(key) for key in result["data_schema"].schema} == {
        "scan_interval",
        "include",
        "exclude",
        "devices",
    }
    result = await hass.config_entries.options.async_configure(
        result["flow_id"],
        {"scan_interval": 5, "devices": "groups_and_areas", "exclude": []},
    )
    await hass.async_block_till_done()
    assert len(keys(hass, entry)) == HOUSE_POINTS
    assert "hw.neuron_l203_fw_version" in keys(hass, entry)


# --- credentials ----------------------------------------------------------------------------


async def test_the_controller_moves_to_another_address(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    mervis: MervisSimulator,
    socket_enabled: None,
) -> None:
    entry = await add_house(hass, hass_client, mervis)
    moved = MervisSimulator(mervis.project, username=USER, password=PASSWORD)
    await moved.start()
    try:
        result = await hass.config_entries.flow.async_init(
            DOMAIN, context={"source": "reconfigure", "entry_id": entry.entry_id}
        )
        assert result["step_id"] == "reconfigure_mervis"
        result = await hass.config_entries.flow.async_configure(
            result["flow_id"],
            {CONF_HOST: moved.host, CONF_USERNAME: USER, CONF_VERIFY_SSL: True},
        )
        assert result["reason"] == "mervis_reconfigured"
        await hass.async_block_till_done()
        assert entry.data[CONF_HOST] == moved.url
        assert entry.data[CONF_PASSWORD] == PASSWORD
        assert entry.state is ConfigEntryState.LOADED
        # The title the flow gave names where the controller is now.
        assert entry.title == f"Mervis · {HOUSE_NAME} · {moved.host}"
        # A title the user gave stays.
        hass.config_entries.async_update_entry(entry, title="Chalupa")
        result = await reconfigure(hass, entry, mervis)
        assert result["reason"] == "mervis_reconfigured"
        await hass.async_block_till_done()
        assert (entry.data[CONF_HOST], entry.title) == (mervis.url, "Chalupa")
    finally:
        await hass.config_entries.async_unload(entry.entry_id)
        await moved.stop()


async def test_a_controller_gone_is_logged_as_the_controller_once_and_once_back(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    mervis: MervisSimulator,
    freezer: FrozenDateTimeFactory,
    caplog: pytest.LogCaptureFixture,
) -> None:
    entry = await add_house(hass, hass_client, mervis)
    port = mervis.port
    caplog.clear()
    await mervis.stop()
    for _ in range(3):
        await poll(hass, freezer)
    await mervis.start(port=port)
    for _ in range(2):
        await poll(hass, freezer)
    lines = [
        (record.levelno, record.getMessage())
        for record in caplog.records
        if record.name.startswith("custom_components.tecoapi")
        and record.levelno >= logging.INFO
    ]
    assert [level for level, _ in lines] == [logging.INFO, logging.INFO]
    assert lines[0][1].startswith(f"The controller {entry.title} is unavailable: ")
    assert lines[1][1] == f"The controller {entry.title} is available again"


async def test_diagnostics_never_hold_the_credentials(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    mervis: MervisSimulator,
    freezer: FrozenDateTimeFactory,
) -> None:
    entry = await add_house(hass, hass_client, mervis)
    await poll(hass, freezer)
    diagnostics = await async_get_config_entry_diagnostics(hass, entry)
    text = repr(diagnostics)
    assert PASSWORD not in text
    assert USER not in text
    session = entry.runtime_data.source.client.session_credentials["p"]
    assert session not in text
    assert diagnostics["read_plans"]["values"]["ids"] == 26
    assert diagnostics["requests"]["logins"] == 1
    assert diagnostics["catalogue"]["points"] == HOUSE_POINTS


# --- the filters, and a point's form -------------------------------------------------------


@pytest.mark.parametrize(
    ("exclude", "key", "shown"),
    [
        (DEFAULT_EXCLUDE, "hw.neuron_l203_ro_2.01", True),
        (DEFAULT_EXCLUDE, "hw.neuron_l203_di_1.04", True),
        (DEFAULT_EXCLUDE, "hw.neuron_l203_ai_1.01", True),
        (DEFAULT_EXCLUDE, "hw.neuron_l203_di_1.04_counter", False),
        (DEFAULT_EXCLUDE, "hw.neuron_l203_led_1.01", False),
        (DEFAULT_EXCLUDE, "koupelna.temperature", True),
        (("!hw.*", "hw.*"), "hw.a_ro_1.01", False),
        (("hw.*", "!hw.*_ro_*", "*_ro_2.*"), "hw.a_ro_2.01", False),
        (("hw.*", "!hw.*_ro_*", "*_ro_2.*"), "hw.a_ro_1.01", True),
        (("hw.*", "*_ro_*"), "hw.a_ro_1.01", False),
    ],
)
def test_an_exclude_pattern_with_an_exclamation_mark_takes_back(
    exclude: tuple[str, ...], key: str, shown: bool
) -> None:
    assert PlcOptions(exclude=exclude).matches(key) is shown


@pytest.mark.parametrize(
    ("address", "type_name", "problem"),
    [
        ("7001[0,2]", "REAL", "takes 4 bytes, not 2"),
        ("7001", "REAL", "not CommUid[offset,length]"),
        ("7001[0,2]", "TIME", "takes 4 or 8 bytes"),
        ("7001[0,4]", "TIME", None),
        ("7001[0,3]", "STRING", None),
        ("7001[0,1]", "BOOL", None),
    ],
)
def test_a_point_s_address_is_checked_against_its_type(
    address: str, type_name: str, problem: str | None
) -> None:
    found = data_type(type_name)
    assert found is not None
    point = MapPoint(id="p", name="P", address=address, type=found)
    checked = check_address(point)
    if problem is None:
        assert checked is None
    else:
        assert checked is not None
        assert problem in str(checked)


def test_a_controller_without_its_vlist_is_none() -> None:
    with pytest.raises(NoPublicVariablesError, match=r"needs its \.vlist"):
        MERVIS.create(
            SourceContext(http=lambda verify: None),  # type: ignore[arg-type,return-value]
            {CONF_HOST: "unipi.local"},
            SourceOptions(),
        )


def dashboard_entities(node: Any) -> set[str]:
    """Every ``entity:`` a dashboard's part names, at any depth."""
    if isinstance(node, dict):
        own = {node["entity"]} if isinstance(node.get("entity"), str) else set()
        return own.union(*(dashboard_entities(value) for value in node.values()))
    if isinstance(node, list):
        return set().union(*(dashboard_entities(item) for item in node))
    return set()


@pytest.mark.primary_only
async def test_the_demo_cottage_shows_every_card_of_its_view(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    mervis: MervisSimulator,
    caplog: pytest.LogCaptureFixture,
) -> None:
    """The map scripts/develop adds, complete at once: the view's entities exist.

    Each has what the map says from the first state on (a unit, writable), so
    no point changes afterwards. (Entity IDs start with the area from Home
    Assistant 2026.6: the primary target.)
    """
    vlist = demo_vlist(mervis.project.vlist().encode()).decode()
    result = await add(hass, hass_client, mervis, vlist)
    assert result["type"] is FlowResultType.CREATE_ENTRY
    await hass.async_block_till_done()
    for key, changes in MERVIS_DEMO_POINTS.items():
        point = result["result"].runtime_data.point_map.by_key()[key]
        assert {name: form_values(point).get(name) for name in changes} == changes
    assert "The points of" not in caplog.text
    dashboard = yaml.safe_load(DEMO_DASHBOARD.read_text("utf-8"))
    (view,) = [view for view in dashboard["views"] if view["path"] == "chata"]
    wanted = dashboard_entities(view)
    assert len(wanted) == 16
    shown = {entity_id: hass.states.get(entity_id) for entity_id in wanted}
    assert {
        entity_id: state and state.state
        for entity_id, state in shown.items()
        if state is None or state.state == STATE_UNAVAILABLE
    } == {}
    assert shown["climate.jidelna_thermostat"].attributes["temperature"] == 21.0


async def test_a_block_named_for_a_room_is_spelled_and_says_it_once(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, mervis: MervisSimulator
) -> None:
    """*Jidelna* is the device *Jídelna*; where IDs start with the area, it has none."""
    entry = await add_house(hass, hass_client, mervis)
    registry = dr.async_get(hass)
    (device,) = [
        device
        for device in dr.async_entries_for_config_entry(registry, entry.entry_id)
        if device.name == "Jídelna"
    ]
    if AREA_IN_ENTITY_ID:
        assert device.area_id is None
        assert entity(hass, "sensor", "jidelna.temperature") == (
            "sensor.jidelna_temperature"
        )
    else:
        assert device.area_id == "jidelna"
