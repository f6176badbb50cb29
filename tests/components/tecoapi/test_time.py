"""Times: the memory house's, read and written raw."""

from datetime import time, timedelta

from homeassistant.core import HomeAssistant

from tests.components.tecoapi import memory_house
from tests.fake_source import MemoryDevice


async def test_time(hass: HomeAssistant, house: MemoryDevice) -> None:
    assert memory_house.state(hass, "time", "wake_up").state == "06:30:00"
    await memory_house.call(hass, "time", "set_value", "wake_up", time=time(7, 15))
    assert house.values["m8"] == timedelta(hours=7, minutes=15)
