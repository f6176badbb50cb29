"""Entity IDs and names say each word once; IDs already registered stay.

Home Assistant 2026.10 makes a new entity's ID from its device's area, its
device's name and its own name, and its friendly name from its device's name and
its own. ``light.detsky_pokoj_detsky_pokoj_light`` and "Ventilation Ventilation
filter clogged" said a room or a device twice; Home Assistant's own "recreate
entity IDs" proposed the same.
"""

from collections.abc import Iterator
import json
from pathlib import Path
import re

from homeassistant.core import HomeAssistant
from homeassistant.helpers import (
    area_registry as ar,
    device_registry as dr,
    entity_registry as er,
)
from homeassistant.util import slugify
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.tecoapi.compat import AREA_IN_ENTITY_ID
from custom_components.tecoapi.const import DOMAIN
from custom_components.tecoapi.device_info import ENGLISH_KIND_NAMES, KIND_NAMES
from custom_components.tecoapi.names import (
    Room,
    folded,
    room_of,
    spelled,
    vocabulary,
    without_leading,
)
from tests.components.tecoapi.conftest import entity_id_of, make_entry, setup_entry
from tests.conftest import SIM_PASSWORD, SIM_USERNAME
from tests.simulator import Simulator
from tests.simulator.program import Program, load_program

SERIAL = "SD 2080"


def repeated(words: list[str]) -> list[str]:
    """The word sequences said twice in a row (numbers alone do not count)."""
    found = []
    for size in range(1, len(words) // 2 + 1):
        for start in range(len(words) - 2 * size + 1):
            said = words[start : start + size]
            if said == words[start + size : start + 2 * size] and any(
                not word.isdigit() for word in said
            ):
                found.append(" ".join(said))
    return found


def test_repeated() -> None:
    """The check finds a room or a device said twice, not an array's indexes."""
    assert repeated(["detsky", "pokoj", "detsky", "pokoj", "thermostat"]) == [
        "detsky pokoj"
    ]
    assert repeated(["ventilation", "ventilation", "filter", "clogged"]) == [
        "ventilation"
    ]
    assert repeated(["arr", "3", "arr3", "0", "0", "0"]) == []


def names_of(
    hass: HomeAssistant, entry: MockConfigEntry
) -> Iterator[tuple[er.RegistryEntry, str, str, str | None]]:
    """Each entity with its friendly name, its device's name and its area's name."""
    devices, areas = dr.async_get(hass), ar.async_get(hass)
    for entity in er.async_entries_for_config_entry(er.async_get(hass), entry.entry_id):
        device = devices.async_get(entity.device_id or "")
        assert device is not None, entity.entity_id
        area = areas.async_get_area(device.area_id or "")
        state = hass.states.get(entity.entity_id)
        assert state is not None, entity.entity_id
        yield entity, state.name, device.name or "", area.name if area else None


@pytest.mark.usefixtures("entity_registry_enabled_by_default")
async def test_new_entity_ids_and_names_say_each_word_once(
    hass: HomeAssistant, program_entry: MockConfigEntry
) -> None:
    """Area, device and entity name do not repeat one another, in IDs or names.

    A title that starts with its device's name drops it (*Heating* ·
    *Curve shift*); a device in an area does not say its room again (*Obývák* ·
    *Strop*); a group that is nothing but a room is in no area. Home
    Assistant's own proposal for each ID is the ID it has.
    """
    registry = er.async_get(hass)
    checked = 0
    for entity, friendly, device, area in names_of(hass, program_entry):
        object_id = entity.entity_id.split(".", 1)[1]
        assert repeated(object_id.split("_")) == [], entity.entity_id
        assert repeated(folded(friendly).split()) == [], friendly
        if entity.original_name is not None:
            assert not folded(entity.original_name).startswith(f"{folded(device)} ")
        if area is not None:
            # A device may say its room; the ID says it once all the same.
            assert object_id.count(slugify(area)) <= 1, entity.entity_id
        if hasattr(registry, "async_regenerate_entity_id"):
            assert registry.async_regenerate_entity_id(entity) == entity.entity_id
        checked += 1
    assert checked > 50


@pytest.mark.usefixtures("entity_registry_enabled_by_default")
async def test_the_demo_reads_as_a_house(
    hass: HomeAssistant, demo_entry: MockConfigEntry
) -> None:
    """The demo's lights, thermostats and blinds are in their rooms' areas."""
    expected = {
        ("climate", "struct:climate:detskypokoj.thermostat"): "Dětský pokoj",
        ("light", "struct:light:detskypokoj.light"): "Dětský pokoj",
        ("light", "gtsap1:light:obyvak_strop"): "Obývák",
        ("light", "gtsap1:light:kuchyne_linka"): "Kuchyň",
        ("light", "gtsap1:light:loznice"): "Ložnice",
        ("light", "gtsap1:light:chodba"): "Chodba",
        ("climate", "gtsap1:thermostat:termostaty.pracovna"): "Pracovna",
        ("cover", "gtsap1:opener:stineni.garaz_vrata"): "Garáž",
        ("cover", "struct:cover:podkrovi.stresniokno"): "Podkroví",
    }
    devices, areas = dr.async_get(hass), ar.async_get(hass)
    registry = er.async_get(hass)
    for (domain, key), room in expected.items():
        entity = registry.async_get(entity_id_of(hass, domain, f"{SERIAL}_{key}"))
        assert entity is not None
        device = devices.async_get(entity.device_id or "")
        assert device is not None
        area = areas.async_get_area(device.area_id or "")
        assert area is not None
        assert area.name == room, key
    assert hass.states.get("light.detsky_pokoj_light") is not None
    assert hass.states.get("climate.detsky_pokoj_thermostat") is not None
    assert hass.states.get("light.obyvak_strop") is not None
    assert hass.states.get("number.heating_curve_shift").name == "Heating Curve shift"
    # The energy device's sensors say "energy" once.
    assert hass.states.get("sensor.energy_solar_yield_today").name == (
        "Energy Solar yield today"
    )
    assert (
        hass.states.get("binary_sensor.ventilation_filter_clogged").name
        == "Ventilation Filter clogged"
    )
    # Group names have their accents back; a group that is only a room is in
    # no area where IDs start with the area (its typed devices are).
    group_names = {
        device.name
        for device in dr.async_entries_for_config_entry(devices, demo_entry.entry_id)
    }
    assert {"Stínění", "Dětský pokoj", "Podkroví", "Termostaty"} <= group_names


FAMILY_WORDS = {"light", "thermostat", "blind", "gate", "switch", "sensor", "button"}
"""What a typed device is, in words that say nothing of which one it is."""


@pytest.mark.usefixtures("entity_registry_enabled_by_default")
async def test_the_demo_names_each_typed_device_apart(
    hass: HomeAssistant, demo_entry: MockConfigEntry
) -> None:
    """Seven thermostats and lights are not all *Thermostat* and *Light*.

    A typed device's name says what it is and, where that is what tells it
    apart, its room (*Obývák thermostat*); its entity's ID says the room once
    (``climate.obyvak_thermostat``) and is Home Assistant's own proposal.
    """
    devices = dr.async_get(hass)
    registry = er.async_get(hass)
    names = [
        device.name or ""
        for device in dr.async_entries_for_config_entry(devices, demo_entry.entry_id)
        if any(":" in ident for _, ident in device.identifiers)  # typed: kind:path
    ]
    assert len(names) > 15
    assert len(set(map(folded, names))) == len(names), sorted(names)
    assert not [name for name in names if folded(name) in FAMILY_WORDS]
    assert {
        "Obývák thermostat",
        "Ložnice thermostat",
        "Pracovna thermostat",
        "Dětský pokoj thermostat",
        "Ložnice light",
        "Chodba light",
        "Dětský pokoj light",
        "Dětský pokoj blind",
    } <= set(names)
    expected = {
        "climate.obyvak_thermostat": "Obývák thermostat",
        "climate.detsky_pokoj_thermostat": "Dětský pokoj thermostat",
        "light.loznice_light": "Ložnice light",
        "cover.detsky_pokoj_blind": "Dětský pokoj blind",
        "light.obyvak_strop": "Strop" if AREA_IN_ENTITY_ID else "Obývák strop",
    }
    assert_named(hass, registry, expected)


def assert_named(
    hass: HomeAssistant, registry: er.EntityRegistry, expected: dict[str, str]
) -> None:
    """Each entity ID has its name, and is Home Assistant's own proposal for it."""
    for entity_id, name in expected.items():
        state = hass.states.get(entity_id)
        assert state is not None, entity_id
        assert state.name == name
        entity = registry.async_get(entity_id)
        assert entity is not None
        if hasattr(registry, "async_regenerate_entity_id"):
            assert registry.async_regenerate_entity_id(entity) == entity_id


def demo_with_look_alikes() -> Program:
    """The demo with a second *Strop* (in the kitchen), two groups of no room
    with a thermostat each, and two sockets in neither, both named *Zásuvka*."""
    source = load_program("demo").to_mapping()
    source["variables"] |= {
        "KUCHYNE_STROP_GTSAP1_LIGHT_onoff": {"type": "BOOL", "value": False},
        "KUCHYNE_STROP_GTSAP1_LIGHT_type": {"type": "BOOL", "value": False},
        "KUCHYNE_STROP_GTSAP1_LIGHT_name": {
            "type": "STRING[32]",
            "value": "Kuchyň strop",
        },
        "groundFloor": {"type": "TKidsRoom"},
        "upperFloor": {"type": "TKidsRoom"},
        **{
            f"ZASUVKA_{side}_GTSAP1_SOCKET_{member}": variable
            for side in ("VYCHOD", "ZAPAD")
            for member, variable in (
                ("onoff", {"type": "BOOL", "value": False}),
                ("name", {"type": "STRING[32]", "value": "Zásuvka"}),
            )
        },
    }
    return Program.from_mapping(source)


@pytest.mark.usefixtures("entity_registry_enabled_by_default")
async def test_look_alikes_are_named_by_their_room_or_group(
    hass: HomeAssistant, socket_enabled: None
) -> None:
    """Two *Strop*: each says its room; two *Thermostat* in no room: their group;
    two *Zásuvka* in neither: their own identifiers.

    Their IDs say the room once, and are Home Assistant's own proposals.
    """
    sim = Simulator(
        demo_with_look_alikes(), username=SIM_USERNAME, password=SIM_PASSWORD
    )
    await sim.start()
    try:
        entry = await setup_entry(hass, make_entry(sim))
        expected = {
            "light.obyvak_strop": "Obývák strop",
            "light.kuchyn_strop": "Kuchyň strop",
            "climate.ground_floor_thermostat": "Ground floor thermostat",
            "climate.upper_floor_thermostat": "Upper floor thermostat",
            "light.ground_floor_light": "Ground floor light",
            "switch.zasuvka_vychod": "Zásuvka vychod",
            "switch.zasuvka_zapad": "Zásuvka zapad",
        }
        registry = er.async_get(hass)
        assert_named(hass, registry, expected)
        names = [
            device.name or ""
            for device in dr.async_entries_for_config_entry(
                dr.async_get(hass), entry.entry_id
            )
            if any(":" in ident for _, ident in device.identifiers)
        ]
        assert len(set(map(folded, names))) == len(names), sorted(names)
    finally:
        await sim.stop()


async def test_a_new_entity_of_a_renamed_or_moved_device_takes_home_assistants_id(
    hass: HomeAssistant, simulator: Simulator, config_entry: MockConfigEntry
) -> None:
    """The ID says the room once only where the device is in its room's area.

    A device the user renamed, or moved to another area, before its entity
    came (an earlier version made the device) gets the ID Home Assistant makes
    of its area and name.
    """
    config_entry.add_to_hass(hass)
    devices, areas = dr.async_get(hass), ar.async_get(hass)
    study = areas.async_create("Pracovna")
    bedroom = areas.async_create("Ložnice")
    made_before = {
        "light:chodba": {"area_id": study.id},
        "light:loznice": {"area_id": bedroom.id, "name_by_user": "Lampa"},
        "thermostat:termostaty.pracovna": {"area_id": study.id},
    }
    for key, change in made_before.items():
        device = devices.async_get_or_create(
            config_entry_id=config_entry.entry_id,
            identifiers={(DOMAIN, f"{SERIAL}_gtsap1:{key}")},
            name="Thermostat" if "thermostat" in key else "Light",
        )
        devices.async_update_device(device.id, **change)

    await setup_entry(hass, config_entry)

    made = {
        key: entity_id_of(
            hass,
            key.partition(":")[0].replace("thermostat", "climate"),
            f"{SERIAL}_gtsap1:{key}",
        )
        for key in made_before
    }
    assert made == {
        "light:chodba": (
            "light.pracovna_chodba_light" if AREA_IN_ENTITY_ID else "light.chodba_light"
        ),
        "light:loznice": "light.loznice_lampa" if AREA_IN_ENTITY_ID else "light.lampa",
        # In its room's area, not renamed: the room once, as for a new device.
        "thermostat:termostaty.pracovna": "climate.pracovna_thermostat",
    }


def test_ids_say_the_english_words_of_the_kinds() -> None:
    """The words an entity ID says for a kind are the English device names'."""
    english = json.loads(
        (
            Path(__file__).parents[3] / "custom_components/tecoapi/translations/en.json"
        ).read_text(encoding="utf-8")
    )["device"]
    assert {
        key.removesuffix("_in"): value["name"]
        for key, value in english.items()
        if key.endswith("_in")
    } == {key: f"{{room}} {word.lower()}" for key, word in ENGLISH_KIND_NAMES.items()}
    assert set(ENGLISH_KIND_NAMES) == {*KIND_NAMES.values(), "gate"}


async def test_an_upgrade_renames_the_family_named_devices_the_user_did_not(
    hass: HomeAssistant, simulator: Simulator, config_entry: MockConfigEntry
) -> None:
    """Devices named *Thermostat* by the version before take their room's name.

    One the user renamed keeps the user's name; every entity keeps its ID.
    """
    config_entry.add_to_hass(hass)
    devices, entities = dr.async_get(hass), er.async_get(hass)
    before = {
        "termostaty.obyvak": ("climate.obyvak_thermostat", None),
        "termostaty.loznice": ("climate.loznice_thermostat", "Postel"),
    }
    for key, (entity_id, by_user) in before.items():
        device = devices.async_get_or_create(
            config_entry_id=config_entry.entry_id,
            identifiers={(DOMAIN, f"{SERIAL}_gtsap1:thermostat:{key}")},
            name="Thermostat",
        )
        devices.async_update_device(device.id, name_by_user=by_user)
        entities.async_get_or_create(
            "climate",
            DOMAIN,
            f"{SERIAL}_gtsap1:thermostat:{key}",
            config_entry=config_entry,
            device_id=device.id,
            suggested_object_id=entity_id.split(".")[1] + "_kept",
        )

    await setup_entry(hass, config_entry)

    shown = {}
    for key, (entity_id, _) in before.items():
        kept = entity_id_of(hass, "climate", f"{SERIAL}_gtsap1:thermostat:{key}")
        assert kept == f"{entity_id}_kept"
        device = devices.async_get(entities.async_get(kept).device_id or "")  # type: ignore[union-attr]
        assert device is not None
        shown[key] = (device.name, device.name_by_user, hass.states.get(kept).name)  # type: ignore[union-attr]
    assert shown == {
        "termostaty.obyvak": ("Obývák thermostat", None, "Obývák thermostat"),
        "termostaty.loznice": ("Ložnice thermostat", "Postel", "Postel"),
    }


OLD_IDS = {
    "climate.detsky_pokoj_detsky_pokoj_thermostat": (
        "struct:climate:detskypokoj.thermostat"
    ),
    "light.detsky_pokoj_detsky_pokoj_light": "struct:light:detskypokoj.light",
    "light.tecomat_cp_2080_obyvak_strop": "gtsap1:light:obyvak_strop",
    "binary_sensor.ventilation_ventilation_filter_clogged": (
        "ventilation.filter.clogged"
    ),
    "number.heating_heating_curve_shift": "heating.curveshift",
    "sensor.detsky_pokoj_detsky_pokoj_kids_room_temperature": (
        "detskypokoj.thermostat.temperature"
    ),
}


async def test_an_upgrade_keeps_the_entity_ids_registered(
    hass: HomeAssistant, simulator: Simulator, config_entry: MockConfigEntry
) -> None:
    """Entity IDs an earlier version registered stay, with their unique IDs.

    Only new entities get the new IDs; the old ones keep working under theirs.
    """
    config_entry.add_to_hass(hass)
    registry = er.async_get(hass)
    for entity_id, key in OLD_IDS.items():
        domain, object_id = entity_id.split(".")
        registry.async_get_or_create(
            domain,
            DOMAIN,
            f"{SERIAL}_{key}",
            config_entry=config_entry,
            suggested_object_id=object_id,
        )

    await setup_entry(hass, config_entry)

    for entity_id, key in OLD_IDS.items():
        domain = entity_id.split(".")[0]
        assert entity_id_of(hass, domain, f"{SERIAL}_{key}") == entity_id
        assert hass.states.get(entity_id) is not None, entity_id
    assert hass.states.get("light.detsky_pokoj_light") is None
    # What was not registered before is named anew.
    assert hass.states.get("cover.detsky_pokoj_blind") is not None
    assert not [
        entity.entity_id
        for entity in er.async_entries_for_config_entry(registry, config_entry.entry_id)
        if re.search(r"_\d$", entity.entity_id)
    ]


@pytest.mark.parametrize(
    ("name", "room"),
    [
        ("Obývák strop", ("Obývák", "Strop")),
        ("Kuchyňská linka", ("Kuchyň", "Linka")),
        ("Ložnice", ("Ložnice", "")),
        ("Dětský pokoj", ("Dětský pokoj", "")),
        ("Detsky pokoj", ("Dětský pokoj", "")),
        ("Světlo v ložnici", ("Ložnice", "Světlo")),
        ("Light in the hall", ("Hall", "Light")),
        ("Garážová vrata", ("Garáž", "Vrata")),
        ("Living room thermostat", ("Living room", "Thermostat")),
        ("Kids room light", ("Kids room", "Light")),
        ("Vjezdová brána", None),
        ("Stínění", None),
        ("Rooms", None),
    ],
)
def test_the_room_a_name_says(name: str, room: tuple[str, str] | None) -> None:
    """A room in any case, with or without accents; the rest of the name."""
    assert room_of(name) == (None if room is None else Room(*room))


def test_accents_come_from_the_program_and_the_house() -> None:
    """ASCII words get the accents the program's texts, or a house's words, give."""
    words = vocabulary(["Obývák žaluzie", "Kotel v suterénu"])

    assert spelled("Obyvak zaluzie", words) == "Obývák žaluzie"
    assert spelled("Stineni", words) == "Stínění"
    assert spelled("Detsky pokoj", words) == "Dětský pokoj"
    assert spelled("Suterenu kotel", words) == "Suterénu kotel"
    assert spelled("Heating CO2", words) == "Heating CO2"


@pytest.mark.parametrize(
    ("name", "said", "expected"),
    [
        ("Ventilation filter clogged", ("Ventilation",), "Filter clogged"),
        ("Heating curve shift", ("Heating", None), "Curve shift"),
        ("Kuchyň světla teplota", ("Světla", "Kuchyň"), "Teplota"),
        ("Boiler", ("Boiler",), ""),
        ("Boiler runtime today", ("Heating",), "Boiler runtime today"),
        ("Heatingpump", ("Heating",), "Heatingpump"),
        ("outside temperature", ("Main",), "outside temperature"),
        ("Plant status", ("Heating plant",), "Status"),
        ("Heating", ("Heating plant",), ""),
        ("Heating pump", ("Heating plant",), "Heating pump"),
        ("Plant", ("Heating plant", None), ""),
        ("Room heating plant", ("Heating plant",), "Room heating plant"),
    ],
)
def test_a_name_does_not_say_its_device_again(
    name: str, said: tuple[str | None, ...], expected: str
) -> None:
    """Whole words its device (or area) said before it go; the rest stays as typed.

    Said before: the device's whole name, its last words where the name goes
    on from them (*Heating plant* · *Plant status*), or its first words where
    the name says nothing else (*Heating plant* · *Heating*).
    """
    assert without_leading(name, *said) == expected


async def test_a_room_area_made_before_accents_is_the_rooms_area(
    hass: HomeAssistant, simulator: Simulator, config_entry: MockConfigEntry
) -> None:
    """An area named without accents (an earlier version made it) is used, not doubled."""
    old = ar.async_get(hass).async_create("Detsky pokoj")

    await setup_entry(hass, config_entry)

    entity = er.async_get(hass).async_get("climate.detsky_pokoj_thermostat")
    assert entity is not None
    device = dr.async_get(hass).async_get(entity.device_id or "")
    assert device is not None
    assert device.area_id == old.id
    assert ar.async_get(hass).async_get_area_by_name("Dětský pokoj") is None


async def test_a_device_taken_out_of_its_area_says_its_room(
    hass: HomeAssistant, simulator: Simulator, config_entry: MockConfigEntry
) -> None:
    """Out of the area, nothing says the room: the device's name says it again."""
    await setup_entry(hass, config_entry)
    devices = dr.async_get(hass)
    light = entity_id_of(hass, "light", f"{SERIAL}_gtsap1:light:obyvak_strop")
    device_id = er.async_get(hass).async_get(light).device_id  # type: ignore[union-attr]
    assert device_id is not None
    assert devices.async_get(device_id).area_id is not None  # type: ignore[union-attr]

    devices.async_update_device(device_id, area_id=None)
    await hass.config_entries.async_reload(config_entry.entry_id)
    await hass.async_block_till_done()

    assert devices.async_get(device_id).name == "Obývák strop"  # type: ignore[union-attr]
    assert hass.states.get(light).name == "Obývák strop"
