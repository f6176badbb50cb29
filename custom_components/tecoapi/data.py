"""What the entities show, and which of it one poll changed."""

from collections.abc import Callable, Mapping
from dataclasses import dataclass
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
from .pytecoapi import Catalogue, PlcInfo, PlcMode, Point, PointMeta, PollResult

# Which GetInfo field each PLC status entity shows: a status entity is told about
# an update only when its field changed.
STATUS_FIELDS: Final[Mapping[str, Callable[[PlcInfo], object]]] = {
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
class TecoApiData:
    """What the entities show: the PLC's info and its points' values and attributes.

    ``changed`` holds the keys (point keys and PLC status keys) whose value,
    attributes or availability changed in the update that produced this data;
    only their entities are told about it.
    """

    info: PlcInfo
    values: Mapping[str, Any]
    meta: Mapping[str, PointMeta]
    missing: frozenset[str]
    changed: frozenset[str]
    clock_offset: int | None
    """The PLC's clock minus Home Assistant's, in whole seconds (None: no PLC time)."""

    @property
    def running(self) -> bool:
        """Whether the PLC runs its user program (mode RUN)."""
        return self.info.mode is PlcMode.RUN


def shown_clock_offset(
    info: PlcInfo, received: datetime, shown: int | None
) -> int | None:
    """Return the offset of the PLC's clock from Home Assistant's to show (seconds).

    ``received`` is Home Assistant's time when GetInfo answered with ``info``. The
    measurement is blurred by the answer's latency, so an offset that moved by
    less than ``CLOCK_OFFSET_TOLERANCE`` keeps ``shown``: an offset flipping
    between two whole seconds would write a state on every GetInfo.
    """
    if info.time is None:
        return None
    measured = (info.time - received).total_seconds()
    if shown is not None and abs(measured - shown) < CLOCK_OFFSET_TOLERANCE:
        return shown
    return round(measured)


def discovered_data(
    info: PlcInfo,
    catalogue: Catalogue,
    points: Mapping[str, Point],
    previous: TecoApiData | None = None,
    *,
    info_received: datetime,
) -> TecoApiData:
    """Return the data discovery read: every selected point's value and attributes.

    After a program change ``previous`` is what the entities showed; the keys that
    differ from it are marked changed. ``info_received`` is when GetInfo answered.
    """
    values = {key: catalogue.values.get(key) for key in points}
    meta = {key: point.meta for key, point in points.items() if point.meta is not None}
    if previous is None:
        return TecoApiData(
            info=info,
            values=values,
            meta=meta,
            missing=frozenset(),
            changed=frozenset(),
            clock_offset=shown_clock_offset(info, info_received, None),
        )
    return _with_changes(
        previous,
        info,
        info_received,
        values=values,
        meta=meta,
        missing=frozenset(),
        read=values,
        read_meta=meta,
    )


def polled_data(
    previous: TecoApiData,
    info: PlcInfo,
    result: PollResult | None,
    *,
    info_received: datetime | None = None,
) -> TecoApiData:
    """Return the data after a poll; ``result`` is None when no value was read.

    ``info_received`` is when GetInfo answered with ``info``; it matters only when
    ``info`` is not the previous data's (the poll read GetInfo).
    """
    if result is None:
        return _with_changes(
            previous,
            info,
            info_received,
            values=previous.values,
            meta=previous.meta,
            missing=previous.missing,
            read={},
            read_meta={},
        )
    values = {**previous.values, **result.values}
    meta = {**previous.meta, **result.meta}
    return _with_changes(
        previous,
        info,
        info_received,
        values=values,
        meta=meta,
        missing=result.missing,
        read=result.values,
        read_meta=result.meta,
    )


def _with_changes(
    previous: TecoApiData,
    info: PlcInfo,
    info_received: datetime | None,
    *,
    values: Mapping[str, Any],
    meta: Mapping[str, PointMeta],
    missing: frozenset[str],
    read: Mapping[str, Any],
    read_meta: Mapping[str, PointMeta],
) -> TecoApiData:
    """Return the new data, noting which keys changed since the previous data.

    Only what was read (``read``, ``read_meta``) is compared: a poll costs in
    proportion to what it read, not to the whole catalogue.
    """
    changed = set(previous.missing ^ missing)
    for key, value in read.items():
        old = previous.values.get(key, _ABSENT)
        if old != value or type(old) is not type(value):
            changed.add(key)
    changed.update(
        key for key, attrs in read_meta.items() if previous.meta.get(key) != attrs
    )
    if info != previous.info:
        changed.update(
            key
            for key, field in STATUS_FIELDS.items()
            if field(info) != field(previous.info)
        )
    offset = previous.clock_offset
    if info is not previous.info and info_received is not None:
        offset = shown_clock_offset(info, info_received, offset)
        if offset != previous.clock_offset:
            changed.add(STATUS_CLOCK_OFFSET)
    if (info.mode is PlcMode.RUN) != previous.running:
        # Every point entity is available only while the program runs.
        changed.update(values)
    return TecoApiData(
        info=info,
        values=values,
        meta=meta,
        missing=missing,
        changed=frozenset(changed),
        clock_offset=offset,
    )
