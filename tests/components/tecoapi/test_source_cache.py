"""What a source keeps beside its entry: one store each, gone with the entry."""

from homeassistant.core import HomeAssistant

from custom_components.tecoapi.source_cache import EntryCache


async def test_a_cache_keeps_what_was_saved_last_per_entry(
    hass: HomeAssistant,
) -> None:
    cache, other = EntryCache(hass, "e1"), EntryCache(hass, "e2")
    assert await cache.load() is None

    await cache.save({"hash": "a1", "items": [1, 2]})
    await cache.save({"hash": "b2", "items": [3]})

    assert await cache.load() == {"hash": "b2", "items": [3]}
    assert await EntryCache(hass, "e1").load() == {"hash": "b2", "items": [3]}
    assert await other.load() is None
    await cache.remove()
    assert await EntryCache(hass, "e1").load() is None
