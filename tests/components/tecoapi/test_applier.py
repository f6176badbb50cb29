"""What an entry asks for, applied in place (``applier.OptionsApplier``).

New intervals apply at once; another choice of entities selects anew from the
catalogue known, without reading the device again; the user's overrides
swap the source for one that discovers the points with them.
"""

from datetime import timedelta
from typing import TYPE_CHECKING

from homeassistant.core import HomeAssistant
from homeassistant.helpers import entity_registry as er
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.tecoapi.applier import create_entry_source
from custom_components.tecoapi.const import DOMAIN
from custom_components.tecoapi.options import PlcOptions
from custom_components.tecoapi.pyplc.core.models import PointOverride
from tests.components.tecoapi.typed import SERIAL
from tests.simulator import Simulator

if TYPE_CHECKING:
    from custom_components.tecoapi.coordinator import PlcCoordinator

OUTSIDE = "sensor.tecomat_cp_2080_outside_temperature"
SETPOINT = "number.heating_living_room_setpoint"


async def test_new_intervals_apply_at_once(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    coordinator: PlcCoordinator = demo_entry.runtime_data
    source = coordinator.source
    polls = source.statistics.polls
    options = PlcOptions(
        scan_interval=timedelta(seconds=2), attribute_interval=timedelta(seconds=30)
    )

    reselected = await coordinator.applier.async_apply_options(options, [])
    await hass.async_block_till_done()

    assert not reselected
    assert coordinator.options is options
    assert coordinator.update_interval == timedelta(seconds=2)
    assert source.metadata_interval == timedelta(seconds=30)
    assert coordinator.source is source
    assert source.statistics.polls == polls + 1


async def test_another_choice_of_entities_selects_anew(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    """The entities chosen away leave the registry; the others keep showing."""
    coordinator: PlcCoordinator = demo_entry.runtime_data
    discoveries = coordinator.source.statistics.discoveries

    reselected = await coordinator.applier.async_apply_options(
        PlcOptions(exclude=("outsidetemp",)), []
    )
    await hass.async_block_till_done()

    assert reselected
    assert "outsidetemp" not in coordinator.data.points
    registry = er.async_get(hass)
    assert (
        registry.async_get_entity_id("sensor", DOMAIN, f"{SERIAL}_outsidetemp") is None
    )
    assert hass.states.get(SETPOINT).state == "21.5"
    assert coordinator.source.statistics.discoveries == discoveries


async def test_overrides_swap_the_source_for_one_that_applies_them(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    coordinator: PlcCoordinator = demo_entry.runtime_data
    old = coordinator.source
    changed = {"outsidetemp": PointOverride(unit="K")}
    assert hass.states.get(OUTSIDE).attributes["device_class"] == "temperature"

    await coordinator.applier.async_replace_overrides(changed)
    await hass.async_block_till_done()

    assert coordinator.source is not old
    assert coordinator.applier.overrides == changed
    assert coordinator.data.points["outsidetemp"].unit_of() == "K"
    # Kelvin is a temperature difference's unit: shown as one.
    assert hass.states.get(OUTSIDE).attributes["device_class"] == "temperature_delta"


async def test_a_source_is_made_as_the_options_say(
    hass: HomeAssistant, demo_entry: MockConfigEntry
) -> None:
    source = create_entry_source(
        hass,
        demo_entry,
        PlcOptions(attribute_interval=timedelta(seconds=45)),
        None,
    )
    try:
        assert source.metadata_interval == timedelta(seconds=45)
        assert source is not demo_entry.runtime_data.source
    finally:
        await source.close()
