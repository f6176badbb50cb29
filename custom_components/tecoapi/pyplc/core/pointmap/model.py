"""A point map in neutral terms: its points, their types, its JSON, its catalogue.

Nothing here does I/O; the package's docstring tells what a map is.
"""

from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from types import MappingProxyType
from typing import Any, Final, Self

from ..models import (
    NO_TEXTS,
    Access,
    Catalogue,
    DataType,
    DeviceNode,
    Point,
    PointAttributes,
    ValueKind,
)

FORMAT_VERSION: Final = 1
"""The version of a stored map's JSON (:meth:`PointMap.as_json`)."""

MAX_POINTS: Final = 20_000
"""The most points one map may hold (a file with more is refused)."""


class PointMapError(ValueError):
    """A point map that cannot be imported; ``row`` and ``column`` say where.

    ``row`` is the file's line (1: the first), 0 for the file as a whole;
    ``column`` the column's name ("" for a whole row).
    """

    def __init__(self, message: str, *, row: int = 0, column: str = "") -> None:
        """Say what is wrong, and where."""
        where = f"row {row}" if row else "the file"
        if column:
            where += f", column {column}"
        super().__init__(f"{where}: {message}")
        self.row = row
        self.column = column
        self.message = message


# The data types a map may name, IEC 61131-3 and the IDEs' spellings alike.
TYPE_NAMES: Final[Mapping[str, DataType]] = MappingProxyType(
    {
        "bool": DataType(kind=ValueKind.BOOL, bits=1),
        "byte": DataType(kind=ValueKind.INTEGER, bits=8, signed=False),
        "usint": DataType(kind=ValueKind.INTEGER, bits=8, signed=False),
        "sint": DataType(kind=ValueKind.INTEGER, bits=8),
        "word": DataType(kind=ValueKind.INTEGER, bits=16, signed=False),
        "uint": DataType(kind=ValueKind.INTEGER, bits=16, signed=False),
        "int": DataType(kind=ValueKind.INTEGER, bits=16),
        "dword": DataType(kind=ValueKind.INTEGER, bits=32, signed=False),
        "udint": DataType(kind=ValueKind.INTEGER, bits=32, signed=False),
        "dint": DataType(kind=ValueKind.INTEGER, bits=32),
        "lword": DataType(kind=ValueKind.INTEGER, bits=64, signed=False),
        "ulint": DataType(kind=ValueKind.INTEGER, bits=64, signed=False),
        "lint": DataType(kind=ValueKind.INTEGER, bits=64),
        "real": DataType(kind=ValueKind.REAL, bits=32),
        "lreal": DataType(kind=ValueKind.REAL, bits=64),
        "string": DataType(kind=ValueKind.STRING),
        "date": DataType(kind=ValueKind.DATE),
        "time": DataType(kind=ValueKind.DURATION),
        "tod": DataType(kind=ValueKind.TIME),
        "time_of_day": DataType(kind=ValueKind.TIME),
        "dt": DataType(kind=ValueKind.DATETIME),
        "date_and_time": DataType(kind=ValueKind.DATETIME),
    }
)


def data_type(name: str, length: int | None = None) -> DataType | None:
    """Return the data type a map names (None: unknown); ``length`` for text."""
    found = TYPE_NAMES.get(name.strip().lower())
    if found is None or length is None:
        return found
    return replace(found, length=length)


def type_name(data_type: DataType) -> str:
    """Return the name a map gives a data type (the first of :data:`TYPE_NAMES`)."""
    plain = replace(data_type, length=None, encoding=None)
    return next(
        (name for name, known in TYPE_NAMES.items() if known == plain),
        data_type.kind.value,
    )


@dataclass(frozen=True, slots=True, kw_only=True)
class MapPoint:
    """One point of a map (see the module's docstring).

    ``device`` names the device below the source's own that the point belongs
    to ("" for the source's own: a station, a function block); ``platform`` and
    ``device_class`` are what the user wants it shown as ("" for the default);
    ``invert`` shows (and writes) a flag as its opposite; ``details`` keep what a format says beyond the neutral fields.
    """

    id: str
    name: str
    address: str
    type: DataType
    access: Access = Access.READ
    unit: str = ""
    scale: float = 1.0
    offset: float = 0.0
    minimum: float | None = None
    maximum: float | None = None
    step: float | None = None
    device: str = ""
    platform: str = ""
    device_class: str = ""
    invert: bool = False
    description: str = ""
    details: Mapping[str, str] = field(default=NO_TEXTS)

    @property
    def key(self) -> str:
        """The key of the point made of it: its ID in lower case."""
        return point_key(self.id)


def point_key(ident: str) -> str:
    """Return the key of a map's ID: lower case, white space folded."""
    return " ".join(ident.split()).lower()


@dataclass(frozen=True, slots=True)
class PointMap:
    """The points a user supplied, in the order the file gave them.

    ``format`` is what the points came from (``csv``, ``vlist``); ``skipped``
    the rows a loader kept out, with the reason; ``properties`` what the file
    says of itself beyond its points (a Mervis project's name: ``project``).
    """

    points: tuple[MapPoint, ...]
    format: str = "csv"
    skipped: tuple[tuple[int, str], ...] = ()
    properties: Mapping[str, str] = field(default=NO_TEXTS)

    def __post_init__(self) -> None:
        """Refuse a map whose points share a key, or that holds too many."""
        if len(self.points) > MAX_POINTS:
            raise PointMapError(f"more than {MAX_POINTS} points")
        seen: set[str] = set()
        for point in self.points:
            if point.key in seen:
                raise PointMapError(f"two points have the ID {point.id!r}")
            seen.add(point.key)

    def by_key(self) -> dict[str, MapPoint]:
        """Return the points by key."""
        return {point.key: point for point in self.points}

    def with_point(self, point: MapPoint, replacing: str | None = None) -> Self:
        """Return the map with ``point`` added, or in the place of ``replacing``'s."""
        replaced = point_key(replacing) if replacing is not None else point.key
        points = list(self.points)
        for index, existing in enumerate(points):
            if existing.key == replaced:
                points[index] = point
                break
        else:
            points.append(point)
        return type(self)(tuple(points), self.format, self.skipped, self.properties)

    def with_new_point(self, point: MapPoint) -> Self:
        """Return the map with a point added; its ID must be a new one."""
        if any(existing.key == point.key for existing in self.points):
            raise PointMapError(f"{point.id!r} is taken by another point", column="id")
        return self.with_point(point)

    def without(self, key: str) -> Self:
        """Return the map without the point of a key."""
        return type(self)(
            tuple(point for point in self.points if point.key != key),
            self.format,
            self.skipped,
            self.properties,
        )

    def as_json(self) -> dict[str, Any]:
        """Return the map as JSON-serialisable data (for a store)."""
        data: dict[str, Any] = {
            "version": FORMAT_VERSION,
            "format": self.format,
            "points": [_point_json(point) for point in self.points],
        }
        if self.properties:
            data["properties"] = dict(self.properties)
        return data

    @classmethod
    def from_json(cls, data: Mapping[str, Any]) -> Self:
        """Return a map stored by :meth:`as_json`."""
        points = []
        for index, item in enumerate(data.get("points", ()), start=1):
            found = data_type(item["type"], item.get("length"))
            if found is None:
                raise PointMapError(f"unknown type {item['type']!r}", row=index)
            points.append(
                MapPoint(
                    id=item["id"],
                    name=item["name"],
                    address=item["address"],
                    type=found,
                    access=Access(item.get("access", Access.READ)),
                    unit=item.get("unit", ""),
                    scale=item.get("scale", 1.0),
                    offset=item.get("offset", 0.0),
                    minimum=item.get("minimum"),
                    maximum=item.get("maximum"),
                    step=item.get("step"),
                    device=item.get("device", ""),
                    platform=item.get("platform", ""),
                    device_class=item.get("device_class", ""),
                    invert=bool(item.get("invert", False)),
                    description=item.get("description", ""),
                    details=MappingProxyType(dict(item.get("details", {}))),
                )
            )
        return cls(
            tuple(points),
            str(data.get("format", "csv")),
            properties=MappingProxyType(dict(data.get("properties", {}))),
        )


def _point_json(point: MapPoint) -> dict[str, Any]:
    """Return one point as JSON, leaving out what is its default."""
    data: dict[str, Any] = {
        "id": point.id,
        "name": point.name,
        "address": point.address,
        "type": type_name(point.type),
        "access": point.access.value,
    }
    if point.type.length is not None:
        data["length"] = point.type.length
    optional: dict[str, Any] = {
        "unit": point.unit,
        "scale": point.scale if point.scale != 1.0 else None,
        "offset": point.offset if point.offset != 0.0 else None,
        "minimum": point.minimum,
        "maximum": point.maximum,
        "step": point.step,
        "device": point.device,
        "platform": point.platform,
        "device_class": point.device_class,
        "invert": point.invert or None,
        "description": point.description,
        "details": dict(point.details),
    }
    # What is left out is its default: None, empty text, no details (a 0 stays).
    data.update(
        (key, value)
        for key, value in optional.items()
        if value is not None and value not in ("", {})
    )
    return data


def map_catalogue(point_map: PointMap) -> Catalogue:
    """Return the catalogue of a map's points (no values: a source reads them).

    Each point's key is its ID's (:func:`point_key`), its path the ID, its
    attributes the map's name, unit, access and range; each ``device`` named is
    a device below the source's own, keyed by its name in lower case.
    """
    points: dict[str, Point] = {}
    devices: dict[str, DeviceNode] = {}
    for item in point_map.points:
        device = point_key(item.device) if item.device else ""
        if device and device not in devices:
            devices[device] = DeviceNode(key=device, name=item.device)
        points[item.key] = Point(
            key=item.key,
            path=item.id,
            address=item.address,
            type=item.type,
            attributes=PointAttributes(
                name=item.name,
                unit=item.unit,
                access=item.access,
                minimum=item.minimum,
                maximum=item.maximum,
            ),
            device=device,
            scale=item.scale,
            offset=item.offset,
            step=item.step,
            platform=item.platform,
            device_class=item.device_class,
            invert=item.invert,
            description=item.description,
            details=item.details,
        )
    return Catalogue(
        points=points, values={}, groups=(), skipped_groups=(), devices=devices
    )
