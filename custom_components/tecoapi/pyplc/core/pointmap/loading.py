"""Loading a point map from a file: its bytes decoded, its format picked by its name.

Nothing here does I/O: the caller reads the file.
"""

from collections.abc import Iterable, Mapping
from types import MappingProxyType
from typing import Final, Protocol

from ..texts import Template
from .csvmap import AddressCheck, load_csv
from .model import TYPE_NAMES, PointMap, PointMapError

MAX_FILE_BYTES: Final = 8 * 1024 * 1024
"""The largest file a loader reads."""
TOO_LARGE: Final = Template("map_too_large", "larger than {mib} MiB")
NOT_FORMAT: Final = Template("map_not_format", "not a {format} file")
NOT_FORMATS: Final = Template(
    "map_not_formats", "not a file of these formats: {formats}"
)


def decode_text(data: bytes) -> str:
    """Decode a file: UTF-8 (with or without a BOM), else Windows-1250."""
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError:
        return data.decode("cp1250", errors="replace")


class Loader(Protocol):
    """A format's reader, the plug-in point of point maps.

    A file's text, the source's address check (or None) and the type names a
    point may take, to a :class:`PointMap` (or :class:`PointMapError`);
    ``file_name`` is the name the file was uploaded under ("" when none is
    known), for a format whose names say something of the map (a Mervis
    ``.vlist`` names its project). A system declares the formats it takes,
    each with its loader, in its descriptor (``point_map_loaders``): the core's
    CSV (:data:`CSV`), or one of its own (Mervis's ``.vlist``),
    written with the package's parts (:func:`~.csvmap.csv_point`,
    :func:`~.csvmap.run_check`, :func:`~.model.data_type`).
    """

    def __call__(
        self,
        text: str,
        check: AddressCheck | None = None,
        types: Iterable[str] = TYPE_NAMES,
        /,
        *,
        file_name: str = "",
    ) -> PointMap:
        """Read a map from a file's text."""
        ...


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
        raise PointMapError(TOO_LARGE(mib=MAX_FILE_BYTES // (1024 * 1024)))
    extension = file_name.rpartition(".")[2].lower() if "." in file_name else ""
    if extension not in loaders:
        endings = [f".{name}" for name in loaders]
        raise PointMapError(
            NOT_FORMAT(format=endings[0])
            if len(endings) == 1
            else NOT_FORMATS(formats=", ".join(endings))
        )
    return loaders[extension](decode_text(data), check, types, file_name=file_name)
