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
from ..texts import Template, Text

FORMAT_VERSION: Final = 1
"""The version of a stored map's JSON (:meth:`PointMap.as_json`)."""

MAX_POINTS: Final = 20_000
"""The most points one map may hold (a file with more is refused)."""


class PointMapError(ValueError):
    """A point map that cannot be imported; ``row`` and ``column`` say where.

    ``text`` says what is wrong (:mod:`..texts`): ``key`` and ``params`` for a
    caller that says it in its user's language, ``message`` in English.
    ``row`` is the file's line (1: the first), 0 for the file as a whole;
    ``column`` the column's name ("" for a whole row).
    """

    def __init__(self, text: Text, *, row: int = 0, column: str = "") -> None:
        """Say what is wrong, and where."""
        where = str(self.where_of(row, column) or "the file")
        if column and not row:
            where += f", column {column}"
        self.text = text
        self.message = str(text)
        super().__init__(f"{where}: {self.message}")
        self.row = row
        self.column = column

    @property
    def key(self) -> str:
        """The key of what is wrong (its text's)."""
        return self.text.key

    @property
    def params(self) -> Mapping[str, str]:
        """What fills the text of what is wrong."""
        return self.text.params

    @property
    def where(self) -> Text | None:
        """Where the file is wrong: its row, and its column (None: the file, a form)."""
        return self.where_of(self.row, self.column)

    @staticmethod
    def where_of(row: int, column: str) -> Text | None:
        """Return the text of a row and a column (None: no row)."""
        if not row:
            return None
        return AT_CELL(row=row, column=column) if column else AT_ROW(row=row)


AT_ROW: Final = Template("map_at_row", "row {row}")
AT_CELL: Final = Template("map_at_cell", "row {row}, column {column}")
NOT_AN_ADDRESS: Final = Template("map_not_address", "not an address the device reads")
"""A source's check may say this of an address it has no words of its own for."""
# What a map's errors say (their keys are the texts' of every loader: a
# system's loader takes these where they fit, and adds its own).
TOO_MANY_POINTS: Final = Template("map_too_many_points", "more than {most} points")
ID_TWICE: Final = Template("map_id_twice", "two points have the ID {id}")
ID_TAKEN: Final = Template("map_id_taken", "{id} is taken by another point")
STORED_TYPE: Final = Template("map_stored_type", "unknown type {type}")


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
    to ("" for the source's own: a station, a function block); ``platform``,
    ``device_class`` and ``state_class`` are what the user wants it shown as
    ("" for the default: a state class as its unit says); ``invert`` shows (and writes) a flag as its opposite; ``details`` keep what a format says beyond the neutral fields.
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
    state_class: str = ""

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
            raise PointMapError(TOO_MANY_POINTS(most=MAX_POINTS))
        seen: set[str] = set()
        for point in self.points:
            if point.key in seen:
                raise PointMapError(ID_TWICE(id=repr(point.id)))
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
            raise PointMapError(ID_TAKEN(id=repr(point.id)), column="id")
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
                raise PointMapError(STORED_TYPE(type=repr(item["type"])), row=index)
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
                    state_class=item.get("state_class", ""),
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
        "state_class": point.state_class,
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
            state_class=item.state_class,
            invert=item.invert,
            description=item.description,
            details=item.details,
        )
    return Catalogue(
        points=points, values={}, groups=(), skipped_groups=(), devices=devices
    )
