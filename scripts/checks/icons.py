"""icons.json: icons for entities and actions that exist, named as mdi: icons."""

from collections.abc import Mapping
import re
from typing import Any, Final

from .common import dotted, has_path, leaves

MDI_ICON: Final = re.compile(r"mdi:[a-z0-9]+(-[a-z0-9]+)*")
ICON_SECTIONS: Final = frozenset({"entity", "services"})


def icon_problems(
    icons: Mapping[str, Any],
    strings: Mapping[str, Any],
    services_yaml: Mapping[str, Any],
) -> list[str]:
    """Icons for entities or actions that do not exist, and malformed icon names."""
    problems = [
        f"icons.json section {key!r} is not checked here"
        for key in icons
        if key not in ICON_SECTIONS
    ]
    for platform, keys in icons.get("entity", {}).items():
        problems += [
            f"icon for entity.{platform}.{key} has no entity translation"
            for key in keys
            if not has_path(strings, ("entity", platform, key))
        ]
    actions = set(icons.get("services", {}))
    problems += [
        f"icon for action {name!r} that services.yaml lacks"
        for name in sorted(actions - set(services_yaml))
    ]
    problems += [
        f"action {name!r} has no icon" for name in sorted(set(services_yaml) - actions)
    ]
    problems += [
        f"{dotted(path)}: {value!r} is not an mdi: icon"
        for path, value in leaves(icons)
        if not isinstance(value, str) or not MDI_ICON.fullmatch(value)
    ]
    return problems
