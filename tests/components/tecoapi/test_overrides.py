"""What the user changed of an entry's points: a store beside the entry."""

from homeassistant.core import HomeAssistant

from custom_components.tecoapi.overrides import (
    async_load_overrides,
    async_remove_overrides,
    async_save_overrides,
)
from custom_components.tecoapi.pyplc.core.models import PointOverride


async def test_overrides_are_kept_per_entry_until_it_goes(hass: HomeAssistant) -> None:
    assert await async_load_overrides(hass, "e1") == {}
    changed = {
        "heating.setpoint": PointOverride(writable=True, unit="°C"),
        "door": PointOverride(invert=True),
    }

    await async_save_overrides(hass, "e1", changed)

    assert await async_load_overrides(hass, "e1") == changed
    assert await async_load_overrides(hass, "e2") == {}
    await async_remove_overrides(hass, "e1")
    assert await async_load_overrides(hass, "e1") == {}
