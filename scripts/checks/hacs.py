"""hacs.json: what HACS's integration checks reject, and the minimum release."""

from collections.abc import Mapping
from typing import Any, Final

HACS_KEYS: Final = frozenset(
    {
        "name",
        "content_in_root",
        "zip_release",
        "filename",
        "hide_default_branch",
        "country",
        "homeassistant",
        "render_readme",
        "hacs",
        "persistent_directory",
    }
)


def hacs_problems(hacs: Mapping[str, Any], floor: str) -> list[str]:
    """What HACS would reject in hacs.json, and a minimum that is not the floor."""
    problems = [
        f"key {key!r} is not one HACS accepts" for key in hacs if key not in HACS_KEYS
    ]
    if not isinstance(hacs.get("name"), str) or not hacs["name"].strip():
        problems.append("'name' is missing or empty")
    if hacs.get("homeassistant") != floor:
        problems.append(
            f"'homeassistant' is {hacs.get('homeassistant')!r}, the tested floor is {floor!r}"
        )
    return problems
