"""The point-map editor of the options: a newer map file, a point added, changed, removed.

Driven with the memory source (``tests/fake_source.py``) and an FP-I4C gateway
(its simulator), each added through the config flow as a user would. A map
uploaded in the options replaces the entry's map in place, keeping the entities
of the points it keeps; a map or point with an error, or one the device refuses,
changes nothing and says why on its field.
"""

from typing import Any

from homeassistant.config_entries import ConfigEntryState
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType, InvalidData
from homeassistant.helpers.storage import Store
import pytest
from pytest_homeassistant_custom_component.typing import ClientSessionGenerator

from custom_components.tecoapi.const import DOMAIN
from custom_components.tecoapi.pyplc.core.descriptor import CONF_POINT_MAP
from custom_components.tecoapi.pyplc.core.exceptions import (
    PlcAuthenticationError,
    PlcConnectionError,
)
from custom_components.tecoapi.pyplc.panasonic.descriptor import FPI4C
from tests.components.tecoapi import fpi4c_gateway, mervis_house
from tests.components.tecoapi.memory_house import (
    add_house,
    choose,
    entity_ids,
    open_options,
    upload,
)
from tests.fake_source import DEVICES, HOUSE_CSV
from tests.simulator.fpi4c import FpI4cSimulator, demo_stations
from tests.simulator.mervis import HOUSE_NAME, MervisSimulator, generated


async def test_a_newer_map_keeps_the_entities_of_the_points_it_keeps(
    hass: HomeAssistant, memory: None, hass_client: ClientSessionGenerator
) -> None:
    entry = (await add_house(hass, hass_client))["result"]
    coordinator = entry.runtime_data
    before = entity_ids(hass, entry.entry_id)
    newer = (
        HOUSE_CSV.replace("Boiler temperature", "Boiler water").replace(
            "starts,Burner starts,m5,UDINT,,,,,no,,,,Boiler,,,\n", ""
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
        result["flow_id"], {"point": "cellar_temp"}
    )
    assert result["step_id"] == "point"
    assert result["description_placeholders"]["point"] == "cellar_temp"
    changed = {key: value for key, value in point.items() if key != "id"}
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {**changed, "name": "Cellar air", "scale": 0.5}
    )
    await hass.async_block_till_done()
    assert entity_ids(hass, entry.entry_id)["cellar_temp"] == cellar
    shown = hass.states.get(cellar)
    assert shown.state == "8.5"
    assert shown.attributes["friendly_name"] == "Cellar Air"

    # A bad address is refused on its field, the map unchanged.
    result = await choose(hass, await open_options(hass, entry.entry_id), "edit_point")
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {"point": "cellar_temp"}
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
    await hass.async_block_till_done()
    remaining = entity_ids(hass, entry.entry_id)
    assert "cellar_temp" not in remaining
    assert "garden_pump" not in remaining
    assert "boiler_temp" in remaining


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
    result = await choose(hass, await open_options(hass, entry.entry_id), "add_point")
    result = await hass.config_entries.options.async_configure(
        result["flow_id"],
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
    await hass.async_block_till_done()
    assert result["type"] is FlowResultType.CREATE_ENTRY
    ids = fpi4c_gateway.entity_ids(hass, entry)
    assert fpi4c_gateway.state(hass, ids["door_cycles"]) == "123"

    result = await fpi4c_gateway.options_step(hass, entry, "edit_point")
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {"point": "door_cycles"}
    )
    changed = {key: value for key, value in point.items() if key != "id"}
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {**changed, "scale": 0.1}
    )
    await hass.async_block_till_done()
    assert fpi4c_gateway.entity_ids(hass, entry)["door_cycles"] == ids["door_cycles"]
    assert fpi4c_gateway.state(hass, ids["door_cycles"]) == "12.3"

    result = await fpi4c_gateway.options_step(hass, entry, "remove_point")
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {"point": ["door_cycles"]}
    )
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


# --- a Mervis controller's .vlist (mervis_house.py) -----------------------------------


async def test_the_point_to_change_is_searched_for_or_its_id_typed(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, mervis: MervisSimulator
) -> None:
    """Among thousands of points (hw.*), the picker searches: a custom value.

    The frontend shows a single choice that takes a custom value as a picker
    filtering as one types (a plain dropdown has no search). What is typed
    must be a point's ID (any case); anything else is a translated error on
    the field, the form kept.
    """
    entry = await mervis_house.add_house(hass, hass_client, mervis)
    result = await hass.config_entries.options.async_init(entry.entry_id)
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {"next_step_id": "edit_point"}
    )
    schema = result["data_schema"].schema
    selector = schema[next(key for key in schema if key == "point")]
    assert selector.config["custom_value"] is True
    assert selector.config["mode"] == "dropdown"
    count = len(entry.runtime_data.point_map.points)
    assert len(selector.config["options"]) == count
    assert result["description_placeholders"] == {"count": str(count)}
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {"point": "hw.no_such_point"}
    )
    assert (result["step_id"], result["errors"]) == (
        "edit_point",
        {"point": "point_unknown"},
    )
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {"point": " HW.Neuron_L203_RO_2.01 "}
    )
    assert result["step_id"] == "point"
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
    assert result["type"] is FlowResultType.CREATE_ENTRY
    await hass.async_block_till_done()
    assert (
        hass.states.get(mervis_house.entity(hass, "sensor", "kotel.vratna")).state
        == "44.0"
    )
