"""Mervis installations as real exports show them: several projects, arrays, titles.

A real ``.vlist`` holds rows of the installation's project, of a shared project
of its solution and of libraries, the first row often a library's; the IDE
names the file ``<project>_<guid>.vlist`` (MERVIS.md). The simulated
controller serves such an export (``solution()``: written from that
description), over real HTTP; the files are uploaded as the frontend posts
them.
"""

from collections.abc import AsyncIterator

from homeassistant.config_entries import ConfigEntry
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
from homeassistant.helpers import device_registry as dr
import pytest
from pytest_homeassistant_custom_component.typing import ClientSessionGenerator

from custom_components.tecoapi.const import DOMAIN
from custom_components.tecoapi.pyplc.core.descriptor import CONF_POINT_MAP
from custom_components.tecoapi.pyplc.mervis.vlist import PROJECT
from tests.components.tecoapi.mervis_house import (
    PASSWORD,
    USER,
    add,
    form,
    keys,
    upload_newer,
)
from tests.simulator.mervis import (
    HOUSE_NAME,
    SHARED_NAME,
    SOLUTION_NAME,
    MervisSimulator,
    house,
    solution,
)


@pytest.fixture
async def cottage(
    socket_enabled: None, uploads: None
) -> AsyncIterator[MervisSimulator]:
    """A controller running an installation exported as real ones are."""
    async with MervisSimulator(solution(), username=USER, password=PASSWORD) as sim:
        yield sim


async def added(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    sim: MervisSimulator,
    name: str,
    **changes: str,
) -> ConfigEntry:
    """Add the controller with its export (re-saved, with a BOM) under a file name."""
    result = await add(
        hass, hass_client, sim, sim.project.vlist(bom=True), name=name, **changes
    )
    assert result["type"] is FlowResultType.CREATE_ENTRY, result.get("errors")
    entry: ConfigEntry = result["result"]
    return entry


async def test_an_export_is_its_installation_s_by_the_file_s_name(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, cottage: MervisSimulator
) -> None:
    """*Chalupa*, though its first rows are a library's and a shared project has more.

    The title named the first row's project (here ``Lib.Core``, on real files
    a shared project's): two of three real installations were misnamed.
    """
    entry = await added(hass, hass_client, cottage, cottage.project.export_name)
    assert entry.title == f"Mervis · {SOLUTION_NAME} · {cottage.host}"
    assert entry.unique_id == f"Mervis {SOLUTION_NAME} @ {cottage.host}"
    devices = {
        device.name
        for device in dr.async_entries_for_config_entry(
            dr.async_get(hass), entry.entry_id
        )
    }
    assert SOLUTION_NAME in devices
    assert not devices & {"Lib.Core", SHARED_NAME}
    # Every variable of every project is a point: arrays' elements by index.
    found = keys(hass, entry)
    assert found["in[3]"] == "binary_sensor.in_3"
    assert hass.states.get(found["in[3]"]).state == "on"
    assert hass.states.get(found["kotelna.ekviterm.y"]).state == "52.0"
    transformation = found["hw_hidden.markcom3.mxio.ai08.transformation"]
    assert hass.states.get(transformation).state == "21.25"
    assert hass.states.get(found["hvac.season"]).state == "2"


async def test_a_renamed_export_is_corrected_in_the_form(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, cottage: MervisSimulator
) -> None:
    """A file renamed (or re-saved) says no project: the one of most rows, or the user's."""
    result = await add(
        hass,
        hass_client,
        cottage,
        cottage.project.vlist(),
        name="chalupa.vlist",
        **{PROJECT: "Lib.Core"},
    )
    assert result["errors"] == {PROJECT: "point_map_invalid"}
    assert result["description_placeholders"]["error"] == (
        "the file has no variables of a project 'Lib.Core' "
        f"(its projects: {SHARED_NAME}, {SOLUTION_NAME})"
    )
    # The file read stays with the flow: the form again without it, the project
    # typed again, in any case.
    again = form(cottage, "", **{PROJECT: " chalupa "})
    del again[CONF_POINT_MAP]
    result = await hass.config_entries.flow.async_configure(result["flow_id"], again)
    await hass.async_block_till_done()
    assert result["type"] is FlowResultType.CREATE_ENTRY
    entry: ConfigEntry = result["result"]
    assert entry.title == f"Mervis · {SOLUTION_NAME} · {cottage.host}"
    assert entry.unique_id == f"Mervis {SOLUTION_NAME} @ {cottage.host}"


async def test_the_project_of_most_rows_is_corrected_in_a_newer_upload(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, cottage: MervisSimulator
) -> None:
    """Added from a renamed file (*Spolecne*), corrected later: the identity stays.

    A newer file renamed again keeps the project the user named; one named as
    the IDE names exports says its own.
    """
    entry = await added(hass, hass_client, cottage, "export.vlist")
    identity = f"Mervis {SHARED_NAME} @ {cottage.host}"
    assert (entry.unique_id, entry.title) == (
        identity,
        f"Mervis · {SHARED_NAME} · {cottage.host}",
    )
    before = keys(hass, entry)
    result = await upload_newer(
        hass,
        hass_client,
        entry,
        cottage.project.vlist(),
        "export.vlist",
        **{PROJECT: SOLUTION_NAME},
    )
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert entry.title == f"Mervis · {SOLUTION_NAME} · {cottage.host}"
    assert entry.runtime_data.data.info.program_name == SOLUTION_NAME
    # Renamed again: the project the user named stays.
    await upload_newer(hass, hass_client, entry, cottage.project.vlist(), "x.vlist")
    assert entry.title == f"Mervis · {SOLUTION_NAME} · {cottage.host}"
    assert (entry.unique_id, keys(hass, entry)) == (identity, before)
    # A project the file has not: refused, nothing changes.
    result = await upload_newer(
        hass, hass_client, entry, cottage.project.vlist(), "x.vlist", **{PROJECT: "X"}
    )
    assert result["errors"] == {PROJECT: "point_map_invalid"}
    # Shown again with what was typed (the file read stays with the flow).
    shown = {
        str(key): (key.description or {}).get("suggested_value")
        for key in result["data_schema"].schema
    }
    assert (result["step_id"], shown) == (
        "mervis_upload",
        {CONF_POINT_MAP: None, PROJECT: "X"},
    )
    assert entry.title == f"Mervis · {SOLUTION_NAME} · {cottage.host}"


async def test_a_renamed_title_stays_whatever_the_project(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, cottage: MervisSimulator
) -> None:
    entry = await added(hass, hass_client, cottage, "export.vlist")
    hass.config_entries.async_update_entry(entry, title="Chalupa u lesa")
    await upload_newer(
        hass, hass_client, entry, cottage.project.vlist(), cottage.project.export_name
    )
    assert entry.runtime_data.data.info.program_name == SOLUTION_NAME
    assert entry.title == "Chalupa u lesa"


async def test_two_controllers_of_one_project_are_told_apart_by_their_titles(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, uploads: None
) -> None:
    """Both were "Mervis · Chata Lipno"; each names its address now."""
    async with (
        MervisSimulator(house(), username=USER, password=PASSWORD) as first,
        MervisSimulator(house(), username=USER, password=PASSWORD) as second,
    ):
        one = await added(hass, hass_client, first, "house.vlist")
        other = await added(hass, hass_client, second, "house.vlist")
        assert one.title == f"Mervis · {HOUSE_NAME} · {first.host}"
        assert other.title == f"Mervis · {HOUSE_NAME} · {second.host}"
        for entry in hass.config_entries.async_entries(DOMAIN):
            await hass.config_entries.async_unload(entry.entry_id)
