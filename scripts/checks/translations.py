"""Translation files: hassfest's translation schema rules, two languages in step."""

from collections.abc import Mapping
import re
from typing import Any, Final

from .common import dotted, key_paths, leaves

# hassfest: lower case, digits, '-' and '_', not doubled, not at either end.
TRANSLATION_KEY: Final = re.compile(r"(?!.*[_-]{2})(?![_-])[a-z0-9_-]+(?<![_-])")
# Children of these keys name config fields or service fields, not translation keys.
FREE_KEY_PARENTS: Final = frozenset({"data", "data_description", "fields", "sections"})
PLACEHOLDER: Final = re.compile(r"\{(\w+)\}")
SINGLE_QUOTED_PLACEHOLDER: Final = re.compile(r"'[^']*\{[^}]+\}[^']*'")
HTML_TAG: Final = re.compile(r"<[a-zA-Z/][^>]*>")


def structure_differences(
    left: Mapping[str, Any], right: Mapping[str, Any], left_name: str, right_name: str
) -> list[str]:
    """Keys one translation tree has and the other lacks (or has as a leaf)."""
    left_paths, right_paths = key_paths(left), key_paths(right)
    problems = [
        f"{dotted(path)} is in {left_name} but not in {right_name}"
        for path in sorted(left_paths - right_paths)
    ]
    problems += [
        f"{dotted(path)} is in {right_name} but not in {left_name}"
        for path in sorted(right_paths - left_paths)
    ]
    left_leaves, right_leaves = dict(leaves(left)), dict(leaves(right))
    problems += [
        f"{dotted(path)} is a string in one file and an object in the other"
        for path in sorted(left_paths & right_paths)
        if (path in left_leaves) != (path in right_leaves)
    ]
    return problems


def translation_string_problems(tree: Mapping[str, Any], file_name: str) -> list[str]:
    """Keys hassfest would reject and strings a user would see broken."""
    problems = [
        f"{file_name}: key {dotted(path)} is not a valid translation key"
        for path in sorted(key_paths(tree))
        if (len(path) < 2 or path[-2] not in FREE_KEY_PARENTS)
        and not TRANSLATION_KEY.fullmatch(path[-1])
    ]
    for path, value in leaves(tree):
        where = f"{file_name}: {dotted(path)}"
        if not isinstance(value, str):
            problems.append(f"{where} is not a string")
        elif not value.strip():
            problems.append(f"{where} is empty")
        elif value != value.strip():
            problems.append(f"{where} has leading or trailing whitespace")
        elif "[%key:" in value:
            problems.append(
                f"{where} uses a [%key:…%] reference, which custom integrations do not resolve"
            )
        elif SINGLE_QUOTED_PLACEHOLDER.search(value):
            problems.append(f"{where} puts a placeholder in single quotes")
        elif HTML_TAG.search(value):
            problems.append(f"{where} contains HTML")
    return problems


def placeholder_differences(
    left: Mapping[str, Any], right: Mapping[str, Any], left_name: str, right_name: str
) -> list[str]:
    """Strings whose `{placeholder}` names differ between two translations."""
    right_leaves = dict(leaves(right))
    problems: list[str] = []
    for path, value in leaves(left):
        other = right_leaves.get(path)
        if not isinstance(value, str) or not isinstance(other, str):
            continue
        mine, theirs = set(PLACEHOLDER.findall(value)), set(PLACEHOLDER.findall(other))
        if mine != theirs:
            problems.append(
                f"{dotted(path)}: {left_name} has {sorted(mine)}, {right_name} has {sorted(theirs)}"
            )
    return problems
