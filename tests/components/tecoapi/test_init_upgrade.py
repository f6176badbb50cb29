"""Installations upgraded: every entity, its ID, its customisation and the options stay.

``fixtures/registry_0_2.json`` is what version 0.2 (commit 922450a) stored for
the demo PLC with options a user had set: the config entry's version and
options, and the entity registry (unique ID and entity ID of all 168
entities). The entry is stored here as 0.2 left it -- its data without a
``transport`` (a TecoApi entry never had one), its registry entries with their
IDs -- and set up by this version.

Entries of version 1.1 (0.2's and 0.3's) kept the push server's settings at
the top level of their options (``plccoms_host``, ``plccoms_port``); 1.2 keeps
them in one mapping (``push``) and, in step, where 1.1 reads them: the entry is
migrated, its push server kept. Going back to 0.3 and forth keeps push as the
user left it, whatever 0.3's options changed (0.3.0 is commit 5b5de6a: its
``options.py`` reads and its options form writes the legacy keys only).

A Mervis entry added before two units of one project could be added keeps the
identity ``Mervis <project>`` it was added with, and its entities; one added
from a real export keeps its array elements' IDs (``in.[1]``) and its identity
(named after a library) through later uploads.
"""

from collections.abc import Mapping
from dataclasses import replace
import json
from pathlib import Path
import tempfile
from typing import Any, Final

from homeassistant.config_entries import ConfigEntryState
from homeassistant.const import (
    CONF_HOST,
    CONF_PASSWORD,
    CONF_PORT,
    CONF_USERNAME,
    CONF_VERIFY_SSL,
    STATE_UNAVAILABLE,
)
from homeassistant.core import DOMAIN as HOMEASSISTANT_DOMAIN, HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
from homeassistant.helpers import (
    area_registry as ar,
    entity_registry as er,
    issue_registry as ir,
)
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry
from pytest_homeassistant_custom_component.typing import ClientSessionGenerator

from custom_components.tecoapi.const import (
    CONF_EXCLUDE,
    CONF_PUSH,
    CONF_TRANSPORT,
    DOMAIN,
)
from custom_components.tecoapi.point_maps import async_save_point_map
from custom_components.tecoapi.pyplc.core.descriptor import CONF_POINT_MAP
from custom_components.tecoapi.pyplc.core.pointmap import PointMap
from custom_components.tecoapi.pyplc.mervis.descriptor import DEFAULT_EXCLUDE
from custom_components.tecoapi.pyplc.mervis.vlist import load_vlist
from custom_components.tecoapi.pyplc.tecomat import PushedTecoApiSession
from tests.components.tecoapi.conftest import add_tecoapi, entry_data, open_settings
from tests.components.tecoapi.mervis_house import PASSWORD, USER, add, upload_newer
from tests.components.tecoapi.overridden import as_stored, change_point, open_step
from tests.simulator import Simulator
from tests.simulator.mervis import (
    HOUSE_NAME,
    SOLUTION_NAME,
    MervisSimulator,
    house,
    solution,
)
from tests.simulator.plccoms import PlcComsServer

STORED: Final[dict[str, Any]] = json.loads(
    (Path(__file__).parent / "fixtures" / "registry_0_2.json").read_text("utf-8")
)


def stored_entry(
    hass: HomeAssistant,
    simulator: Simulator,
    options: dict[str, Any] | None = None,
    *,
    version: tuple[int, int] | None = None,
) -> MockConfigEntry:
    """The entry and the registry entries 0.2 stored, for the simulated PLC.

    ``options`` and ``version`` stand for those stored, as another release left them.
    """
    major, minor = version or (STORED["version"], STORED["minor_version"])
    entry = MockConfigEntry(
        domain=DOMAIN,
        title=STORED["title"],
        unique_id=STORED["unique_id"],
        data=entry_data(simulator),
        options=STORED["options"] if options is None else options,
        version=major,
        minor_version=minor,
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
            original_name=item["original_name"],
        )
    return entry


LEGACY: Final = ("plccoms_host", "plccoms_port")
"""Where 0.3 (entry version 1.1) reads and writes a push server's host and port."""
OPTIONS_0_3: Final = (
    "scan_interval",
    "attribute_interval",
    "plain_variables",
    "include",
    "exclude",
    "devices",
    *LEGACY,
)
"""What 0.3's options form stores: these keys, and nothing else (``push`` dropped)."""


def migrated(options: dict[str, Any]) -> dict[str, Any]:
    """Options of version 1.1 as 1.2 stores them, spelt out: push in both places."""
    push = {CONF_HOST: options["plccoms_host"], CONF_PORT: options["plccoms_port"]}
    return {**options, CONF_PUSH: push}


def written_by_0_3(options: Mapping[str, Any], **changed: Any) -> dict[str, Any]:
    """The options 0.3's options form stores after a downgrade, ``changed`` there.

    0.3 reads the form's defaults from the legacy keys (so push shows as this
    release left it) and stores its own keys only.
    """
    return {key: options[key] for key in OPTIONS_0_3} | changed


def assert_every_entity_kept(hass: HomeAssistant, entry: MockConfigEntry) -> None:
    """Every entity 0.2 registered has the entry's, with its unique ID and entity ID."""
    kept = {
        item.unique_id: item.entity_id
        for item in er.async_entries_for_config_entry(
            er.async_get(hass), entry.entry_id
        )
    }
    assert {
        item["unique_id"]: kept.get(item["unique_id"], "(gone)")
        for item in STORED["entities"]
    } == {item["unique_id"]: item["entity_id"] for item in STORED["entities"]}


async def test_an_entry_of_0_2_keeps_every_entity_and_its_options(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    data = entry_data(simulator)
    entry = stored_entry(hass, simulator)
    registry = er.async_get(hass)
    outside = "sensor.tecomat_cp_2080_outside_temperature"
    registry.async_update_entity(outside, name="Venku", icon="mdi:home-thermometer")

    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()

    assert entry.state is ConfigEntryState.LOADED
    assert dict(entry.data) == data
    assert CONF_TRANSPORT not in entry.data
    assert dict(entry.options) == migrated(STORED["options"])
    assert (entry.version, entry.minor_version) == (1, 2)
    options = entry.runtime_data.options
    assert (options.scan_interval.seconds, options.attribute_interval.seconds) == (
        10,
        120,
    )
    assert options.exclude == ("installernote",)
    assert options.push_server is None  # push off, as it was
    assert_every_entity_kept(hass, entry)
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


async def test_an_entry_of_1_1_with_push_on_keeps_its_push_server(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    """The push server named at the top level of 1.1's options pushes after the upgrade.

    The entry reads through it at once, shows it in its options (unfolded),
    and keeps every entity and every other option.
    """
    async with PlcComsServer(simulator, scan_interval=None) as coms:
        options = {
            **STORED["options"],
            "plccoms_host": "127.0.0.1",
            "plccoms_port": coms.port,
        }
        entry = stored_entry(hass, simulator, options)

        assert await hass.config_entries.async_setup(entry.entry_id)
        await hass.async_block_till_done()

        assert entry.state is ConfigEntryState.LOADED
        assert dict(entry.options) == migrated(options)
        assert entry.options[CONF_PUSH] == {
            CONF_HOST: "127.0.0.1",
            CONF_PORT: coms.port,
        }
        assert isinstance(entry.runtime_data.source, PushedTecoApiSession)
        assert_every_entity_kept(hass, entry)
        result = await open_settings(hass, entry.entry_id)
        assert result["type"] is FlowResultType.FORM
        push = result["data_schema"].schema[CONF_PUSH]
        assert push.options == {"collapsed": False}
        assert {
            str(key): (key.description or {}).get("suggested_value")
            for key in push.schema.schema
        } == {CONF_HOST: "127.0.0.1", CONF_PORT: coms.port}
        hass.config_entries.options.async_abort(result["flow_id"])
        await hass.config_entries.async_unload(entry.entry_id)


async def start(hass: HomeAssistant, entry: MockConfigEntry) -> None:
    """Start this release on an entry as it is stored."""
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    assert entry.state is ConfigEntryState.LOADED


@pytest.mark.parametrize(
    ("before", "in_0_3"),
    [
        pytest.param("on", None, id="push on, 0.3 changed nothing"),
        pytest.param("on", "off", id="push on, switched off in 0.3"),
        pytest.param("off", "on", id="push off, switched on in 0.3"),
        pytest.param("on", "moved", id="push on, moved to another server in 0.3"),
    ],
)
async def test_going_back_to_0_3_and_forth_keeps_push_as_the_user_left_it(
    hass: HomeAssistant, simulator: Simulator, before: str, in_0_3: str | None
) -> None:
    """0.3 -> this release -> 0.3 (its options changed or not) -> this release.

    After the first upgrade 0.3 still finds push where it reads it; after the
    second, push is what the user left in 0.3 (the entry is at 1.2 already, so
    no migration runs: the start reads back what 0.3 wrote), and the options
    keep both places in step for the next downgrade.
    """
    async with (
        PlcComsServer(simulator, scan_interval=None) as coms,
        PlcComsServer(simulator, scan_interval=None) as other,
    ):
        settings = {
            "on": {"plccoms_host": "127.0.0.1", "plccoms_port": coms.port},
            "off": {"plccoms_host": "", "plccoms_port": 5010},
            "moved": {"plccoms_host": "localhost", "plccoms_port": other.port},
        }
        entry = stored_entry(hass, simulator, STORED["options"] | settings[before])

        await start(hass, entry)  # the upgrade from 0.3
        assert (entry.version, entry.minor_version) == (1, 2)
        upgraded = dict(entry.options)
        # What 0.3 reads after a downgrade: push as it was.
        assert {key: upgraded[key] for key in LEGACY} == settings[before]
        assert await hass.config_entries.async_unload(entry.entry_id)

        # Back in 0.3: its options form stores its own keys (push dropped).
        left = settings[in_0_3 or before]
        hass.config_entries.async_update_entry(
            entry,
            options=upgraded
            if in_0_3 is None
            else written_by_0_3(upgraded, **settings[in_0_3]),
        )
        await start(hass, entry)  # the upgrade again

        push = {CONF_HOST: left["plccoms_host"], CONF_PORT: left["plccoms_port"]}
        pushing = bool(push[CONF_HOST])
        assert (entry.version, entry.minor_version) == (1, 2)
        assert entry.options[CONF_PUSH] == push
        assert {key: entry.options[key] for key in LEGACY} == left
        assert entry.runtime_data.options.push_server == (push if pushing else None)
        assert isinstance(entry.runtime_data.source, PushedTecoApiSession) is pushing
        # Every other option as the user set it.
        assert {key: entry.options[key] for key in OPTIONS_0_3[:-2]} == {
            key: STORED["options"][key] for key in OPTIONS_0_3[:-2]
        }
        assert_every_entity_kept(hass, entry)
        assert await hass.config_entries.async_unload(entry.entry_id)


async def test_an_entry_this_release_stores_is_one_0_3_reads(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    """An entry added and changed by this release, as 0.3 (commit 5b5de6a) reads it.

    0.3 has no migration handler, so Home Assistant loads an entry of the same
    major version (1.2) as it is; it reads the connection from the data (a
    TecoApi entry: host, username, password, verify_ssl; no transport) and
    its options by its own keys, push from ``plccoms_host``/``plccoms_port``.
    """
    async with PlcComsServer(simulator, scan_interval=None) as coms:
        result = await add_tecoapi(hass, simulator.url)
        assert result["type"] is FlowResultType.CREATE_ENTRY
        entry = hass.config_entries.async_get_entry(result["result"].entry_id)
        assert entry is not None
        await hass.async_block_till_done()
        result = await open_settings(hass, entry.entry_id)
        result = await hass.config_entries.options.async_configure(
            result["flow_id"],
            {
                "scan_interval": 7,
                "attribute_interval": 90,
                "plain_variables": "enabled",
                "include": [],
                "exclude": ["*debug*"],
                "devices": "groups",
                CONF_PUSH: {CONF_HOST: "127.0.0.1", CONF_PORT: coms.port},
            },
        )
        assert result["type"] is FlowResultType.CREATE_ENTRY
        await hass.async_block_till_done()

        assert (entry.version, entry.minor_version) == (1, 2)
        assert {CONF_HOST, CONF_USERNAME, CONF_PASSWORD, CONF_VERIFY_SSL} <= set(
            entry.data
        )
        assert CONF_TRANSPORT not in entry.data  # 0.3 takes a TecoApi entry so
        assert {key: entry.options[key] for key in OPTIONS_0_3} == {
            "scan_interval": 7,
            "attribute_interval": 90,
            "plain_variables": "enabled",  # one of 0.3's: disabled, enabled, ignored
            "include": [],
            "exclude": ["*debug*"],
            "devices": "groups",  # one of 0.3's: groups_and_areas, groups, single
            "plccoms_host": "127.0.0.1",
            "plccoms_port": coms.port,
        }
        assert await hass.config_entries.async_unload(entry.entry_id)


async def test_an_entry_of_a_later_minor_version_loads_as_it_is(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    """A newer release's entry of the same major version: nothing is moved."""
    options = {**migrated(STORED["options"]), "from_a_later_release": 1}
    entry = stored_entry(hass, simulator, options, version=(1, 3))
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    assert entry.state is ConfigEntryState.LOADED
    assert (entry.version, entry.minor_version) == (1, 3)
    assert dict(entry.options) == options


async def test_an_entry_of_a_later_major_version_is_not_loaded(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    """A newer release's entry this one cannot read: left as it is, not loaded."""
    entry = stored_entry(hass, simulator, version=(2, 1))
    assert not await hass.config_entries.async_setup(entry.entry_id)
    assert entry.state is ConfigEntryState.MIGRATION_ERROR
    assert dict(entry.options) == STORED["options"]


async def test_a_thermostat_the_user_put_in_an_area_keeps_its_name(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    """0.2 named the thermostat *Obývák*; now it is its device's main feature.

    In an area of its own without a name of its own, Home Assistant (2026.6 and
    later) raises the repair ``entity_own_area_without_own_name``: the name it
    had stays, as the user's. One without an area of its own is named anew.
    """
    entry = stored_entry(hass, simulator)
    registry = er.async_get(hass)
    room = ar.async_get(hass).async_create("Obývák")
    registry.async_update_entity("climate.termostaty_obyvak", area_id=room.id)
    setpoint = "number.heating_bathroom_setpoint"
    registry.async_update_entity(setpoint, area_id=room.id)

    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()

    in_area = registry.async_get("climate.termostaty_obyvak")
    assert in_area is not None
    issue = f"entity_own_area_without_own_name_{in_area.id}"
    assert ir.async_get(hass).async_get_issue(HOMEASSISTANT_DOMAIN, issue) is None
    assert (in_area.name, in_area.original_name, in_area.area_id) == (
        "Obývák",
        None,
        room.id,
    )
    assert hass.states.get(in_area.entity_id) is not None
    # One that still has a name of its own is named by the integration still.
    named = registry.async_get(setpoint)
    assert named is not None
    assert (named.name, named.original_name) == (None, "Bathroom setpoint")
    other = registry.async_get("climate.termostaty_loznice")
    assert other is not None
    assert (other.name, other.original_name) == (None, None)


async def test_a_mervis_entry_keeps_its_identity_and_a_second_unit_is_added_beside(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    socket_enabled: None,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """``Mervis <project>``, as entries were added before: nothing stored changes.

    Another unit running the same project is added beside it, as a new entry
    (``Mervis <project> @ <address>``); the first keeps its address.
    """
    async with (
        MervisSimulator(house(), username=USER, password=PASSWORD) as first,
        MervisSimulator(house(), username=USER, password=PASSWORD) as other,
    ):
        point_map = load_vlist(first.project.vlist())
        map_id = await async_save_point_map(hass, point_map)
        data = {
            CONF_HOST: first.url,
            CONF_USERNAME: USER,
            CONF_PASSWORD: PASSWORD,
            CONF_VERIFY_SSL: True,
            CONF_TRANSPORT: "mervis",
            CONF_POINT_MAP: map_id,
        }
        identity = f"Mervis {HOUSE_NAME}"
        entry = MockConfigEntry(
            domain=DOMAIN,
            title=f"Mervis · {HOUSE_NAME}",
            unique_id=identity,
            data=data,
            options={CONF_EXCLUDE: list(DEFAULT_EXCLUDE)},
        )
        entry.add_to_hass(hass)
        registry = er.async_get(hass)
        outside = registry.async_get_or_create(
            "sensor",
            DOMAIN,
            f"{identity}_outside_temp",
            suggested_object_id="chata_lipno_outside_temp",
            config_entry=entry,
        )
        assert await hass.config_entries.async_setup(entry.entry_id)
        await hass.async_block_till_done()

        assert entry.state is ConfigEntryState.LOADED
        assert (entry.unique_id, dict(entry.data)) == (identity, data)
        assert entry.runtime_data.data.info.identity == identity
        kept = registry.async_get(outside.entity_id)
        assert kept is not None
        assert kept.unique_id == f"{identity}_outside_temp"
        assert hass.states.get(outside.entity_id).state == "4.5"

        # The same project on another unit: an entry of its own.
        monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
        result = await add(hass, hass_client, other)
        await hass.async_block_till_done()
        assert result["result"].unique_id == f"{identity} @ {other.host}"
        assert (entry.unique_id, dict(entry.data)) == (identity, data)
        for added in hass.config_entries.async_entries(DOMAIN):
            await hass.config_entries.async_unload(added.entry_id)


def mervis_entry(
    hass: HomeAssistant, sim: MervisSimulator, map_id: str, identity: str, title: str
) -> MockConfigEntry:
    """A Mervis entry as an earlier release stored it (its map stored beside it)."""
    entry = MockConfigEntry(
        domain=DOMAIN,
        title=title,
        unique_id=identity,
        data={
            CONF_HOST: sim.url,
            CONF_USERNAME: USER,
            CONF_PASSWORD: PASSWORD,
            CONF_VERIFY_SSL: True,
            CONF_TRANSPORT: "mervis",
            CONF_POINT_MAP: map_id,
        },
        options={CONF_EXCLUDE: list(DEFAULT_EXCLUDE)},
    )
    entry.add_to_hass(hass)
    return entry


async def test_a_mervis_entry_keeps_its_array_elements_and_project_after_uploads(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    socket_enabled: None,
    uploads: None,
) -> None:
    """An entry an earlier release added from a real export: ``in.[1]``, ``Lib.Core``.

    Its loader made an element's ID ``in.[1]`` (the element's segment after a
    dot) and named the installation after the first row's project (a
    library's). After the upgrade, and after uploading the same export and a
    newer one, every entity keeps its unique ID and entity ID; the entry its
    identity. Its title, the one the flow gave, gains the address, then the
    installation's project the file's name says.
    """
    async with MervisSimulator(solution(), username=USER, password=PASSWORD) as sim:
        current = load_vlist(sim.project.vlist())
        stored = PointMap(
            tuple(
                replace(point, id=point.id.replace("[", ".["))
                if point.id.startswith("in[")
                else point
                for point in current.points
            ),
            "vlist",
            properties={"project": "Lib.Core"},
        )
        identity = f"Mervis Lib.Core @ {sim.host}"
        entry = mervis_entry(
            hass,
            sim,
            await async_save_point_map(hass, stored),
            identity,
            "Mervis · Lib.Core",
        )
        registry = er.async_get(hass)
        elements = {
            f"in.[{index}]": registry.async_get_or_create(
                "binary_sensor",
                DOMAIN,
                f"{identity}_in.[{index}]",
                suggested_object_id=f"lib_core_in_{index}",
                config_entry=entry,
            ).entity_id
            for index in range(1, 5)
        }
        assert await hass.config_entries.async_setup(entry.entry_id)
        await hass.async_block_till_done()

        def entities() -> dict[str, str]:
            return {
                item.unique_id: item.entity_id
                for item in er.async_entries_for_config_entry(registry, entry.entry_id)
            }

        before = entities()
        assert {before[f"{identity}_{key}"] for key in elements} == set(
            elements.values()
        )
        assert hass.states.get(elements["in.[3]"]).state == "on"
        assert entry.title == f"Mervis · Lib.Core · {sim.host}"

        # The same export, named as the IDE names it.
        result = await upload_newer(
            hass, hass_client, entry, sim.project.vlist(), sim.project.export_name
        )
        assert result["type"] is FlowResultType.CREATE_ENTRY
        assert entities() == before
        assert entry.unique_id == identity
        assert entry.title == f"Mervis · {SOLUTION_NAME} · {sim.host}"
        assert hass.states.get(elements["in.[3]"]).state == "on"

        # A newer one: a variable more.
        newer = (
            sim.project.vlist() + f"{SOLUTION_NAME};$venku2$;$real$;3019;0;4;none;\n"
        )
        await upload_newer(hass, hass_client, entry, newer, sim.project.export_name)
        after = entities()
        assert {key: after[key] for key in before} == before
        assert set(after) - set(before) == {f"{identity}_venku2"}
        assert entry.runtime_data.point_map.by_key()["in.[2]"].id == "in.[2]"
        await hass.config_entries.async_unload(entry.entry_id)


async def test_a_mervis_title_the_flow_gave_gains_the_address_a_renamed_one_stays(
    hass: HomeAssistant, socket_enabled: None
) -> None:
    """Two units of one project had the same title ("Mervis · Chata Lipno")."""
    async with MervisSimulator(house(), username=USER, password=PASSWORD) as sim:
        map_id = await async_save_point_map(hass, load_vlist(sim.project.vlist()))
        given = mervis_entry(
            hass, sim, map_id, f"Mervis {HOUSE_NAME}", f"Mervis · {HOUSE_NAME}"
        )
        renamed = mervis_entry(
            hass, sim, map_id, f"Mervis {HOUSE_NAME} @ x", "Chalupa u lesa"
        )
        # Setting the integration up sets up both.
        assert await hass.config_entries.async_setup(given.entry_id)
        await hass.async_block_till_done()
        assert given.state is renamed.state is ConfigEntryState.LOADED
        assert given.title == f"Mervis · {HOUSE_NAME} · {sim.host}"
        assert renamed.title == "Chalupa u lesa"
        for entry in (given, renamed):
            await hass.config_entries.async_unload(entry.entry_id)


async def test_points_changed_after_an_upgrade_leave_the_entry_as_1_2_stored_it(
    hass: HomeAssistant, simulator: Simulator, hass_storage: dict[str, Any]
) -> None:
    """What the user changes of the points is kept beside the entry, not in it.

    An entry of 1.2 (the previous release's) needs no migration: its data,
    options and version stay as that release reads them, and every entity but
    the changed point's keeps its entity ID. The changed point's entity keeps
    its unique ID on its new platform, and has its old entity ID again once
    returned to what the PLC says.
    """
    entry = stored_entry(hass, simulator, migrated(STORED["options"]), version=(1, 2))
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    stored = as_stored(entry)

    result = await change_point(hass, entry, "doorbellcount", writable=True)
    assert result["type"] is FlowResultType.CREATE_ENTRY

    assert as_stored(entry) == stored
    assert f"{DOMAIN}.overrides.{entry.entry_id}" in hass_storage
    registry = er.async_get(hass)
    unique_id = f"{STORED['unique_id']}_doorbellcount"
    assert registry.async_get_entity_id("number", DOMAIN, unique_id) is not None
    others = [item for item in STORED["entities"] if item["unique_id"] != unique_id]
    kept = {
        item.unique_id: item.entity_id
        for item in er.async_entries_for_config_entry(registry, entry.entry_id)
    }
    assert {item["unique_id"]: kept.get(item["unique_id"]) for item in others} == {
        item["unique_id"]: item["entity_id"] for item in others
    }

    result = await open_step(hass, entry, "remove_overrides")
    await hass.config_entries.options.async_configure(
        result["flow_id"], {"point": ["doorbellcount"]}
    )
    await hass.async_block_till_done(wait_background_tasks=True)

    assert_every_entity_kept(hass, entry)
