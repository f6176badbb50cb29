"""Point maps: the points of a device that does not list them, as the user supplies them.

Some systems have no listing of their values: the integrator exports a project's
variables from an IDE (a Mervis ``.vlist``) or keeps a register list in a
spreadsheet (a CSV). A :class:`PointMap` is that list in neutral terms, one
:class:`MapPoint` per value: a stable ``id`` (what the point's key, and so its
entity's unique ID, is made of -- never a row number), a display name, the
address the source reads, a data type, access, unit, scale and offset, a range
and a step, the device it belongs to and what the user wants it to be.

Loaders read the formats: this module's reads a CSV, and a system's subpackage
may have one of its own (:data:`Loader`; Mervis's ``.vlist`` in ``mervis.vlist``);
:func:`load` picks one of those a caller takes by the file's name. A file with an
error imports nothing: :class:`PointMapError` names the row (1 is the header's
line) and the column. Rows a loader cannot use but a file may
legitimately hold (a type it does not know) are kept out and reported in
:attr:`PointMap.skipped`. A map is stored as JSON (:meth:`PointMap.as_json`,
:meth:`PointMap.from_json`). Nothing here does I/O.
"""

from collections.abc import Callable, Iterable, Mapping
import csv
from dataclasses import dataclass, field, replace
import io
import math
from types import MappingProxyType
from typing import Any, Final, Self

from .models import (
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
MAX_FILE_BYTES: Final = 8 * 1024 * 1024
"""The largest file a loader reads."""


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


# --- CSV ---------------------------------------------------------------------

CSV_COLUMNS: Final = (
    "id",
    "name",
    "address",
    "type",
    "length",
    "unit",
    "scale",
    "offset",
    "writable",
    "min",
    "max",
    "step",
    "device",
    "platform",
    "device_class",
    "invert",
    "description",
)
"""The columns of a CSV map; ``name``, ``address`` and ``type`` are required."""
CSV_AREA: Final = "area"
"""A column a file may have beside :data:`CSV_COLUMNS`: the memory area written
before the address (an area ``DT`` and an address ``100`` are ``DT100``), for
register lists that keep them apart. A map keeps the whole address."""
CSV_REQUIRED: Final = ("name", "address", "type")
# Other spellings integrators use for the same column.
CSV_ALIASES: Final[Mapping[str, str]] = MappingProxyType(
    {
        "key": "id",
        "count": "length",
        "access": "writable",
        "station": "device",
        "minimum": "min",
        "maximum": "max",
        "comment": "description",
        "class": "device_class",
    }
)
_TRUE: Final = frozenset({"1", "true", "yes", "y", "x", "rw", "w", "write"})
_FALSE: Final = frozenset({"", "0", "false", "no", "n", "r", "ro", "read"})

type AddressCheck = Callable[[MapPoint], str | None]
"""A source's check of a point's address: None, or what is wrong with it.

A check that finds another column at fault (a type the address cannot hold)
raises :class:`PointMapError` naming that column; the loader adds the row.
"""


def run_check(check: AddressCheck, point: MapPoint, row: int, column: str) -> None:
    """Run a source's check of a point; raise its problem at the row and column."""
    try:
        problem = check(point)
    except PointMapError as err:
        raise PointMapError(err.message, row=row, column=err.column or column) from None
    if problem is not None:
        raise PointMapError(problem, row=row, column=column)


def load_csv(
    text: str, check: AddressCheck | None = None, types: Iterable[str] = TYPE_NAMES
) -> PointMap:
    """Read a CSV map: a header of :data:`CSV_COLUMNS`, then one point a row.

    The delimiter is a comma or a semicolon (what spreadsheets in Czech and
    Slovak write), found from the header; blank rows and rows whose first cell
    starts with ``#`` are comments. ``check`` is the source's check of each
    address; ``types`` the type names an unknown type's error lists (those the
    source reads). Any error imports nothing.
    """
    lines = text.lstrip("\ufeff").splitlines()
    header_row = next(
        (index for index, line in enumerate(lines) if _is_content(line)), None
    )
    if header_row is None:
        raise PointMapError("the file has no header")
    header_line = lines[header_row]
    delimiter = ";" if header_line.count(";") > header_line.count(",") else ","
    reader = csv.reader(io.StringIO("\n".join(lines)), delimiter=delimiter)
    rows = list(reader)
    header = [_column(name) for name in rows[header_row]]
    for required in CSV_REQUIRED:
        if required not in header:
            raise PointMapError(
                f"the header has no {required!r} column", row=header_row + 1
            )
    unknown = [name for name in header if name and name not in (*CSV_COLUMNS, CSV_AREA)]
    if unknown:
        raise PointMapError(
            f"unknown column {unknown[0]!r} (known: {', '.join(CSV_COLUMNS)})",
            row=header_row + 1,
        )
    points: list[MapPoint] = []
    seen: dict[str, int] = {}
    for index in range(header_row + 1, len(rows)):
        cells = rows[index]
        # A comment starts with # as written: a quoted "#1" is an ID.
        if not any(cell.strip() for cell in cells) or not _is_content(lines[index]):
            continue
        row = index + 1
        if len(cells) > len(header):
            raise PointMapError(
                f"{len(cells)} cells, the header has {len(header)}", row=row
            )
        values = {
            name: cells[position].strip() if position < len(cells) else ""
            for position, name in enumerate(header)
        }
        point = csv_point(values, row, types)
        if check is not None:
            run_check(check, point, row, "address")
        if point.key in seen:
            raise PointMapError(
                f"the ID {point.id!r} is taken by row {seen[point.key]}",
                row=row,
                column="id" if values.get("id") else "name",
            )
        seen[point.key] = row
        points.append(point)
    if not points:
        raise PointMapError("the file holds no point")
    return PointMap(tuple(points), "csv")


def point_of(
    values: Mapping[str, str],
    check: AddressCheck | None = None,
    types: Iterable[str] = TYPE_NAMES,
) -> MapPoint:
    """Return one point from its cells by column (what a form asks of one point).

    The columns and their rules are a CSV map's (:data:`CSV_COLUMNS`, and
    :func:`load_csv`'s ``check`` and ``types``); :class:`PointMapError` names
    the column at fault (its ``row`` is 0).
    """
    point = csv_point(
        {_column(key): value.strip() for key, value in values.items()}, 0, types
    )
    if check is not None:
        run_check(check, point, 0, "address")
    return point


def cells_of(point: MapPoint) -> dict[str, str]:
    """Return a point's cells by column, as :func:`point_of` reads them back."""
    rows = list(csv.reader(io.StringIO(dump_csv(PointMap((point,))))))
    return dict(zip(rows[0], rows[1], strict=True))


def _is_content(line: str) -> bool:
    stripped = line.strip()
    return bool(stripped) and not stripped.startswith("#")


def _column(name: str) -> str:
    """Return a header cell's column: lower case, aliases resolved."""
    column = name.strip().lower().replace(" ", "_")
    return CSV_ALIASES.get(column, column)


def csv_point(
    values: Mapping[str, str], row: int, types: Iterable[str] = TYPE_NAMES
) -> MapPoint:
    """Return the point of one CSV row (its cells by column); ``types``: see load_csv."""

    def required(column: str) -> str:
        if not (value := values.get(column, "")):
            raise PointMapError("is empty", row=row, column=column)
        return value

    name = required("name")
    address = values.get(CSV_AREA, "") + required("address")
    type_text = required("type")
    length = _integer(values.get("length", ""), row, "length")
    found = data_type(type_text, length)
    if found is None:
        raise PointMapError(
            f"unknown type {type_text!r} (known: {', '.join(types).upper()})",
            row=row,
            column="type",
        )
    writable = _flag(values, row, "writable")
    invert = _flag(values, row, "invert")
    if invert and found.kind is not ValueKind.BOOL:
        raise PointMapError(
            f"only a BOOL can be inverted, not {type_text.upper()}",
            row=row,
            column="invert",
        )
    scale = _number(values.get("scale", ""), row, "scale", 1.0)
    if scale == 0:
        raise PointMapError("must not be 0", row=row, column="scale")
    minimum = _optional_number(values.get("min", ""), row, "min")
    maximum = _optional_number(values.get("max", ""), row, "max")
    if minimum is not None and maximum is not None and minimum > maximum:
        raise PointMapError(
            f"{minimum:g} is above max {maximum:g}", row=row, column="min"
        )
    return MapPoint(
        id=values.get("id") or name,
        name=name,
        address=address,
        type=found,
        access=Access.READ_WRITE if writable else Access.READ,
        unit=values.get("unit", ""),
        scale=scale,
        offset=_number(values.get("offset", ""), row, "offset", 0.0),
        minimum=minimum,
        maximum=maximum,
        step=_optional_number(values.get("step", ""), row, "step"),
        device=values.get("device", ""),
        platform=values.get("platform", "").lower(),
        device_class=values.get("device_class", "").lower(),
        invert=invert,
        description=values.get("description", ""),
    )


def _flag(values: Mapping[str, str], row: int, column: str) -> bool:
    """Read a yes/no cell (empty: no)."""
    text = values.get(column, "").lower()
    if text not in _TRUE | _FALSE:
        raise PointMapError(
            f"{values[column]!r} is neither yes nor no", row=row, column=column
        )
    return text in _TRUE


def _number(text: str, row: int, column: str, default: float) -> float:
    found = _optional_number(text, row, column)
    return default if found is None else found


def _optional_number(text: str, row: int, column: str) -> float | None:
    """Read a number (a decimal comma too); None for an empty cell."""
    if not text:
        return None
    try:
        number = float(text.replace(",", "."))
    except ValueError:
        raise PointMapError(
            f"{text!r} is not a number", row=row, column=column
        ) from None
    if not math.isfinite(number):
        raise PointMapError(f"{text!r} is not a number", row=row, column=column)
    return number


def _integer(text: str, row: int, column: str) -> int | None:
    if not text:
        return None
    if not text.isdigit() or int(text) == 0:
        raise PointMapError(
            f"{text!r} is not a positive whole number", row=row, column=column
        )
    return int(text)


def dump_csv(point_map: PointMap) -> str:
    """Return a map as CSV (what :func:`load_csv` reads back to the same points)."""
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(CSV_COLUMNS)
    for point in point_map.points:
        out.write(_first_cell(point.id) + ",")
        writer.writerow(
            [
                point.name,
                point.address,
                type_name(point.type),
                "" if point.type.length is None else point.type.length,
                point.unit,
                _number_text(point.scale, 1.0),
                _number_text(point.offset, 0.0),
                "yes" if point.access.writable else "no",
                _number_text(point.minimum),
                _number_text(point.maximum),
                _number_text(point.step),
                point.device,
                point.platform,
                point.device_class,
                "yes" if point.invert else "",
                point.description,
            ]
        )
    return out.getvalue()


def _first_cell(text: str) -> str:
    """Return a row's first cell: quoted where CSV needs it, and when it starts with #.

    (Unquoted, a row whose first cell starts with # is a comment.)
    """
    if text.lstrip().startswith("#") or any(char in text for char in ',"\r\n'):
        return '"' + text.replace('"', '""') + '"'
    return text


def _number_text(value: float | None, default: float | None = None) -> str:
    if value is None or value == default:
        return ""
    return repr(float(value))


def decode_text(data: bytes) -> str:
    """Decode a file: UTF-8 (with or without a BOM), else Windows-1250."""
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError:
        return data.decode("cp1250", errors="replace")


type Loader = Callable[[str, AddressCheck | None, Iterable[str]], PointMap]
"""A format's reader, the plug-in point of point maps: a file's text, the
source's address check (or None) and the type names a point may take, to a
:class:`PointMap` (or :class:`PointMapError`). A system declares the formats it
takes, each with its loader, in its descriptor (``point_map_loaders``): the CSV
of this module (:data:`CSV`), or one of its own (Mervis's ``.vlist``), written
with this module's parts (:func:`csv_point`, :func:`run_check`, :func:`data_type`)."""

CSV: Final[Mapping[str, Loader]] = MappingProxyType({"csv": load_csv})
"""The core's own format, by the file name's ending: a CSV map."""


def load(
    data: bytes,
    file_name: str,
    loaders: Mapping[str, Loader] = CSV,
    check: AddressCheck | None = None,
    types: Iterable[str] = TYPE_NAMES,
) -> PointMap:
    """Read a map from a file's bytes, in the format its name ends with.

    ``loaders`` are the formats the caller takes, by the file name's ending (a
    descriptor's ``point_map_loaders``); a file of another format, or larger
    than :data:`MAX_FILE_BYTES`, is refused. ``types`` are the type names a
    CSV's unknown type's error lists (a ``.vlist`` names its project's own).
    """
    if len(data) > MAX_FILE_BYTES:
        raise PointMapError(f"larger than {MAX_FILE_BYTES // (1024 * 1024)} MiB")
    extension = file_name.rpartition(".")[2].lower() if "." in file_name else ""
    if extension not in loaders:
        raise PointMapError(f"not a {' or '.join(f'.{name}' for name in loaders)} file")
    return loaders[extension](decode_text(data), check, types)


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
        points=points, values={}, roots=(), skipped_roots=(), devices=devices
    )
