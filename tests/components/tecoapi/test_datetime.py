"""Date-times: the memory house's, read and written raw."""

from datetime import UTC, datetime

from homeassistant.core import HomeAssistant

from tests.components.tecoapi import memory_house
from tests.fake_source import MemoryDevice


async def test_datetime(hass: HomeAssistant, house: MemoryDevice) -> None:
    shown = memory_house.state(hass, "datetime", "last_service")
    assert shown.state == "2026-03-01T08:00:00+00:00"
    await memory_house.call(
        hass,
        "datetime",
        "set_value",
        "last_service",
        datetime=datetime(2026, 4, 1, 9, 30, tzinfo=UTC),
    )
    assert house.values["m9"] == datetime(2026, 4, 1, 9, 30, tzinfo=UTC)
