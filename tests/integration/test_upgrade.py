"""An installation of 0.2 upgraded: every entity, its ID, its customisation and the options stay.

``fixtures/registry_0_2.json`` is what version 0.2 (commit 922450a) stored for
the demo PLC with options a user had set: the config entry's version and
options, and the entity registry (unique ID and entity ID of all 168
entities). The entry is stored here as 0.2 left it -- its data without a
``transport`` (a TecoApi entry never had one), its registry entries with their
IDs -- and set up by this version.
"""

import json
from pathlib import Path
from typing import Any, Final

from homeassistant.config_entries import ConfigEntryState
from homeassistant.const import STATE_UNAVAILABLE
from homeassistant.core import HomeAssistant
from homeassistant.helpers import entity_registry as er
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.tecoapi.const import CONF_TRANSPORT, DOMAIN
from tests.integration.conftest import entry_data
from tests.simulator import Simulator

STORED: Final[dict[str, Any]] = json.loads(
    (Path(__file__).parent / "fixtures" / "registry_0_2.json").read_text("utf-8")
)


async def test_an_entry_of_0_2_keeps_every_entity_and_its_options(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    data = entry_data(simulator)
    entry = MockConfigEntry(
        domain=DOMAIN,
        title=STORED["title"],
        unique_id=STORED["unique_id"],
        data=data,
        options=STORED["options"],
        version=STORED["version"],
        minor_version=STORED["minor_version"],
    )
    entry.add_to_hass(hass)
    registry = er.async_get(hass)
    for item in STORED["entities"]:
        domain, object_id = item["entity_id"].split(".", 1)
        registry.async_get_or_create(
            domain,
            DOMAIN,
            item["unique_id"],
            suggested_object_id=object_id,
            config_entry=entry,
            disabled_by=er.RegistryEntryDisabler(item["disabled_by"])
            if item["disabled_by"]
            else None,
        )
    outside = "sensor.tecomat_cp_2080_outside_temperature"
    registry.async_update_entity(outside, name="Venku", icon="mdi:home-thermometer")

    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()

    assert entry.state is ConfigEntryState.LOADED
    assert dict(entry.data) == data
    assert CONF_TRANSPORT not in entry.data
    assert dict(entry.options) == STORED["options"]
    kept = {
        item.unique_id: item.entity_id
        for item in er.async_entries_for_config_entry(registry, entry.entry_id)
    }
    assert {
        item["unique_id"]: kept.get(item["unique_id"], "(gone)")
        for item in STORED["entities"]
    } == {item["unique_id"]: item["entity_id"] for item in STORED["entities"]}
    customised = registry.async_get(outside)
    assert customised is not None
    assert (customised.name, customised.icon) == ("Venku", "mdi:home-thermometer")
    # Every enabled entity shows a state; only those the program disables
    # (attr.enable = false) are unavailable, as in 0.2.
    data = entry.runtime_data.data
    prefix = f"{STORED['unique_id']}_"
    for item in STORED["entities"]:
        if item["disabled_by"]:
            continue
        state = hass.states.get(item["entity_id"])
        assert state is not None, item["entity_id"]
        attributes = data.point_attributes(item["unique_id"].removeprefix(prefix))
        disabled = attributes is not None and not attributes.enabled
        assert (state.state == STATE_UNAVAILABLE) == disabled, item["entity_id"]
