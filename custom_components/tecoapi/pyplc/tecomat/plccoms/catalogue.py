"""T_ApiObjects among PLCComS variables: the same points TecoApi discovers.

``LIST:`` names elementary variables only, so a T_ApiObject (manual chapter 5.3)
shows as eight of them: ``P.value`` and ``P.attr.enable``, ``.visibility``,
``.readOnly``, ``.title``, ``.minValue``, ``.maxValue``, ``.units``. Grouped
again, with the attributes read by ``GET:``, they make one point ``P`` with its
metadata, whose ``value_path`` (``P.value``) is the PLCComS name of its value:
the keys, kinds and metadata are then those of a TecoApi discovery of the same
program, and so are the entities built on them. Every other variable of a known
type is a plain point (no metadata). Nothing here does I/O.
"""

from collections import Counter
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from typing import Any, Final

from ...core.models import Catalogue, Point, PointAttributes, ValueKind
from ..points import tecomat_point
from ..tecoapi.catalogue import meta_of_attributes
from . import variables as plccoms
from .variables import PlcComsVariable

VALUE: Final = "value"
ATTRIBUTE_KINDS: Final[Mapping[str, ValueKind]] = {
    "enable": ValueKind.BOOL,
    "visibility": ValueKind.BOOL,
    "readonly": ValueKind.BOOL,
    "title": ValueKind.STRING,
    "minvalue": ValueKind.REAL,
    "maxvalue": ValueKind.REAL,
    "units": ValueKind.STRING,
}
_LEAVES: Final = 1 + len(ATTRIBUTE_KINDS)


@dataclass(frozen=True, slots=True)
class ApiObjectNames:
    """The PLCComS variables of one T_ApiObject, as the server spells them."""

    path: str
    value: PlcComsVariable
    attributes: Mapping[str, str]
    """Variable names by lower-case attribute (``readonly``, ``minvalue``...)."""

    @property
    def key(self) -> str:
        """The point's key: its path in lower case."""
        return self.path.lower()


def _prefixes(key: str) -> Iterable[str]:
    """Yield the struct prefixes of a lower-case name: ``a.b.c`` -> ``a``, ``a.b``."""
    index = key.find(".")
    while index > 0:
        yield key[:index]
        index = key.find(".", index + 1)


def find_api_objects(
    variables: Iterable[PlcComsVariable],
) -> dict[str, ApiObjectNames]:
    """Return the T_ApiObjects among ``LIST:`` variables, by point key.

    A T_ApiObject is a struct of exactly ``value`` (a known type) and the seven
    attributes with their types (BOOL, STRING, REAL or LREAL), as TecoApi's
    catalogue recognises one.
    """
    listed = [variable for variable in variables if not variable.name.startswith("__")]
    by_key = {variable.key: variable for variable in listed}
    leaves = Counter(
        prefix for variable in listed for prefix in _prefixes(variable.key)
    )
    objects: dict[str, ApiObjectNames] = {}
    for variable in listed:
        key = variable.key
        if not key.endswith(f".{VALUE}") or variable.kind is None:
            continue
        base = key[: -len(VALUE) - 1]
        if leaves[base] != _LEAVES or leaves[f"{base}.attr"] != len(ATTRIBUTE_KINDS):
            continue
        attributes: dict[str, str] = {}
        for attribute, kind in ATTRIBUTE_KINDS.items():
            member = by_key.get(f"{base}.attr.{attribute}")
            if member is None or member.kind is not kind:
                break
            attributes[attribute] = member.name
        else:
            path = variable.name[: -len(VALUE) - 1]
            objects[base] = ApiObjectNames(path, variable, attributes)
    return objects


def meta_of(values: Mapping[str, Any]) -> PointAttributes | None:
    """Return the metadata of attribute values by lower-case attribute (None if unfit).

    TecoApi's reading of the attributes (:func:`.catalogue.meta_of_attributes`),
    the limits finite too.
    """
    return meta_of_attributes(values, finite=True)


def build_catalogue(
    variables: Iterable[PlcComsVariable],
    objects: Mapping[str, ApiObjectNames],
    metas: Mapping[str, PointAttributes],
) -> Catalogue:
    """Build the catalogue of ``LIST:`` variables, T_ApiObjects grouped again.

    ``objects`` are :func:`find_api_objects`' answer, ``metas`` their metadata as
    read (an object without metadata stays eight plain points). Points keep the
    order of ``LIST:``; the server's own ``__*`` variables and those of unknown
    types are left out (the latter listed in ``skipped_groups``).
    """
    grouped: dict[str, Point] = {}
    members: set[str] = set()
    for key, names in objects.items():
        if key not in metas or (kind := names.value.kind) is None:
            continue
        grouped[names.value.key] = tecomat_point(
            names.path, kind, metas[key], names.value.data_type
        )
        members.update(name.lower() for name in names.attributes.values())
    return plccoms.build_catalogue(variables, grouped=grouped, members=members)
