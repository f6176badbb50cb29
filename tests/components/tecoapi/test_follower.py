"""Each platform's entities, as the selection's points and devices come and go.

A platform creates the entities of the selection's descriptions and typed
devices on it; after a new selection an entity new to it is created, and one
whose description changed is made again under its registry entry (its entity
ID and the user's settings stay).
"""

from typing import TYPE_CHECKING

from homeassistant.const import ATTR_UNIT_OF_MEASUREMENT
from homeassistant.core import HomeAssistant
from homeassistant.helpers import entity_registry as er
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.tecoapi.const import DOMAIN, STATUS_KEYS
from custom_components.tecoapi.mapping import DEVICE_PLATFORMS
from custom_components.tecoapi.options import PlcOptions
from custom_components.tecoapi.pyplc.core.models import PointOverride
from tests.components.tecoapi.typed import SERIAL

if TYPE_CHECKING:
    from custom_components.tecoapi.coordinator import PlcCoordinator

SETPOINT = "number.heating_living_room_setpoint"


async def test_each_platform_has_the_entities_of_its_points_and_devices(
    hass: HomeAssistant, demo_entry: MockConfigEntry
) -> None:
    coordinator: PlcCoordinator = demo_entry.runtime_data
    data = coordinator.data
    registered: dict[str, set[str]] = {}
    for item in er.async_entries_for_config_entry(
        er.async_get(hass), demo_entry.entry_id
    ):
        key = item.unique_id.removeprefix(f"{SERIAL}_")
        if key not in STATUS_KEYS:
            registered.setdefault(item.domain, set()).add(key)

    wanted: dict[str, set[str]] = {}
    for key, description in data.descriptions.items():
        wanted.setdefault(description.platform.value, set()).add(key)
    for key, device in data.devices.items():
        wanted.setdefault(DEVICE_PLATFORMS[device.kind].value, set()).add(key)
    assert registered == wanted


async def test_a_point_back_in_the_selection_gets_its_entity_again(
    hass: HomeAssistant, demo_entry: MockConfigEntry
) -> None:
    coordinator: PlcCoordinator = demo_entry.runtime_data

    await coordinator.applier.async_apply_options(
        PlcOptions(exclude=("heating.livingsetpoint",)), []
    )
    await hass.async_block_till_done()
    assert hass.states.get(SETPOINT) is None

    await coordinator.applier.async_apply_options(PlcOptions(), [])
    await hass.async_block_till_done()
    assert hass.states.get(SETPOINT).state == "21.5"


async def test_a_changed_description_is_made_again_under_its_entity_id(
    hass: HomeAssistant, demo_entry: MockConfigEntry
) -> None:
    coordinator: PlcCoordinator = demo_entry.runtime_data
    registry = er.async_get(hass)
    registry.async_update_entity(SETPOINT, name="Living")

    await coordinator.applier.async_replace_overrides(
        {"heating.livingsetpoint": PointOverride(unit="K")}
    )
    await hass.async_block_till_done()

    state = hass.states.get(SETPOINT)
    assert state.attributes[ATTR_UNIT_OF_MEASUREMENT] == "K"
    assert state.name == "Living"
    kept = registry.async_get(SETPOINT)
    assert kept is not None
    assert kept.unique_id == f"{SERIAL}_heating.livingsetpoint"
    assert registry.async_get_entity_id("number", DOMAIN, kept.unique_id) == SETPOINT
