"""Point maps: the points of a device that does not list them, as the user supplies them.

Some systems have no listing of their values: the integrator exports a project's
variables from an IDE (a Mervis ``.vlist``) or keeps a register list in a
spreadsheet (a CSV). A :class:`PointMap` is that list in neutral terms, one
:class:`MapPoint` per value: a stable ``id`` (what the point's key, and so its
entity's unique ID, is made of -- never a row number), a display name, the
address the source reads, a data type, access, unit, scale and offset, a range
and a step, the device it belongs to and what the user wants it to be.

Loaders read the formats: :mod:`.csvmap` reads a CSV, and a system's subpackage
may have one of its own (:data:`Loader`; Mervis's ``.vlist`` in ``mervis.vlist``);
:func:`load` picks one of those a caller takes by the file's name. A file with an
error imports nothing: :class:`PointMapError` names the row (1 is the header's
line) and the column. Rows a loader cannot use but a file may
legitimately hold (a type it does not know) are kept out and reported in
:attr:`PointMap.skipped`. A map is stored as JSON (:meth:`PointMap.as_json`,
:meth:`PointMap.from_json`). Nothing here does I/O.

The parts: :mod:`.model` (the map, its points and types, its JSON and
catalogue), :mod:`.csvmap` (the CSV format), :mod:`.loading` (a file's bytes
to a map, by the loader its name picks); every name is importable from here.
"""

from .csvmap import (
    CSV_ALIASES,
    CSV_AREA,
    CSV_COLUMNS,
    CSV_REQUIRED,
    AddressCheck,
    cells_of,
    csv_point,
    dump_csv,
    load_csv,
    point_of,
    run_check,
)
from .loading import CSV, MAX_FILE_BYTES, Loader, decode_text, load
from .model import (
    FORMAT_VERSION,
    MAX_POINTS,
    TYPE_NAMES,
    MapPoint,
    PointMap,
    PointMapError,
    data_type,
    map_catalogue,
    point_key,
    type_name,
)

__all__ = [
    "CSV",
    "CSV_ALIASES",
    "CSV_AREA",
    "CSV_COLUMNS",
    "CSV_REQUIRED",
    "FORMAT_VERSION",
    "MAX_FILE_BYTES",
    "MAX_POINTS",
    "TYPE_NAMES",
    "AddressCheck",
    "Loader",
    "MapPoint",
    "PointMap",
    "PointMapError",
    "cells_of",
    "csv_point",
    "data_type",
    "decode_text",
    "dump_csv",
    "load",
    "load_csv",
    "map_catalogue",
    "point_key",
    "point_of",
    "run_check",
    "type_name",
]
