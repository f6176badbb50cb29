"""Mervis's point map: the IDE's ``.vlist`` export, read as a :class:`PointMap`.

A loader of the core's point maps (:data:`~..core.pointmap.Loader`): the Mervis
descriptor declares it for the ``vlist`` format, so the core reads ``.vlist``
files without knowing them. Each variable of the project is a point; members of
a function block, struct or array sit on their parent's device; types no map
knows are reported in ``skipped`` (see :func:`load_vlist`).
"""

from collections import Counter
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field, replace
import re
from types import MappingProxyType
from typing import Any, Final

from ..core.models import DataType, ValueKind
from ..core.pointmap import (
    CSV_COLUMNS,
    TYPE_NAMES,
    AddressCheck,
    MapPoint,
    PointMap,
    PointMapError,
    csv_point,
    data_type,
    point_key,
    run_check,
    type_name,
)
from ..core.pointmap.csvmap import CELLS, NO_COLUMN, NO_HEADER, NOT_NUMBER, ZERO
from ..core.texts import Template

NOT_A_NAME: Final = Template("vlist_not_name", "{name} is not a name")
NO_VERSION: Final = Template("vlist_no_version", "not a .vlist file (no #ver: line)")
VERSION: Final = Template("vlist_version", "version {version} is not 1.x")
NAME_TAKEN: Final = Template(
    "vlist_name_taken", "the name {name} is taken by row {row}"
)
NO_VARIABLE: Final = Template(
    "vlist_no_variable", "the file holds no variable a map knows"
)
NO_PROJECT: Final = Template(
    "vlist_no_project",
    "the file has no variables of a project {project} (its projects: {projects})",
)

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
VLIST_TYPES: Final[Mapping[str, str]] = MappingProxyType({"bool_1": "bool"})
"""Types real exports name beside a map's, as the map's: ``bool_1`` is a
function block's ``en`` input, a flag of one byte."""
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
# A name: $segment$ parts joined by dots, array indexes after any of them, or
# as segments of their own ($in$.$[1]$, as real exports write them).
_NAME_PART: Final = re.compile(r"\$([^$]*[^$\s][^$]*)\$|\[([0-9]+(?:,[0-9]+)*)\]")
_INDEX: Final = re.compile(r"\[\s*([0-9]+(?:\s*,\s*[0-9]+)*)\s*\]")
_TYPE: Final = re.compile(r"\$([^$]*)\$")
_NAME: Final = re.compile(
    r"\$[^$]*[^$\s][^$]*\$(?:\.\$[^$]*[^$\s][^$]*\$|\[[0-9]+(?:,[0-9]+)*\])*"
)


UNIPI_WORDS: Final = frozenset(
    {"di", "do", "ro", "ai", "ao", "air", "uart", "led", "uled", "pwm", "ds"}
)
"""The abbreviations Unipi writes in capitals in its boards' I/O names (DI, RO, AI...)."""
_MODEL: Final = re.compile(r"[a-z]+[0-9]+[a-z0-9]*")
"""A board's model or a bus in a ``hw`` name (``l203``, ``s103``, ``rs485``)."""
HW: Final = "hw"
"""The namespace of a Unipi project's boards: their I/O, settings and registers."""


def readable_name(parts: Iterable[str], *, hardware: bool = False) -> str:
    """Spell a name's parts in words: ``("obyvak", "teplotaZadana_1")`` → ``Obyvak teplota zadana 1``.

    Underscores are spaces and a lower-case letter followed by a capital starts
    a word; dots inside a part stay (``di_1.04`` → ``di 1.04``). A board's name
    (``hardware``: the ``hw`` namespace) keeps Unipi's capitals: its I/O
    abbreviations (:data:`UNIPI_WORDS`) and its model (``Hw neuron L203 DI
    1.04``).
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
    if hardware:
        text = " ".join(
            word.upper() if word in UNIPI_WORDS or _MODEL.fullmatch(word) else word
            for word in text.split(" ")
        )
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
        raise PointMapError(NOT_A_NAME(name=repr(text)), row=row, column="Name")
    ident = ""
    parts: list[str] = []
    parents: list[str] = []
    for match in _NAME_PART.finditer(text):
        if ident:
            parents.append(ident.lower())
        segment, index = match.groups()
        if segment is not None and (element := _INDEX.fullmatch(segment)):
            # An element of an array, a segment of its own: $in$.$[1]$ is in[1].
            segment, index = None, re.sub(r"\s", "", element.group(1))
            if not ident:
                raise PointMapError(NOT_A_NAME(name=repr(text)), row=row, column="Name")
        if segment is not None:
            ident = f"{ident}.{segment}" if ident else segment
            parts.append(segment)
        else:
            ident += f"[{index}]"
            parts.append(str(index).replace(",", " "))
    return ident, tuple(parts), tuple(parents)


def _vlist_rows(text: str) -> list[_VlistRow]:
    """Read a ``.vlist``'s rows, its header and cells checked."""
    lines = text.lstrip("\ufeff").splitlines()
    content = [(index + 1, line) for index, line in enumerate(lines) if line.strip()]
    if not content or not content[0][1].lower().startswith("#ver:"):
        raise PointMapError(NO_VERSION(), row=1)
    version = content[0][1].split(":", 1)[1].strip()
    if not version.startswith("1."):
        raise PointMapError(VERSION(version=version), row=content[0][0])
    if len(content) < 2:
        raise PointMapError(NO_HEADER(), row=content[0][0])
    header_row, header_line = content[1]
    header = [cell.strip().lower() for cell in header_line.split(";")]
    missing = [name for name in VLIST_HEADER[:6] if name not in header]
    if missing:
        raise PointMapError(NO_COLUMN(column=repr(missing[0])), row=header_row)
    position = {name: header.index(name) for name in header if name}
    rows: list[_VlistRow] = []
    for row, line in content[2:]:
        cells = line.split(";")
        # The IDE's last column may be cut; a map's own columns may be too.
        if len(cells) < min(len(header), len(VLIST_HEADER)) - 1:
            raise PointMapError(CELLS(cells=len(cells), header=len(header)), row=row)

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
                    NOT_NUMBER(value=repr(value)), row=row, column=column
                )
        if int(length) == 0:
            raise PointMapError(ZERO(), row=row, column="Length")
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
    found = data_type(VLIST_TYPES.get(row.type_text.lower(), row.type_text))
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


def load_vlist(
    text: str,
    check: AddressCheck | None = None,
    types: Iterable[str] = TYPE_NAMES,
    *,
    file_name: str = "",
) -> PointMap:
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
    The installation's project (:func:`installation`, from the rows and
    ``file_name``) is the map's ``properties["project"]``, every project the
    rows name its ``properties["projects"]`` (``;``-separated). Columns of a
    CSV map after the IDE's (:data:`VLIST_OWN_COLUMNS`: a unit, writable, a
    range) set what the options would, point by point. ``types`` is taken as
    every loader takes it (:data:`~..core.pointmap.Loader`) and not used: a
    ``.vlist``'s unknown types are its project's own, reported in ``skipped``.
    """
    del types
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
        if found.kind is ValueKind.INTEGER and data_type(row.type_text) is None:
            details["enum"] = row.type_text
        point = MapPoint(
            id=row.ident,
            name=readable_name(row.parts, hardware=row.parts[0].lower() == HW),
            address=f"{row.commuid}[{row.offset},{row.length}]",
            type=found,
            device=_vlist_device(row, blocks, names),
            details=MappingProxyType(details),
        )
        if row.own:
            point = _with_own_cells(point, row)
        if check is not None:
            run_check(check, point, row.row, "CommUid")
        if point.key in seen:
            raise PointMapError(
                NAME_TAKEN(name=repr(row.ident), row=seen[point.key]),
                row=row.row,
                column="Name",
            )
        seen[point.key] = row.row
        points.append(point)
    if not points:
        raise PointMapError(NO_VARIABLE())
    projects = list(dict.fromkeys(row.project for row in rows if row.project))
    properties = {}
    if project := installation([row.project for row in rows], file_name):
        properties["project"] = project
        if project == exported_as(projects, file_name):
            properties["exported_as"] = project
    if len(projects) > 1:
        properties["projects"] = ";".join(projects)
    return PointMap(
        tuple(points), "vlist", tuple(skipped), MappingProxyType(properties)
    )


_LIBRARY: Final = re.compile(r"lib\..*|base", re.IGNORECASE)
"""The projects of Mervis's libraries a solution's export carries (``Lib.Core``,
``Lib.Iec``, ``Lib.Hvac``, ``base``): never an installation's."""
_EXPORT_NAME: Final = re.compile(
    r"(.+)_[0-9a-f]{8}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{12}",
    re.IGNORECASE,
)
"""The name the IDE gives an export: ``<project>_<guid>.vlist``."""


def is_library(project: str) -> bool:
    """Whether a project of an export is one of Mervis's libraries."""
    return _LIBRARY.fullmatch(project.strip()) is not None


def installation(projects: Sequence[str], file_name: str = "") -> str:
    """Return the installation's project among an export's rows' (their ``Project``).

    A real export holds rows of the installation's own project, of shared
    projects of its solution and of libraries, the first row often a
    library's. The IDE names the file ``<project>_<guid>.vlist`` after the
    installation's project: that project, when the rows have it; else the
    project of the most rows (the first of those, on a tie) that is not a
    library; never a library ("": none).
    """
    counts = Counter(name for name in projects if name and not is_library(name))
    return exported_as(list(counts), file_name) or max(
        counts, key=counts.__getitem__, default=""
    )


def exported_as(projects: Iterable[str], file_name: str) -> str:
    """Return the project (of these) a file's name names as the IDE names an export ("": none)."""
    stem = file_name.replace("\\", "/").rpartition("/")[2].rpartition(".")[0]
    if (named := _EXPORT_NAME.fullmatch(stem)) is None:
        return ""
    wanted = named.group(1).casefold()
    return next(
        (
            name
            for name in projects
            if name.casefold() == wanted and not is_library(name)
        ),
        "",
    )


def projects_of(point_map: PointMap) -> list[str]:
    """Return the projects a map's rows named (its own, for a map stored before they were kept)."""
    properties = point_map.properties
    listed = properties.get("projects") or properties.get("project", "")
    return [name for name in listed.split(";") if name]


def with_project(point_map: PointMap, project: str) -> PointMap:
    """Return a map of the installation's project the user names (its rows' spelling).

    Raises :class:`PointMapError` for a project the file has no rows of, or a
    library's (the message lists the file's projects).
    """
    wanted = project.strip()
    known = [name for name in projects_of(point_map) if not is_library(name)]
    found = next((name for name in known if name.casefold() == wanted.casefold()), None)
    if found is None:
        raise PointMapError(
            NO_PROJECT(project=repr(wanted), projects=", ".join(known) or "—"),
            column="project",
        )
    return replace(
        point_map,
        properties=MappingProxyType({**point_map.properties, "project": found}),
    )


def _with_own_cells(point: MapPoint, row: _VlistRow) -> MapPoint:
    """Return a ``.vlist`` row's point with its own columns' cells applied.

    The cells are read as a CSV map's (the same checks, the same errors).
    """
    cells = {"name": point.name, "address": point.address, **row.own}
    read = csv_point({**cells, "type": type_name(point.type)}, row.row)
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
                "state_class",
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


PROJECT: Final = "project"
"""The connection form's field naming the installation's project (and the upload's)."""
_OLD_ELEMENT: Final = re.compile(r"\.(?=\[)")
"""The dot before an array element's index in the IDs loaders made before an
element's own segment was read as its index (``in.[1]``, now ``in[1]``)."""


def adopt_vlist(
    point_map: PointMap, form: Mapping[str, Any], stored: PointMap | None
) -> PointMap:
    """Return an uploaded ``.vlist``'s map as an entry takes it (the descriptor's ``adopt_map``).

    Its installation's project is the one the user names in the form
    (:func:`with_project`); else the one the file's name names; else the
    entry's stored map's, when the file has rows of it and it is no library
    (the user may have named it before); else the loader's choice. Each point
    the stored map had keeps the ID the stored map spells it with: an array's
    element stored as ``in.[1]`` stays that (its entity's unique ID is made of
    it).
    """
    typed = str(form.get(PROJECT) or "").strip()
    if typed:
        point_map = with_project(point_map, typed)
    elif stored is not None and "exported_as" not in point_map.properties:
        kept = stored.properties.get("project", "")
        if kept and not is_library(kept) and kept in projects_of(point_map):
            point_map = with_project(point_map, kept)
    if stored is None:
        return point_map
    spelled = {
        point_key(canonical): point.id
        for point in stored.points
        if (canonical := _OLD_ELEMENT.sub("", point.id)) != point.id
    }
    if not spelled:
        return point_map
    return replace(
        point_map,
        points=tuple(
            replace(point, id=spelled[point.key]) if point.key in spelled else point
            for point in point_map.points
        ),
    )
