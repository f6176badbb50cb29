"""What a source keeps beside its entry, in one versioned form.

A source keeps what it learned of its device between runs (a gateway's address
space, a controller's request limits) in its entry's
:class:`~.descriptor.SourceCache` as one object, ``{"version": N, ...}``.
:class:`VersionedCache` reads it back only in the version the source writes:
what another version stored, or something of another shape, is nothing, and is
learned again from the device. Without a cache (a form being checked) nothing is
read or kept.
"""

from typing import Any

from .descriptor import SourceCache


class VersionedCache:
    """A source's :class:`~.descriptor.SourceCache` in one version of its form."""

    __slots__ = ("_cache", "version")

    def __init__(self, cache: SourceCache | None, version: int) -> None:
        """Read and write ``cache`` (None: nowhere) as version ``version``."""
        self._cache = cache
        self.version = version

    @property
    def enabled(self) -> bool:
        """Whether anything is read and kept (a cache was given)."""
        return self._cache is not None

    async def load(self) -> dict[str, Any] | None:
        """Return what was saved in this version (None: nothing, or another version)."""
        if self._cache is None:
            return None
        kept = await self._cache.load()
        if isinstance(kept, dict) and kept.get("version") == self.version:
            return kept
        return None

    async def save(self, **kept: Any) -> None:
        """Keep ``kept`` (JSON-shaped), with the version, in place of what was kept."""
        if self._cache is not None:
            await self._cache.save({"version": self.version, **kept})
