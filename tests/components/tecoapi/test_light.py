"""Lights: GTSAP1 lights of each dimtype, struct dimmers, composed lights, the memory house's.

The demo's lights are driven through Home Assistant and the PLC's variables checked
over real HTTP; the memory house's light through the in-memory source.
"""

from typing import Any

from freezegun.api import FrozenDateTimeFactory
from homeassistant.components.light import ATTR_SUPPORTED_COLOR_MODES
from homeassistant.core import HomeAssistant
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry
from syrupy.assertion import SnapshotAssertion

from custom_components.tecoapi.compat import (
    AREA_IN_ENTITY_ID,
    ATTR_BRIGHTNESS,
    ATTR_COLOR_TEMP_KELVIN,
    ATTR_RGB_COLOR,
)
from tests.components.tecoapi import memory_house
from tests.components.tecoapi.conftest import poll, snapshot_entities
from tests.components.tecoapi.flows.test_subentry import compose, composed_entity
from tests.components.tecoapi.typed import call, typed
from tests.fake_source import MemoryDevice
from tests.simulator import Simulator


@pytest.mark.primary_only
@pytest.mark.parametrize("program_entry", ["demo"], indirect=True)
async def test_lights(
    hass: HomeAssistant, program_entry: MockConfigEntry, snapshot: SnapshotAssertion
) -> None:
    """Every light of the demo: registry entry and state."""
    await snapshot_entities(hass, snapshot, program_entry, "light")


async def test_dimmable_light(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    """GTSAP1 dimtype 0: on/off and brightness; brightness writes the target level."""
    light = typed(hass, "light", "gtsap1:light:obyvak_strop")
    state = hass.states.get(light)
    assert state.state == "on"
    # Its GTSAP1 name, in its room's area without the room where IDs start with it.
    assert state.name == ("Strop" if AREA_IN_ENTITY_ID else "Obývák strop")
    assert state.attributes[ATTR_SUPPORTED_COLOR_MODES] == ["brightness"]
    assert state.attributes[ATTR_BRIGHTNESS] == 153  # 60 %

    await call(hass, "light", "turn_on", entity_id=light, brightness=51)
    assert simulator.get_value("OBYVAK_STROP_GTSAP1_LIGHT_tgtlevel") == 20.0
    assert simulator.get_value("OBYVAK_STROP_GTSAP1_LIGHT_onoff") is True

    await call(hass, "light", "turn_off", entity_id=light)
    assert simulator.get_value("OBYVAK_STROP_GTSAP1_LIGHT_onoff") is False
    assert hass.states.get(light).state == "off"


async def test_rgb_light(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    """GTSAP1 dimtype 1: the colour is written as R + G·256 + B·65536."""
    light = typed(hass, "light", "gtsap1:light:kuchyne_linka")
    assert hass.states.get(light).attributes[ATTR_SUPPORTED_COLOR_MODES] == ["rgb"]

    await call(hass, "light", "turn_on", entity_id=light, rgb_color=(255, 128, 1))

    assert (
        simulator.get_value("KUCHYNE_LINKA_GTSAP1_LIGHT_rgb") == 255 + 128 * 256 + 65536
    )
    assert simulator.get_value("KUCHYNE_LINKA_GTSAP1_LIGHT_onoff") is True
    assert hass.states.get(light).attributes[ATTR_RGB_COLOR] == (255, 128, 1)


async def test_tunable_light(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    """GTSAP1 dimtype 2: colour temperature in kelvin within the block's range."""
    light = typed(hass, "light", "gtsap1:light:loznice")
    state = hass.states.get(light)
    assert state.attributes[ATTR_SUPPORTED_COLOR_MODES] == ["color_temp"]
    low = simulator.get_value("LOZNICE_GTSAP1_LIGHT_minTempK")
    high = simulator.get_value("LOZNICE_GTSAP1_LIGHT_maxTempK")
    assert state.attributes["min_color_temp_kelvin"] == low
    assert state.attributes["max_color_temp_kelvin"] == high

    await call(hass, "light", "turn_on", entity_id=light, color_temp_kelvin=3000)

    assert simulator.get_value("LOZNICE_GTSAP1_LIGHT_colortemp") == 3000
    assert hass.states.get(light).attributes[ATTR_COLOR_TEMP_KELVIN] == 3000


async def test_on_off_light(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    """A light that is not dimmable: on and off only."""
    light = typed(hass, "light", "gtsap1:light:chodba")
    assert hass.states.get(light).attributes[ATTR_SUPPORTED_COLOR_MODES] == ["onoff"]

    await call(hass, "light", "turn_on", entity_id=light)

    assert simulator.get_value("CHODBA_GTSAP1_LIGHT_onoff") is True


async def test_struct_dimmer(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    """Our convention: a dimmer's brightness T_ApiObject is its state and level."""
    light = typed(hass, "light", "struct:light:detskypokoj.light")

    await call(hass, "light", "turn_on", entity_id=light, brightness=255)

    assert simulator.get_value("detskyPokoj.light.brightness.value") == 100
    assert simulator.get_value("detskyPokoj.light.onoff.value") is True
    assert hass.states.get(light).attributes[ATTR_BRIGHTNESS] == 255


@pytest.mark.parametrize(
    ("key", "dark", "level", "expected"),
    [
        # Nothing above zero known: full.
        ("gtsap1:light:kuchyne_linka", {}, "KUCHYNE_LINKA_GTSAP1_LIGHT_dimlevel", 100),
        (
            "gtsap1:light:obyvak_strop",
            {
                "OBYVAK_STROP_GTSAP1_LIGHT_tgtlevel": 0,
                "OBYVAK_STROP_GTSAP1_LIGHT_dimlevel": 0,
            },
            "OBYVAK_STROP_GTSAP1_LIGHT_tgtlevel",
            60,
        ),
        (
            "gtsap1:light:loznice",
            {"LOZNICE_GTSAP1_LIGHT_dimlevel": 0},
            "LOZNICE_GTSAP1_LIGHT_dimlevel",
            35,
        ),
        (
            "struct:light:detskypokoj.light",
            {},
            "detskyPokoj.light.brightness.value",
            100,
        ),
        (
            "struct:light:podkrovi.satnasvetlo",
            {"Podkrovi.satnaSvetlo.brightness.value": 0},
            "Podkrovi.satnaSvetlo.brightness.value",
            80,
        ),
    ],
    ids=["rgb", "dimmer", "tunable", "struct dimmer", "struct tunable"],
)
async def test_switched_on_a_dark_light_returns_to_its_last_level(
    hass: HomeAssistant,
    simulator: Simulator,
    demo_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
    *,
    key: str,
    dark: dict[str, Any],
    level: str,
    expected: int,
) -> None:
    """On from its icon (no brightness): the last level above zero, else full.

    Not on at 0 %: each light is switched off and dark (the PLC set its level to 0),
    then switched on without a brightness.
    """
    light = typed(hass, "light", key)
    await call(hass, "light", "turn_off", entity_id=light)
    for path, value in dark.items():
        simulator.set_value(path, value)
    await poll(hass, freezer)
    state = hass.states.get(light)
    assert state.state == "off"
    assert state.attributes[ATTR_BRIGHTNESS] is None

    await call(hass, "light", "turn_on", entity_id=light)

    assert simulator.get_value(level) == expected
    if level.endswith("_tgtlevel"):
        # Its level follows the target in the PLC: read again a second later.
        simulator.clear_requests()
        await poll(hass, freezer, 1)
        (read,) = simulator.requests
        assert set(read.query.split("&")) == {
            f"OBYVAK_STROP_GTSAP1_LIGHT_{prop}"
            for prop in ("onoff", "dimlevel", "tgtlevel")
        }
    state = hass.states.get(light)
    assert state.state == "on"
    assert state.attributes[ATTR_BRIGHTNESS] == round(expected * 255 / 100)


@pytest.mark.parametrize(
    "roles",
    [{"onoff": "lights[3]", "level": "blinds[3]"}, {"level": "blinds[3]"}],
    ids=["with onoff", "level alone"],
)
async def test_a_composed_dark_light_switched_on_goes_full(
    hass: HomeAssistant,
    simulator: Simulator,
    demo_entry: MockConfigEntry,
    roles: dict[str, str],
) -> None:
    """A composed light at level 0, nothing above zero known: full, not on at 0 %."""
    await compose(hass, demo_entry, "light", {"name": "Study lamp", **roles})
    light = composed_entity(hass, "light", demo_entry)
    assert simulator.get_value("blinds[3].value") == 0
    assert hass.states.get(light).state == "off"

    await call(hass, "light", "turn_on", entity_id=light)

    assert simulator.get_value("blinds[3].value") == 100
    state = hass.states.get(light)
    assert state.state == "on"
    assert state.attributes[ATTR_BRIGHTNESS] == 255


async def test_switched_on_a_bright_light_keeps_its_level(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    """A light off at a level above zero is switched on by ``onoff`` alone."""
    light = typed(hass, "light", "gtsap1:light:obyvak_strop")
    await call(hass, "light", "turn_off", entity_id=light)
    simulator.clear_requests()

    await call(hass, "light", "turn_on", entity_id=light)

    assert simulator.get_value("OBYVAK_STROP_GTSAP1_LIGHT_tgtlevel") == 60
    assert simulator.get_value("OBYVAK_STROP_GTSAP1_LIGHT_onoff") is True
    # One write, of onoff: the level stays.
    writes = [r for r in simulator.requests if r.service in {"SetObject", "PutObject"}]
    assert len(writes) == 1
    assert hass.states.get(light).attributes[ATTR_BRIGHTNESS] == 153


# --- the memory house (memory_house.py): through the in-memory source ---------


async def test_light(hass: HomeAssistant, house: MemoryDevice) -> None:
    key = "gtsap1:light:kitchen"
    assert memory_house.state(hass, "light", key).state == "off"
    await memory_house.call(hass, "light", "turn_on", key, brightness=128)
    assert house.values["k1"] is True
    assert house.values["k4"] == 50
