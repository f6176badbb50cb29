"""Variable paths: splitting, the names GetObject may read, encoding, lookups.

A path is the PLC's spelling of a variable: ``Main.myObject3``,
``plcData.varStringArray[2]``, ``arr2[1][3]``. Names are case-insensitive on the
PLC, so lookups in responses fold case. In request targets every name and value
is percent-encoded per RFC 3986 (``%20``, never ``+``) keeping the unreserved
characters and ``[``/``]`` readable, so nothing can add a parameter.
"""

from collections.abc import Iterable, Mapping
import functools
import re
from typing import Any, Final
from urllib.parse import quote

SERVICE_PREFIX: Final = "/TecoApi/"
GET_OBJECT: Final = f"{SERVICE_PREFIX}GetObject?"
SET_OBJECT: Final = f"{SERVICE_PREFIX}SetObject?"
MAX_TARGET_LENGTH: Final = 256

_SEGMENT: Final = re.compile(r"\.?([^.\[\]]+)|\[([0-9]+)\]")

type Segment = str | int


class _Missing:
    """Marker for "not present in the response"."""


MISSING: Final = _Missing()


def split_path(path: str) -> list[Segment]:
    """Split a path into member names and array indexes.

    ``"a.b[1][2].c"`` → ``["a", "b", 1, 2, "c"]``. Raises ValueError for text
    that is not a path (empty members, unbalanced brackets, leading dot).
    """
    segments: list[Segment] = []
    position = 0
    while position < len(path):
        match = _SEGMENT.match(path, position)
        if (
            match is None
            or (position == 0 and path.startswith("."))
            or (position > 0 and match.group(1) is not None and path[position] != ".")
        ):
            raise ValueError(f"Not a variable path: {path!r}")
        name, index = match.groups()
        segments.append(name if name is not None else int(index))
        position = match.end()
    if not segments or not isinstance(segments[0], str):
        raise ValueError(f"Not a variable path: {path!r}")
    return segments


def join_path(segments: Iterable[Segment]) -> str:
    """Join segments into a path, the inverse of :func:`split_path`."""
    text = ""
    for segment in segments:
        if isinstance(segment, int):
            text += f"[{segment}]"
        else:
            text += f".{segment}" if text else segment
    return text


def readable_name(path: str) -> str:
    """Return the longest prefix of a path GetObject may read: before any index.

    Array elements are read through their array, never as ``arr[2]``.
    """
    return path.partition("[")[0]


def encode_name(name: str) -> str:
    """Encode a variable name for a query: percent-encoded, ``.[]_`` kept readable."""
    return quote(name, safe="[]")


def encode_value(text: str) -> str:
    """Encode a SetObject value: percent-encoded, ``&=#"`` and spaces escaped."""
    return quote(text, safe="")


def get_object_target(names: Iterable[str]) -> str:
    """Return the request target of a GetObject of ``names``."""
    return GET_OBJECT + "&".join(encode_name(name) for name in names)


def member(node: Any, name: str) -> Any:
    """Return the member ``name`` of a JSON object ignoring case, or :data:`MISSING`.

    The exact spelling is tried first; otherwise the first member whose name
    folds to the same lower case wins.
    """
    if not isinstance(node, dict):
        return MISSING
    if (found := node.get(name, MISSING)) is not MISSING:
        return found
    folded = name.lower()
    return next(
        (value for key, value in node.items() if str(key).lower() == folded), MISSING
    )


type _Step = tuple[str, tuple[int, ...], str]
"""A member name, the indexes that follow it, and both as one literal key."""
type Steps = tuple[_Step, ...]
"""A path as :func:`walk` follows it through an answer."""


def _steps(segments: Iterable[Segment]) -> tuple[_Step, ...] | None:
    """Group segments into steps: a name and the indexes after it; None if invalid."""
    groups: list[tuple[str, list[int]]] = []
    for segment in segments:
        if isinstance(segment, int) and groups:
            groups[-1][1].append(segment)
        elif isinstance(segment, str):
            groups.append((segment, []))
        else:
            return None
    return tuple(
        (name, tuple(indexes), name + "".join(f"[{index}]" for index in indexes))
        for name, indexes in groups
    )


@functools.lru_cache(maxsize=8192)
def path_steps(path: str) -> Steps:
    """Return the steps of a path (:func:`walk`); raises ValueError if it is not one.

    Cached: every poll looks up the same paths.
    """
    steps = _steps(split_path(path))
    if steps is None:  # pragma: no cover - split_path starts every path with a name
        raise ValueError(f"Not a variable path: {path!r}")
    return steps


def walk(tree: Any, steps: Steps, bracketed: dict[int, bool] | None = None) -> Any:
    """Return the value at a path's steps in a JSON tree ignoring case, or :data:`MISSING`.

    ``bracketed`` remembers, by ``id``, which objects of ``tree`` have a key with
    ``[`` (only those may hold an indexed member under its literal key): many
    paths through one answer look at each object once (None: every time).
    """
    node = tree
    for name, indexes, literal in steps:
        if indexes and _may_hold_literal(node, bracketed):
            found = member(node, literal)
            if found is not MISSING:
                node = found
                continue
        node = member(node, name)
        for index in indexes:
            if not isinstance(node, list) or index >= len(node):
                return MISSING
            node = node[index]
        if node is MISSING:
            return MISSING
    return node


def _may_hold_literal(node: Any, bracketed: dict[int, bool] | None) -> bool:
    """Whether an object may hold an indexed member under its literal key (``arr[2]``).

    A key that folds to such a name has a ``[``: an object without one never does.
    """
    if bracketed is None or not isinstance(node, dict):
        return True
    found = bracketed.get(id(node))
    if found is None:
        found = bracketed[id(node)] = any("[" in str(key) for key in node)
    return found


def lookup(tree: Any, segments: Iterable[Segment]) -> Any:
    """Return the value at ``segments`` in a JSON tree ignoring case, or :data:`MISSING`.

    An indexed member is found nested (``{"arr": [..]}``) or, as some servers
    answer an indexed read, under its literal key (``{"arr[2]": ..}``).
    """
    steps = _steps(segments)
    return MISSING if steps is None else walk(tree, steps)


def lookup_path(tree: Any, path: str) -> Any:
    """:func:`lookup` of a path's text; raises ValueError if it is not a path."""
    return walk(tree, path_steps(path))


def merge_into(target: dict[str, Any], tree: Mapping[str, Any]) -> None:
    """Merge a GetObject response into ``target``, object by object, ignoring case."""
    index = {key.lower(): key for key in target}
    for key, value in tree.items():
        existing = index.get(key.lower())
        if existing is None:
            target[key] = value
            index[key.lower()] = key
        elif isinstance(target[existing], dict) and isinstance(value, dict):
            merge_into(target[existing], value)
        else:
            target[existing] = value
