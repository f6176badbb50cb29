"""Point maps: the points of a device that does not list them, as the user supplies them.

Some systems have no listing of their values: the integrator exports a project's
variables from an IDE (a Mervis ``.vlist``) or keeps a register list in a
spreadsheet (a CSV). A :class:`PointMap` is that list in neutral terms, one
:class:`MapPoint` per value: a stable ``id`` (what the point's key, and so its
entity's unique ID, is made of -- never a row number), a display name, the
address the source reads, a data type, access, unit, scale and offset, a range
and a step, the device it belongs to and what the user wants it to be.

Loaders read the formats (:data:`LOADERS`; :func:`load` picks one by the file's
name). A file with an error imports nothing: :class:`PointMapError` names the row
(1 is the header's line) and the column. Rows a loader cannot use but a file may
legitimately hold (a type it does not know) are kept out and reported in
:attr:`PointMap.skipped`. A map is stored as JSON (:meth:`PointMap.as_json`,
:meth:`PointMap.from_json`). Nothing here does I/O.
"""

from collections.abc import Callable, Iterable, Mapping
import csv
from dataclasses import dataclass, field, replace
import io
import math
import re
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


def _check(check: AddressCheck, point: MapPoint, row: int, column: str) -> None:
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
        point = _csv_point(values, row, types)
        if check is not None:
            _check(check, point, row, "address")
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
    point = _csv_point(
        {_column(key): value.strip() for key, value in values.items()}, 0, types
    )
    if check is not None:
        _check(check, point, 0, "address")
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


def _csv_point(
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


# --- Mervis .vlist ---------------------------------------------------------------

VLIST_HEADER: Final = (
    "project",
    "name",
    "type",
    "commuid",
    "offset",
    "length",
    "parenttypefamily",
    "historyid",
)
VLIST_OWN_COLUMNS: Final = tuple(
    column
    for column in CSV_COLUMNS
    if column not in VLIST_HEADER and column not in ("id", "address", "device")
)
"""A CSV map's columns a ``.vlist`` may have after the IDE's (``unit``,
``writable``, ``min``, ...): what a user would otherwise set point by point in
the options, read as a CSV map's cells are (an empty cell sets nothing)."""
ENUM_BYTES: Final = 4
"""An enumeration's width: the web panel encodes every enum as a 32-bit integer."""
# How many bytes a type of no fixed bit width takes (ticks are 64-bit; a TIME
# may also be a 32-bit count of them).
_TICK_BYTES: Final[Mapping[ValueKind, frozenset[int]]] = MappingProxyType(
    {
        ValueKind.DATETIME: frozenset({8}),
        ValueKind.DATE: frozenset({8}),
        ValueKind.TIME: frozenset({4, 8}),
        ValueKind.DURATION: frozenset({4, 8}),
    }
)
# A name: $segment$ parts joined by dots, array indexes after any of them.
_NAME_PART: Final = re.compile(r"\$([^$]*[^$\s][^$]*)\$|\[([0-9]+(?:,[0-9]+)*)\]")
_TYPE: Final = re.compile(r"\$([^$]*)\$")
_NAME: Final = re.compile(
    r"\$[^$]*[^$\s][^$]*\$(?:\.\$[^$]*[^$\s][^$]*\$|\[[0-9]+(?:,[0-9]+)*\])*"
)


def decode_text(data: bytes) -> str:
    """Decode a file: UTF-8 (with or without a BOM), else Windows-1250."""
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError:
        return data.decode("cp1250", errors="replace")


def readable_name(parts: Iterable[str]) -> str:
    """Spell a name's parts in words: ``("obyvak", "teplotaZadana_1")`` → ``Obyvak teplota zadana 1``.

    Underscores are spaces and a lower-case letter followed by a capital starts
    a word; dots inside a part stay (``di_1.04`` → ``di 1.04``).
    """
    words: list[str] = []
    for part in parts:
        spaced = []
        previous = ""
        for char in part.replace("_", " "):
            if previous.islower() and char.isupper():
                spaced.append(" ")
            spaced.append(char)
            previous = char
        words.append("".join(spaced))
    text = " ".join(" ".join(words).split()).lower()
    return text[:1].upper() + text[1:]


@dataclass(frozen=True, slots=True, kw_only=True)
class _VlistRow:
    """One row of a ``.vlist``, checked but not yet a point."""

    row: int
    project: str
    ident: str
    parts: tuple[str, ...]
    parents: tuple[str, ...]
    """The lower-case IDs of what the name sits in, outermost first."""
    type_text: str
    commuid: str
    offset: str
    length: int
    family: str
    own: Mapping[str, str] = field(default_factory=dict)
    """The row's non-empty cells of :data:`VLIST_OWN_COLUMNS`."""


def _vlist_name(text: str, row: int) -> tuple[str, tuple[str, ...], tuple[str, ...]]:
    """Parse ``$a$.$b$[2]``: its ID ``a.b[2]``, its parts, the IDs above it.

    Anything but ``$``-wrapped segments joined by dots, with array indexes
    after them, is refused.
    """
    if not _NAME.fullmatch(text):
        raise PointMapError(f"{text!r} is not a name", row=row, column="Name")
    ident = ""
    parts: list[str] = []
    parents: list[str] = []
    for match in _NAME_PART.finditer(text):
        if ident:
            parents.append(ident.lower())
        segment, index = match.groups()
        if segment is not None:
            ident = f"{ident}.{segment}" if ident else segment
            parts.append(segment)
        else:
            ident += f"[{index}]"
            parts.append(index.replace(",", " "))
    return ident, tuple(parts), tuple(parents)


def _vlist_rows(text: str) -> list[_VlistRow]:
    """Read a ``.vlist``'s rows, its header and cells checked."""
    lines = text.lstrip("\ufeff").splitlines()
    content = [(index + 1, line) for index, line in enumerate(lines) if line.strip()]
    if not content or not content[0][1].lower().startswith("#ver:"):
        raise PointMapError("not a .vlist file (no #ver: line)", row=1)
    version = content[0][1].split(":", 1)[1].strip()
    if not version.startswith("1."):
        raise PointMapError(f"version {version} is not 1.x", row=content[0][0])
    if len(content) < 2:
        raise PointMapError("the file has no header", row=content[0][0])
    header_row, header_line = content[1]
    header = [cell.strip().lower() for cell in header_line.split(";")]
    missing = [name for name in VLIST_HEADER[:6] if name not in header]
    if missing:
        raise PointMapError(f"the header has no {missing[0]!r} column", row=header_row)
    position = {name: header.index(name) for name in header if name}
    rows: list[_VlistRow] = []
    for row, line in content[2:]:
        cells = line.split(";")
        # The IDE's last column may be cut; a map's own columns may be too.
        if len(cells) < min(len(header), len(VLIST_HEADER)) - 1:
            raise PointMapError(
                f"{len(cells)} cells, the header has {len(header)}", row=row
            )

        def cell(name: str, cells: list[str] = cells) -> str:
            index = position.get(name)
            return (
                cells[index].strip() if index is not None and index < len(cells) else ""
            )

        ident, parts, parents = _vlist_name(cell("name"), row)
        wrapped = _TYPE.fullmatch(cell("type"))
        type_text = wrapped.group(1).strip() if wrapped else cell("type")
        commuid, offset, length = cell("commuid"), cell("offset"), cell("length")
        for column, value in (
            ("CommUid", commuid),
            ("Offset", offset),
            ("Length", length),
        ):
            if not value.isdigit():
                raise PointMapError(
                    f"{value!r} is not a number", row=row, column=column
                )
        if int(length) == 0:
            raise PointMapError("must not be 0", row=row, column="Length")
        rows.append(
            _VlistRow(
                row=row,
                project=cell("project"),
                ident=ident,
                parts=parts,
                parents=parents,
                type_text=type_text,
                commuid=commuid,
                offset=str(int(offset)),
                length=int(length),
                family=cell("parenttypefamily").lower() or "none",
                own={
                    column: text
                    for column in VLIST_OWN_COLUMNS
                    if (text := cell(column))
                },
            )
        )
    return rows


def _vlist_type(row: _VlistRow, containers: frozenset[str]) -> DataType | str | None:
    """Return a row's data type, why it has none, or None for a container.

    A type a map does not know is a container when other rows sit in it (a
    function block, a struct, an array: its members are the points), an
    enumeration when it is 4 bytes wide (the web panel encodes enums as 32-bit
    integers), and reported otherwise. A known type's width must be the row's.
    """
    found = data_type(row.type_text)
    if found is None:
        if row.ident.lower() in containers:
            return None
        if row.length == ENUM_BYTES:
            return DataType(kind=ValueKind.INTEGER, bits=32)
        return f"type {row.type_text!r} is not one a map knows"
    if found.kind is ValueKind.STRING:
        return replace(found, length=row.length, encoding="utf-8")
    widths = type_widths(found)
    if row.length not in widths:
        wanted = " or ".join(str(width) for width in sorted(widths))
        return f"type {row.type_text!r} takes {wanted} bytes, the row says {row.length}"
    return found


def type_widths(data_type: DataType) -> frozenset[int]:
    """Return the bytes a value of a fixed-width type may take in a ``.vlist`` row.

    Ticks (dates, times, durations) by their table, any other type by its bits
    (at least one byte). Text has no fixed width: do not ask for it.
    """
    widths = _TICK_BYTES.get(data_type.kind)
    if widths is None:
        widths = frozenset({max(1, (data_type.bits or 8) // 8)})
    return widths


def load_vlist(text: str, check: AddressCheck | None = None) -> PointMap:
    """Read a Mervis IDE ``.vlist`` export (see MERVIS.md).

    ``#ver:1.0``, a header, then ``;``-separated rows: project, the dotted name
    of ``$``-wrapped segments (array indexes in brackets), the ``$type$``,
    CommUid, offset and length in bytes, the parent's type family (``none``,
    ``fb``, ``struct``, ``array``) and a history ID.

    A point's ID is its name without the ``$`` (the CommUid may change when the
    project is compiled again; the name does not), its name that spelled in
    words (:func:`readable_name`), its address ``CommUid[offset,length]``. Its
    device is the innermost function block instance it sits in, else its
    top-level segment (a namespace, a struct, an array); a top-level variable
    has none. A row of a type no map knows is a function block, struct or
    array whose members are rows of their own (not a point, not reported), a
    4-byte enumeration (a 32-bit integer; ``details["enum"]`` names its type),
    or reported in ``skipped``; so is a row whose length is not its type's.
    The project's name is the map's ``properties["project"]``. Columns of a
    CSV map after the IDE's (:data:`VLIST_OWN_COLUMNS`: a unit, writable, a
    range) set what the options would, point by point.
    """
    rows = _vlist_rows(text)
    skipped: list[tuple[int, str]] = []
    containers = frozenset(parent for row in rows for parent in row.parents)
    blocks = frozenset(row.parents[-1] for row in rows if row.family == "fb")
    names = {row.ident.lower(): row.parts for row in rows}
    points: list[MapPoint] = []
    seen: dict[str, int] = {}
    for row in rows:
        found = _vlist_type(row, containers)
        if found is None:
            continue
        if isinstance(found, str):
            skipped.append((row.row, found))
            continue
        details = {
            "project": row.project,
            "commuid": row.commuid,
            "offset": row.offset,
            "length": str(row.length),
            "family": row.family,
        }
        if data_type(row.type_text) is None:
            details["enum"] = row.type_text
        point = MapPoint(
            id=row.ident,
            name=readable_name(row.parts),
            address=f"{row.commuid}[{row.offset},{row.length}]",
            type=found,
            device=_vlist_device(row, blocks, names),
            details=MappingProxyType(details),
        )
        if row.own:
            point = _with_own_cells(point, row)
        if check is not None:
            _check(check, point, row.row, "CommUid")
        if point.key in seen:
            raise PointMapError(
                f"the name {row.ident!r} is taken by row {seen[point.key]}",
                row=row.row,
                column="Name",
            )
        seen[point.key] = row.row
        points.append(point)
    if not points:
        raise PointMapError("the file holds no variable a map knows")
    project = rows[0].project
    return PointMap(
        tuple(points),
        "vlist",
        tuple(skipped),
        MappingProxyType({"project": project} if project else {}),
    )


def _with_own_cells(point: MapPoint, row: _VlistRow) -> MapPoint:
    """Return a ``.vlist`` row's point with its own columns' cells applied.

    The cells are read as a CSV map's (the same checks, the same errors).
    """
    cells = {"name": point.name, "address": point.address, **row.own}
    read = _csv_point({**cells, "type": type_name(point.type)}, row.row)
    return replace(
        point,
        **{
            attribute: getattr(read, attribute)
            for attribute in (
                "access",
                "unit",
                "scale",
                "minimum",
                "maximum",
                "step",
                "platform",
                "device_class",
                "invert",
                "description",
            )
        },
    )


def _vlist_device(
    row: _VlistRow, blocks: frozenset[str], names: Mapping[str, tuple[str, ...]]
) -> str:
    """Return the device of a row: its innermost function block, else its top level."""
    for parent in reversed(row.parents):
        if parent in blocks:
            # A block's own row may be missing: its name is its member's first parts.
            parts = names.get(parent, row.parts[: row.parents.index(parent) + 1])
            return readable_name(parts)
    return readable_name(row.parts[:1]) if row.parents else ""


type Loader = Callable[[str, AddressCheck | None], PointMap]

LOADERS: Final[Mapping[str, Loader]] = MappingProxyType(
    {"csv": load_csv, "vlist": load_vlist}
)
"""The formats a map is read from, by the file name's ending."""


def load(
    data: bytes,
    file_name: str,
    formats: Iterable[str] = LOADERS,
    check: AddressCheck | None = None,
    types: Iterable[str] = TYPE_NAMES,
) -> PointMap:
    """Read a map from a file's bytes, in the format its name ends with.

    ``formats`` are those the caller takes; a file of another format, or larger
    than :data:`MAX_FILE_BYTES`, is refused. ``types`` are the type names a
    CSV's unknown type's error lists (a ``.vlist`` names its project's own).
    """
    if len(data) > MAX_FILE_BYTES:
        raise PointMapError(f"larger than {MAX_FILE_BYTES // (1024 * 1024)} MiB")
    taken = tuple(formats)
    extension = file_name.rpartition(".")[2].lower() if "." in file_name else ""
    if extension not in taken or extension not in LOADERS:
        raise PointMapError(f"not a {' or '.join(f'.{name}' for name in taken)} file")
    if extension == "csv":
        return load_csv(decode_text(data), check, types)
    return LOADERS[extension](decode_text(data), check)


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
