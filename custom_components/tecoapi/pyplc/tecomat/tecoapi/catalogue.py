"""The catalogue walker: from GetList roots and GetObject trees to points.

Every T_ApiObject (an object of exactly ``value`` and ``attr``, the ``attr``
carrying the seven documented keys with their types) anywhere in the tree -- at
the top, in a program instance such as ``Main``, in structs, in arrays --
becomes one point with its metadata. Every other scalar leaf becomes a plain
point; arrays of scalars give one point per element (``arr1[0]``...).

Names are matched ignoring case and kept as the PLC spells them in GetObject
responses. Members whose names would make an ambiguous path (empty, or
containing ``.``, ``[`` or ``]``) and JSON ``null`` leaves are skipped; so is a
second member whose name differs from an earlier one only in case.
"""

from collections.abc import Iterable, Mapping, Sequence
import math
from typing import Any, Final

from ...core.exceptions import MalformedResponseError
from ...core.models import Catalogue, DiscoveryCost, Point, PointAttributes
from ..points import api_object_attributes, tecomat_point
from .paths import MISSING, member
from .values import infer_kind, parse_value, real

_BOOL_ATTRS: Final = ("enable", "visibility", "readonly")
_TEXT_ATTRS: Final = ("title", "units")
_NUMBER_ATTRS: Final = ("minvalue", "maxvalue")
ATTR_ITEMS: Final = len(_BOOL_ATTRS) + len(_TEXT_ATTRS) + len(_NUMBER_ATTRS)
API_OBJECT_ITEMS: Final = 1 + ATTR_ITEMS  # value + attr, as the item limit counts


def parse_root_list(body: Any) -> tuple[str, ...]:
    """Root names from a GetList body in either shape.

    ``{"a": {}, "b": {}}`` (``listType=struct``) or ``[{"a": {}}, {"b": {}}]``
    (``listType=array``); duplicates differing only in case are dropped.
    """
    if isinstance(body, dict):
        names: Iterable[Any] = body
    elif isinstance(body, list) and all(isinstance(entry, dict) for entry in body):
        names = (name for entry in body for name in entry)
    else:
        raise MalformedResponseError(
            "GetList answered neither an object nor a list of objects", status=200
        )
    roots: dict[str, str] = {}
    for name in names:
        if isinstance(name, str) and name and name.lower() not in roots:
            roots[name.lower()] = name
    return tuple(roots.values())


def parse_meta(attr: Any) -> PointAttributes | None:
    """Return the attributes of a T_ApiObject ``attr`` object, or None if it is not one."""
    if not isinstance(attr, dict):
        return None
    return meta_of_attributes(
        {str(key).lower(): value for key, value in reversed(attr.items())}
    )


def meta_of_attributes(
    values: Mapping[str, Any], *, finite: bool = False
) -> PointAttributes | None:
    """Return the attributes of ``attr`` values by lower-case attribute (None if unfit).

    The limits must be numbers (not booleans), and finite ones when ``finite``.
    """
    if not all(isinstance(values.get(key), bool) for key in _BOOL_ATTRS):
        return None
    if not all(isinstance(values.get(key), str) for key in _TEXT_ATTRS):
        return None
    if not all(_is_limit(values.get(key), finite=finite) for key in _NUMBER_ATTRS):
        return None
    return api_object_attributes(
        title=values["title"],
        units=values["units"],
        read_only=values["readonly"],
        min_value=real(values["minvalue"]),
        max_value=real(values["maxvalue"]),
        enable=values["enable"],
        visibility=values["visibility"],
    )


def _is_limit(value: Any, *, finite: bool) -> bool:
    """Whether an attribute value can be a ``minValue``/``maxValue``."""
    if not isinstance(value, int | float) or isinstance(value, bool):
        return False
    return not finite or math.isfinite(value)


def as_api_object(node: Mapping[str, Any]) -> tuple[Any, PointAttributes] | None:
    """``(raw value, attributes)`` when a JSON object is a T_ApiObject, else None."""
    if len(node) != 2:
        return None
    members = {str(key).lower(): value for key, value in node.items()}
    if "value" not in members or infer_kind(members["value"]) is None:
        return None
    meta = parse_meta(members.get("attr"))
    return None if meta is None else (members["value"], meta)


def _is_member_name(name: Any) -> bool:
    """Whether a JSON key can be a path segment without ambiguity."""
    return (
        isinstance(name, str) and bool(name) and not any(char in name for char in ".[]")
    )


class _Walker:
    """Collects the points of one GetObject tree in the PLC's order."""

    def __init__(self) -> None:
        self.points: dict[str, Point] = {}
        self.values: dict[str, Any] = {}

    def walk(self, root_path: str, root: Any) -> None:
        """Add every point under ``root`` (iteratively: trees may be deep)."""
        stack: list[tuple[str, Any]] = [(root_path, root)]
        while stack:
            path, node = stack.pop()
            if isinstance(node, dict):
                if (api_object := as_api_object(node)) is not None:
                    self._add(path, *api_object)
                    continue
                children: list[tuple[str, Any]] = []
                seen: set[str] = set()
                for name, child in node.items():
                    if _is_member_name(name) and name.lower() not in seen:
                        seen.add(name.lower())
                        children.append((f"{path}.{name}", child))
                stack.extend(reversed(children))
            elif isinstance(node, list):
                stack.extend(
                    (f"{path}[{index}]", item)
                    for index, item in reversed(list(enumerate(node)))
                )
            else:
                self._add(path, node, None)

    def _add(self, path: str, raw: Any, attributes: PointAttributes | None) -> None:
        """Add one point unless the value is not a scalar or the key is taken."""
        kind = infer_kind(raw)
        key = path.lower()
        if kind is None or key in self.points:
            return
        self.points[key] = tecomat_point(path, kind, attributes)
        self.values[key] = parse_value(kind, raw)


def build_catalogue(
    roots: Sequence[str],
    tree: Mapping[str, Any],
    *,
    skipped_roots: Sequence[str] = (),
    discovery: DiscoveryCost | None = None,
) -> Catalogue:
    """Build the catalogue of ``roots`` as read into ``tree`` (merged GetObject answers).

    A listed root missing from the tree, or whose name cannot start a path, is
    reported in the catalogue's ``skipped_groups`` (its ``groups`` are
    the roots); ``discovery`` is what reading them cost.
    """
    spelled = {str(key).lower(): str(key) for key in reversed(list(tree))}
    walker = _Walker()
    skipped = list(skipped_roots)
    skipped_keys = {root.lower() for root in skipped}
    for root in roots:
        if root.lower() in skipped_keys:
            continue
        if not _is_member_name(root) or member(tree, root) is MISSING:
            skipped.append(root)
            skipped_keys.add(root.lower())
            continue
        walker.walk(spelled[root.lower()], tree[spelled[root.lower()]])
    return Catalogue(
        points=walker.points,
        values=walker.values,
        groups=tuple(roots),
        skipped_groups=tuple(skipped),
        discovery=discovery,
    )
