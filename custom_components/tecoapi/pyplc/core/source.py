"""The transport-neutral seam between a caller (Home Assistant) and a way into a device.

A *source* is one way into one PLC or gateway -- TecoApi and PLCComS into a
Tecomat PLC, Mervis's web panel, the FP-I4C's and Tekon's gateway APIs. A
caller knows it through the core alone: this module, the neutral models
(``models``) and exceptions (``exceptions``), and the source's descriptor, found
in the core's registry (``descriptor``, ``registry``); never through a system's
subpackage. Every source implements :class:`PlcSource`:

- ``identify()`` -- who the device is (its identity, model, firmware, and what it
  tells of a program, a MAC), checked to be a device that serves points (a PLC
  that publishes variables, a controller that knows the map's);
- ``poll(polled)`` -- one immutable :class:`Snapshot`: the device's info, the values
  and metadata read, by point key, the points that went missing and whether the
  program changed. The source owns the schedule (what to read on which poll) and
  its protocol's limits; the first poll discovers the catalogue of points;
- ``read_points(keys)`` -- some points' values now, between polls (what moves,
  such as a blind on its way), without touching the poll's schedule;
- ``check_points(keys)`` -- on a source not polled yet, whether the device reads
  some points (a user's, typed by hand), each refused one with the device's reason;
- ``follow(polled)`` -- follow the polled points at once rather than from the
  next poll (a push source enables their pushes);
- ``write(key, value)`` / ``write_many(values)`` (one batch, every value checked
  before any is sent) / ``write_variable(path, value)`` / ``read_variable(path)``;
- ``subscribe(listener)`` -- snapshots the source pushes between polls (a value the
  PLC acknowledged, a change a push protocol reported);
- ``statistics``, ``recent_errors`` and ``diagnostics()`` for the diagnostics
  download, ``metadata_interval`` for how often metadata is read again, and
  ``close()``.

Every failure is one of the exceptions of ``exceptions``: callers decide by class.
"""

from abc import ABC, abstractmethod
from collections import deque
from collections.abc import (
    Awaitable,
    Callable,
    Collection,
    Iterable,
    Mapping,
    Sequence,
)
from dataclasses import asdict, dataclass, field
from datetime import UTC, datetime, timedelta
import logging
from typing import Any, Final, Protocol, TypedDict

from .codec import check_write, to_raw, to_shown
from .exceptions import (
    InvalidPathError,
    InvalidWriteError,
    MissingPointError,
    PlcError,
    ValueRejectedError,
    VariableNotFoundError,
)
from .models import (
    Catalogue,
    Point,
    PointAttributes,
    PointOverride,
    PointQuality,
    Quality,
    SourceInfo,
    WireCounts,
)
from .overrides import apply_overrides
from .pointmap import point_key
from .texts import Template

_LOGGER = logging.getLogger(__name__)

RECENT_ERRORS: Final = 20
"""Failures a source keeps for the diagnostics download."""
DEFAULT_METADATA_INTERVAL: Final = timedelta(seconds=60)
"""How often a source reads metadata again unless told otherwise."""
NEVER: Final = datetime.max.replace(tzinfo=UTC)
"""A time that never comes: what is due then is not due."""

NOT_FOUND: Final = PointQuality(
    quality=Quality.BAD,
    reason="not_found",
    text=Template("quality_not_found", "the device has no such point")(),
)
"""The quality of a point the device no longer has (or cannot read now)."""

type Clock = Callable[[], datetime]
"""Gives the current UTC time."""

type SnapshotListener = Callable[["Snapshot"], None]
"""Told of every snapshot a source pushes between polls."""


@dataclass(frozen=True, slots=True, kw_only=True)
class Snapshot:
    """What one poll (or one push) of a source learned about the device.

    ``values`` and ``attributes`` hold what was read this time, by point key (a
    poll reads the points it was asked for; a push carries the points that
    changed). ``quality`` is every point whose value the source currently knows
    not to be good, and why (a BAD one is unreadable: :attr:`missing`);
    ``offline`` every device below the source's own that currently exchanges no
    data, and why. ``info_read_at`` is when ``info`` was read, if this snapshot
    read it (a clock offset is measured against it). ``program_changed`` is true
    when the device runs a new program (or has a new catalogue) since the
    previous snapshot: ``catalogue`` is then the new one, and
    ``values``/``attributes`` hold all of its points.
    """

    info: SourceInfo
    catalogue: Catalogue
    values: Mapping[str, Any]
    attributes: Mapping[str, PointAttributes]
    quality: Mapping[str, PointQuality] = field(default_factory=dict)
    offline: Mapping[str, str] = field(default_factory=dict)
    info_read_at: datetime | None = None
    program_changed: bool = False

    @property
    def missing(self) -> frozenset[str]:
        """The points that cannot be read now (their quality is bad)."""
        return frozenset(
            key
            for key, quality in self.quality.items()
            if quality.quality is Quality.BAD
        )


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


def counted(statistics: SourceStatistics, changes: str | None) -> dict[str, Any]:
    """Return what a source counted, for its diagnostics, in its system's words.

    ``changes`` names what a new catalogue is to it (``address_space_changes``);
    None: a source whose catalogue never changes under it (a map's) has none.
    """
    figures = asdict(statistics)
    program_changes = figures.pop("program_changes")
    if changes is not None:
        figures[changes] = program_changes
    return figures


@dataclass(frozen=True, slots=True, kw_only=True)
class RecentError:
    """A failure kept for the diagnostics download."""

    time: datetime
    operation: str
    """``discovery``, ``poll``, ``write`` or ``read``."""
    error: str
    """The exception's class."""
    message: str


@dataclass(frozen=True, slots=True, kw_only=True)
class Write[Wire]:
    """One value of a write batch, checked against its point and encoded for the wire.

    ``value`` is what the caller gave, ``wire`` what the source sends (its own
    encoding), ``shown`` what the subscribers are told once the device took it.
    """

    point: Point
    value: Any
    wire: Wire
    shown: Any

    @property
    def key(self) -> str:
        """The point's key."""
        return self.point.key


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


def utcnow() -> datetime:
    """Return the current UTC time (the default :data:`Clock`)."""
    return datetime.now(UTC)


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

    async def identify(self) -> SourceInfo:
        """Who the device is; raises unless it is a device that serves points."""

    async def poll(self, polled: Collection[str]) -> Snapshot:
        """Read what is due: the polled points' values, metadata and info on cadence."""

    async def read_points(self, keys: Collection[str]) -> Snapshot | None:
        """Read some points' values now, between polls, without moving the schedule.

        For what moves after a write (a blind on its way): only what pushes do not
        bring by themselves is read, with the fewest requests and no metadata.
        None when nothing was read, or when a point went missing (the next poll
        tells).
        """

    async def check_points(self, keys: Collection[str]) -> dict[str, PointQuality]:
        """Read some points once on a source not polled yet: those the device refuses.

        How a point a user typed (an address, a type) is checked before it is
        taken, as a newer map is: a source made for the check, of a map holding
        the points, reads them in the fewest requests it can (one for one
        point) and returns each it cannot read, with the device's reason (and
        its code, where it gives one); none: the device reads them all. A key
        the source does not know is refused as not found. A failure of the
        device as a whole (nothing answers, credentials refused) raises, as
        ``identify()`` does.
        """

    async def follow(self, polled: Collection[str]) -> None:
        """Follow the polled points now rather than from the next poll.

        A push source has their changes pushed from now on, and pushes what
        changed since discovery; a polling source has nothing to do. A failure is
        left to the next poll, which follows them as every poll does.
        """

    async def write(self, key: str, value: Any) -> Snapshot | None:
        """Validate and write a point's value, then read it back.

        The acknowledged value is pushed to subscribers at once; the returned
        snapshot holds what the PLC holds afterwards (None when that could not be
        read: the next poll tells).
        """

    async def write_many(self, values: Mapping[str, Any]) -> Snapshot | None:
        """Write several points' values as one batch, in the order given.

        Every value is checked before anything is sent: one refused value leaves
        the device as it was. The acknowledged values are pushed to subscribers;
        the returned snapshot holds what the device holds afterwards, for the
        points it could read back (None: nothing, the next poll tells).
        """

    async def write_variable(self, path: str, value: Any) -> Snapshot | None:
        """Write a JSON-shaped value to any variable path (a point's is validated)."""

    async def read_variable(self, path: str) -> Any:
        """Read the JSON-shaped value of any variable path."""

    def subscribe(self, listener: SnapshotListener) -> Callable[[], None]:
        """Hear of snapshots pushed between polls; returns the unsubscribe function."""

    def discovered_point(self, key: str) -> Point | None:
        """Return a point as the device describes it, without the user's override.

        None: the catalogue discovered last has no such point (or none was yet).
        """

    def diagnostics(self) -> dict[str, Any]:
        """Protocol details for the diagnostics download (no credentials, no host)."""

    async def close(self) -> None:
        """Release what the source holds (connections); it is not used again."""


class SourceSettings(TypedDict, total=False):
    """What every source may be told when it is made (see :class:`BaseSource`)."""

    metadata_interval: timedelta
    clock: Clock
    overrides: Mapping[str, PointOverride]


class BaseSource(ABC):
    """What every :class:`PlcSource` keeps and counts alike (a base to build on).

    It holds the PLC's info, the catalogue and the missing points, the statistics,
    the recent errors and the listeners. :meth:`poll` discovers when due and polls
    otherwise, counting both; writes and reads of any path are counted and their
    failures kept by :meth:`_send` and :meth:`_read`. A subclass discovers,
    polls, writes and describes itself.

    Writing is one template (:meth:`write_many`; :meth:`write` is a batch of
    one), as a zigpy radio implements ``send_packet`` only: a subclass gives
    its encoding (:meth:`_encode`), its batch form (:meth:`_sends`, what goes
    on the wire together), the sending itself (:meth:`_send_writes`) and its
    read-back (:meth:`_read_back`); the check that every point exists, the
    order, the counting, the pushes and a failed read-back are the base's.

    Its settings (:class:`SourceSettings`) are ``metadata_interval``, how often a
    poll reads metadata again, ``clock``, which gives the current UTC time, and
    ``overrides``, what the user changed of the points by key, applied to every
    catalogue discovered (:meth:`_discovered`: the catalogue of its snapshots
    and of its writes' checks is the one changed); a subclass takes them as
    keywords and passes them on. ``wire`` is where its client counts the
    requests it sends (a poll's are the difference).
    """

    def __init__(
        self,
        *,
        wire: WireCounts | None = None,
        metadata_interval: timedelta = DEFAULT_METADATA_INTERVAL,
        clock: Clock = utcnow,
        overrides: Mapping[str, PointOverride] | None = None,
    ) -> None:
        """Start with nothing known and nothing counted."""
        self.wire = WireCounts() if wire is None else wire
        """What the source's client sent on the wire (its requests counted)."""
        self._metadata_interval = metadata_interval
        self._clock = clock
        self._overrides = dict(overrides or {})
        # The catalogue discovered last, as the device told it, and with the
        # overrides applied (a source that discovers the same catalogue again
        # gets the same one back).
        self._overridden: tuple[Catalogue, Catalogue] | None = None
        # When a poll reads metadata next (the subclass schedules it).
        self._metadata_due = NEVER
        self._statistics = SourceStatistics()
        self._recent_errors: deque[RecentError] = deque(maxlen=RECENT_ERRORS)
        self._listeners = PushListeners()
        self._catalogue: Catalogue | None = None
        self._info: SourceInfo | None = None
        # The points that cannot be read now (their quality is bad: not found),
        # and the other points whose quality is not good, with the reason.
        self._missing: frozenset[str] = frozenset()
        self._quality: dict[str, PointQuality] = {}
        # The devices below the source's own that exchange no data now.
        self._offline: dict[str, str] = {}

    @property
    def metadata_interval(self) -> timedelta:
        """How often a poll reads metadata again."""
        return self._metadata_interval

    @metadata_interval.setter
    def metadata_interval(self, interval: timedelta) -> None:
        """Use a new interval; a shorter one applies from now on."""
        self._metadata_interval = interval
        self._metadata_due = min(self._metadata_due, self._clock() + interval)

    @property
    def statistics(self) -> SourceStatistics:
        """What the source did since it was created."""
        return self._statistics

    @property
    def overrides(self) -> Mapping[str, PointOverride]:
        """What the user changed of the points, by key (applied at each discovery)."""
        return self._overrides

    def discovered_point(self, key: str) -> Point | None:
        """Return a point as the device describes it, without the user's override."""
        described = (
            self._overridden[0] if self._overridden is not None else self._catalogue
        )
        return described.points.get(key) if described is not None else None

    @property
    def recent_errors(self) -> Sequence[RecentError]:
        """The latest failures, oldest first."""
        return tuple(self._recent_errors)

    async def poll(self, polled: Collection[str]) -> Snapshot:
        """Discover on the first poll (and when due again); else poll, counting it."""
        wire = self.wire
        requests = wire.requests
        catalogue = None if self._discovery_due() else self._catalogue
        operation = "discovery" if catalogue is None else "poll"
        try:
            if catalogue is None:
                return await self._discover_catalogue(frozenset(polled))
            self._statistics.polls += 1
            return await self._poll(catalogue, frozenset(polled))
        except PlcError as err:
            self._poll_failed()
            if catalogue is not None:
                self._statistics.failed_polls += 1
            self._note(operation, err)
            raise
        finally:
            self._statistics.last_poll_requests = wire.requests - requests

    def subscribe(self, listener: SnapshotListener) -> Callable[[], None]:
        """Hear of snapshots pushed between polls; returns the unsubscribe function."""
        return self._listeners.subscribe(listener)

    async def check_points(self, keys: Collection[str]) -> dict[str, PointQuality]:
        """Read some points once (see :class:`PlcSource`): here, a first poll of them.

        A source whose first poll reads more than it is asked (or identifies
        the device by reading the points) checks them its own way.
        """
        snapshot = await self.poll(keys)
        return {
            key: snapshot.quality.get(key, NOT_FOUND)
            for key in keys
            if key not in snapshot.catalogue.points or key in snapshot.missing
        }

    async def follow(self, polled: Collection[str]) -> None:  # noqa: B027 (optional)
        """Nothing to do before the next poll (a push source enables its pushes)."""

    async def write(self, key: str, value: Any) -> Snapshot | None:
        """Check and write a point's value, push it, read it back: a batch of one."""
        return await self.write_many({key: value})

    async def write_many(self, values: Mapping[str, Any]) -> Snapshot | None:
        """Check every value, then send, push and read back (see :class:`PlcSource`).

        The one write path of every source. Each value is checked and encoded
        before anything is sent (:meth:`check_write`), so a refused one leaves
        the device as it was. The batch then goes in the source's sends
        (:meth:`_sends`), in order: each counted and its failure kept
        (:meth:`_send`), its values pushed once the device took them. Last,
        what the device holds is read back (:meth:`_read_back`); a read-back
        that fails is left to the next poll (None). A source supplies its
        encoding, its sends and its read-back, never this order.
        """
        batch = [self._checked(key, value) for key, value in values.items()]
        if not batch:
            return None
        carried: dict[str, Any] = {}
        for send in self._sends(batch):
            read = await self._send(self._send_writes(send), values=len(send))
            carried.update(read or {})
            self._push({write.key: write.shown for write in send})
        try:
            return await self._read_back(batch, carried)
        except PlcError as err:  # the write went through: a poll tells
            paths = ", ".join(write.point.path for write in batch)
            _LOGGER.debug("Reading back %s after a write failed: %s", paths, err)
            return None

    def check_write(self, key: str, value: Any) -> None:
        """Raise what :meth:`write` would raise for this value, sending nothing.

        A caller may check every value of a form or an action before it writes
        any (:meth:`write_many` checks so). Nothing is sent or changed.
        """
        self._checked(key, value)

    def _checked(self, key: str, value: Any) -> Write[Any]:
        """Check a value for the point of a key; its write, encoded for the wire.

        The one check that the point exists (:class:`MissingPointError`, the
        key named), then the source's :meth:`_encode`.
        """
        return self._encode(self._point(key), value)

    # --- what a subclass provides ----------------------------------------------

    def _discovery_due(self) -> bool:
        """Whether the next poll discovers the catalogue (the first one does)."""
        return self._catalogue is None

    @abstractmethod
    async def _discover_catalogue(self, polled: frozenset[str]) -> Snapshot:
        """Discover the program's catalogue: every point's value and metadata."""

    @abstractmethod
    async def _poll(self, catalogue: Catalogue, polled: frozenset[str]) -> Snapshot:
        """One poll after discovery."""

    def _encode(self, point: Point, value: Any) -> Write[Any]:
        """Check a value for a point and encode it for the wire, or raise why not.

        Here the core's check (:func:`~.codec.check_write`: the point's data
        type and attributes), the raw value on the wire (the point's scale and
        offset turned back) and the value shown pushed; a source whose writes
        are checked or spelled otherwise overrides it.
        """
        raw = to_raw(point, check_write(point, value))
        return Write(point=point, value=value, wire=raw, shown=to_shown(point, raw))

    def _sends(self, batch: Sequence[Write[Any]]) -> Iterable[Sequence[Write[Any]]]:
        """Cut a checked batch into what is sent together, in order (its batch form).

        Here the whole batch at once (:meth:`_send_writes` packs it into its
        requests); a device that takes one value at a time sends each alone,
        a gateway one station's at a time groups them so.
        """
        return (batch,)

    @abstractmethod
    async def _send_writes(
        self, writes: Sequence[Write[Any]]
    ) -> Mapping[str, Any] | None:
        """Send some checked writes together; return once the device took them all.

        A refusal raises (the core's exception, naming the point). What the
        same exchange read back of them, by key, is returned (None: nothing)
        and handed to :meth:`_read_back`.
        """

    async def _read_back(
        self, batch: Sequence[Write[Any]], carried: Mapping[str, Any]
    ) -> Snapshot | None:
        """Return what the device holds of written points (None: the next poll tells).

        ``carried`` is what the sends read back themselves. Here the points
        are read again (:meth:`read_points`).
        """
        return await self.read_points([write.key for write in batch])

    @abstractmethod
    async def read_points(self, keys: Collection[str]) -> Snapshot | None:
        """Read some points' values now, between polls (see :class:`PlcSource`)."""

    def _poll_failed(self) -> None:  # noqa: B027 (an optional hook)
        """Prepare for the poll after a failed one (nothing unless overridden)."""

    # --- the shared bookkeeping ------------------------------------------------

    def _discovered(
        self,
        info: SourceInfo,
        catalogue: Catalogue,
        values: Mapping[str, Any],
        attributes: Mapping[str, PointAttributes],
        info_read_at: datetime | None,
        *,
        program_changed: bool,
    ) -> Snapshot:
        """Count a discovery; return its snapshot, with the points' quality.

        The user's overrides are applied to the catalogue, which becomes the
        source's own (its next snapshots' and its writes' checks').
        """
        catalogue = self._catalogue = self._with_overrides(catalogue)
        self._statistics.discoveries += 1
        if program_changed:
            self._statistics.program_changes += 1
        return Snapshot(
            info=info,
            catalogue=catalogue,
            values=values,
            attributes=attributes,
            quality=self._qualities(),
            offline=dict(self._offline),
            info_read_at=info_read_at,
            program_changed=program_changed,
        )

    def _with_overrides(self, catalogue: Catalogue) -> Catalogue:
        """Return a catalogue discovered with the user's overrides applied.

        The same catalogue discovered again gives the same one back: a
        caller that selects from each new catalogue selects again only when
        something changed.
        """
        if self._overridden is not None and self._overridden[0] is catalogue:
            return self._overridden[1]
        overridden = apply_overrides(catalogue, self._overrides)
        self._overridden = (catalogue, overridden)
        return overridden

    def _discovered_map(
        self, info: SourceInfo, catalogue: Catalogue, values: Mapping[str, Any]
    ) -> Snapshot:
        """Count the discovery of points a map declares: no program, the map's attributes."""
        return self._discovered(
            info,
            catalogue,
            values,
            {
                key: point.attributes
                for key, point in catalogue.points.items()
                if point.attributes is not None
            },
            None,
            program_changed=False,
        )

    def _snapshot(
        self,
        catalogue: Catalogue,
        values: Mapping[str, Any],
        attributes: Mapping[str, PointAttributes],
        info_read_at: datetime | None,
    ) -> Snapshot:
        """Return a snapshot of what was read, with the info and the quality."""
        assert self._info is not None
        return Snapshot(
            info=self._info,
            catalogue=catalogue,
            values=values,
            attributes=attributes,
            quality=self._qualities(),
            offline=dict(self._offline),
            info_read_at=info_read_at,
        )

    def _qualities(self) -> dict[str, PointQuality]:
        """Every point whose value is not good now: the missing ones bad."""
        return {
            **self._quality,
            **dict.fromkeys(self._missing, NOT_FOUND),
        }

    def _push(self, values: Mapping[str, Any]) -> None:
        """Tell the listeners about values (or a new mode with none)."""
        if self._catalogue is not None and self._info is not None:
            self._listeners.push(self._snapshot(self._catalogue, values, {}, None))

    def _map_key(self, path: str) -> str:
        """Return the key of the map's point a path names (its ID, any case)."""
        key = point_key(path)
        if self._catalogue is None or key not in self._catalogue.points:
            raise VariableNotFoundError(
                f"{path!r} is not a point of the map", path=path
            )
        return key

    def _point(self, key: str) -> Point:
        """Return the catalogue's point of a key (:class:`MissingPointError`: none)."""
        catalogue = self._catalogue
        point = catalogue.points.get(key) if catalogue is not None else None
        if point is None:
            raise MissingPointError(key)
        return point

    async def _send[T](self, write: Awaitable[T], *, values: int = 1) -> T:
        """Await a write of ``values`` values, counting them; keep a failure not refused."""
        self._statistics.writes += values
        try:
            return await write
        except (InvalidWriteError, ValueRejectedError):
            raise
        except PlcError as err:
            self._statistics.failed_writes += 1
            self._note("write", err)
            raise

    async def _read[T](self, read: Awaitable[T]) -> T:
        """Await a read of any path; keep a failure that is not the path's fault."""
        try:
            return await read
        except (VariableNotFoundError, InvalidPathError):
            # The user's path, not the PLC's failure.
            raise
        except PlcError as err:
            self._note("read", err)
            raise

    def _note(self, operation: str, err: PlcError) -> None:
        """Keep a failure for the diagnostics download."""
        self._recent_errors.append(
            RecentError(
                time=self._clock(),
                operation=operation,
                error=type(err).__name__,
                message=str(err),
            )
        )
