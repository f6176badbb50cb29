"""A point's classes: the one step both forms of one point end with.

A map's point (the memory source's map, *Add a point*) and a discovered point
(the demo PLC through TecoApi, *Change a point*) are asked their classes the
same way, once their form has passed: Home Assistant's device classes of the
platform they are shown on (the numeric ones for a number with a unit), a
state class for a sensor, each checked against the unit and each other. An
energy counter in kWh kept as *Total increasing* is what the Energy dashboard
takes, whichever system it comes from.
"""

from collections.abc import Awaitable, Callable
from typing import Any, Final

from homeassistant.config_entries import ConfigEntry
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
from homeassistant.helpers import entity_registry as er
import pytest
from pytest_homeassistant_custom_component.typing import ClientSessionGenerator

from custom_components.tecoapi.const import CONF_PLAIN_VARIABLES, DOMAIN
from custom_components.tecoapi.flows.point_class import CLASS_STEP
from custom_components.tecoapi.overrides import async_load_overrides
from custom_components.tecoapi.pyplc.core.models import PointOverride
from tests.components.tecoapi.conftest import make_entry, setup_entry
from tests.components.tecoapi.memory_house import add_house, choose, open_options
from tests.components.tecoapi.overridden import offered, open_point, submit
from tests.fake_source import DEVICES
from tests.simulator import Simulator

type Opened = tuple[ConfigEntry, Any, str]
"""An entry, its class step for a counter in kWh, and the counter's unique ID."""

METER: Final = {
    "id": "meter",
    "name": "Energy meter",
    "address": "m40",
    "type": "UDINT",
    "unit": "kWh",
    "writable": False,
}


async def map_counter(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, simulator: Simulator
) -> Opened:
    """A map's counter in kWh, added to the memory house: its class step."""
    del simulator
    entry = (await add_house(hass, hass_client))["result"]
    DEVICES["MEM-0001"].values["m40"] = 1234
    result = await choose(hass, await open_options(hass, entry.entry_id), "add_point")
    result = await hass.config_entries.options.async_configure(result["flow_id"], METER)
    return entry, result, "MEM-0001_meter"


async def discovered_counter(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, simulator: Simulator
) -> Opened:
    """The demo PLC's plain counter (no unit), given kWh: its class step."""
    del hass_client
    entry = await setup_entry(
        hass, make_entry(simulator, **{CONF_PLAIN_VARIABLES: "enabled"})
    )
    result = await open_point(hass, entry, "doorbellcount")
    result = await submit(hass, result, unit="kWh")
    return entry, result, "SD 2080_doorbellcount"


@pytest.mark.usefixtures("memory")
@pytest.mark.parametrize(
    "counter", [map_counter, discovered_counter], ids=["map", "discovered"]
)
async def test_an_energy_counter_is_a_total_of_energy_in_either_form(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    simulator: Simulator,
    counter: Callable[..., Awaitable[Opened]],
) -> None:
    """The same step, the same choices, the same refusals, the same entity."""
    _, result, unique_id = await counter(hass, hass_client, simulator)
    manager = hass.config_entries.options

    assert result["step_id"] == CLASS_STEP
    assert offered(result) == {"device_class": "number", "state_class": None}
    assert result["description_placeholders"]["unit"] == "kWh"
    # kWh is energy, whose history is a total: a measurement keeps none.
    result = await manager.async_configure(
        result["flow_id"], {"state_class": "measurement"}
    )
    assert result["errors"] == {"state_class": "point_class_state"}
    result = await manager.async_configure(
        result["flow_id"],
        {"device_class": "temperature", "state_class": "total_increasing"},
    )
    assert result["errors"] == {"device_class": "point_class_unit"}
    result = await manager.async_configure(
        result["flow_id"], {"device_class": "energy", "state_class": "total_increasing"}
    )
    await hass.async_block_till_done(wait_background_tasks=True)

    assert result["type"] is FlowResultType.CREATE_ENTRY
    entity_id = er.async_get(hass).async_get_entity_id("sensor", DOMAIN, unique_id)
    assert entity_id is not None
    state = hass.states.get(entity_id)
    assert state is not None
    assert state.attributes["device_class"] == "energy"
    assert state.attributes["state_class"] == "total_increasing"
    assert state.attributes["unit_of_measurement"] == "kWh"


@pytest.mark.usefixtures("memory")
async def test_a_map_point_s_state_class_is_kept_and_offered_again(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, simulator: Simulator
) -> None:
    """Stored with the map; changing the point offers it; a class emptied is none."""
    entry, result, _ = await map_counter(hass, hass_client, simulator)
    manager = hass.config_entries.options
    await manager.async_configure(result["flow_id"], {"state_class": "total"})
    await hass.async_block_till_done()
    assert entry.runtime_data.point_map.by_key()["meter"].state_class == "total"

    result = await choose(hass, await open_options(hass, entry.entry_id), "edit_point")
    result = await manager.async_configure(result["flow_id"], {"point": ["meter"]})
    result = await submit(hass, result)
    assert result["step_id"] == CLASS_STEP
    result = await submit(hass, result, state_class=None)
    await hass.async_block_till_done()
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert entry.runtime_data.point_map.by_key()["meter"].state_class == ""


async def test_a_discovered_point_s_classes_follow_the_device_unless_changed(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    """A class as the device says is no change; an emptied one is none, kept."""
    entry = await setup_entry(
        hass, make_entry(simulator, **{CONF_PLAIN_VARIABLES: "enabled"})
    )
    result = await open_point(hass, entry, "doorbellcount")
    result = await submit(hass, result, unit="kWh")
    result = await submit(hass, result, state_class="total_increasing")
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert await async_load_overrides(hass, entry.entry_id) == {
        "doorbellcount": PointOverride(unit="kWh", state_class="total_increasing")
    }
    # Changed again without touching its classes: the same override.
    result = await open_point(hass, entry, "doorbellcount")
    result = await submit(hass, await submit(hass, result))
    assert await async_load_overrides(hass, entry.entry_id) == {
        "doorbellcount": PointOverride(unit="kWh", state_class="total_increasing")
    }
