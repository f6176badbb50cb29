"""Typed, transport-neutral models of a PLC: its info, its points and their catalogue."""

from collections.abc import Mapping
from dataclasses import dataclass
from datetime import datetime
from enum import StrEnum
import re
from typing import Any, Final

ITEM_LIMIT_CP1: Final = 128
ITEM_LIMIT_CP2: Final = 256
ITEM_LIMIT_UNKNOWN: Final = ITEM_LIMIT_CP1

_CPU_SERIES = re.compile(r"CP-?(\d)", re.IGNORECASE)


class ValueKind(StrEnum):
    """What a point's value is, inferred from its JSON and the manual's formats."""

    BOOL = "bool"
    INTEGER = "integer"
    REAL = "real"
    STRING = "string"
    DATE = "date"
    TIME = "time"
    DATETIME = "datetime"


class PlcMode(StrEnum):
    """The PLC's mode from GetInfo; anything the manual does not list is ERR."""

    RUN = "RUN"
    HALT = "HALT"
    ERR = "ERR"


def item_limit_for_type(plc_type: str | None) -> int:
    """Return the per-response item limit of a CPU type: 128 CP-1xxx, 256 CP-2xxx.

    Types the manual does not cover (CP-7xxx, simulators, unknown) get the
    smaller 128, which every TecoApi CPU accepts.
    """
    if plc_type and (match := _CPU_SERIES.search(plc_type)):
        if match.group(1) == "2":
            return ITEM_LIMIT_CP2
        if match.group(1) == "1":
            return ITEM_LIMIT_CP1
    return ITEM_LIMIT_UNKNOWN


@dataclass(frozen=True, slots=True, kw_only=True)
class PlcInfo:
    """What GetInfo tells about the PLC and its user program."""

    family: str | None
    type: str | None
    serial_number: str
    firmware: str | None
    mac: str | None
    mode: PlcMode
    program_name: str | None
    program_compiled: datetime | None
    program_stamp: str | None
    time: datetime | None
    api_version: str | None

    @property
    def item_limit(self) -> int:
        """The most items one GetObject response may hold on this CPU."""
        return item_limit_for_type(self.type)


@dataclass(frozen=True, slots=True, kw_only=True)
class PointMeta:
    """The ``attr`` of a T_ApiObject (manual chapter 5.3)."""

    title: str
    units: str
    read_only: bool
    min_value: float
    max_value: float
    enable: bool
    visibility: bool

    @property
    def has_range(self) -> bool:
        """Whether min/max bound the value (both 0 means "no range")."""
        return not (self.min_value == 0 and self.max_value == 0)


@dataclass(frozen=True, slots=True, kw_only=True)
class Point:
    """One readable value of the PLC: a T_ApiObject or a plain scalar leaf."""

    path: str
    key: str
    kind: ValueKind
    meta: PointMeta | None

    @property
    def is_api_object(self) -> bool:
        """Whether the point is a T_ApiObject (it has metadata)."""
        return self.meta is not None

    @property
    def writable(self) -> bool:
        """Whether the PLC declares the point writable (plain points: unknown, no)."""
        return self.meta is not None and not self.meta.read_only

    @property
    def value_path(self) -> str:
        """The path that holds the value: ``path.value`` for T_ApiObjects."""
        return f"{self.path}.value" if self.meta is not None else self.path


@dataclass(frozen=True, slots=True, kw_only=True)
class DiscoveryStats:
    """What discovery cost, against what it had to cost (see ``pyplc.tecomat.tecoapi.roots``).

    ``requests`` are the GetList and GetObject requests sent (authentication
    challenges not counted); ``lower_bound`` is the fewest any client needs to read
    the same roots knowing their sizes beforehand. ``too_large`` counts the answers
    413; ``overflowing_roots`` the roots that turned out too big to share the
    request they were first sent in (each then read alone) and ``oversized_roots``
    those too big for any answer: ``too_large <= overflowing_roots +
    oversized_roots`` always holds.
    """

    requests: int
    lower_bound: int
    too_large: int
    overflowing_roots: int
    oversized_roots: int
    item_limit: int


@dataclass(frozen=True, slots=True)
class Catalogue:
    """Everything discovery learned: the points, their values, the roots."""

    points: Mapping[str, Point]
    values: Mapping[str, Any]
    roots: tuple[str, ...]
    skipped_roots: tuple[str, ...]
    discovery: DiscoveryStats | None = None
