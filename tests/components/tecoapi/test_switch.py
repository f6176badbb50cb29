"""Switches: writable boolean points, written through the coordinator."""

from homeassistant.components.switch import DOMAIN as SWITCH_DOMAIN
from homeassistant.config_entries import SOURCE_REAUTH
from homeassistant.const import (
    ATTR_ENTITY_ID,
    SERVICE_TURN_OFF,
    SERVICE_TURN_ON,
    STATE_OFF,
    STATE_ON,
    STATE_UNAVAILABLE,
)
from homeassistant.core import HomeAssistant
from homeassistant.exceptions import HomeAssistantError
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry
from syrupy.assertion import SnapshotAssertion

from custom_components.tecoapi.const import DOMAIN
from tests.components.tecoapi import memory_house
from tests.components.tecoapi.conftest import snapshot_entities
from tests.fake_source import MemoryDevice
from tests.simulator import Simulator

KITCHEN_LIGHT = "switch.lights_kitchen_light"
LIVING_LIGHT = "switch.lights_living_room_light"


@pytest.mark.primary_only
@pytest.mark.parametrize("program_entry", ["demo"], indirect=True)
@pytest.mark.usefixtures("entity_registry_enabled_by_default")
async def test_switches(
    hass: HomeAssistant, program_entry: MockConfigEntry, snapshot: SnapshotAssertion
) -> None:
    """Every switch of the demo (the manual has none): registry entry and state."""
    await snapshot_entities(hass, snapshot, program_entry, "switch")


async def turn(hass: HomeAssistant, service: str, entity_id: str) -> None:
    """Call switch.turn_on / turn_off and wait for it."""
    await hass.services.async_call(
        SWITCH_DOMAIN, service, {ATTR_ENTITY_ID: entity_id}, blocking=True
    )


@pytest.mark.usefixtures("demo_entry")
async def test_turning_switches_writes_the_plc(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    """Turning a light on and off changes the PLC's value and the entity's state."""
    simulator.clear_requests()

    await turn(hass, SERVICE_TURN_ON, LIVING_LIGHT)

    assert simulator.get_value("lights[0].value") is True
    assert hass.states.get(LIVING_LIGHT).state == STATE_ON
    assert [request.service for request in simulator.requests][:1] == ["SetObject"]
    assert "lights%5B0%5D.value=true" in simulator.requests[0].query or (
        "lights[0].value=true" in simulator.requests[0].query
    )

    await turn(hass, SERVICE_TURN_OFF, KITCHEN_LIGHT)

    assert simulator.get_value("lights[1].value") is False
    assert hass.states.get(KITCHEN_LIGHT).state == STATE_OFF


@pytest.mark.usefixtures("demo_entry")
async def test_disabled_object_is_unavailable(hass: HomeAssistant) -> None:
    """attr.enable = false: the holiday-mode switch is unavailable."""
    assert hass.states.get("switch.heating_holiday_mode").state == (STATE_UNAVAILABLE)


@pytest.mark.usefixtures("demo_entry")
async def test_failed_write_raises_and_keeps_the_plc_value(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    """A write the PLC does not acknowledge raises; the entity shows the PLC's value."""
    simulator.faults.http_500 = True
    simulator.faults.remaining = 1

    with pytest.raises(HomeAssistantError) as raised:
        await turn(hass, SERVICE_TURN_OFF, KITCHEN_LIGHT)

    assert raised.value.translation_domain == DOMAIN
    assert raised.value.translation_key == "write_failed"
    assert str(raised.value).startswith("Writing False to lights[1] failed: ")
    assert simulator.get_value("lights[1].value") is True
    assert hass.states.get(KITCHEN_LIGHT).state == STATE_ON


async def test_rejected_credentials_on_write_start_reauth(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    """A write with revoked credentials raises and asks the user to sign in again."""
    simulator.password = "changed-on-the-plc"

    with pytest.raises(HomeAssistantError) as raised:
        await turn(hass, SERVICE_TURN_ON, LIVING_LIGHT)

    assert raised.value.translation_key == "auth_failed"
    assert simulator.get_value("lights[0].value") is False
    await hass.async_block_till_done()
    flows = hass.config_entries.flow.async_progress_by_handler(DOMAIN)
    assert [flow["context"]["source"] for flow in flows] == [SOURCE_REAUTH]


# --- the memory house (memory_house.py): through the in-memory source ---------


async def test_switch(hass: HomeAssistant, house: MemoryDevice) -> None:
    assert memory_house.state(hass, "switch", "garden_pump").state == "on"
    await memory_house.call(hass, "switch", "turn_off", "garden_pump")
    assert house.values["m2"] is False
    assert memory_house.state(hass, "switch", "garden_pump").state == "off"
