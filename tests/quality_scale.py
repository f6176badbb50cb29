"""Finders of what breaks a rule of the Integration Quality Scale.

tests/components/tecoapi/test_quality_scale.py runs each on the integration (none may
find anything) and on a planted fault (it must find it).
"""

import ast
from collections.abc import Iterator, Mapping
import importlib
import inspect
from pathlib import Path
from types import ModuleType
from typing import Any, Final

from homeassistant.data_entry_flow import FlowError
from homeassistant.exceptions import HomeAssistantError
from homeassistant.helpers.entity import Entity, EntityDescription

from custom_components.tecoapi import PLATFORMS
from custom_components.tecoapi.entity import PlcEntity

ROOT: Final = Path(__file__).resolve().parents[1]
INTEGRATION: Final = ROOT / "custom_components" / "tecoapi"
PACKAGE: Final = "custom_components.tecoapi"
HA_MODULES: Final = sorted(
    path
    for path in INTEGRATION.rglob("*.py")
    if path.relative_to(INTEGRATION).parts[0] != "pyplc"
)
"""Home Assistant's side of the integration (the library, pyplc/, aside): flows/ too."""


def module_name(path: Path) -> str:
    """The dotted name of a module of the integration (a package's: the package)."""
    parts = path.relative_to(INTEGRATION).with_suffix("").parts
    return ".".join((PACKAGE, *parts[: -1 if parts[-1] == "__init__" else None]))


def _defined_tests(path: Path) -> set[str]:
    """``function`` and ``Class::method`` names a test module defines."""
    names: set[str] = set()
    for node in ast.parse(path.read_text(encoding="utf-8")).body:
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            names.add(node.name)
        elif isinstance(node, ast.ClassDef):
            names.update(
                f"{node.name}::{item.name}"
                for item in node.body
                if isinstance(item, ast.FunctionDef | ast.AsyncFunctionDef)
            )
    return names


def missing_tests(node_ids: list[str], root: Path = ROOT) -> list[str]:
    """The pytest node IDs that name no test (no such file, or no such function)."""
    missing = []
    for node_id in node_ids:
        path, _, name = node_id.partition("::")
        file = root / path
        if not file.is_file() or name.split("[")[0] not in _defined_tests(file):
            missing.append(node_id)
    return missing


def _heading_level(line: str) -> int:
    level = len(line) - len(line.lstrip("#"))
    return level if line[level : level + 1] == " " else 0


def section(page: str, heading: str, root: Path = ROOT) -> str | None:
    """The text under a heading, down to the next of its level (a title's: of any)."""
    lines = (root / page).read_text(encoding="utf-8").splitlines()
    for start, line in enumerate(lines):
        level = _heading_level(line)
        if level and line[level:].strip() == heading:
            end = next(
                (
                    index
                    for index in range(start + 1, len(lines))
                    if 0 < _heading_level(lines[index]) <= max(level, 2)
                ),
                len(lines),
            )
            return "\n".join(lines[start + 1 : end])
    return None


def platform_modules() -> dict[str, ModuleType]:
    """The integration's platform modules, by platform."""
    return {
        platform.value: importlib.import_module(f"{PACKAGE}.{platform.value}")
        for platform in PLATFORMS
    }


def missing_parallel_updates(modules: Mapping[str, ModuleType]) -> list[str]:
    """Platform modules without an integer PARALLEL_UPDATES."""
    return [
        name
        for name, module in modules.items()
        if not isinstance(getattr(module, "PARALLEL_UPDATES", None), int)
    ]


def entity_classes() -> Iterator[type[Entity]]:
    """The entity classes the platform modules define or use."""
    for module in platform_modules().values():
        yield from (
            value
            for value in vars(module).values()
            if inspect.isclass(value)
            and issubclass(value, Entity)
            and value.__module__.startswith(PACKAGE)
        )


def entity_class_problems(classes: list[type[Entity]]) -> list[str]:
    """Entity classes not on the common base, or not named by has_entity_name."""
    problems = []
    for cls in classes:
        if not issubclass(cls, PlcEntity):
            problems.append(f"{cls.__name__} does not derive from PlcEntity")
        if object.__new__(cls).has_entity_name is not True:
            problems.append(f"{cls.__name__} does not set has_entity_name")
    return problems


def entity_descriptions() -> list[tuple[str, EntityDescription]]:
    """(platform, description) of the descriptions the platform modules hold.

    Home Assistant makes each description class a dataclass of its own (not an
    instance of the EntityDescription it exports): they are known by their name.
    """
    return [
        (name, item)
        for name, module in platform_modules().items()
        for value in vars(module).values()
        for item in (value if isinstance(value, tuple) else (value,))
        if type(item).__name__.endswith("Description")
        and hasattr(item, "entity_category")
    ]


def _resolve(node: ast.expr, namespace: Mapping[str, Any]) -> Any:
    """What a name or a dotted attribute (``exceptions.HomeAssistantError``) names."""
    if isinstance(node, ast.Name):
        return namespace.get(node.id)
    if isinstance(node, ast.Attribute):
        return getattr(_resolve(node.value, namespace), node.attr, None)
    return None


def _is_ha_error(node: ast.expr, namespace: Mapping[str, Any]) -> bool:
    """Whether the node names a Home Assistant error (a flow's abort aside)."""
    made = _resolve(node, namespace)
    return (
        inspect.isclass(made)
        and issubclass(made, HomeAssistantError)
        and not issubclass(made, FlowError)  # its reason is a flow's string
    )


def _says_its_translation(call: ast.Call) -> bool:
    """Whether the call names a translation domain and key (a literal or a name)."""
    given = {keyword.arg: keyword.value for keyword in call.keywords}
    return all(
        isinstance(value := given.get(arg), ast.Name)
        or (isinstance(value, ast.Constant) and isinstance(value.value, str))
        for arg in ("translation_domain", "translation_key")
    )


def untranslated_errors(source: str, namespace: Mapping[str, Any]) -> list[str]:
    """Home Assistant errors made or raised without a translation (a flow's abort aside).

    ``namespace`` resolves the names the source uses (its module's globals). An
    error is made by a call (its domain and key must be a string or a name, not
    None) or raised as a bare class (which carries no translation at all).
    """
    problems: list[tuple[int, str]] = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Call):
            made = node.func
            if not _is_ha_error(made, namespace) or _says_its_translation(node):
                continue
        elif isinstance(node, ast.Raise) and isinstance(
            node.exc, ast.Name | ast.Attribute
        ):
            made = node.exc
            if not _is_ha_error(made, namespace):
                continue
        else:
            continue
        problems.append((node.lineno, ast.unparse(made)))
    return [f"line {line}: {made}" for line, made in sorted(problems)]


def hass_data_uses(source: str) -> list[int]:
    """Lines that reach into hass.data (an entry's runtime data belongs on it)."""
    return [
        node.lineno
        for node in ast.walk(ast.parse(source))
        if isinstance(node, ast.Attribute)
        and node.attr == "data"
        and ast.unparse(node.value) in {"hass", "self.hass", "coordinator.hass"}
    ]


def icons_in_code(source: str) -> list[int]:
    """Lines that set an entity's icon in code instead of icons.json."""
    return [
        node.lineno
        for node in ast.walk(ast.parse(source))
        if (isinstance(node, ast.Attribute) and node.attr == "_attr_icon")
        or (isinstance(node, ast.Name) and node.id == "_attr_icon")
        or (isinstance(node, ast.keyword) and node.arg == "icon")
        or (isinstance(node, ast.FunctionDef) and node.name == "icon")
    ]


BLOCKING: Final = frozenset(
    {"requests", "urllib3", "http.client", "urllib.request", "httpx"}
)


def blocking_io(source: str) -> list[int]:
    """Lines that import a blocking HTTP client or sleep the thread."""
    return [
        node.lineno
        for node in ast.walk(ast.parse(source))
        if (isinstance(node, ast.Import) and {a.name for a in node.names} & BLOCKING)
        or (isinstance(node, ast.ImportFrom) and node.module in BLOCKING)
        or (isinstance(node, ast.Call) and ast.unparse(node.func) == "time.sleep")
    ]
