"""services.yaml: registered actions, their declaration and translations agree."""

from collections.abc import Mapping
from typing import Any


def service_fields(service: Mapping[str, Any] | None) -> set[str]:
    """Field names of one services.yaml action, sections flattened."""
    fields: set[str] = set()
    for name, definition in ((service or {}).get("fields") or {}).items():
        if isinstance(definition, Mapping) and "fields" in definition:
            fields |= set(definition["fields"] or {})
        else:
            fields.add(name)
    return fields


def service_problems(
    services_yaml: Mapping[str, Any],
    strings: Mapping[str, Any],
    registered: Mapping[str, str],
) -> list[str]:
    """Disagreements between registered actions, services.yaml and translations."""
    declared, translated = set(services_yaml), set(strings.get("services", {}))
    problems = [
        f"action {name!r} is registered but not in services.yaml"
        for name in sorted(set(registered) - declared)
    ]
    problems += [
        f"action {name!r} is in services.yaml but never registered"
        for name in sorted(declared - set(registered))
    ]
    problems += [
        f"action {name!r} has no translation" for name in sorted(declared - translated)
    ]
    problems += [
        f"translated action {name!r} is not in services.yaml"
        for name in sorted(translated - declared)
    ]
    for name in sorted(declared & translated):
        translation = strings["services"][name]
        problems += [
            f"action {name!r} has no translated {part}"
            for part in ("name", "description")
            if not translation.get(part)
        ]
        fields, named = (
            service_fields(services_yaml[name]),
            set(translation.get("fields", {})),
        )
        problems += [
            f"field {name}.{item} has no translation" for item in sorted(fields - named)
        ]
        problems += [
            f"translated field {name}.{item} is not in services.yaml"
            for item in sorted(named - fields)
        ]
        for item in sorted(fields & named):
            problems += [
                f"field {name}.{item} has no translated {part}"
                for part in ("name", "description")
                if not translation["fields"][item].get(part)
            ]
    return problems
