"""Dates: the memory house's, read and written raw."""

from datetime import date

from homeassistant.core import HomeAssistant

from tests.components.tecoapi import memory_house
from tests.fake_source import MemoryDevice


async def test_date(hass: HomeAssistant, house: MemoryDevice) -> None:
    assert memory_house.state(hass, "date", "holiday_from").state == "2026-12-20"
    await memory_house.call(
        hass, "date", "set_value", "holiday_from", date=date(2027, 1, 2)
    )
    assert house.values["m7"] == date(2027, 1, 2)
