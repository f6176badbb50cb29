"""A point map beside its entry, and the uploaded file it is read from.

An upload is read by the source's own loaders; a file that is gone or that
cannot be read is a form error with its reason. A flow keeps the map of the
file it was given last, so that a form shown again need not name it.
"""

from homeassistant.core import HomeAssistant
import pytest
from pytest_homeassistant_custom_component.typing import ClientSessionGenerator

from custom_components.tecoapi.point_maps import (
    KeptUpload,
    PointMapUploadError,
    async_load_point_map,
    async_read_upload,
    async_remove_point_map,
    async_save_point_map,
)
from tests.components.tecoapi.file_upload import upload
from tests.fake_source import HOUSE_CSV, MEMORY, house_map


async def test_a_map_is_kept_under_its_id_until_removed(hass: HomeAssistant) -> None:
    stored = house_map()

    map_id = await async_save_point_map(hass, stored)

    assert await async_load_point_map(hass, map_id) == stored
    assert await async_save_point_map(hass, stored, map_id) == map_id
    await async_remove_point_map(hass, map_id)
    assert await async_load_point_map(hass, map_id) is None


async def test_an_upload_is_read_by_the_source_s_loaders_once(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, uploads: None
) -> None:
    file_id = await upload(hass, hass_client, "house.csv", HOUSE_CSV)

    read = await async_read_upload(hass, MEMORY, file_id)

    assert [point.id for point in read.points] == [
        point.id for point in house_map().points
    ]
    # Home Assistant removed the file once it was read.
    with pytest.raises(PointMapUploadError) as gone:
        await async_read_upload(hass, MEMORY, file_id)
    assert gone.value.key == "point_map_missing"


async def test_a_file_that_is_no_map_names_its_row(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, uploads: None
) -> None:
    file_id = await upload(hass, hass_client, "bad.csv", "id,name\n,\n")

    with pytest.raises(PointMapUploadError) as invalid:
        await async_read_upload(hass, MEMORY, file_id)

    assert invalid.value.key == "point_map_invalid"
    assert invalid.value.message


async def test_a_flow_keeps_the_map_of_the_file_it_was_given_last(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, uploads: None
) -> None:
    kept = KeptUpload()
    assert kept.map is None
    good = await upload(hass, hass_client, "house.csv", HOUSE_CSV)
    bad = await upload(hass, hass_client, "bad.csv", "id,name\n,\n")

    read = await kept.async_read(hass, MEMORY, good)

    # The same file again: the map read, though Home Assistant removed the file.
    assert await kept.async_read(hass, MEMORY, good) is read
    assert kept.map is read
    for _ in range(2):
        with pytest.raises(PointMapUploadError) as invalid:
            await kept.async_read(hass, MEMORY, bad)
        assert invalid.value.key == "point_map_invalid"
    assert kept.map is None
