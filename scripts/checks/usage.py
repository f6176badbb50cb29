"""What the integration's code needs from its translations, and those needs checked.

`reader.read_usage` fills a `TranslationUsage` from the code (and
`descriptors.descriptor_usage` from the source descriptors); the functions here
hold it against one translation file.
"""

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Final

from .common import KeyPath, KeyTemplate, dotted, has_path
from .translations import PLACEHOLDER

# The strings of a step, exception or issue that receive its placeholders.
TEXT_PARTS: Final = ("title", "description", "message")

type Parameter = tuple[str, int | None]
"""A parameter's name and position (self not counted; None if keyword-only)."""


@dataclass(frozen=True, slots=True)
class Forwarding:
    """A function whose callers choose the translation key (a helper raising)."""

    key: Parameter
    placeholders: Parameter | None
    template: KeyTemplate


@dataclass(slots=True)
class TranslationUsage:
    """What the integration's Python code needs from its translations."""

    required: dict[KeyPath, str] = field(default_factory=dict)
    """Translation key path -> where the code needs it (module:line)."""
    services: dict[str, str] = field(default_factory=dict)
    """Registered action -> where it is registered."""
    literals: set[str] = field(default_factory=set)
    """Every string constant in the code (keys chosen at runtime come from these)."""
    problems: list[str] = field(default_factory=list)
    """Uses this reader cannot place; extend the reader rather than ignore them."""
    forwarded: dict[str, Forwarding] = field(default_factory=dict)
    """Functions that pass a parameter on as translation_key, by name."""
    placeholders: dict[KeyPath, tuple[frozenset[str], str]] = field(
        default_factory=dict
    )
    """Form step or exception -> the placeholder names the code always passes it
    (where that can be read), and where."""


def integration_sources(root: Path) -> dict[str, str]:
    """Every Python module of the integration, by dotted name relative to it."""
    return {
        ".".join(path.relative_to(root).with_suffix("").parts): path.read_text(
            encoding="utf-8"
        )
        for path in sorted(root.rglob("*.py"))
        if "__pycache__" not in path.parts
    }


def missing_translations(
    usage: TranslationUsage, strings: Mapping[str, Any]
) -> list[str]:
    """Keys the code uses that the translation lacks."""
    return [
        f"{dotted(path)} (used at {where})"
        for path, where in sorted(usage.required.items())
        if not has_path(strings, path)
    ]


def unused_translations(
    strings: Mapping[str, Any], usage: TranslationUsage
) -> list[str]:
    """Entity, exception and issue keys that no code can reach."""
    used = {path[:3] for path in usage.required}
    candidates: list[tuple[KeyPath, str]] = []
    for platform, keys in strings.get("entity", {}).items():
        candidates += [(("entity", platform, key), key) for key in keys]
    for section in ("exceptions", "issues"):
        candidates += [((section, key), key) for key in strings.get(section, {})]
    return [
        dotted(path)
        for path, key in candidates
        if not any(found[: len(path)] == path for found in used)
        and key not in usage.literals
    ]


def placeholder_gaps(usage: TranslationUsage, strings: Mapping[str, Any]) -> list[str]:
    """`{placeholders}` in strings that the code showing them does not pass.

    Steps and exceptions are checked against what their call passes (when that
    can be read); form errors against what is passed with them where that is
    known (a descriptor's failure and its details), else against what any form
    of the same flow passes.
    """
    problems: list[str] = []

    def check(path: KeyPath, provided: frozenset[str], where: str) -> None:
        node: Any = strings
        for key in path:
            node = node.get(key) if isinstance(node, Mapping) else None
        if isinstance(node, Mapping):
            texts = [((*path, part), node.get(part)) for part in TEXT_PARTS]
        else:
            texts = [(path, node)]
        for text_path, text in texts:
            if not isinstance(text, str):
                continue
            if missing := sorted(set(PLACEHOLDER.findall(text)) - provided):
                problems.append(
                    f"{dotted(text_path)} uses {missing}, not passed at {where}"
                )

    for path, (provided, where) in sorted(usage.placeholders.items()):
        check(path, provided, where)
    for section in ("config", "options"):
        forms = [
            provided
            for path, (provided, _where) in usage.placeholders.items()
            if path[:2] == (section, "step")
        ]
        for path, where in sorted(usage.required.items()):
            if (
                forms
                and path[:2] == (section, "error")
                and path not in usage.placeholders
            ):
                check(path, frozenset().union(*forms), where)
    return problems
