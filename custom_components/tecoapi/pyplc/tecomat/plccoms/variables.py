"""PLCComS variables as ``LIST:`` names them, and their neutral catalogue.

Nothing here does I/O.
"""

from collections.abc import Collection, Iterable, Mapping
from dataclasses import dataclass, field

from ...core.models import Catalogue, DataType, Point, ValueKind
from ...core.pointmap import data_type
from ..points import tecomat_point
from .protocol import DISABLED_FLAG, HIDDEN_FLAG, kind_of_type


@dataclass(frozen=True, slots=True)
class PlcComsVariable:
    """One ``LIST:`` entry: the name as the server spells it, its type and flags.

    The flags (``*`` disabled, ``~`` hidden) describe the connection's state, not
    the program: two entries with the same name and type are equal whatever
    their flags.
    """

    name: str
    type: str
    flags: str = field(default="", compare=False)

    @property
    def key(self) -> str:
        """The name in lower case: names are case-insensitive."""
        return self.name.lower()

    @property
    def kind(self) -> ValueKind | None:
        """The library's kind of the type (None for a type it does not know)."""
        return kind_of_type(self.type)

    @property
    def data_type(self) -> DataType | None:
        """An integer's IEC type, with its bounds (None: another kind's, Tecomat's)."""
        if self.kind is not ValueKind.INTEGER:
            return None
        return data_type(self.type)

    @property
    def hidden(self) -> bool:
        """Whether the server lists it as hidden (``~``)."""
        return HIDDEN_FLAG in self.flags

    @property
    def enabled(self) -> bool:
        """Whether its changes are pushed to this connection (no ``*``)."""
        return DISABLED_FLAG not in self.flags


def build_catalogue(
    variables: Iterable[PlcComsVariable],
    *,
    grouped: Mapping[str, Point] | None = None,
    members: Collection[str] = (),
) -> Catalogue:
    """Build a neutral catalogue of ``LIST:`` variables.

    Every variable of a known type is a point (key the lower-case name, path the
    server's spelling, no metadata); the server's own ``__*`` variables are left
    out, those of unknown types listed in ``skipped_groups``. ``groups`` are the
    first segments of the names, in order.

    A point standing for several variables (a T_ApiObject) is given in
    ``grouped`` by the key of the variable carrying its value, and takes that
    variable's place; the keys of its other variables are ``members``: they give
    no points of their own, but their roots count.
    """
    grouped = grouped or {}
    points: dict[str, Point] = {}
    roots: dict[str, str] = {}
    skipped: list[str] = []
    for variable in variables:
        if variable.name.startswith("__"):
            continue
        kind = variable.kind
        if kind is None:
            skipped.append(variable.name)
            continue
        key = variable.key
        if key in grouped:
            points[grouped[key].key] = grouped[key]
        elif key in points:
            continue
        elif key not in members:
            points[key] = tecomat_point(
                variable.name, kind, data_type=variable.data_type
            )
        root = variable.name.split(".", 1)[0].split("[", 1)[0]
        roots.setdefault(root.lower(), root)
    return Catalogue(
        points=points,
        values={},
        groups=tuple(roots.values()),
        skipped_groups=tuple(skipped),
    )
