"""A Panasonic FP-I4C gateway in Home Assistant, against the simulated gateway over HTTP.

Added in the UI with its register map (a real file upload), checked with a
harmless read; each station a device under the gateway with its own health;
writes scaled and checked (the map edited in the options: flows/test_point_map.py);
moved to another address keeping every entity; devices composed of its points.
"""

import json
import logging
from pathlib import Path
import re
from typing import Any, Final

from freezegun.api import FrozenDateTimeFactory
from homeassistant.config_entries import (
    SOURCE_RECONFIGURE,
    SOURCE_USER,
    ConfigEntry,
    ConfigEntryState,
)
from homeassistant.const import ATTR_ENTITY_ID, CONF_HOST, STATE_UNAVAILABLE
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
from homeassistant.exceptions import HomeAssistantError, ServiceValidationError
from homeassistant.helpers import (
    device_registry as dr,
    entity_registry as er,
    issue_registry as ir,
)
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry
from pytest_homeassistant_custom_component.typing import ClientSessionGenerator

from custom_components.tecoapi.compat import entry_device
from custom_components.tecoapi.const import CONF_TRANSPORT, DOMAIN
from custom_components.tecoapi.diagnostics import async_get_config_entry_diagnostics
from custom_components.tecoapi.pyplc.core.descriptor import CONF_POINT_MAP
from custom_components.tecoapi.pyplc.core.pointmap import CSV_COLUMNS
from tests.components.tecoapi.conftest import poll
from tests.components.tecoapi.fpi4c_gateway import (
    EXAMPLE,
    add_gateway,
    entity_ids,
    options_step,
    start_flow,
    state,
    submit,
)
from tests.components.tecoapi.memory_house import upload
from tests.simulator.fpi4c import FpI4cSimulator, demo_stations

TRANSLATIONS: Final = (
    Path(__file__).parents[3] / "custom_components" / DOMAIN / "translations"
)


async def add_with_rows(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    gateway: FpI4cSimulator,
    *rows: str,
) -> tuple[ConfigEntry, dict[str, str]]:
    """Add the gateway with the example map and more rows; its entity IDs by key."""
    result = await submit(
        hass,
        hass_client,
        await start_flow(hass),
        {CONF_HOST: gateway.url},
        EXAMPLE + "".join(f"{row}\n" for row in rows),
    )
    assert result["type"] is FlowResultType.CREATE_ENTRY, result.get("errors")
    entry: ConfigEntry = result["result"]
    return entry, entity_ids(hass, entry)


# --- adding a gateway --------------------------------------------------------------


async def test_the_form_asks_the_address_interface_station_and_map(
    hass: HomeAssistant,
) -> None:
    result = await start_flow(hass)
    assert result["type"] is FlowResultType.FORM
    assert result["step_id"] == "fpi4c"
    assert [str(key) for key in result["data_schema"].schema] == [
        "host",
        "interface",
        "station",
        CONF_POINT_MAP,
    ]


@pytest.mark.parametrize("language", ["en", "cs"])
@pytest.mark.parametrize("step", ["fpi4c", "reconfigure_fpi4c"])
def test_the_station_s_help_names_the_column_a_point_gives_its_station_in(
    language: str, step: str
) -> None:
    """The map's device column holds a point's station (issue 39: not "its row")."""
    strings = json.loads(
        (TRANSLATIONS / f"{language}.json").read_text(encoding="utf-8")
    )
    text = strings["config"]["step"][step]["data_description"]["station"]
    assert "device" in CSV_COLUMNS
    assert re.search(r"\bdevice\b", text), text


@pytest.mark.usefixtures("uploads")
async def test_a_gateway_is_added_with_a_device_per_station(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, gateway: FpI4cSimulator
) -> None:
    entry = await add_gateway(hass, hass_client, gateway)
    assert entry.title == f"FP-I4C · 127.0.0.1:{gateway.port}"
    assert entry.unique_id == f"127.0.0.1:{gateway.port}"
    assert entry.data[CONF_HOST] == gateway.url
    assert entry.data[CONF_TRANSPORT] == "fpi4c"
    assert "interface" not in entry.data
    assert entry.state is ConfigEntryState.LOADED
    ids = entity_ids(hass, entry)
    assert len(ids) == 24
    assert state(hass, ids["boiler_temp"]) == "65.2"
    assert state(hass, ids["dhw_temp"]) == "49.8"
    assert state(hass, ids["pressure"]) == "1.8"
    assert state(hass, ids["heating_pump"]) == "on"
    assert state(hass, ids["status"]) == "Heating"
    assert state(hass, ids["car_present"]) == "on"
    devices = dr.async_get(hass)
    registry = er.async_get(hass)
    gateway_device = entry_device(
        hass, entry.entry_id, identifier=(DOMAIN, str(entry.unique_id))
    )
    assert gateway_device is not None
    assert (gateway_device.manufacturer, gateway_device.model) == (
        "Panasonic",
        "FP-I4C",
    )
    # Its link opens the port it is reached on (its REST API and HTTP server).
    assert gateway_device.configuration_url == gateway.url
    for key, name in (
        ("boiler_temp", "Heating plant"),
        ("door_target", "Door controller"),
    ):
        item = registry.async_get(ids[key])
        assert item is not None
        device = devices.async_get(str(item.device_id))
        assert device is not None
        assert device.name == name
        assert device.via_device_id == gateway_device.id


@pytest.mark.usefixtures("uploads")
async def test_the_example_s_names_say_the_station_s_words_once(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, gateway: FpI4cSimulator
) -> None:
    """On *Heating plant*, "Plant status" is its Status and "Heating" the plant's own.

    The map's names start where the station's name ends, or say only its first
    word: the entity does not say them again (it said "Heating plant Plant
    status" and "Heating plant Heating").
    """
    ids = entity_ids(hass, await add_gateway(hass, hass_client, gateway))
    names = {key: hass.states.get(entity_id).name for key, entity_id in ids.items()}  # type: ignore[union-attr]
    assert names["status"] == "Heating plant Status"
    assert names["heating_on"] == "Heating plant"
    assert ids["heating_on"] == "switch.heating_plant"
    assert names["heating_pump"] == "Heating plant Heating pump"
    assert names["boiler_temp"] == "Heating plant Boiler temperature"
    assert len(set(names.values())) == len(names)


@pytest.mark.usefixtures("uploads")
async def test_the_same_gateway_is_not_added_twice(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, gateway: FpI4cSimulator
) -> None:
    await add_gateway(hass, hass_client, gateway)
    result = await submit(
        hass, hass_client, await start_flow(hass), {CONF_HOST: gateway.url}
    )
    assert result["type"] is FlowResultType.ABORT
    assert result["reason"] == "fpi4c_already_configured"


@pytest.mark.usefixtures("uploads")
async def test_an_entry_s_title_names_the_address_and_station_it_reaches(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, gateway: FpI4cSimulator
) -> None:
    """Two stations of one gateway are two entries a user tells apart."""
    for station, title in (
        ({"station": "1"}, f"FP-I4C · 127.0.0.1:{gateway.port}, station 1"),
        ({"station": "2"}, f"FP-I4C · 127.0.0.1:{gateway.port}, station 2"),
    ):
        result = await submit(
            hass,
            hass_client,
            await start_flow(hass),
            {CONF_HOST: f"127.0.0.1:{gateway.port}", **station},
        )
        assert result["type"] is FlowResultType.CREATE_ENTRY, result.get("errors")
        assert result["result"].title == title
    for added in hass.config_entries.async_entries(DOMAIN):
        await hass.config_entries.async_unload(added.entry_id)


@pytest.mark.usefixtures("uploads")
async def test_a_gateway_added_by_name_before_is_found_by_its_address(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, gateway: FpI4cSimulator
) -> None:
    """An entry made before names resolved keeps its identity, and is found."""
    MockConfigEntry(domain=DOMAIN, unique_id="tecoapi-plc", data={}).add_to_hass(hass)
    MockConfigEntry(
        domain=DOMAIN,
        unique_id="192.0.2.1:2000",
        data={CONF_HOST: "http://192.0.2.1:2000", CONF_TRANSPORT: "fpi4c"},
    ).add_to_hass(hass)
    before = MockConfigEntry(
        domain=DOMAIN,
        unique_id=f"localhost:{gateway.port}",
        data={CONF_HOST: f"http://localhost:{gateway.port}", CONF_TRANSPORT: "fpi4c"},
        options={"scan_interval": 3600},
        state=ConfigEntryState.LOADED,
    )
    before.add_to_hass(hass)
    result = await submit(
        hass, hass_client, await start_flow(hass), {CONF_HOST: gateway.url}
    )
    assert result["type"] is FlowResultType.ABORT
    assert result["reason"] == "fpi4c_already_configured"
    assert before.unique_id == f"localhost:{gateway.port}"
    assert before.data[CONF_HOST] == gateway.url


@pytest.mark.usefixtures("uploads")
async def test_each_failure_of_the_check_is_told_and_then_fixed(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    gateway: FpI4cSimulator,
    closed_port: str,
    web_server: str,
) -> None:
    result = await start_flow(hass)
    url = gateway.url

    async def attempt(
        form: dict[str, Any], csv: str = EXAMPLE
    ) -> tuple[dict[str, str], dict[str, str]]:
        nonlocal result
        result = await submit(hass, hass_client, result, form, csv)
        assert result["type"] is FlowResultType.FORM
        return result["errors"], result["description_placeholders"]

    assert (await attempt({CONF_HOST: closed_port}))[0] == {
        "base": "fpi4c_cannot_connect"
    }
    assert (await attempt({CONF_HOST: web_server}))[0] == {"base": "not_fpi4c"}
    assert (await attempt({CONF_HOST: "http://gw/plcpost"}))[0] == {
        CONF_HOST: "invalid_fpi4c_host"
    }
    assert (await attempt({CONF_HOST: url, "interface": "9"}))[0] == {
        "interface": "invalid_interface"
    }
    assert (await attempt({CONF_HOST: url, "station": "x"}))[0] == {
        "station": "invalid_station"
    }
    errors, placeholders = await attempt({CONF_HOST: url, "interface": "1"})
    assert errors == {"base": "gateway_refused"}
    assert placeholders["message"] == "Interface 1 is not enabled"
    gateway.silent.add(2)
    errors, placeholders = await attempt({CONF_HOST: url})
    assert errors == {"base": "station_not_answering"}
    assert (placeholders["station"], placeholders["code"]) == ("2", "28")
    assert placeholders["message"] == "No response from the PLC"
    gateway.silent = {1}
    errors, placeholders = await attempt(
        {CONF_HOST: url}, "name,address,type\nBoiler,DT0,INT\n"
    )
    assert errors == {"base": "plc_not_answering"}
    assert placeholders["code"] == "28"
    errors, placeholders = await attempt(
        {CONF_HOST: url}, EXAMPLE.replace("X1,BOOL,,,,,no", "X1,INT,,,,,no", 1)
    )
    assert errors == {CONF_POINT_MAP: "point_map_invalid"}
    assert placeholders["error"] == "row 23, column type: X1 is a bit: its type is BOOL"
    gateway.silent.clear()
    result = await submit(hass, hass_client, result, {CONF_HOST: url, "station": "1"})
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert result["result"].data["station"] == "1"
    assert result["result"].unique_id == f"127.0.0.1:{gateway.port}/A1"


@pytest.mark.usefixtures("uploads")
async def test_the_upload_outlives_a_wrong_port(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    gateway: FpI4cSimulator,
    closed_port: str,
) -> None:
    """The file the form still shows after an error is the one read before."""
    result = await start_flow(hass)
    file_id = await upload(hass, hass_client, "map.csv", EXAMPLE)
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {CONF_HOST: closed_port, CONF_POINT_MAP: file_id}
    )
    assert result["errors"] == {"base": "fpi4c_cannot_connect"}
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {CONF_HOST: gateway.url, CONF_POINT_MAP: file_id}
    )
    await hass.async_block_till_done()
    assert result["type"] is FlowResultType.CREATE_ENTRY, result.get("errors")
    assert len(entity_ids(hass, result["result"])) == 24


@pytest.mark.usefixtures("uploads")
async def test_an_unreadable_map_says_why_again_when_submitted_again(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, gateway: FpI4cSimulator
) -> None:
    """Not "the file is gone": the same file's same problem."""
    result = await start_flow(hass)
    file_id = await upload(hass, hass_client, "map.csv", "name,address,type\n")
    for _ in range(2):
        result = await hass.config_entries.flow.async_configure(
            result["flow_id"], {CONF_HOST: gateway.url, CONF_POINT_MAP: file_id}
        )
        assert result["errors"] == {CONF_POINT_MAP: "point_map_invalid"}
        assert result["description_placeholders"]["error"] == (
            "the file holds no point"
        )


# --- stations and items ----------------------------------------------------------------


@pytest.mark.usefixtures("uploads")
async def test_a_silent_station_makes_its_own_entities_unavailable(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    gateway: FpI4cSimulator,
    freezer: FrozenDateTimeFactory,
) -> None:
    entry = await add_gateway(hass, hass_client, gateway)
    ids = entity_ids(hass, entry)
    gateway.silent.add(2)
    await poll(hass, freezer)
    assert state(hass, ids["door_target"]) == STATE_UNAVAILABLE
    assert state(hass, ids["garage_light"]) == STATE_UNAVAILABLE
    assert state(hass, ids["boiler_temp"]) == "65.2"
    gateway.silent.clear()
    gateway.set(2, "DT11", "INT", 40)
    await poll(hass, freezer)
    assert state(hass, ids["door_target"]) == "40"


def logged(caplog: pytest.LogCaptureFixture) -> list[tuple[int, str]]:
    """(level, message) the integration logged at info or above."""
    return [
        (record.levelno, record.getMessage())
        for record in caplog.records
        if record.name.startswith("custom_components.tecoapi")
        and record.levelno >= logging.INFO
    ]


@pytest.mark.usefixtures("uploads")
async def test_a_silent_station_is_logged_once_and_once_when_it_answers_again(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    gateway: FpI4cSimulator,
    freezer: FrozenDateTimeFactory,
    caplog: pytest.LogCaptureFixture,
) -> None:
    """The gateway answers for station 1 meanwhile: the entry stays available."""
    await add_gateway(hass, hass_client, gateway)
    caplog.clear()
    gateway.silent.add(2)
    for _ in range(3):
        await poll(hass, freezer)
    gateway.silent.clear()
    for _ in range(2):
        await poll(hass, freezer)
    behind = f"Station 2 behind the FP-I4C gateway 127.0.0.1:{gateway.port}"
    reason = "err_code 28: No response from the PLC"
    assert logged(caplog) == [
        (
            logging.INFO,
            f"{behind} does not answer, its entities are unavailable: {reason}",
        ),
        (logging.INFO, f"{behind} answers again"),
    ]


@pytest.mark.usefixtures("uploads")
async def test_a_gateway_gone_is_logged_as_the_gateway_once_and_once_back(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    gateway: FpI4cSimulator,
    freezer: FrozenDateTimeFactory,
    caplog: pytest.LogCaptureFixture,
) -> None:
    """Not "the PLC": the entry reaches a gateway."""
    entry = await add_gateway(hass, hass_client, gateway)
    caplog.clear()
    gateway.broken = True
    for _ in range(3):
        await poll(hass, freezer)
    gateway.broken = False
    for _ in range(2):
        await poll(hass, freezer)
    lines = logged(caplog)
    assert [level for level, _ in lines] == [logging.INFO, logging.INFO]
    assert lines[0][1].startswith(f"The gateway {entry.title} is unavailable: ")
    assert lines[1][1] == f"The gateway {entry.title} is available again"


def refused(hass: HomeAssistant, entry: ConfigEntry) -> list[str] | None:
    """The points the entry's "refuses some points" repair lists (None: no repair)."""
    issue = ir.async_get(hass).async_get_issue(
        DOMAIN, f"points_refused_{entry.entry_id}"
    )
    if issue is None:
        return None
    assert issue.severity is ir.IssueSeverity.WARNING
    assert not issue.is_fixable
    assert issue.translation_key == "fpi4c_points_refused"  # in its own words
    assert issue.translation_placeholders is not None
    assert issue.translation_placeholders["name"] == entry.title
    return issue.translation_placeholders["points"].split("\n")


@pytest.mark.usefixtures("uploads")
async def test_a_failed_item_makes_its_points_unavailable_only(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    gateway: FpI4cSimulator,
    freezer: FrozenDateTimeFactory,
) -> None:
    """The point is unavailable, and listed with its code in Repairs while it fails."""
    entry = await add_gateway(hass, hass_client, gateway)
    ids = entity_ids(hass, entry)
    assert refused(hass, entry) is None
    gateway.item_errors[1, "DT210"] = (61, "Data error")
    await poll(hass, freezer)
    assert state(hass, ids["pressure"]) == STATE_UNAVAILABLE
    assert state(hass, ids["burner_starts"]) == "12345"
    assert state(hass, ids["boiler_temp"]) == "65.2"
    assert refused(hass, entry) == [
        "- System pressure (pressure), DT210: the device says: err_code 61: Data error"
    ]
    gateway.item_errors.clear()
    await poll(hass, freezer)
    assert state(hass, ids["pressure"]) == "1.8"
    assert refused(hass, entry) is None


NEAR_THE_END = (
    "near_end,Near the end,DT32760,INT,,,,,no,,,,1 Heating plant,,,\n"
    "typo,A typo,DT32766,INT,,,,,no,,,,1 Heating plant,,,\n"
)
"""A register near the end of the PLC's DT area (DT32764), and one past it."""


def requests_after(gateway: FpI4cSimulator, posts: int) -> list[str]:
    """Every request of the POSTs since ``posts``, as ``DT32760 x7``."""
    return [
        f"{item['area']}{item['start']} x{item.get('count', 1)}"
        for body in gateway.posts[posts:]
        for item in body["req"]
    ]


@pytest.mark.usefixtures("uploads")
async def test_an_address_past_the_plc_s_area_costs_only_its_own_entity(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    gateway: FpI4cSimulator,
    freezer: FrozenDateTimeFactory,
) -> None:
    """DT32760 and DT32766 share a request the PLC fails as a whole (issue 28).

    The read halves it once: DT32760 shows its value, DT32766 alone is
    unavailable, with its code and the gateway's message in the diagnostics;
    later polls read them apart without searching; a newer map starts afresh.
    """
    gateway.set(1, "DT32760", "INT", 42)
    entry = await add_gateway(hass, hass_client, gateway, EXAMPLE + NEAR_THE_END)
    ids = entity_ids(hass, entry)
    assert state(hass, ids["near_end"]) == "42"
    assert state(hass, ids["typo"]) == STATE_UNAVAILABLE
    assert state(hass, ids["boiler_temp"]) == "65.2"
    posts = len(gateway.posts)
    await poll(hass, freezer)
    await poll(hass, freezer)
    requests = requests_after(gateway, posts)
    assert "DT32760 x7" not in requests
    assert requests.count("DT32760 x1") == requests.count("DT32766 x1") == 2
    assert state(hass, ids["near_end"]) == "42"
    assert state(hass, ids["typo"]) == STATE_UNAVAILABLE
    diagnostics = await async_get_config_entry_diagnostics(hass, entry)  # type: ignore[arg-type]
    assert diagnostics["catalogue"]["missing"] == ["typo"]
    assert diagnostics["source"]["failed_points"] == [
        {
            "key": "typo",
            "request": "DT32766",
            "err_code": "61",
            "meaning": "DT32766..DT32766 is past DT32764",
        }
    ]
    # The map fixed: the new source reads DT32760..DT32763 in one request.
    result = await options_step(hass, entry, "upload")
    file_id = await upload(
        hass, hass_client, "map.csv", EXAMPLE + NEAR_THE_END.replace("32766", "32763")
    )
    posts = len(gateway.posts)
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {CONF_POINT_MAP: file_id}
    )
    await hass.async_block_till_done()
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert "DT32760 x4" in requests_after(gateway, posts)
    assert state(hass, entity_ids(hass, entry)["typo"]) == "0"
    diagnostics = await async_get_config_entry_diagnostics(hass, entry)  # type: ignore[arg-type]
    assert diagnostics["source"]["failed_points"] == []


@pytest.mark.usefixtures("uploads")
async def test_points_the_gateway_refuses_are_listed_in_repairs_until_they_read(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    gateway: FpI4cSimulator,
    freezer: FrozenDateTimeFactory,
) -> None:
    """The repair lists each refused point with its address, code and message (issue 28).

    It changes with the set of points, stays while their station is offline
    (nothing tells whether they read again), goes with the entry and comes
    back with it, and goes for good once the map is fixed.
    """
    typo = (
        "- A typo (typo), DT32766: "
        "the device says: err_code 61: DT32766..DT32766 is past DT32764"
    )
    entry = await add_gateway(hass, hass_client, gateway, EXAMPLE + NEAR_THE_END)
    assert refused(hass, entry) == [typo]
    gateway.item_errors[1, "DT210"] = (61, "Data error")
    await poll(hass, freezer)
    pressure = (
        "- System pressure (pressure), DT210: the device says: err_code 61: Data error"
    )
    assert refused(hass, entry) == [pressure, typo]
    gateway.silent.add(1)
    await poll(hass, freezer)
    assert state(hass, entity_ids(hass, entry)["boiler_temp"]) == STATE_UNAVAILABLE
    assert refused(hass, entry) == [pressure, typo]
    gateway.silent.clear()
    gateway.item_errors.clear()
    await poll(hass, freezer)
    assert refused(hass, entry) == [typo]
    assert await hass.config_entries.async_unload(entry.entry_id)
    assert refused(hass, entry) is None
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    assert refused(hass, entry) == [typo]
    # The map fixed: every point reads, the repair goes.
    result = await options_step(hass, entry, "upload")
    file_id = await upload(
        hass, hass_client, "map.csv", EXAMPLE + NEAR_THE_END.replace("32766", "32763")
    )
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {CONF_POINT_MAP: file_id}
    )
    await hass.async_block_till_done()
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert refused(hass, entry) is None


@pytest.mark.usefixtures("uploads")
async def test_a_repair_lists_twenty_refused_points_and_counts_the_others(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    gateway: FpI4cSimulator,
    freezer: FrozenDateTimeFactory,
) -> None:
    """A map whose addresses are all past the PLC's area: the diagnostics list them all.

    They fail in one request; each poll halves what still fails in one more
    POST (the budget), and the repair lists a point once it fails alone: all
    22 by the fifth poll (a halving a poll: 22, 11, 6, 3, 2, 1).
    """
    past_the_end = "".join(
        f"bad{index:02},Bad {index},DT{32770 + index},INT,,,,,no,,,,1,,,\n"
        for index in range(22)
    )
    entry = await add_gateway(hass, hass_client, gateway, EXAMPLE + past_the_end)
    assert refused(hass, entry) is None
    for _ in range(4):
        await poll(hass, freezer)
    listed = refused(hass, entry)
    assert listed is not None
    assert len(listed) == 21
    assert listed[0].startswith(
        "- Bad 0 (bad00), DT32770: the device says: err_code 61: "
    )
    assert listed[19].startswith(
        "- Bad 19 (bad19), DT32789: the device says: err_code 61: "
    )
    assert listed[20] == "- … (+2)"
    diagnostics = await async_get_config_entry_diagnostics(hass, entry)  # type: ignore[arg-type]
    assert len(diagnostics["source"]["failed_points"]) == 22


@pytest.mark.usefixtures("uploads")
async def test_a_broken_answer_makes_all_unavailable_until_the_next_good_one(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    gateway: FpI4cSimulator,
    freezer: FrozenDateTimeFactory,
) -> None:
    entry = await add_gateway(hass, hass_client, gateway)
    ids = entity_ids(hass, entry)
    gateway.broken = True
    await poll(hass, freezer)
    assert state(hass, ids["boiler_temp"]) == STATE_UNAVAILABLE
    assert state(hass, ids["door_target"]) == STATE_UNAVAILABLE
    gateway.broken = False
    gateway.lenient = True
    await poll(hass, freezer)
    assert state(hass, ids["boiler_temp"]) == "65.2"
    assert state(hass, ids["door_target"]) == "0"


# --- writes ------------------------------------------------------------------------


async def set_number(hass: HomeAssistant, entity_id: str, value: float) -> None:
    await hass.services.async_call(
        "number",
        "set_value",
        {ATTR_ENTITY_ID: entity_id, "value": value},
        blocking=True,
    )


@pytest.mark.usefixtures("uploads")
async def test_a_write_is_scaled_and_shown_at_once(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, gateway: FpI4cSimulator
) -> None:
    entry = await add_gateway(hass, hass_client, gateway)
    ids = entity_ids(hass, entry)
    posts = len(gateway.posts)
    await set_number(hass, ids["room_setpoint"], 22.0)
    assert gateway.get(1, "DT101", "INT") == 220
    assert state(hass, ids["room_setpoint"]) == "22.0"
    assert len(gateway.posts) == posts + 1
    await hass.services.async_call(
        "switch", "turn_off", {ATTR_ENTITY_ID: ids["heating_pump"]}, blocking=True
    )
    assert gateway.get(1, "Y0", "BOOL") is False
    assert state(hass, ids["heating_pump"]) == "off"


@pytest.mark.usefixtures("uploads")
async def test_a_number_offers_the_range_of_its_type_and_scale(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, gateway: FpI4cSimulator
) -> None:
    """A UINT is 0..65535, an INT in tenths -3276.8..3276.7, within the map's range."""
    entry, ids = await add_with_rows(
        hass,
        hass_client,
        gateway,
        "limit,Counter limit,DT400,UINT,,,,,yes,,,,1 Heating plant,,,,",
        "trim,Sensor trim,DT401,INT,,°C,0.1,,yes,,,,1 Heating plant,,,,",
    )
    ranges = {}
    for key in ("limit", "trim", "room_setpoint", "door_target"):
        shown = hass.states.get(ids[key])
        assert shown is not None
        ranges[key] = (shown.attributes["min"], shown.attributes["max"])
    assert ranges == {
        "limit": (0, 65535),
        "trim": (-3276.8, 3276.7),
        "room_setpoint": (15, 28),
        "door_target": (0, 100),
    }
    await set_number(hass, ids["limit"], 65535)
    await set_number(hass, ids["trim"], -3276.8)
    assert gateway.get(1, "DT400", "UINT") == 65535
    assert gateway.get(1, "DT401", "INT") == -32768
    with pytest.raises(ServiceValidationError):
        await set_number(hass, ids["limit"], 65536)
    await hass.config_entries.async_unload(entry.entry_id)


@pytest.mark.usefixtures("uploads")
async def test_a_refused_write_changes_nothing_and_says_why(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, gateway: FpI4cSimulator
) -> None:
    entry = await add_gateway(hass, hass_client, gateway)
    ids = entity_ids(hass, entry)
    posts = len(gateway.posts)
    with pytest.raises(ServiceValidationError) as raised:
        await set_number(hass, ids["room_setpoint"], 40.0)
    assert raised.value.translation_key == "out_of_range"
    assert len(gateway.posts) == posts
    gateway.write_errors[1, "DT101"] = (65, "Protect error")
    with pytest.raises(ServiceValidationError) as raised:
        await set_number(hass, ids["room_setpoint"], 23.0)
    assert raised.value.translation_key == "value_rejected"
    # The seed's write item has no message: its code is what the user reads.
    assert raised.value.translation_placeholders["message"] == (
        "the device says: err_code 65"
    )
    gateway.silent.add(2)
    with pytest.raises(HomeAssistantError) as raised:
        await set_number(hass, ids["door_target"], 50)
    assert raised.value.translation_key == "write_failed"
    assert "err_code 28" in raised.value.translation_placeholders["error"]
    assert gateway.get(1, "DT101", "INT") == 215
    assert state(hass, ids["room_setpoint"]) == "21.5"


@pytest.mark.usefixtures("uploads")
async def test_a_map_inverts_a_flag_both_ways_and_a_title_never_does(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    gateway: FpI4cSimulator,
    freezer: FrozenDateTimeFactory,
) -> None:
    """The example's limit switch (on when closed) shows a closed garage door.

    Its map says ``garage_door`` and ``invert``; the same title without them
    gets no class (a door's on is open); an inverted switch writes the opposite.
    """
    entry, ids = await add_with_rows(
        hass,
        hass_client,
        gateway,
        "closed_plain,Garage door closed,X0,BOOL,,,,,no,,,,2 Door controller,,,,",
        "pump_stop,Pump stopped,Y2,BOOL,,,,,yes,,,,1 Heating plant,,,yes,",
    )
    closed = hass.states.get(ids["door_closed"])
    assert closed is not None
    assert (closed.state, closed.attributes["device_class"]) == ("off", "garage_door")
    plain = hass.states.get(ids["closed_plain"])
    assert plain is not None
    assert plain.state == "on"
    assert "device_class" not in plain.attributes
    gateway.set(2, "X0", "BOOL", False)
    await poll(hass, freezer)
    assert state(hass, ids["door_closed"]) == "on"
    assert state(hass, ids["closed_plain"]) == "off"
    # Y2 is false: the inverted switch is on; turned off, it writes true.
    assert state(hass, ids["pump_stop"]) == "on"
    await hass.services.async_call(
        "switch", "turn_off", {ATTR_ENTITY_ID: ids["pump_stop"]}, blocking=True
    )
    assert gateway.get(1, "Y2", "BOOL") is True
    assert state(hass, ids["pump_stop"]) == "off"
    await hass.services.async_call(
        "switch", "turn_on", {ATTR_ENTITY_ID: ids["pump_stop"]}, blocking=True
    )
    assert gateway.get(1, "Y2", "BOOL") is False
    await hass.config_entries.async_unload(entry.entry_id)


# --- moved, composed, downloaded ------------------------------------------------------


@pytest.mark.usefixtures("uploads")
async def test_a_gateway_moved_to_another_address_keeps_its_entities(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, gateway: FpI4cSimulator
) -> None:
    entry = await add_gateway(hass, hass_client, gateway)
    before = entity_ids(hass, entry)
    identity = entry.unique_id
    map_id = entry.data[CONF_POINT_MAP]
    async with FpI4cSimulator(demo_stations(), station=1) as moved:
        moved.silent.add(2)
        result = await hass.config_entries.flow.async_init(
            DOMAIN,
            context={"source": SOURCE_RECONFIGURE, "entry_id": entry.entry_id},
        )
        assert result["step_id"] == "reconfigure_fpi4c"
        result = await hass.config_entries.flow.async_configure(
            result["flow_id"], {CONF_HOST: moved.url}
        )
        assert result["errors"] == {"base": "station_not_answering"}
        assert result["description_placeholders"]["station"] == "2"
        moved.silent.clear()
        result = await hass.config_entries.flow.async_configure(
            result["flow_id"], {CONF_HOST: moved.url, "interface": "4"}
        )
        await hass.async_block_till_done()
        assert result["type"] is FlowResultType.ABORT
        assert result["reason"] == "fpi4c_reconfigured"
        assert entry.data[CONF_HOST] == moved.url
        assert entry.data["interface"] == "4"
        assert entry.data[CONF_POINT_MAP] == map_id
        assert entry.unique_id == identity
        assert entry.state is ConfigEntryState.LOADED
        assert entity_ids(hass, entry) == before
        moved.set(1, "DT0", "INT", 700)
        await entry.runtime_data.async_refresh()
        assert state(hass, before["boiler_temp"]) == "70.0"
        assert moved.posts[-1]["interface"] == 4
        # A map changed in the options keeps the identity too.
        result = await options_step(hass, entry, "remove_point")
        result = await hass.config_entries.options.async_configure(
            result["flow_id"], {"point": ["car_present"]}
        )
        result = await hass.config_entries.options.async_configure(
            result["flow_id"], {}
        )
        await hass.async_block_till_done()
        kept = {key: value for key, value in before.items() if key != "car_present"}
        assert entity_ids(hass, entry) == kept
        assert state(hass, before["boiler_temp"]) == "70.0"
        # So does a newer file, checked on the gateway at its new address.
        result = await options_step(hass, entry, "upload")
        file_id = await upload(hass, hass_client, "map.csv", EXAMPLE)
        result = await hass.config_entries.options.async_configure(
            result["flow_id"], {CONF_POINT_MAP: file_id}
        )
        await hass.async_block_till_done()
        assert result["type"] is FlowResultType.CREATE_ENTRY, result
        assert entry.unique_id == identity
        assert entity_ids(hass, entry) == before
        await hass.config_entries.async_unload(entry.entry_id)


@pytest.mark.usefixtures("uploads")
async def test_a_thermostat_and_a_garage_door_are_composed_of_its_points(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, gateway: FpI4cSimulator
) -> None:
    entry = await add_gateway(hass, hass_client, gateway)
    composed = {
        "thermostat": {
            "name": "Living room",
            "temperature": "room_temp",
            "setpoint": "room_setpoint",
            "heat_mode": "heating_on",
        },
        "blind": {
            "name": "Garage door",
            "position": "door_position",
            "target": "door_target",
            "moving": "door_moving",
        },
    }
    for kind, data in composed.items():
        result = await hass.config_entries.subentries.async_init(
            (entry.entry_id, kind), context={"source": SOURCE_USER}
        )
        result = await hass.config_entries.subentries.async_configure(
            result["flow_id"], data
        )
        assert result["type"] is FlowResultType.CREATE_ENTRY
        await hass.async_block_till_done()
    climate = next(
        entity_id
        for entity_id in entity_ids(hass, entry).values()
        if entity_id.startswith("climate.")
    )
    shown = hass.states.get(climate)
    assert shown is not None
    assert shown.attributes["current_temperature"] == 21.4
    await hass.services.async_call(
        "climate",
        "set_temperature",
        {ATTR_ENTITY_ID: climate, "temperature": 23.5},
        blocking=True,
    )
    assert gateway.get(1, "DT101", "INT") == 235
    cover = next(
        entity_id
        for entity_id in entity_ids(hass, entry).values()
        if entity_id.startswith("cover.")
    )
    await hass.services.async_call(
        "cover",
        "set_cover_position",
        {ATTR_ENTITY_ID: cover, "position": 60},
        blocking=True,
    )
    assert gateway.get(2, "DT11", "INT") == 60
    await hass.config_entries.async_unload(entry.entry_id)


@pytest.mark.usefixtures("uploads")
async def test_diagnostics_tell_the_plan_and_not_the_address(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, gateway: FpI4cSimulator
) -> None:
    entry = await add_gateway(hass, hass_client, gateway)
    gateway.dropped.add(2)
    await entry.runtime_data.async_refresh()
    diagnostics = await async_get_config_entry_diagnostics(hass, entry)  # type: ignore[arg-type]
    plan = diagnostics["read_plans"]["values"]
    assert plan["posts"] == plan["lower_bound"]
    assert diagnostics["requests"]["posts"] >= 4
    assert diagnostics["catalogue"]["points"] == 24
    text = str(diagnostics)
    assert "127.0.0.1" not in text
    assert str(gateway.port) not in text
    assert any(
        error["error"] == "PlcNotAnsweringError"
        for error in diagnostics["recent_errors"]
    )
