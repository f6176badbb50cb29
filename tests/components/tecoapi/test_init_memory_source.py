"""A source written in the test suite reaches Home Assistant through the registry alone.

The memory source (``tests/fake_source.py``) is not part of the integration: no
Home Assistant module knows it. Registered, it is offered in the config flow's
first menu; its form (a host and a point map file, uploaded through Home
Assistant's ``file_upload`` over HTTP) comes from its descriptor; the map is
kept in a store beside the entry; and its points become entities that read and
write the device. Declared with a push companion of its own (written here, at
the end), its options have the companion's section, and what the user sets
there reaches the source.
"""

from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from dataclasses import replace
from pathlib import Path
import tempfile
from typing import Any, Final
from unittest.mock import patch
from uuid import uuid4

from freezegun.api import FrozenDateTimeFactory
from homeassistant.config_entries import SOURCE_USER, ConfigEntryState
from homeassistant.const import ATTR_ENTITY_ID, CONF_HOST
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
from homeassistant.exceptions import ServiceValidationError
from homeassistant.helpers import entity_registry as er
from homeassistant.helpers.storage import Store
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry
from pytest_homeassistant_custom_component.typing import ClientSessionGenerator

from custom_components.tecoapi.compat import vol
from custom_components.tecoapi.config_flow import PlcConfigFlow
from custom_components.tecoapi.const import CONF_PUSH, CONF_TRANSPORT, DOMAIN
from custom_components.tecoapi.pyplc import Point, ValueKind
from custom_components.tecoapi.pyplc.core import registry
from custom_components.tecoapi.pyplc.core.descriptor import (
    CONF_POINT_MAP,
    Companion,
    ErrorRule,
    Field,
    FieldKind,
    SourceContext,
    SourceDescriptor,
    SourceOptions,
)
from custom_components.tecoapi.pyplc.core.devices import (
    DeviceKind,
    LightMode,
    Recognised,
    Recogniser,
    Role,
    TypedDevice,
    name_from_base,
)
from custom_components.tecoapi.pyplc.core.exceptions import PlcConnectionError
from custom_components.tecoapi.pyplc.core.pointmap import PointMap
from custom_components.tecoapi.pyplc.core.source import PlcSource
from tests.components.tecoapi.conftest import poll
from tests.components.tecoapi.file_upload import map_field
from tests.components.tecoapi.memory_house import (
    add_house,
    choose,
    entity_ids,
    open_options,
    start_memory_flow,
    upload,
)
from tests.fake_source import (
    DEVICES,
    HOUSE_CSV,
    MEMORY,
    NAME,
    MemoryDevice,
    MemorySource,
    house_device,
    house_map,
    memory_registered,
)


async def test_the_menu_offers_only_registered_sources(hass: HomeAssistant) -> None:
    """Without the registration, the menu has no memory source (the proof's other half)."""
    result = await hass.config_entries.flow.async_init(
        DOMAIN, context={"source": SOURCE_USER}
    )
    assert NAME not in result["menu_options"]
    with memory_registered():
        result = await hass.config_entries.flow.async_init(
            DOMAIN, context={"source": SOURCE_USER}
        )
    assert result["menu_options"][-1] == NAME


async def test_a_registered_source_is_added_and_has_entities(
    hass: HomeAssistant, memory: None, hass_client: ClientSessionGenerator
) -> None:
    result = await start_memory_flow(hass)
    assert result["type"] is FlowResultType.FORM
    assert result["step_id"] == NAME
    assert {str(key) for key in result["data_schema"].schema} == {
        CONF_HOST,
        CONF_POINT_MAP,
    }
    house_device()
    file_id = await upload(hass, hass_client, "house.csv", HOUSE_CSV)
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {CONF_HOST: "MEM-0001", CONF_POINT_MAP: file_id}
    )
    await hass.async_block_till_done()

    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert result["title"] == "M1"
    entry = result["result"]
    assert entry.unique_id == "MEM-0001"
    assert entry.data[CONF_TRANSPORT] == NAME
    assert entry.state is ConfigEntryState.LOADED
    # The map lives in a store of its own; the entry only names it.
    stored = await Store[dict[str, Any]](
        hass, 1, f"{DOMAIN}.point_map.{entry.data[CONF_POINT_MAP]}"
    ).async_load()
    assert stored is not None
    assert len(PointMap.from_json(stored).points) == 26
    ids = entity_ids(hass, entry.entry_id)
    assert hass.states.get(ids["boiler_temp"]).state == "65.2"
    assert hass.states.get(ids["garden_pump"]).state == "on"
    assert hass.states.get(ids["hall_motion"]).attributes["device_class"] == "motion"


async def test_a_registered_source_reads_and_writes_its_device(
    hass: HomeAssistant,
    memory: None,
    hass_client: ClientSessionGenerator,
    freezer: FrozenDateTimeFactory,
) -> None:
    """A change on the device shows at the next poll; a write reaches the device raw."""
    entry = (await add_house(hass, hass_client))["result"]
    device = DEVICES["MEM-0001"]
    ids = entity_ids(hass, entry.entry_id)

    device.values["m3"] = 700
    await poll(hass, freezer)
    assert hass.states.get(ids["boiler_temp"]).state == "70.0"

    await hass.services.async_call(
        "number",
        "set_value",
        {ATTR_ENTITY_ID: ids["boiler_setpoint"], "value": 65.5},
        blocking=True,
    )
    # Shown in tenths on the device: 65.5 °C is 655.
    assert device.values["m4"] == 655
    assert hass.states.get(ids["boiler_setpoint"]).state == "65.5"


async def test_a_map_with_an_error_imports_nothing_and_says_where(
    hass: HomeAssistant, memory: None, hass_client: ClientSessionGenerator
) -> None:
    house_device()
    result = await start_memory_flow(hass)
    broken = HOUSE_CSV.replace("m5,UDINT", "m5,QWORD")
    file_id = await upload(hass, hass_client, "house.csv", broken)
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {CONF_HOST: "MEM-0001", CONF_POINT_MAP: file_id}
    )
    assert result["type"] is FlowResultType.FORM
    assert result["errors"] == {CONF_POINT_MAP: "point_map_invalid"}
    assert result["description_placeholders"]["error"].startswith(
        "row 6, column type: unknown type 'QWORD'"
    )
    assert hass.config_entries.async_entries(DOMAIN) == []


async def test_a_file_of_another_format_is_refused(
    hass: HomeAssistant, memory: None, hass_client: ClientSessionGenerator
) -> None:
    house_device()
    result = await start_memory_flow(hass)
    file_id = await upload(hass, hass_client, "house.vlist", HOUSE_CSV)
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {CONF_HOST: "MEM-0001", CONF_POINT_MAP: file_id}
    )
    assert result["errors"] == {CONF_POINT_MAP: "point_map_invalid"}
    assert result["description_placeholders"]["error"] == "not a .csv file"


async def test_an_upload_that_is_gone_is_asked_for_again(
    hass: HomeAssistant, memory: None, hass_client: ClientSessionGenerator
) -> None:
    house_device()
    result = await start_memory_flow(hass)
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {CONF_HOST: "MEM-0001", CONF_POINT_MAP: uuid4().hex}
    )
    assert result["errors"] == {CONF_POINT_MAP: "point_map_missing"}


@pytest.mark.parametrize(
    ("host", "values", "error"),
    [
        ("MEM-9999", None, "cannot_connect"),
        ("MEM-0001", {"x1": 1}, "no_public_variables"),
    ],
)
@pytest.mark.usefixtures("memory")
async def test_the_descriptor_maps_failures_to_form_errors(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    host: str,
    values: dict[str, Any] | None,
    error: str,
) -> None:
    """No device at the host; a device that has none of the map's points."""
    device = house_device()
    if values is not None:
        device.values = values
    result = await start_memory_flow(hass)
    file_id = await upload(hass, hass_client, "house.csv", HOUSE_CSV)
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {CONF_HOST: host, CONF_POINT_MAP: file_id}
    )
    assert result["errors"] == {"base": error}


async def test_removing_the_entry_removes_its_map(
    hass: HomeAssistant, memory: None, hass_client: ClientSessionGenerator
) -> None:
    """The entry's stores go with it: its map, its points' overrides, its source's
    cache (the test storage only records the removal)."""
    entry = (await add_house(hass, hass_client))["result"]
    removed: list[str] = []
    original = Store.async_remove

    async def remove(store: Store[Any]) -> None:
        removed.append(store.key)
        await original(store)

    with patch.object(Store, "async_remove", remove):
        await hass.config_entries.async_remove(entry.entry_id)
        await hass.async_block_till_done()
    assert removed == [
        f"{DOMAIN}.point_map.{entry.data[CONF_POINT_MAP]}",
        f"{DOMAIN}.overrides.{entry.entry_id}",
        f"{DOMAIN}.source_cache.{entry.entry_id}",
    ]


async def test_an_entry_whose_map_is_lost_does_not_load(
    hass: HomeAssistant, memory: None, hass_client: ClientSessionGenerator
) -> None:
    """A store removed behind Home Assistant's back: a clear error, not a crash."""
    entry = (await add_house(hass, hass_client))["result"]
    await hass.config_entries.async_unload(entry.entry_id)
    await Store[dict[str, Any]](
        hass, 1, f"{DOMAIN}.point_map.{entry.data[CONF_POINT_MAP]}"
    ).async_remove()
    await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    assert entry.state is ConfigEntryState.SETUP_ERROR
    assert entry.reason is not None
    assert entry.reason.startswith("The list of points of this entry is missing")


async def test_the_uploaded_file_is_read_once(
    hass: HomeAssistant, memory: None, hass_client: ClientSessionGenerator
) -> None:
    """An upload is read once (file_upload removes it) and kept for its flow's life.

    The form shown again after an error still names the file: submitted again,
    its map is there. Another flow cannot have it.
    """
    house_device()
    result = await start_memory_flow(hass)
    file_id = await upload(hass, hass_client, "house.csv", HOUSE_CSV)
    first = await hass.config_entries.flow.async_configure(
        result["flow_id"], {CONF_HOST: "MEM-9999", CONF_POINT_MAP: file_id}
    )
    assert first["errors"] == {"base": "cannot_connect"}
    other = await start_memory_flow(hass)
    elsewhere = await hass.config_entries.flow.async_configure(
        other["flow_id"], {CONF_HOST: "MEM-0001", CONF_POINT_MAP: file_id}
    )
    assert elsewhere["errors"] == {CONF_POINT_MAP: "point_map_missing"}
    again = await hass.config_entries.flow.async_configure(
        result["flow_id"], {CONF_HOST: "MEM-0001", CONF_POINT_MAP: file_id}
    )
    assert again["type"] is FlowResultType.CREATE_ENTRY


async def test_a_newer_file_read_before_an_error_is_kept_not_shown(
    hass: HomeAssistant, memory: None, hass_client: ClientSessionGenerator
) -> None:
    """The upload form shown again after an error does not suggest the file.

    Home Assistant's file selector names only a file it uploaded itself (another
    is an "Unknown file", issue 39): the field is empty, optional once a map was
    read, and left empty the map read before is used. A file that could not be
    read is not kept: the field stays required.
    """
    entry = (await add_house(hass, hass_client))["result"]
    device = DEVICES["MEM-0001"]
    options = hass.config_entries.options
    result = await choose(hass, await open_options(hass, entry.entry_id), "upload")
    assert map_field(result) == (vol.Required, None)
    unreadable = await upload(hass, hass_client, "house.csv", "name,address\nx,y\n")
    result = await options.async_configure(
        result["flow_id"], {CONF_POINT_MAP: unreadable}
    )
    assert result["errors"] == {CONF_POINT_MAP: "point_map_invalid"}
    assert map_field(result) == (vol.Required, None)
    device.values["m14"] = 48.5
    device.fail = PlcConnectionError("gone")
    newer = HOUSE_CSV + "hot_water,Hot water,m14,REAL,,°C,,,no,,,,Boiler,,,\n"
    file_id = await upload(hass, hass_client, "house.csv", newer)
    result = await options.async_configure(result["flow_id"], {CONF_POINT_MAP: file_id})
    assert result["errors"] == {"base": "cannot_connect"}
    assert map_field(result) == (vol.Optional, None)
    device.fail = None
    result = await options.async_configure(result["flow_id"], {})
    await hass.async_block_till_done()
    assert result["type"] is FlowResultType.CREATE_ENTRY
    hot_water = entity_ids(hass, entry.entry_id)["hot_water"]
    assert hass.states.get(hot_water).state == "48.5"


async def test_settings_of_a_map_source_are_its_menu_s_first_choice(
    hass: HomeAssistant, memory: None, hass_client: ClientSessionGenerator
) -> None:
    entry = (await add_house(hass, hass_client))["result"]
    result = await choose(hass, await open_options(hass, entry.entry_id), "settings")
    assert result["step_id"] == "settings"
    fields = {str(key) for key in result["data_schema"].schema}
    # No attribute cadence, no plain variables, no push: the source has none.
    assert fields == {"scan_interval", "include", "exclude", "devices"}
    result = await hass.config_entries.options.async_configure(
        result["flow_id"],
        {"scan_interval": 30, "devices": "groups", "exclude": ["runtime"]},
    )
    assert result["type"] is FlowResultType.CREATE_ENTRY
    await hass.async_block_till_done()
    assert "runtime" not in entity_ids(hass, entry.entry_id)


def test_a_step_no_source_has_is_no_step() -> None:
    """The flow answers the steps of its sources' forms only."""
    flow = PlcConfigFlow()
    with pytest.raises(AttributeError):
        _ = flow.async_step_no_such_source
    with pytest.raises(AttributeError):
        _ = flow.no_such_thing


async def test_an_entry_of_a_source_this_version_lacks_says_so(
    hass: HomeAssistant,
) -> None:
    entry = MockConfigEntry(
        domain=DOMAIN,
        title="Future",
        unique_id="F-1",
        data={CONF_HOST: "x", CONF_TRANSPORT: "from_the_future"},
    )
    entry.add_to_hass(hass)
    await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    assert entry.state is ConfigEntryState.SETUP_ERROR
    assert entry.reason is not None
    assert "from_the_future" in entry.reason


async def test_the_variable_actions_refuse_a_source_without_paths(
    hass: HomeAssistant, memory: None, hass_client: ClientSessionGenerator
) -> None:
    entry = (await add_house(hass, hass_client))["result"]
    with pytest.raises(ServiceValidationError) as raised:
        await hass.services.async_call(
            DOMAIN,
            "read_variable",
            {"config_entry_id": entry.entry_id, "path": "m1"},
            blocking=True,
            return_response=True,
        )
    assert raised.value.translation_key == "paths_not_supported"


# --- a push companion of the memory source's own ----------------------------------
#
# A memory device may have a push server beside it: reached by the device's name
# (its host) on a channel. Nothing of it is anywhere but here.

CHANNEL: Final = "channel"
CREATED: list[SourceOptions] = []
"""What each memory source made with the companion was told, in order."""


def _push_alone(
    context: SourceContext, connection: Mapping[str, Any], options: SourceOptions
) -> PlcSource:
    """The push server alone (the options check it): the device its host names."""
    gone = MemoryDevice(fail=PlcConnectionError(f"No push at {connection[CONF_HOST]}"))
    device = DEVICES.get(connection[CONF_HOST], gone)
    return MemorySource(device, house_map(), clock=context.clock)


def _create_noting(
    context: SourceContext, data: Mapping[str, Any], options: SourceOptions
) -> PlcSource:
    """The memory source, its options noted."""
    CREATED.append(options)
    return MEMORY.create(context, data, options)


MEMORY_PUSH: Final = Companion(
    title="Memory push",
    fields=(
        Field(key=CONF_HOST, kind=FieldKind.TEXT, required=False),
        Field(key=CHANNEL, kind=FieldKind.TEXT, default="changes"),
    ),
    create=_push_alone,
    errors=(ErrorRule(error=PlcConnectionError, key="memory_push_cannot_connect"),),
    other_device="memory_push_other_device",
)


@pytest.fixture
def memory_with_push(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> Iterator[list[SourceOptions]]:
    """The memory source with its push companion, offered while the test runs."""
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    descriptor = replace(
        MEMORY,
        create=_create_noting,
        companion=MEMORY_PUSH,
    )
    unregister = registry.register(descriptor)
    try:
        yield CREATED
    finally:
        unregister()
        DEVICES.clear()
        CREATED.clear()


def push_section(result: Mapping[str, Any]) -> tuple[bool, dict[str, Any]]:
    """Whether the settings form's push section is folded, and what it suggests."""
    section = result["data_schema"].schema[CONF_PUSH]
    return section.options["collapsed"], {
        str(key): (key.description or {}).get("suggested_value")
        for key in section.schema.schema
    }


async def submit_settings(
    hass: HomeAssistant, entry_id: str, push: dict[str, Any]
) -> Any:
    """Submit the settings form with these push settings."""
    result = await choose(hass, await open_options(hass, entry_id), "settings")
    return await hass.config_entries.options.async_configure(
        result["flow_id"],
        {"scan_interval": 5, "devices": "groups", CONF_PUSH: push},
    )


async def test_a_source_s_own_companion_has_its_section_and_reaches_the_source(
    hass: HomeAssistant,
    memory_with_push: list[SourceOptions],
    hass_client: ClientSessionGenerator,
) -> None:
    """Its fields, folded while off; checked; its settings reach the source in place.

    A new entry's push is off (its source is told none); a host the check
    cannot reach is the section's error, nothing stored; one it reaches is
    stored under ``push`` and a new source is told it, without a reload; an
    empty host switches it off again.
    """
    entry = (await add_house(hass, hass_client))["result"]
    coordinator = entry.runtime_data
    # The flow's check, then the entry's source: neither is told of push.
    assert [options.companion for options in memory_with_push] == [None, None]
    assert CONF_PUSH not in entry.options

    result = await choose(hass, await open_options(hass, entry.entry_id), "settings")
    assert push_section(result) == (True, {CONF_HOST: "", CHANNEL: "changes"})

    refused = await submit_settings(
        hass, entry.entry_id, {CONF_HOST: "MEM-9999", CHANNEL: "fast"}
    )
    assert refused["errors"] == {CONF_PUSH: "memory_push_cannot_connect"}
    assert push_section(refused) == (False, {CONF_HOST: "MEM-9999", CHANNEL: "fast"})
    assert CONF_PUSH not in entry.options

    result = await submit_settings(
        hass, entry.entry_id, {CONF_HOST: " MEM-0001 ", CHANNEL: "fast"}
    )
    await hass.async_block_till_done()
    assert result["type"] is FlowResultType.CREATE_ENTRY
    settings = {CONF_HOST: "MEM-0001", CHANNEL: "fast"}
    assert entry.options[CONF_PUSH] == settings
    assert entry.runtime_data is coordinator  # in place: no reload
    assert memory_with_push[-1].companion == settings
    assert coordinator.source.point_map == memory_with_push[-1].point_map

    result = await choose(hass, await open_options(hass, entry.entry_id), "settings")
    assert push_section(result) == (False, settings)
    await submit_settings(hass, entry.entry_id, {CONF_HOST: "", CHANNEL: "fast"})
    await hass.async_block_till_done()
    assert entry.options[CONF_PUSH] == {CONF_HOST: "", CHANNEL: "fast"}
    assert memory_with_push[-1].companion is None


# --- a convention of its own: typed devices through its descriptor alone -------

LAMP: Final = "lamp"
LAMP_CSV: Final = HOUSE_CSV + "porch_lamp,Porch lamp,m20,BOOL,,,,,yes,,,,,,,\n"
"""The house, with a point the memory source's own convention makes a lamp."""


def find_lamps(
    points: Mapping[str, Point], values: Mapping[str, Any], taken: frozenset[str]
) -> Recognised:
    """The memory source's own convention: a flag whose ID ends in ``_lamp`` is a lamp.

    An on/off light named by the rest of the ID (``porch_lamp``: *Porch*), its
    key ``lamp:<rest>``.
    """
    lamps = (
        (key.removesuffix("_lamp"), point)
        for key, point in points.items()
        if key.endswith("_lamp") and key not in taken and point.kind is ValueKind.BOOL
    )
    return Recognised(
        devices=tuple(
            TypedDevice(
                key=f"{LAMP}:{rest}",
                kind=DeviceKind.LIGHT,
                source=LAMP,
                base=point.path,
                name=name_from_base(rest),
                roles={Role.ONOFF: point.key},
                light_mode=LightMode.ONOFF,
            )
            for rest, point in lamps
        )
    )


LAMPS: Final = Recogniser(name=LAMP, find=find_lamps)


@contextmanager
def offered(descriptor: SourceDescriptor) -> Iterator[None]:
    """Offer a descriptor of the memory source's name while the block runs."""
    unregister = registry.register(descriptor)
    try:
        yield
    finally:
        unregister()
        DEVICES.clear()


async def add_lamp_house(
    hass: HomeAssistant, hass_client: ClientSessionGenerator
) -> MemoryDevice:
    """Add the house with its lamp through the config flow, as a user would."""
    device = house_device()
    device.values["m20"] = False
    result = await start_memory_flow(hass)
    file_id = await upload(hass, hass_client, "house.csv", LAMP_CSV)
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {CONF_HOST: "MEM-0001", CONF_POINT_MAP: file_id}
    )
    await hass.async_block_till_done()
    assert result["type"] is FlowResultType.CREATE_ENTRY
    return device


@pytest.mark.usefixtures("uploads")
async def test_a_registered_source_brings_a_recogniser_of_its_own(
    hass: HomeAssistant, hass_client: ClientSessionGenerator
) -> None:
    """Its descriptor registers its convention; its typed device is a light.

    Nothing of the integration knows the convention: the light reads and
    writes the device, its point is the device's (shown disabled, as every
    typed device's), and the conventions it registered before still count.
    """
    own = replace(MEMORY, recognisers=(*MEMORY.recognisers, LAMPS))
    with offered(own):
        device = await add_lamp_house(hass, hass_client)
        entities = er.async_get(hass)
        lamp = entities.async_get_entity_id("light", DOMAIN, "MEM-0001_lamp:porch")
        assert lamp is not None
        state = hass.states.get(lamp)
        assert state is not None
        assert state.state == "off"
        assert state.attributes["supported_color_modes"] == ["onoff"]
        await hass.services.async_call(
            "light", "turn_on", {ATTR_ENTITY_ID: lamp}, blocking=True
        )
        assert device.values["m20"] is True
        assert hass.states.get(lamp).state == "on"  # type: ignore[union-attr]

        plain = entities.async_get_entity_id("switch", DOMAIN, "MEM-0001_porch_lamp")
        assert plain is not None
        entry = entities.async_get(plain)
        assert entry is not None
        assert entry.disabled_by is er.RegistryEntryDisabler.INTEGRATION
        kitchen = "MEM-0001_gtsap1:light:kitchen"
        assert entities.async_get_entity_id("light", DOMAIN, kitchen) is not None


@pytest.mark.usefixtures("uploads")
async def test_without_its_recogniser_the_lamp_is_a_plain_switch(
    hass: HomeAssistant, hass_client: ClientSessionGenerator
) -> None:
    """The other half of the proof: the same house, the descriptor without it."""
    with offered(MEMORY):
        await add_lamp_house(hass, hass_client)
        entities = er.async_get(hass)
        lamp = entities.async_get_entity_id("light", DOMAIN, "MEM-0001_lamp:porch")
        assert lamp is None
        plain = entities.async_get_entity_id("switch", DOMAIN, "MEM-0001_porch_lamp")
        assert plain is not None
        assert hass.states.get(plain).state == "off"  # type: ignore[union-attr]
