"""A point map as a CSV: its columns, read (with a source's check) and written.

The columns and their spellings are the documentation's (``docs/point-map-csv.md``);
a system whose format is not a CSV writes its loader with these parts
(:func:`csv_point`, :func:`run_check`). Nothing here does I/O.
"""

from collections.abc import Callable, Iterable, Mapping
import csv
import io
import math
from types import MappingProxyType
from typing import Final

from ..models import (
    NUMERIC_KINDS,
    Access,
    ValueKind,
)
from ..texts import Template, Text
from .model import (
    TYPE_NAMES,
    MapPoint,
    PointMap,
    PointMapError,
    data_type,
    type_name,
)

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
    "state_class",
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
STATE_CLASSES: Final = ("measurement", "measurement_angle", "total", "total_increasing")
"""The state classes a point may ask for (how its history is kept)."""
_TRUE: Final = frozenset({"1", "true", "yes", "y", "x", "rw", "w", "write"})
_FALSE: Final = frozenset({"", "0", "false", "no", "n", "r", "ro", "read"})

# What a CSV map's errors say.
NO_HEADER: Final = Template("map_no_header", "the file has no header")
NO_COLUMN: Final = Template("map_no_column", "the header has no {column} column")
UNKNOWN_COLUMN: Final = Template(
    "map_unknown_column", "unknown column {column} (known: {known})"
)
CELLS: Final = Template("map_cells", "{cells} cells, the header has {header}")
ID_ROW: Final = Template("map_id_row", "the ID {id} is taken by row {row}")
NO_POINT: Final = Template("map_no_point", "the file holds no point")
EMPTY: Final = Template("map_empty", "is empty")
UNKNOWN_TYPE: Final = Template(
    "map_unknown_type", "unknown type {type} (known: {known})"
)
NOT_INVERTED: Final = Template(
    "map_not_inverted", "only a BOOL can be inverted, not {type}"
)
UNKNOWN_STATE_CLASS: Final = Template(
    "map_unknown_state_class", "unknown state class {value} (known: {known})"
)
NO_STATE_CLASS: Final = Template(
    "map_no_state_class", "only a number has a state class, not {type}"
)
ZERO: Final = Template("map_zero", "must not be 0")
MIN_ABOVE_MAX: Final = Template("map_min_above_max", "{min} is above max {max}")
NOT_YES_NO: Final = Template("map_not_yes_no", "{value} is neither yes nor no")
NOT_NUMBER: Final = Template("map_not_number", "{value} is not a number")
NOT_WHOLE: Final = Template("map_not_whole", "{value} is not a positive whole number")

type AddressCheck = Callable[[MapPoint], Text | None]
"""A source's check of a point's address: None, or what is wrong with it.

A check that finds another column at fault (a type the address cannot hold)
raises :class:`PointMapError` naming that column; the loader adds the row.
"""


def run_check(check: AddressCheck, point: MapPoint, row: int, column: str) -> None:
    """Run a source's check of a point; raise its problem at the row and column."""
    try:
        problem = check(point)
    except PointMapError as err:
        raise PointMapError(err.text, row=row, column=err.column or column) from None
    if problem is not None:
        raise PointMapError(problem, row=row, column=column)


def load_csv(
    text: str,
    check: AddressCheck | None = None,
    types: Iterable[str] = TYPE_NAMES,
    *,
    file_name: str = "",
) -> PointMap:
    """Read a CSV map: a header of :data:`CSV_COLUMNS`, then one point a row.

    The delimiter is a comma or a semicolon (what spreadsheets in Czech and
    Slovak write), found from the header; blank rows and rows whose first cell
    starts with ``#`` are comments. ``check`` is the source's check of each
    address; ``types`` the type names an unknown type's error lists (those the
    source reads). Any error imports nothing. The file's name says nothing
    of a CSV map (``file_name`` is taken as every loader takes it).
    """
    del file_name
    lines = text.lstrip("\ufeff").splitlines()
    header_row = next(
        (index for index, line in enumerate(lines) if _is_content(line)), None
    )
    if header_row is None:
        raise PointMapError(NO_HEADER())
    header_line = lines[header_row]
    delimiter = ";" if header_line.count(";") > header_line.count(",") else ","
    reader = csv.reader(io.StringIO("\n".join(lines)), delimiter=delimiter)
    rows = list(reader)
    header = [_column(name) for name in rows[header_row]]
    for required in CSV_REQUIRED:
        if required not in header:
            raise PointMapError(NO_COLUMN(column=repr(required)), row=header_row + 1)
    unknown = [name for name in header if name and name not in (*CSV_COLUMNS, CSV_AREA)]
    if unknown:
        raise PointMapError(
            UNKNOWN_COLUMN(column=repr(unknown[0]), known=", ".join(CSV_COLUMNS)),
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
            raise PointMapError(CELLS(cells=len(cells), header=len(header)), row=row)
        values = {
            name: cells[position].strip() if position < len(cells) else ""
            for position, name in enumerate(header)
        }
        point = csv_point(values, row, types)
        if check is not None:
            run_check(check, point, row, "address")
        if point.key in seen:
            raise PointMapError(
                ID_ROW(id=repr(point.id), row=seen[point.key]),
                row=row,
                column="id" if values.get("id") else "name",
            )
        seen[point.key] = row
        points.append(point)
    if not points:
        raise PointMapError(NO_POINT())
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
            raise PointMapError(EMPTY(), row=row, column=column)
        return value

    name = required("name")
    address = values.get(CSV_AREA, "") + required("address")
    type_text = required("type")
    length = _integer(values.get("length", ""), row, "length")
    found = data_type(type_text, length)
    if found is None:
        raise PointMapError(
            UNKNOWN_TYPE(type=repr(type_text), known=", ".join(types).upper()),
            row=row,
            column="type",
        )
    writable = _flag(values, row, "writable")
    invert = _flag(values, row, "invert")
    if invert and found.kind is not ValueKind.BOOL:
        raise PointMapError(
            NOT_INVERTED(type=type_text.upper()), row=row, column="invert"
        )
    state_class = values.get("state_class", "").lower()
    if state_class and state_class not in STATE_CLASSES:
        raise PointMapError(
            UNKNOWN_STATE_CLASS(
                value=repr(state_class), known=", ".join(STATE_CLASSES)
            ),
            row=row,
            column="state_class",
        )
    if state_class and found.kind not in NUMERIC_KINDS:
        raise PointMapError(
            NO_STATE_CLASS(type=type_text.upper()), row=row, column="state_class"
        )
    scale = _number(values.get("scale", ""), row, "scale", 1.0)
    if scale == 0:
        raise PointMapError(ZERO(), row=row, column="scale")
    minimum = _optional_number(values.get("min", ""), row, "min")
    maximum = _optional_number(values.get("max", ""), row, "max")
    if minimum is not None and maximum is not None and minimum > maximum:
        raise PointMapError(
            MIN_ABOVE_MAX(min=f"{minimum:g}", max=f"{maximum:g}"), row=row, column="min"
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
        state_class=state_class,
        invert=invert,
        description=values.get("description", ""),
    )


def _flag(values: Mapping[str, str], row: int, column: str) -> bool:
    """Read a yes/no cell (empty: no)."""
    text = values.get(column, "").lower()
    if text not in _TRUE | _FALSE:
        raise PointMapError(
            NOT_YES_NO(value=repr(values[column])), row=row, column=column
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
            NOT_NUMBER(value=repr(text)), row=row, column=column
        ) from None
    if not math.isfinite(number):
        raise PointMapError(NOT_NUMBER(value=repr(text)), row=row, column=column)
    return number


def _integer(text: str, row: int, column: str) -> int | None:
    if not text:
        return None
    if not text.isdigit() or int(text) == 0:
        raise PointMapError(NOT_WHOLE(value=repr(text)), row=row, column=column)
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
                point.state_class,
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
