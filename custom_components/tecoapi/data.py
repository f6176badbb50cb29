"""What the entities show, and which of it one poll changed."""

from collections.abc import Callable, Mapping
from dataclasses import dataclass, replace
from datetime import datetime
from operator import attrgetter
from typing import Any, Final

from .const import (
    STATUS_CLOCK_OFFSET,
    STATUS_MODE,
    STATUS_PROGRAM_COMPILED,
    STATUS_PROGRAM_NAME,
    STATUS_RUNNING_PROBLEM,
)
from .mapping import PointDescription
from .pyplc import (
    Catalogue,
    Point,
    PointAttributes,
    PointQuality,
    Quality,
    SourceInfo,
)
from .pyplc.core.devices import TypedDevice
from .pyplc.core.source import Snapshot
from .selection import Selection, Selector

# Which GetInfo field each PLC status entity shows: a status entity is told about
# an update only when its field changed.
STATUS_FIELDS: Final[Mapping[str, Callable[[SourceInfo], object]]] = {
    STATUS_MODE: attrgetter("mode"),
    STATUS_RUNNING_PROBLEM: attrgetter("mode"),
    STATUS_PROGRAM_NAME: attrgetter("program_name"),
    STATUS_PROGRAM_COMPILED: attrgetter("program_compiled"),
}

# How far (seconds) a new measurement of the PLC's clock may lie from the offset
# shown before the shown offset changes.
CLOCK_OFFSET_TOLERANCE: Final = 1.0

_ABSENT: Final = object()


@dataclass(frozen=True, slots=True, kw_only=True)
class PlcData:
    """What the entities show: the PLC's info and its points' values and attributes.

    ``selection`` is what the catalogue becomes (points, their descriptions, typed
    devices, groups); it is the same object from poll to poll until a new program
    is discovered. ``values`` and ``attributes`` cover every watched point. ``changed``
    holds the keys (point keys and PLC status keys) whose value, attributes or
    availability changed in the update that produced this data: the other
    entities skip it.
    """

    info: SourceInfo
    catalogue: Catalogue
    selection: Selection
    values: Mapping[str, Any]
    attributes: Mapping[str, PointAttributes]
    quality: Mapping[str, PointQuality]
    """Every point whose value is not good now, and why (bad: unavailable)."""
    offline: Mapping[str, str]
    """Every device below the source's own that exchanges no data now, and why."""
    changed: frozenset[str]
    clock_offset: int | None
    """The PLC's clock minus Home Assistant's, in whole seconds (None: no PLC time)."""

    @property
    def points(self) -> Mapping[str, Point]:
        """The points the options select, by key."""
        return self.selection.points

    @property
    def descriptions(self) -> Mapping[str, PointDescription]:
        """The descriptions of the selected points' entities, by key."""
        return self.selection.descriptions

    @property
    def devices(self) -> Mapping[str, TypedDevice]:
        """The typed devices (found and composed), by key."""
        return self.selection.devices

    @property
    def running(self) -> bool:
        """Whether the device serves live values (a PLC in RUN, a source without modes)."""
        return self.info.running

    @property
    def missing(self) -> frozenset[str]:
        """The points that cannot be read now (their quality is bad)."""
        return frozenset(
            key
            for key, quality in self.quality.items()
            if quality.quality is Quality.BAD
        )

    def device_available(self, device: str) -> bool:
        """Whether a device serves live values: the source's own ("") or one below.

        The source's own device does while it runs (a PLC in RUN); a device below
        it while it exchanges data, and while every device above it does
        (``Catalogue.device_serves``).
        """
        return self.catalogue.device_serves(
            device, running=self.running, offline=self.offline
        )

    def point_available(self, key: str) -> bool:
        """Whether a point's value can be shown: its device serves, it reads well.

        A diagnostic point tells how its own device works (a station's data
        exchange): it is shown while the device above that one serves
        (``Catalogue.point_serves``).
        """
        if not self.catalogue.point_serves(
            key, running=self.running, offline=self.offline
        ):
            return False
        quality = self.quality.get(key)
        return quality is None or quality.quality is not Quality.BAD

    def point_attributes(self, key: str) -> PointAttributes | None:
        """Return the latest attributes of a point (None for a plain variable)."""
        if (attributes := self.attributes.get(key)) is not None:
            return attributes
        point = self.catalogue.points.get(key)
        return point.attributes if point is not None else None


def shown_clock_offset(
    info: SourceInfo, received: datetime, shown: int | None
) -> int | None:
    """Return the offset of the PLC's clock from Home Assistant's to show (seconds).

    ``received`` is Home Assistant's time when the device answered with ``info``.
    The measurement is blurred by the answer's latency, so an offset that moved
    by less than ``CLOCK_OFFSET_TOLERANCE`` keeps ``shown``: an offset flipping
    between two whole seconds would write a state on every reading of the info.
    """
    if info.time is None:
        return None
    measured = (info.time - received).total_seconds()
    if shown is not None and abs(measured - shown) < CLOCK_OFFSET_TOLERANCE:
        return shown
    return round(measured)


def updated_data(
    previous: PlcData | None, snapshot: Snapshot, select: Selector
) -> PlcData:
    """Return what the entities show after a snapshot of the PLC.

    A new catalogue (the first discovery, a new program) is selected from again
    (``select``); otherwise ``previous`` carries the selection over. The
    snapshot's values and attributes are merged into the previous ones, and the
    keys that differ are marked changed.
    """
    catalogue = snapshot.catalogue
    values: Mapping[str, Any]
    attributes: Mapping[str, PointAttributes]
    read: Mapping[str, Any]
    read_attributes: Mapping[str, PointAttributes]
    if previous is None or catalogue is not previous.catalogue:
        selection = select(catalogue)
        values = {key: snapshot.values.get(key) for key in selection.watched}
        attributes = {
            key: point.attributes
            for key in selection.watched
            if (point := catalogue.points.get(key)) is not None
            and point.attributes is not None
        }
        read, read_attributes = values, attributes
    else:
        selection = previous.selection
        read, read_attributes = snapshot.values, snapshot.attributes
        values = {**previous.values, **read} if read else previous.values
        attributes = (
            {**previous.attributes, **read_attributes}
            if read_attributes
            else previous.attributes
        )
    offset = previous.clock_offset if previous is not None else None
    if snapshot.info_read_at is not None:
        offset = shown_clock_offset(snapshot.info, snapshot.info_read_at, offset)
    data = PlcData(
        info=snapshot.info,
        catalogue=catalogue,
        selection=selection,
        values=values,
        attributes=attributes,
        quality=snapshot.quality,
        offline=snapshot.offline,
        changed=frozenset(),
        clock_offset=offset,
    )
    if previous is None:
        return data
    return replace(data, changed=_changes(previous, data, read, read_attributes))


def _changes(
    previous: PlcData,
    data: PlcData,
    read: Mapping[str, Any],
    read_attributes: Mapping[str, PointAttributes],
) -> frozenset[str]:
    """Return the keys whose entities show something else than in ``previous``.

    Only what was read (``read``, ``read_attributes``) is compared: an update costs in
    proportion to what it read, not to the whole catalogue.
    """
    changed = {
        key
        for key in previous.quality.keys() | data.quality.keys()
        if previous.quality.get(key) != data.quality.get(key)
    }
    old_values = previous.values
    for key, value in read.items():
        old = old_values.get(key, _ABSENT)
        if old != value or type(old) is not type(value):
            changed.add(key)
    old_attributes = previous.attributes
    for key, attrs in read_attributes.items():
        # A source hands the same attributes again while they stay the same.
        old = old_attributes.get(key)
        if old is not attrs and old != attrs:
            changed.add(key)
    info, old_info = data.info, previous.info
    if info != old_info:
        changed.update(
            key
            for key, field in STATUS_FIELDS.items()
            if field(info) != field(old_info)
        )
    if data.clock_offset != previous.clock_offset:
        changed.add(STATUS_CLOCK_OFFSET)
    if data.running != previous.running:
        # Every point entity is available only while the program runs.
        changed.update(data.selection.watched)
    elif data.offline != previous.offline:
        # The points of a device that went offline or came back (or below it).
        changed.update(
            key
            for key in data.selection.watched
            if data.point_available(key) != previous.point_available(key)
        )
    return frozenset(changed)
