"""A source's cache in one versioned form: another version or shape is nothing."""

import json
from typing import Any

import pytest

from custom_components.tecoapi.pyplc.core.cache import VersionedCache


class JsonCache:
    """A cache that keeps JSON text, as Home Assistant's store does."""

    def __init__(self, text: str | None = None) -> None:
        self.text = text
        self.saves = 0

    async def load(self) -> Any:
        return None if self.text is None else json.loads(self.text)

    async def save(self, data: Any) -> None:
        self.text = json.dumps(data)
        self.saves += 1


async def test_what_is_saved_is_loaded_with_its_version() -> None:
    store = JsonCache()
    cache = VersionedCache(store, 3)
    assert cache.enabled
    assert await cache.load() is None
    await cache.save(hash="abc", items=[["A.B", 1, {"1": "5"}]])
    assert json.loads(store.text or "") == {
        "version": 3,
        "hash": "abc",
        "items": [["A.B", 1, {"1": "5"}]],
    }
    assert await cache.load() == {
        "version": 3,
        "hash": "abc",
        "items": [["A.B", 1, {"1": "5"}]],
    }


async def test_the_stored_form_is_read_as_sources_wrote_it_before() -> None:
    """A store written before the cache was the core's reads the same (version 1)."""
    store = JsonCache('{"version": 1, "limits": {"max_variables": 5}}')
    assert await VersionedCache(store, 1).load() == {
        "version": 1,
        "limits": {"max_variables": 5},
    }


@pytest.mark.parametrize(
    "text",
    ['{"version": 2, "hash": "abc"}', '{"hash": "abc"}', '[1, "abc"]', '"abc"', "1"],
)
async def test_another_version_or_shape_is_nothing(text: str) -> None:
    assert await VersionedCache(JsonCache(text), 1).load() is None


async def test_without_a_cache_nothing_is_read_or_kept() -> None:
    cache = VersionedCache(None, 1)
    assert not cache.enabled
    await cache.save(hash="abc")
    assert await cache.load() is None
