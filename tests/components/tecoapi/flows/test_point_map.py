"""The point-map editor of the options: a newer map file, a point added, changed, removed.

Driven with the memory source (``tests/fake_source.py``) and an FP-I4C gateway
(its simulator), each added through the config flow as a user would. A map
uploaded in the options replaces the entry's map in place, keeping the entities
of the points it keeps; a map or point with an error, or one the device refuses,
changes nothing and says why on its field.
"""

import asyncio
from collections.abc import Mapping
import json
from pathlib import Path
from typing import Any

from homeassistant.config_entries import ConfigEntryState
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType, InvalidData
from homeassistant.helpers.selector import SelectSelector
from homeassistant.helpers.storage import Store
import pytest
from pytest_homeassistant_custom_component.typing import ClientSessionGenerator

from custom_components.tecoapi.compat import vol
from custom_components.tecoapi.const import DOMAIN
from custom_components.tecoapi.flows.point_class import CLASS_STEP
from custom_components.tecoapi.flows.point_map import REMOVE_CONFIRM_STEP, form_values
from custom_components.tecoapi.pyplc.core.descriptor import CONF_POINT_MAP
from custom_components.tecoapi.pyplc.core.exceptions import (
    PlcAuthenticationError,
    PlcConnectionError,
)
from custom_components.tecoapi.pyplc.core.registry import sources
from custom_components.tecoapi.pyplc.panasonic.descriptor import FPI4C
from tests.components.tecoapi import fpi4c_gateway, mervis_house
from tests.components.tecoapi.memory_house import (
    add_house,
    choose,
    entity_ids,
    open_options,
    upload,
)
from tests.fake_source import DEVICES, HOUSE_CSV, MemorySource
from tests.simulator.fpi4c import FpI4cSimulator, demo_stations
from tests.simulator.mervis import HOUSE_NAME, MervisSimulator, generated

TRANSLATIONS = Path(__file__).parents[4] / "custom_components" / DOMAIN / "translations"


async def test_a_newer_map_keeps_the_entities_of_the_points_it_keeps(
    hass: HomeAssistant, memory: None, hass_client: ClientSessionGenerator
) -> None:
    entry = (await add_house(hass, hass_client))["result"]
    coordinator = entry.runtime_data
    before = entity_ids(hass, entry.entry_id)
    newer = (
        HOUSE_CSV.replace("Boiler temperature", "Boiler water").replace(
            "starts,Burner starts,m5,UDINT,,,,,no,,,,Boiler,,,,total_increasing\n", ""
        )
        + "hot_water,Hot water,m14,REAL,,°C,,,no,,,,Boiler,,,\n"
    )
    DEVICES["MEM-0001"].values["m14"] = 48.5
    result = await choose(hass, await open_options(hass, entry.entry_id), "upload")
    file_id = await upload(hass, hass_client, "house.csv", newer)
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {CONF_POINT_MAP: file_id}
    )
    await hass.async_block_till_done()

    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert entry.runtime_data is coordinator  # in place: no reload
    after = entity_ids(hass, entry.entry_id)
    assert after["boiler_temp"] == before["boiler_temp"]
    # On the Boiler device, the title's "Boiler" is not said again.
    renamed = hass.states.get(after["boiler_temp"])
    assert renamed.attributes["friendly_name"] == "Boiler Water"
    assert "starts" not in after
    assert hass.states.get(after["hot_water"]).state == "48.5"


async def test_a_newer_map_with_an_error_changes_nothing(
    hass: HomeAssistant, memory: None, hass_client: ClientSessionGenerator
) -> None:
    entry = (await add_house(hass, hass_client))["result"]
    before = entity_ids(hass, entry.entry_id)
    result = await choose(hass, await open_options(hass, entry.entry_id), "upload")
    file_id = await upload(hass, hass_client, "house.csv", "name,address\nx,y\n")
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {CONF_POINT_MAP: file_id}
    )
    assert result["errors"] == {CONF_POINT_MAP: "point_map_invalid"}
    assert "no 'type' column" in result["description_placeholders"]["error"]
    assert entity_ids(hass, entry.entry_id) == before


async def test_a_newer_map_the_device_refuses_changes_nothing_and_says_why(
    hass: HomeAssistant,
    memory: None,
    hass_client: ClientSessionGenerator,
    caplog: pytest.LogCaptureFixture,
) -> None:
    entry = (await add_house(hass, hass_client))["result"]
    before = entity_ids(hass, entry.entry_id)
    store = Store[dict[str, Any]](
        hass, 1, f"{DOMAIN}.point_map.{entry.data[CONF_POINT_MAP]}"
    )
    stored = await store.async_load()
    device = DEVICES["MEM-0001"]

    async def submit(csv: str) -> dict[str, Any]:
        result = await choose(hass, await open_options(hass, entry.entry_id), "upload")
        file_id = await upload(hass, hass_client, "house.csv", csv)
        return dict(
            await hass.config_entries.options.async_configure(
                result["flow_id"], {CONF_POINT_MAP: file_id}
            )
        )

    # What the descriptor maps is told by its key; the rest is unknown, logged.
    device.fail = PlcConnectionError("gone")
    assert (await submit(HOUSE_CSV))["errors"] == {"base": "cannot_connect"}
    device.fail = PlcAuthenticationError("a memory device has no users")
    assert (await submit(HOUSE_CSV))["errors"] == {"base": "unknown"}
    assert "The device answered the check with an error" in caplog.text
    device.fail = None
    # A file of none of the device's points, and a file another device answers.
    alien = "x,X,m999,INT,,,,,no,,,,Boiler,,,\n"
    header = HOUSE_CSV.splitlines(keepends=True)[0]
    result = await submit(header + alien)
    assert result["errors"] == {"base": "no_public_variables"}
    device.identity = "MEM-0002"
    result = await submit(HOUSE_CSV)
    assert result["errors"] == {"base": "point_map_other_device"}
    assert entity_ids(hass, entry.entry_id) == before
    assert await store.async_load() == stored


async def test_a_point_is_added_changed_and_removed_in_the_ui(
    hass: HomeAssistant, memory: None, hass_client: ClientSessionGenerator
) -> None:
    entry = (await add_house(hass, hass_client))["result"]
    device = DEVICES["MEM-0001"]
    device.values["m20"] = 17

    result = await choose(hass, await open_options(hass, entry.entry_id), "add_point")
    assert result["step_id"] == "add_point"  # a source without words of its own
    point = {
        "id": "cellar_temp",
        "name": "Cellar",
        "address": "m20",
        "type": "INT",
        "unit": "°C",
        "writable": False,
        "device": "Cellar",
    }
    result = await hass.config_entries.options.async_configure(result["flow_id"], point)
    # A number with a unit takes a device class: asked next, none chosen.
    assert result["step_id"] == CLASS_STEP
    result = await hass.config_entries.options.async_configure(result["flow_id"], {})
    await hass.async_block_till_done()
    assert result["type"] is FlowResultType.CREATE_ENTRY
    cellar = entity_ids(hass, entry.entry_id)["cellar_temp"]
    assert hass.states.get(cellar).state == "17"

    # The same ID again is refused on its field.
    result = await choose(hass, await open_options(hass, entry.entry_id), "add_point")
    result = await hass.config_entries.options.async_configure(result["flow_id"], point)
    assert result["errors"] == {"id": "point_invalid"}

    # Changed: a scale and a new name; the entity stays the same one.
    result = await choose(hass, await open_options(hass, entry.entry_id), "edit_point")
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {"point": ["cellar_temp"]}
    )
    assert result["step_id"] == "point"
    assert result["description_placeholders"]["point"] == "cellar_temp"
    changed = {key: value for key, value in point.items() if key != "id"}
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {**changed, "name": "Cellar air", "scale": 0.5}
    )
    result = await hass.config_entries.options.async_configure(result["flow_id"], {})
    await hass.async_block_till_done()
    assert entity_ids(hass, entry.entry_id)["cellar_temp"] == cellar
    shown = hass.states.get(cellar)
    assert shown.state == "8.5"
    assert shown.attributes["friendly_name"] == "Cellar Air"

    # A bad address is refused on its field, the map unchanged.
    result = await choose(hass, await open_options(hass, entry.entry_id), "edit_point")
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {"point": ["cellar_temp"]}
    )
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {**changed, "address": "no address!"}
    )
    assert result["errors"] == {"address": "point_invalid"}

    result = await choose(
        hass, await open_options(hass, entry.entry_id), "remove_point"
    )
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {"point": ["cellar_temp", "garden_pump"]}
    )
    assert result["step_id"] == REMOVE_CONFIRM_STEP
    result = await hass.config_entries.options.async_configure(result["flow_id"], {})
    await hass.async_block_till_done()
    remaining = entity_ids(hass, entry.entry_id)
    assert "cellar_temp" not in remaining
    assert "garden_pump" not in remaining
    assert "boiler_temp" in remaining


def frontend_fills(schema: vol.Schema) -> dict[str, Any]:
    """What the frontend fills a form with before the user touches it.

    As Home Assistant's frontend does (``computeInitialHaFormData``): a field's
    suggested value, else its default, else, for a required one, a first
    value: a select's first option (a list of it when it takes several).
    """
    filled: dict[str, Any] = {}
    for marker, selector in schema.schema.items():
        suggested = (marker.description or {}).get("suggested_value")
        if suggested is not None:
            filled[str(marker)] = suggested
        elif marker.default is not vol.UNDEFINED:
            filled[str(marker)] = marker.default()
        elif isinstance(marker, vol.Required) and isinstance(selector, SelectSelector):
            first = selector.config["options"][0]
            value = first if isinstance(first, str) else first["value"]
            filled[str(marker)] = [value] if selector.config["multiple"] else value
    return filled


async def past_classes(
    hass: HomeAssistant, result: Any, classes: Mapping[str, Any] | None = None
) -> Any:
    """Answer the step of a point's classes, where it is asked (with none: as shown)."""
    if result.get("step_id") != CLASS_STEP:
        return result
    return await hass.config_entries.options.async_configure(
        result["flow_id"], dict(classes or {})
    )


async def add_point(
    hass: HomeAssistant,
    entry_id: str,
    point: dict[str, Any],
    *,
    ask_classes: bool = False,
) -> dict[str, Any]:
    """Add a point to the memory house in its options.

    Its classes, where asked, as the step shows them (``ask_classes``: the
    step is the answer).
    """
    result = await choose(hass, await open_options(hass, entry_id), "add_point")
    result = await hass.config_entries.options.async_configure(result["flow_id"], point)
    return dict(result if ask_classes else await past_classes(hass, result))


async def test_nothing_is_removed_unasked_and_a_removal_says_what_goes(
    hass: HomeAssistant, memory: None, hass_client: ClientSessionGenerator
) -> None:
    """Remove points: none chosen at first, then one confirmation of what goes.

    Submitted untouched, the form removed the map's first point (the frontend
    fills a required choice with its first option). Now nothing is chosen; the
    choice leads to a confirmation naming the points and the entities that
    go (the kitchen light is built on its on/off point); only its Submit
    removes them. Home Assistant keeps a removed entity's registry entry for
    its entry: the point added again gets its entity ID back, as the
    confirmation says.
    """
    entry = (await add_house(hass, hass_client))["result"]
    before = entity_ids(hass, entry.entry_id)
    result = await choose(
        hass, await open_options(hass, entry.entry_id), "remove_point"
    )
    assert frontend_fills(result["data_schema"]) == {}
    result = await hass.config_entries.options.async_configure(result["flow_id"], {})
    assert (result["step_id"], result["errors"]) == (
        "remove_point",
        {"point": "point_none"},
    )
    assert entity_ids(hass, entry.entry_id) == before

    chosen = ["boiler_temp", "kitchen_gtsap1_light_onoff"]
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {"point": chosen}
    )
    assert result["step_id"] == REMOVE_CONFIRM_STEP
    assert frontend_fills(result["data_schema"]) == {}
    shown = result["description_placeholders"]
    assert shown["points"].splitlines() == [
        "- Boiler temperature (boiler_temp)",
        "- Kitchen light (KITCHEN_GTSAP1_LIGHT_onoff)",
    ]
    assert shown["entities"].splitlines() == sorted(
        f"- `{before[key]}`"
        for key in ("boiler_temp", "kitchen_gtsap1_light_onoff", "gtsap1:light:kitchen")
    )
    assert entity_ids(hass, entry.entry_id) == before  # not yet
    result = await hass.config_entries.options.async_configure(result["flow_id"], {})
    await hass.async_block_till_done()
    assert result["type"] is FlowResultType.CREATE_ENTRY
    after = entity_ids(hass, entry.entry_id)
    assert "boiler_temp" not in after
    assert "kitchen_gtsap1_light_onoff" not in after
    assert "gtsap1:light:kitchen" not in after  # no light without its on/off

    # Added again with its ID: its entity comes back with its entity ID.
    result = await add_point(
        hass,
        entry.entry_id,
        {"id": "boiler_temp", "name": "Boiler", "address": "m3", "type": "INT"},
    )
    await hass.async_block_till_done()
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert entity_ids(hass, entry.entry_id)["boiler_temp"] == before["boiler_temp"]


async def test_a_lost_map_ends_its_options_with_a_reason(
    hass: HomeAssistant, memory: None, hass_client: ClientSessionGenerator
) -> None:
    entry = (await add_house(hass, hass_client))["result"]
    await Store[dict[str, Any]](
        hass, 1, f"{DOMAIN}.point_map.{entry.data[CONF_POINT_MAP]}"
    ).async_remove()
    result = await choose(hass, await open_options(hass, entry.entry_id), "add_point")
    assert result["type"] is FlowResultType.ABORT
    assert result["reason"] == "point_map_lost"


async def test_the_map_of_an_entry_not_loaded_changes_for_its_next_start(
    hass: HomeAssistant, memory: None, hass_client: ClientSessionGenerator
) -> None:
    """Unloaded, the map is stored and the next setup takes it (text length too)."""
    entry = (await add_house(hass, hass_client))["result"]
    await hass.config_entries.async_unload(entry.entry_id)
    await hass.async_block_till_done()
    DEVICES["MEM-0001"].values["m21"] = "Hi"
    result = await add_point(
        hass,
        entry.entry_id,
        {
            "id": "greeting",
            "name": "Greeting",
            "address": "m21",
            "type": "STRING",
            "length": 8.0,
            "writable": True,
        },
    )
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert entry.state is ConfigEntryState.NOT_LOADED
    await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    greeting = entity_ids(hass, entry.entry_id)["greeting"]
    assert hass.states.get(greeting).state == "Hi"
    assert hass.states.get(greeting).attributes["max"] == 8


# --- an FP-I4C gateway's register map (fpi4c_gateway.py) ------------------------------


@pytest.mark.usefixtures("uploads")
async def test_points_are_added_checked_changed_and_removed_in_the_options(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, gateway: FpI4cSimulator
) -> None:
    entry = await fpi4c_gateway.add_gateway(hass, hass_client, gateway)
    gateway.set(2, "DT20", "INT", 123)
    point = {
        "id": "door_cycles",
        "name": "Door cycles",
        "address": "DT20",
        "type": "INT",
        "writable": False,
        "device": "2",
    }
    for field, bad in (
        ("address", "DT-20"),
        ("type", "BOOL"),
        ("device", "Garage"),
        ("length", 4.0),
    ):
        result = await fpi4c_gateway.options_step(hass, entry, "add_point")
        result = await hass.config_entries.options.async_configure(
            result["flow_id"], {**point, field: bad}
        )
        assert result["errors"] == {field: "point_invalid"}, (field, bad)
    # The form offers the types the gateway reads only.
    result = await fpi4c_gateway.options_step(hass, entry, "add_point")
    offered = result["data_schema"].schema["type"].config["options"]
    assert offered == [name.upper() for name in FPI4C.point_types]
    with pytest.raises(InvalidData):
        await hass.config_entries.options.async_configure(
            result["flow_id"], {**point, "type": "LREAL"}
        )
    result = await fpi4c_gateway.options_step(hass, entry, "add_point")
    result = await hass.config_entries.options.async_configure(result["flow_id"], point)
    result = await past_classes(hass, result)
    await hass.async_block_till_done()
    assert result["type"] is FlowResultType.CREATE_ENTRY
    ids = fpi4c_gateway.entity_ids(hass, entry)
    assert fpi4c_gateway.state(hass, ids["door_cycles"]) == "123"

    result = await fpi4c_gateway.options_step(hass, entry, "edit_point")
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {"point": ["door_cycles"]}
    )
    assert result["step_id"] == "fpi4c_point"
    changed = {key: value for key, value in point.items() if key != "id"}
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {**changed, "scale": 0.1}
    )
    result = await past_classes(hass, result)
    await hass.async_block_till_done()
    assert fpi4c_gateway.entity_ids(hass, entry)["door_cycles"] == ids["door_cycles"]
    assert fpi4c_gateway.state(hass, ids["door_cycles"]) == "12.3"

    result = await fpi4c_gateway.options_step(hass, entry, "remove_point")
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {"point": ["door_cycles"]}
    )
    result = await hass.config_entries.options.async_configure(result["flow_id"], {})
    await hass.async_block_till_done()
    assert "door_cycles" not in fpi4c_gateway.entity_ids(hass, entry)


@pytest.mark.usefixtures("uploads")
async def test_a_newer_fpi4c_map_keeps_the_entities_of_the_points_it_keeps(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, gateway: FpI4cSimulator
) -> None:
    entry = await fpi4c_gateway.add_gateway(hass, hass_client, gateway)
    before = fpi4c_gateway.entity_ids(hass, entry)
    newer = fpi4c_gateway.EXAMPLE.replace("Boiler temperature", "Boiler water") + (
        "cellar,Cellar temperature,LD3,INT,,°C,0.5,,no,,,,3 Cellar,,,\n"
    )
    gateway.stations[3] = demo_stations()[1]
    gateway.set(3, "LD3", "INT", 31)
    result = await fpi4c_gateway.options_step(hass, entry, "upload")
    file_id = await upload(hass, hass_client, "map.csv", newer)
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {CONF_POINT_MAP: file_id}
    )
    await hass.async_block_till_done()
    assert result["type"] is FlowResultType.CREATE_ENTRY
    after = fpi4c_gateway.entity_ids(hass, entry)
    assert after["boiler_temp"] == before["boiler_temp"]
    assert fpi4c_gateway.state(hass, after["cellar"]) == "15.5"
    result = await fpi4c_gateway.options_step(hass, entry, "upload")
    file_id = await upload(hass, hass_client, "map.csv", newer + "x,x,Q0,INT\n")
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {CONF_POINT_MAP: file_id}
    )
    assert result["errors"] == {CONF_POINT_MAP: "point_map_invalid"}
    assert result["description_placeholders"]["error"].startswith(
        "row 31, column address: 'Q0' is not an FP address"
    )
    # A file naming a station that does not answer is refused, and says which.
    gateway.silent.add(3)
    result = await fpi4c_gateway.options_step(hass, entry, "upload")
    file_id = await upload(hass, hass_client, "map.csv", newer)
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {CONF_POINT_MAP: file_id}
    )
    assert result["errors"] == {"base": "station_not_answering"}
    assert result["description_placeholders"]["station"] == "3"
    assert fpi4c_gateway.entity_ids(hass, entry) == after


@pytest.mark.usefixtures("uploads")
async def test_a_typed_address_the_plc_lacks_is_refused_with_its_reason(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, gateway: FpI4cSimulator
) -> None:
    """``R9999F`` is an FP address, but the garage's PLC has no WR9999.

    Before anything is stored the point is read once, in one POST with its
    station's DT0 (as a newer map is checked); the PLC's reason (MEWTOCOL's
    data error) is the error's, in the gateway's words, and nothing changes.
    A change that reads no other bytes (a new name) is not read again.
    """
    entry = await fpi4c_gateway.add_gateway(hass, hass_client, gateway)
    store = Store[dict[str, Any]](
        hass, 1, f"{DOMAIN}.point_map.{entry.data[CONF_POINT_MAP]}"
    )
    stored = await store.async_load()
    before = fpi4c_gateway.entity_ids(hass, entry)
    point = {
        "id": "far",
        "name": "Far relay",
        "address": "R9999F",
        "type": "BOOL",
        "writable": False,
        "device": "2",
    }
    result = await fpi4c_gateway.options_step(hass, entry, "add_point")
    assert result["step_id"] == "fpi4c_add_point"
    sent = len(gateway.posts)
    result = await hass.config_entries.options.async_configure(result["flow_id"], point)
    assert result["errors"] == {"address": "fpi4c_point_refused"}
    assert result["description_placeholders"]["error"].startswith(
        "the device says: err_code 61: "
    )
    checks = [
        post
        for post in gateway.posts[sent:]
        if any(str(item["start"]).startswith("9999") for item in post["req"])
    ]
    assert [(post["station"], len(post["req"])) for post in checks] == [(2, 2)]
    assert checks[0]["req"][0] == {"area": "DT", "type": "INT", "start": 0, "count": 1}
    assert await store.async_load() == stored
    assert fpi4c_gateway.entity_ids(hass, entry) == before

    # A station that does not answer: its own error, the point not blamed.
    gateway.silent.add(2)
    result = await hass.config_entries.options.async_configure(result["flow_id"], point)
    assert result["errors"] == {"base": "station_not_answering"}
    assert result["description_placeholders"]["station"] == "2"

    # A new name is taken without reading the PLC; a new address is read.
    result = await fpi4c_gateway.options_step(hass, entry, "edit_point")
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {"point": ["door_position"]}
    )
    form = form_values(entry.runtime_data.point_map.by_key()["door_position"])
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {**form, "address": "DT12"}
    )
    assert result["errors"] == {"base": "station_not_answering"}
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {**form, "name": "Door position"}
    )
    assert result["step_id"] == CLASS_STEP


# --- a Mervis controller's .vlist (mervis_house.py) -----------------------------------


async def test_the_point_to_change_is_searched_for_without_custom_values(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, mervis: MervisSimulator
) -> None:
    """Among thousands of points (hw.*), the picker searches, and adds nothing typed.

    The frontend searches a list only where it takes several choices, or a
    custom value (then it offers 'Add custom item' for what was typed): the
    list takes several, none chosen at first, and exactly one must be.
    """
    entry = await mervis_house.add_house(hass, hass_client, mervis)
    result = await hass.config_entries.options.async_init(entry.entry_id)
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {"next_step_id": "edit_point"}
    )
    schema = result["data_schema"]
    selector = schema.schema[next(key for key in schema.schema if key == "point")]
    assert selector.config["custom_value"] is False
    assert selector.config["multiple"] is True
    assert frontend_fills(schema) == {}
    count = len(entry.runtime_data.point_map.points)
    assert len(selector.config["options"]) == count
    assert result["description_placeholders"] == {"count": str(count)}
    with pytest.raises(InvalidData):
        await hass.config_entries.options.async_configure(
            result["flow_id"], {"point": ["hw.no_such_point"]}
        )
    for chosen in ([], ["away", "outside_temp"]):
        result = await hass.config_entries.options.async_configure(
            result["flow_id"], {"point": chosen}
        )
        assert (result["step_id"], result["errors"]) == (
            "edit_point",
            {"point": "point_one"},
        )
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {"point": ["hw.neuron_l203_ro_2.01"]}
    )
    assert result["step_id"] == "mervis_point"
    assert result["description_placeholders"]["point"] == "hw.neuron_l203_ro_2.01"


async def test_a_newer_vlist_keeps_the_entities_of_unchanged_variables(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, mervis: MervisSimulator
) -> None:
    entry = await mervis_house.add_house(hass, hass_client, mervis)
    before = mervis_house.keys(hass, entry)
    newer = "\n".join(
        line for line in mervis.project.vlist().splitlines() if "$away$" not in line
    )
    result = await mervis_house.open_upload(hass, entry)
    file_id = await mervis_house.upload(hass, hass_client, "house.vlist", newer + "\n")
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {CONF_POINT_MAP: file_id}
    )
    await hass.async_block_till_done()
    assert result["type"] is FlowResultType.CREATE_ENTRY
    after = mervis_house.keys(hass, entry)
    assert "away" not in after
    assert {key: value for key, value in before.items() if key != "away"} == after
    assert hass.states.get(after["outside_temp"]).state == "4.5"


def _refusing(sim: MervisSimulator) -> str:
    """The house's file, its controller now refusing a variable read alone."""
    sim.switches.max_request_size = 60
    return sim.project.vlist()


@pytest.mark.parametrize(
    ("make", "error"),
    [
        (_refusing, "unknown"),
        (
            lambda sim: sim.project.vlist().replace(HOUSE_NAME, "Chata"),
            "point_map_other_device",
        ),
        (lambda sim: generated(60, seed=5).vlist(), "vlist_unknown"),
    ],
)
async def test_a_newer_file_of_another_controller_is_refused(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    mervis: MervisSimulator,
    make: Any,
    error: str,
) -> None:
    entry = await mervis_house.add_house(hass, hass_client, mervis)
    before = mervis_house.keys(hass, entry)
    result = await mervis_house.open_upload(hass, entry)
    file_id = await mervis_house.upload(hass, hass_client, "other.vlist", make(mervis))
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {CONF_POINT_MAP: file_id}
    )
    assert result["errors"] == {"base": error}
    assert mervis_house.keys(hass, entry) == before


async def test_a_point_added_in_the_options_is_checked_as_the_file_s(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, mervis: MervisSimulator
) -> None:
    entry = await mervis_house.add_house(hass, hass_client, mervis)
    row = mervis.project.row("kotel.return_temp")
    result = await hass.config_entries.options.async_init(entry.entry_id)
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {"next_step_id": "add_point"}
    )
    point = {
        "id": "kotel.vratna",
        "name": "Vratná voda",
        "address": f"{row.commuid}[{row.offset},2]",
        "type": "REAL",
        "writable": False,
        "device": "Kotel",
    }
    result = await hass.config_entries.options.async_configure(result["flow_id"], point)
    assert result["errors"] == {"address": "point_invalid"}
    assert "takes 4 bytes" in result["description_placeholders"]["error"]
    point["address"] = f"{row.commuid}[{row.offset},4]"
    result = await hass.config_entries.options.async_configure(result["flow_id"], point)
    result = await past_classes(hass, result)
    assert result["type"] is FlowResultType.CREATE_ENTRY
    await hass.async_block_till_done()
    assert (
        hass.states.get(mervis_house.entity(hass, "sensor", "kotel.vratna")).state
        == "44.0"
    )


async def test_a_typed_variable_past_its_block_is_refused_with_the_reason(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, mervis: MervisSimulator
) -> None:
    """``6003[60,1]`` lies past the boiler's block (21 bytes): refused, nothing stored.

    The controller reads the variable once after signing in (and once more in
    its other ID spelling, which knows it no better); its reason is the
    error's, in the controller's words. One it reads is taken after one read.
    """
    entry = await mervis_house.add_house(hass, hass_client, mervis)
    store = Store[dict[str, Any]](
        hass, 1, f"{DOMAIN}.point_map.{entry.data[CONF_POINT_MAP]}"
    )
    stored = await store.async_load()
    before = mervis_house.keys(hass, entry)
    result = await hass.config_entries.options.async_init(entry.entry_id)
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {"next_step_id": "add_point"}
    )
    assert result["step_id"] == "mervis_add_point"
    point = {
        "id": "kotel.test",
        "name": "Test",
        "address": "6003[60,1]",
        "type": "BOOL",
        "writable": False,
        "device": "Kotel",
    }
    sent = len(mervis.requests)
    result = await hass.config_entries.options.async_configure(result["flow_id"], point)
    assert result["errors"] == {"address": "mervis_point_refused"}
    assert result["description_placeholders"]["error"] == (
        "the device says: error: unknown variable"
    )
    assert [record.service for record in mervis.requests[sent:]] == [
        "login",
        "values",
        "values",
    ]
    assert await store.async_load() == stored
    assert mervis_house.keys(hass, entry) == before

    sent = len(mervis.requests)
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {**point, "address": "6003[8,1]"}
    )
    assert result["step_id"] == CLASS_STEP
    assert [record.service for record in mervis.requests[sent:]] == ["login", "values"]
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {"device_class": "heat"}
    )
    await hass.async_block_till_done()
    assert result["type"] is FlowResultType.CREATE_ENTRY
    test = hass.states.get(mervis_house.entity(hass, "binary_sensor", "kotel.test"))
    assert test.attributes["device_class"] == "heat"


# --- each system's point form (issue 39, item 4) ----------------------------------


def _point_texts(language: str, step: str) -> dict[str, Any]:
    strings = json.loads(
        (TRANSLATIONS / f"{language}.json").read_text(encoding="utf-8")
    )
    found: dict[str, Any] = strings["options"]["step"][step]
    return found


@pytest.mark.parametrize("language", ["en", "cs"])
@pytest.mark.parametrize(
    ("system", "examples"),
    [("mervis", ("`CommUid[", "`6003[9,4]`")), ("fpi4c", ("`DT100`", "`R1A`"))],
)
def test_each_system_s_point_form_has_its_own_help_and_examples(
    language: str, system: str, examples: tuple[str, ...]
) -> None:
    """Each map system's point forms (its words' step IDs) explain its addresses.

    One form served every system: the address said no example, the scale
    spoke of registers to a Mervis user, "Show as" said the opposite of what
    it does, and the device class was free text (now a step of its own).
    """
    descriptor = next(item for item in sources() if item.name == system)
    words = descriptor.words
    assert (words.add_point_step_id, words.point_step_id) == (
        f"{system}_add_point",
        f"{system}_point",
    )
    for step in (words.add_point_step_id, words.point_step_id):
        texts = _point_texts(language, step)
        assert "device_class" not in texts["data"]
        address = texts["data_description"]["address"]
        assert all(example in address for example in examples), address
        platform = texts["data_description"]["platform"]
        assert "writable point only" not in platform
        assert "BOOL" in platform
    scale = _point_texts(language, words.add_point_step_id)["data_description"]
    if system == "mervis":
        assert "regist" not in scale["scale"]


async def test_the_device_class_is_one_of_the_platform_s(
    hass: HomeAssistant, memory: None, hass_client: ClientSessionGenerator
) -> None:
    """The class is asked after the point, among its platform's classes.

    A read-only BOOL takes a binary sensor's, a number with a unit a number's
    or a sensor's that fits the unit; a switch, or a number without a unit,
    takes none (no step). A "Show as" the type cannot be is refused.
    """
    entry = (await add_house(hass, hass_client))["result"]
    device = DEVICES["MEM-0001"]
    device.values |= {"m30": True, "m31": 55.0}

    async def add(point: dict[str, Any]) -> dict[str, Any]:
        return await add_point(
            hass, entry.entry_id, {"writable": False, **point}, ask_classes=True
        )

    leak = {"id": "leak", "name": "Leak", "address": "m30", "type": "BOOL"}
    result = await add(leak)
    assert result["step_id"] == CLASS_STEP
    assert frontend_fills(result["data_schema"]) == {}
    with pytest.raises(InvalidData):  # a sensor's class, not a binary sensor's
        await hass.config_entries.options.async_configure(
            result["flow_id"], {"device_class": "temperature"}
        )
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {"device_class": "moisture"}
    )
    await hass.async_block_till_done()
    ids = entity_ids(hass, entry.entry_id)
    assert hass.states.get(ids["leak"]).attributes["device_class"] == "moisture"
    # Changed, it offers the class it has.
    result = await choose(hass, await open_options(hass, entry.entry_id), "edit_point")
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {"point": ["leak"]}
    )
    result = await hass.config_entries.options.async_configure(
        result["flow_id"],
        {**form_values(entry.runtime_data.point_map.by_key()["leak"])},
    )
    assert frontend_fills(result["data_schema"]) == {"device_class": "moisture"}

    # A switch takes no class: no step.
    result = await add({**leak, "id": "valve", "writable": True})
    assert result["type"] is FlowResultType.CREATE_ENTRY

    humidity = {
        "id": "humidity",
        "name": "Humidity",
        "address": "m31",
        "type": "REAL",
        "unit": "%",
        "writable": True,
        "min": 0.0,
        "max": 100.0,
    }
    result = await add(humidity)
    assert result["step_id"] == CLASS_STEP
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {"device_class": "temperature"}
    )
    assert result["errors"] == {"device_class": "point_class_unit"}
    assert result["description_placeholders"]["unit"] == "%"
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {"device_class": "humidity"}
    )
    await hass.async_block_till_done()
    ids = entity_ids(hass, entry.entry_id)
    assert ids["humidity"].startswith("number.")
    assert hass.states.get(ids["humidity"]).attributes["device_class"] == "humidity"

    # A sensor's class of text or dates is no number's: not offered.
    result = await add({**humidity, "id": "shown", "writable": False})
    with pytest.raises(InvalidData):
        await hass.config_entries.options.async_configure(
            result["flow_id"], {"device_class": "enum"}
        )

    # Without a unit a number takes no class; an INT is no binary sensor.
    result = await add({**humidity, "id": "plain", "unit": ""})
    assert result["type"] is FlowResultType.CREATE_ENTRY
    result = await add({**humidity, "id": "odd", "platform": "binary_sensor"})
    assert result["errors"] == {"platform": "point_platform"}


async def test_a_long_removal_is_summed_up_and_one_without_entities_says_so(
    hass: HomeAssistant, memory: None, hass_client: ClientSessionGenerator
) -> None:
    """The confirmation names 20 points, then how many more; none: a dash."""
    entry = (await add_house(hass, hass_client))["result"]
    keys = [point.key for point in entry.runtime_data.point_map.points]
    result = await choose(
        hass, await open_options(hass, entry.entry_id), "remove_point"
    )
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {"point": keys[:23]}
    )
    lines = result["description_placeholders"]["points"].splitlines()
    assert (len(lines), lines[-1]) == (21, "- … +3")
    assert result["description_placeholders"]["count"] == "23"

    # Added while the entry is not loaded, a point has no entity yet.
    await hass.config_entries.async_unload(entry.entry_id)
    DEVICES["MEM-0001"].values["m21"] = 5
    result = await add_point(
        hass,
        entry.entry_id,
        {"id": "spare", "name": "Spare", "address": "m21", "type": "INT"},
    )
    assert result["type"] is FlowResultType.CREATE_ENTRY
    result = await choose(
        hass, await open_options(hass, entry.entry_id), "remove_point"
    )
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {"point": ["spare"]}
    )
    assert result["description_placeholders"]["entities"] == "—"


async def test_a_point_another_flow_took_meanwhile_is_refused_at_its_class(
    hass: HomeAssistant, memory: None, hass_client: ClientSessionGenerator
) -> None:
    """Two options flows add the same ID: the one that finishes second is told."""
    entry = (await add_house(hass, hass_client))["result"]
    DEVICES["MEM-0001"].values["m30"] = True
    point = {"id": "leak", "name": "Leak", "address": "m30", "type": "BOOL"}
    first = await choose(hass, await open_options(hass, entry.entry_id), "add_point")
    first = await hass.config_entries.options.async_configure(first["flow_id"], point)
    assert first["step_id"] == CLASS_STEP
    second = await choose(hass, await open_options(hass, entry.entry_id), "add_point")
    second = await hass.config_entries.options.async_configure(second["flow_id"], point)
    second = await hass.config_entries.options.async_configure(second["flow_id"], {})
    assert second["type"] is FlowResultType.CREATE_ENTRY
    first = await hass.config_entries.options.async_configure(first["flow_id"], {})
    assert first["errors"] == {"base": "point_invalid"}
    assert "taken" in first["description_placeholders"]["error"]


async def test_a_point_another_flow_took_while_the_device_read_it_is_refused(
    hass: HomeAssistant,
    memory: None,
    hass_client: ClientSessionGenerator,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A switch (no class step): another flow adds its ID while it is read."""
    entry = (await add_house(hass, hass_client))["result"]
    DEVICES["MEM-0001"].values["m30"] = True
    point = {"id": "valve", "name": "Valve", "address": "m30", "type": "BOOL"}
    reading, go_on = asyncio.Event(), asyncio.Event()
    check = MemorySource.check_points

    async def held(source: MemorySource, keys: Any) -> Any:
        if not reading.is_set():  # the first flow's read waits; the second's not
            reading.set()
            await go_on.wait()
        return await check(source, keys)

    monkeypatch.setattr(MemorySource, "check_points", held)
    first = await choose(hass, await open_options(hass, entry.entry_id), "add_point")
    taking = hass.async_create_task(
        hass.config_entries.options.async_configure(
            first["flow_id"], {**point, "writable": True}
        )
    )
    await reading.wait()
    second = await add_point(hass, entry.entry_id, {**point, "writable": True})
    assert second["type"] is FlowResultType.CREATE_ENTRY
    go_on.set()
    first = await taking

    assert first["errors"] == {"base": "point_invalid"}
    assert "taken" in first["description_placeholders"]["error"]
