"""Options and composed devices apply in place: untouched entities do not blink.

Switching push on, changing the filters or the devices, or adding a composed
thermostat used to reload the entry: every entity of the PLC went unavailable and
came back, a hundred logbook lines at one moment. Now only the entities that
appear or go away change; a new connection (reconfigure, reauth) still reloads.
"""

from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any
from unittest.mock import patch

from homeassistant.config_entries import SOURCE_USER, ConfigEntryState
from homeassistant.const import (
    CONF_HOST,
    CONF_PORT,
    EVENT_STATE_CHANGED,
    STATE_UNAVAILABLE,
)
from homeassistant.core import Event, EventStateChangedData, HomeAssistant, callback
from homeassistant.helpers import device_registry as dr, entity_registry as er
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.tecoapi.compat import entry_device
from custom_components.tecoapi.connection import create_source
from custom_components.tecoapi.const import (
    CONF_DEVICES,
    CONF_EXCLUDE,
    CONF_INCLUDE,
    CONF_PLAIN_VARIABLES,
    DOMAIN,
    DeviceGrouping,
    PlainVariables,
)
from custom_components.tecoapi.options import PlcOptions
from custom_components.tecoapi.pyplc import PlcConnectionError
from custom_components.tecoapi.pyplc.tecomat import PushedTecoApiSession, TecoApiSession
from tests.components.tecoapi.conftest import entity_id_of, setup_entry
from tests.components.tecoapi.test_init_push import coms  # noqa: F401 (a fixture)
from tests.simulator import Simulator
from tests.simulator.plccoms import PlcComsServer

SERIAL = "SD 2080"


@dataclass
class StateChanges:
    """The state changes of every entity: what a logbook would list."""

    appeared: set[str] = field(default_factory=set)
    gone: set[str] = field(default_factory=set)
    unavailable: set[str] = field(default_factory=set)
    changed: set[str] = field(default_factory=set)

    def untouched(self, kept: set[str]) -> set[str]:
        """The entities among ``kept`` that changed state or went unavailable."""
        return (self.changed | self.unavailable) & kept

    def clear(self) -> None:
        """Forget what was seen."""
        for seen in (self.appeared, self.gone, self.unavailable, self.changed):
            seen.clear()


@pytest.fixture
def state_changes(hass: HomeAssistant) -> Iterator[StateChanges]:
    """Record state changes: entities that appear, go, change or go unavailable."""
    seen = StateChanges()

    @callback
    def record(event: Event[EventStateChangedData]) -> None:
        old, new = event.data["old_state"], event.data["new_state"]
        entity_id = event.data["entity_id"]
        if old is None:
            seen.appeared.add(entity_id)
        elif new is None:
            seen.gone.add(entity_id)
        elif new.state == old.state:
            return  # a new name or device: no logbook line
        elif new.state == STATE_UNAVAILABLE:
            seen.unavailable.add(entity_id)
        else:
            seen.changed.add(entity_id)

    unsubscribe = hass.bus.async_listen(EVENT_STATE_CHANGED, record)
    yield seen
    unsubscribe()


def shown(hass: HomeAssistant) -> set[str]:
    """Every entity with a state now."""
    return set(hass.states.async_entity_ids())


async def set_options(
    hass: HomeAssistant, entry: MockConfigEntry, **changes: Any
) -> None:
    """Store new options, as the options flow does; wait for what follows."""
    hass.config_entries.async_update_entry(
        entry, options={**PlcOptions().as_dict(), **entry.options, **changes}
    )
    await hass.async_block_till_done(wait_background_tasks=True)


async def test_filters_apply_in_place(
    hass: HomeAssistant,
    demo_entry: MockConfigEntry,
    state_changes: StateChanges,
) -> None:
    """Excluding variables removes their entities; no other entity changes.

    Including them again brings them back (their values read at once), again
    without touching the others.
    """
    coordinator = demo_entry.runtime_data
    before = shown(hass)
    energy = {
        entity_id
        for entity_id in before
        if (entry := er.async_get(hass).async_get(entity_id)) is not None
        and entry.unique_id.startswith(f"{SERIAL}_energy.")
    }
    assert len(energy) == 5

    await set_options(hass, demo_entry, **{CONF_EXCLUDE: ["energy.*"]})

    assert demo_entry.runtime_data is coordinator
    assert demo_entry.state is ConfigEntryState.LOADED
    assert shown(hass) == before - energy
    assert state_changes.untouched(before - energy) == set()
    assert state_changes.gone == energy

    state_changes.clear()
    await set_options(hass, demo_entry, **{CONF_EXCLUDE: []})

    assert shown(hass) == before
    assert state_changes.appeared == energy
    assert state_changes.untouched(before - energy) == set()
    power = entity_id_of(hass, "sensor", f"{SERIAL}_energy.powernow")
    assert hass.states.get(power).state == "1432.0"


async def test_plain_variables_and_includes_apply_in_place(
    hass: HomeAssistant,
    demo_entry: MockConfigEntry,
    state_changes: StateChanges,
) -> None:
    """Plain variables ignored, then only some included: nothing else blinks."""
    before = shown(hass)

    await set_options(
        hass, demo_entry, **{CONF_PLAIN_VARIABLES: PlainVariables.IGNORED}
    )
    await set_options(hass, demo_entry, **{CONF_INCLUDE: ["heating.*", "rooms.*"]})

    kept = shown(hass)
    assert kept
    assert kept < before
    assert state_changes.untouched(kept) == set()
    assert state_changes.appeared == set()


async def test_devices_apply_in_place(
    hass: HomeAssistant,
    demo_entry: MockConfigEntry,
    state_changes: StateChanges,
) -> None:
    """Everything on the PLC's device: entities move, keep their IDs and states."""
    registry = er.async_get(hass)
    before = shown(hass)
    boiler = entity_id_of(hass, "switch", f"{SERIAL}_heating.boileron")
    plc = entry_device(hass, demo_entry.entry_id, identifier=(DOMAIN, SERIAL))
    assert plc is not None
    assert registry.async_get(boiler).device_id != plc.id

    await set_options(hass, demo_entry, **{CONF_DEVICES: DeviceGrouping.SINGLE})

    assert shown(hass) == before
    assert state_changes.untouched(before) == set()
    assert registry.async_get(boiler).device_id == plc.id
    # Typed entities too, named by their typed device below the PLC's name.
    button = entity_id_of(hass, "event", f"{SERIAL}_gtsap1:button:dvere_tlacitko")
    light = entity_id_of(hass, "light", f"{SERIAL}_gtsap1:light:obyvak_strop")
    assert registry.async_get(light).device_id == plc.id
    assert hass.states.get(button).name == "Tecomat CP-2080 Tlačítko u dveří"
    assert hass.states.get(light).name == "Tecomat CP-2080 Obývák strop"
    groups = [
        device
        for device in dr.async_entries_for_config_entry(
            dr.async_get(hass), demo_entry.entry_id
        )
        if device.via_device_id == plc.id
        and all(ident.startswith(f"{SERIAL}_") for _, ident in device.identifiers)
        and not any(":" in ident for _, ident in device.identifiers)
    ]
    assert groups == []

    await set_options(hass, demo_entry, **{CONF_DEVICES: DeviceGrouping.GROUPS})

    assert shown(hass) == before
    assert state_changes.untouched(before) == set()
    assert registry.async_get(boiler).device_id != plc.id
    # Devices of their own again, the entity their main feature (no areas here).
    assert registry.async_get(light).device_id != plc.id
    assert hass.states.get(button).name == "Tlačítko u dveří"
    assert hass.states.get(light).name == "Obývák strop"


async def test_adding_a_composed_thermostat_touches_nothing_else(
    hass: HomeAssistant,
    demo_entry: MockConfigEntry,
    state_changes: StateChanges,
) -> None:
    """A new thermostat appears; the PLC's other entities do not blink."""
    coordinator = demo_entry.runtime_data
    before = shown(hass)
    result = await hass.config_entries.subentries.async_init(
        (demo_entry.entry_id, "thermostat"), context={"source": SOURCE_USER}
    )
    await hass.config_entries.subentries.async_configure(
        result["flow_id"],
        {
            "name": "Living room thermostat",
            "temperature": "rooms.livingtemp",
            "setpoint": "heating.livingsetpoint",
        },
    )
    await hass.async_block_till_done(wait_background_tasks=True)

    assert demo_entry.runtime_data is coordinator
    (subentry_id,) = demo_entry.subentries
    climate = entity_id_of(hass, "climate", f"{SERIAL}_composed:{subentry_id}")
    assert shown(hass) == before | {climate}
    assert state_changes.appeared == {climate}
    assert state_changes.untouched(before) == set()
    assert hass.states.get(climate).attributes["current_temperature"] == 21.8

    state_changes.clear()
    hass.config_entries.async_remove_subentry(demo_entry, subentry_id)
    await hass.async_block_till_done(wait_background_tasks=True)

    assert shown(hass) == before
    assert state_changes.untouched(before) == set()


@pytest.mark.usefixtures("simulator")
async def test_switching_push_on_and_off_swaps_the_source_in_place(
    hass: HomeAssistant,
    demo_entry: MockConfigEntry,
    coms: PlcComsServer,  # noqa: F811
    state_changes: StateChanges,
) -> None:
    """Push on: the coordinator reads through PLCComS; the old source is closed.

    No entity goes unavailable; push off again swaps back the same way.
    """
    coordinator = demo_entry.runtime_data
    http = coordinator.source
    before = shown(hass)

    await set_options(
        hass, demo_entry, push={CONF_HOST: "127.0.0.1", CONF_PORT: coms.port}
    )

    assert demo_entry.runtime_data is coordinator
    assert isinstance(coordinator.source, PushedTecoApiSession)
    assert coordinator.last_update_success
    assert shown(hass) == before
    assert state_changes.untouched(before) == set()

    await set_options(hass, demo_entry, push={CONF_HOST: "", CONF_PORT: coms.port})

    assert type(coordinator.source) is TecoApiSession
    assert coordinator.source is not http
    assert coordinator.last_update_success
    assert state_changes.untouched(before) == set()


async def test_a_new_connection_still_reloads(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    """Reconfigure or reauth store a new connection: the entry reloads."""
    coordinator = demo_entry.runtime_data

    hass.config_entries.async_update_entry(
        demo_entry, data={**demo_entry.data, "host": f"{simulator.url}/"}
    )
    await hass.async_block_till_done(wait_background_tasks=True)

    assert demo_entry.state is ConfigEntryState.LOADED
    assert demo_entry.runtime_data is not coordinator


async def test_setup_entry_is_not_needed_for_options(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    """Options of an entry that is not loaded are just stored."""
    entry = MockConfigEntry(
        domain=DOMAIN, data={}, options={}, unique_id=simulator.serial_number
    )
    entry.add_to_hass(hass)

    hass.config_entries.async_update_entry(entry, options={CONF_EXCLUDE: ["x"]})
    await hass.async_block_till_done()

    assert entry.options == {CONF_EXCLUDE: ["x"]}
    assert entry.state is ConfigEntryState.NOT_LOADED


async def test_unchanged_options_change_nothing(
    hass: HomeAssistant,
    demo_entry: MockConfigEntry,
    state_changes: StateChanges,
) -> None:
    """Options stored again as they were: nothing is selected or polled anew."""
    coordinator = demo_entry.runtime_data
    selection = coordinator.data.selection

    await set_options(hass, demo_entry)

    assert coordinator.data.selection is selection
    assert state_changes.untouched(shown(hass)) == set()


async def test_options_of_a_set_up_entry(
    hass: HomeAssistant, simulator: Simulator, config_entry: MockConfigEntry
) -> None:
    """The update listener follows options of an entry set up from scratch too."""
    await setup_entry(hass, config_entry)
    await set_options(hass, config_entry, **{CONF_EXCLUDE: ["heating.*"]})

    assert not any(
        key.startswith("heating.") for key in config_entry.runtime_data.data.points
    )


async def test_a_poll_on_a_source_swapped_meanwhile_asks_the_new_one(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    """A poll under way when push switched on fails with the closed source.

    It is not a failed poll: the new source is asked instead, and the entities
    stay available.
    """
    coordinator = demo_entry.runtime_data
    old = coordinator.source
    new = create_source(hass, demo_entry.data)

    async def swapped_meanwhile(polled: Any) -> Any:
        coordinator.source = new
        await old.close()
        raise PlcConnectionError("closed while reading")

    with patch.object(old, "poll", side_effect=swapped_meanwhile):
        await coordinator.async_refresh()

    assert coordinator.last_update_success
    assert new.statistics.discoveries == 1
