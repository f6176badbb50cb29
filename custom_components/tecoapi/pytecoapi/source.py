"""The transport-neutral seam between Home Assistant and a way into a PLC.

Home Assistant's side depends on this module, the neutral models (``models``) and
the neutral exceptions (``exceptions``) only. A *source* is one way into one PLC --
TecoApi over HTTP today, PLCComS over TCP next, other vendors' HTTP APIs later --
and implements :class:`PlcSource`:

- ``identify()`` -- who the device is (serial number, model, firmware, MAC, its
  program), checked to be a PLC that publishes variables;
- ``poll(polled)`` -- one immutable :class:`Snapshot`: the PLC's info, the values
  and metadata read, by point key, the points that went missing and whether the
  program changed. The source owns the schedule (what to read on which poll) and
  its protocol's limits; the first poll discovers the catalogue of points;
- ``write(key, value)`` / ``write_variable(path, value)`` / ``read_variable(path)``;
- ``subscribe(listener)`` -- snapshots the source pushes between polls (a value the
  PLC acknowledged, a change a push protocol reported);
- ``statistics``, ``recent_errors`` and ``diagnostics()`` for the diagnostics
  download, ``metadata_interval`` for how often metadata is read again, and
  ``close()``.

Every failure is one of the exceptions of ``exceptions``: callers decide by class.
"""

from collections.abc import Callable, Collection, Mapping, Sequence
from dataclasses import dataclass, field
from datetime import datetime, timedelta
from typing import Any, Final, Protocol

from .models import Catalogue, PlcInfo, PointMeta

RECENT_ERRORS: Final = 20
"""Failures a source keeps for the diagnostics download."""

type SnapshotListener = Callable[["Snapshot"], None]
"""Told of every snapshot a source pushes between polls."""


@dataclass(frozen=True, slots=True, kw_only=True)
class Snapshot:
    """What one poll (or one push) of a source learned about the PLC.

    ``values`` and ``meta`` hold what was read this time, by point key (a poll reads
    the points it was asked for; a push carries the points that changed).
    ``missing`` is every point the source currently knows to be unreadable.
    ``info_read_at`` is when ``info`` was read, if this snapshot read it (a clock
    offset is measured against it). ``program_changed`` is true when the PLC runs a
    new program since the previous snapshot: ``catalogue`` is then the new
    program's, and ``values``/``meta`` hold all of its points.
    """

    info: PlcInfo
    catalogue: Catalogue
    values: Mapping[str, Any]
    meta: Mapping[str, PointMeta]
    missing: frozenset[str]
    info_read_at: datetime | None = None
    program_changed: bool = False


@dataclass(slots=True, kw_only=True)
class SourceStatistics:
    """What a source did since it was created (for diagnostics).

    Polls after discovery and those that failed, and the requests the last poll
    took on the wire (None before the first); discoveries (the first, and one per
    new program); writes sent and those the PLC did not take (a refused value is
    not a failure).
    """

    polls: int = 0
    failed_polls: int = 0
    last_poll_requests: int | None = None
    discoveries: int = 0
    program_changes: int = 0
    writes: int = 0
    failed_writes: int = 0


@dataclass(frozen=True, slots=True, kw_only=True)
class RecentError:
    """A failure kept for the diagnostics download."""

    time: datetime
    operation: str
    """``discovery``, ``poll``, ``write`` or ``read``."""
    error: str
    """The exception's class."""
    message: str


@dataclass(slots=True)
class PushListeners:
    """The listeners of a source's pushed snapshots."""

    _listeners: list[SnapshotListener] = field(default_factory=list)

    def subscribe(self, listener: SnapshotListener) -> Callable[[], None]:
        """Add a listener; returns the function that removes it again."""
        self._listeners.append(listener)

        def unsubscribe() -> None:
            if listener in self._listeners:
                self._listeners.remove(listener)

        return unsubscribe

    def push(self, snapshot: Snapshot) -> None:
        """Tell every listener about a snapshot."""
        for listener in list(self._listeners):
            listener(snapshot)


class PlcSource(Protocol):
    """One way into one PLC (see the module's docstring)."""

    metadata_interval: timedelta
    """How often metadata (and the PLC's info) is read again."""

    @property
    def configuration_url(self) -> str | None:
        """Where a user configures or inspects the PLC (its web server), if anywhere."""

    @property
    def statistics(self) -> SourceStatistics:
        """What the source did so far."""

    @property
    def recent_errors(self) -> Sequence[RecentError]:
        """The latest failures, oldest first (at most ``RECENT_ERRORS``)."""

    async def identify(self) -> PlcInfo:
        """Who the device is; raises unless it is a PLC that publishes variables."""

    async def poll(self, polled: Collection[str]) -> Snapshot:
        """Read what is due: the polled points' values, metadata and info on cadence."""

    async def write(self, key: str, value: Any) -> Snapshot | None:
        """Validate and write a point's value, then read it back.

        The acknowledged value is pushed to subscribers at once; the returned
        snapshot holds what the PLC holds afterwards (None when that could not be
        read: the next poll tells).
        """

    async def write_variable(self, path: str, value: Any) -> Snapshot | None:
        """Write a JSON-shaped value to any variable path (a point's is validated)."""

    async def read_variable(self, path: str) -> Any:
        """Read the JSON-shaped value of any variable path."""

    def subscribe(self, listener: SnapshotListener) -> Callable[[], None]:
        """Hear of snapshots pushed between polls; returns the unsubscribe function."""

    def diagnostics(self) -> dict[str, Any]:
        """Protocol details for the diagnostics download (no credentials, no host)."""

    async def close(self) -> None:
        """Release what the source holds (connections); it is not used again."""
