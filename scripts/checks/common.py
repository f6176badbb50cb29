"""Reading JSON and YAML, and walking nested objects by key path."""

import ast
from collections.abc import Iterator, Mapping
import json
from pathlib import Path
from typing import Any, Final

import yaml

type KeyPath = tuple[str, ...]
type KeyTemplate = tuple[str | None, ...]
"""A key path with None where the translation key goes."""
type JsonObject = dict[str, Any]


def load_json(path: Path) -> JsonObject:
    """A JSON file that must hold an object."""
    data = json.loads(path.read_text(encoding="utf-8"))
    if not isinstance(data, dict):
        raise TypeError(f"{path.name} is not a JSON object")
    return data


def load_yaml(path: Path) -> JsonObject:
    """A YAML file that must hold a mapping (an empty file is an empty one)."""
    data = yaml.safe_load(path.read_text(encoding="utf-8")) or {}
    if not isinstance(data, dict):
        raise TypeError(f"{path.name} is not a mapping")
    return data


def key_paths(tree: Mapping[str, Any], prefix: KeyPath = ()) -> set[KeyPath]:
    """The path of every key in a nested object, inner nodes included."""
    paths: set[KeyPath] = set()
    for key, value in tree.items():
        path = (*prefix, key)
        paths.add(path)
        if isinstance(value, Mapping):
            paths |= key_paths(value, path)
    return paths


def leaves(
    tree: Mapping[str, Any], prefix: KeyPath = ()
) -> Iterator[tuple[KeyPath, Any]]:
    """Every non-object value of a nested object, with its path."""
    for key, value in tree.items():
        if isinstance(value, Mapping):
            yield from leaves(value, (*prefix, key))
        else:
            yield (*prefix, key), value


ANY_KEY: Final = "*"
"""A path step that every key at its level must continue (subentry types)."""


def has_path(tree: Mapping[str, Any], path: KeyPath) -> bool:
    """Whether `path` leads to a key in `tree` (`*`: under every key, and one at least)."""
    node: Any = tree
    for index, key in enumerate(path):
        if key == ANY_KEY:
            return (
                isinstance(node, Mapping)
                and bool(node)
                and all(has_path(child, path[index + 1 :]) for child in node.values())
            )
        if not isinstance(node, Mapping) or key not in node:
            return False
        node = node[key]
    return True


def dotted(path: KeyPath) -> str:
    """A key path as translations name it: `config.step.user`."""
    return ".".join(path)


def simple_assignment(node: ast.stmt) -> tuple[str | None, ast.expr | None]:
    """The name and value of `NAME = value` or `NAME: T = value`, else None, None."""
    if (
        isinstance(node, ast.Assign)
        and len(node.targets) == 1
        and isinstance(node.targets[0], ast.Name)
    ):
        return node.targets[0].id, node.value
    if (
        isinstance(node, ast.AnnAssign)
        and isinstance(node.target, ast.Name)
        and node.value is not None
    ):
        return node.target.id, node.value
    return None, None
