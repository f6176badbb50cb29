"""What HACS's and hassfest's validators check, runnable where they cannot run.

Neither validator runs here (no network, no Docker), so this module checks what they
check, plus what Home Assistant's own test suite checks at runtime for core
integrations: every translation key the code uses exists in translations/en.json
and cs.json, and translations, icons, services and brand images agree with each
other and with the code.

Each checker returns a list of problems in words, so a failing test names all of
them at once. The `test_checker_*` tests feed the checkers small bad inputs, to show
each rule can fail.
"""

import ast
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass, field
from http import HTTPStatus
import json
from pathlib import Path
import re
import struct
from typing import Any, Final

from awesomeversion import AwesomeVersion, AwesomeVersionStrategy
from awesomeversion.exceptions import AwesomeVersionException
import homeassistant.const as ha_const
from homeassistant.const import Platform
from homeassistant.core import HomeAssistant
from homeassistant.setup import async_setup_component
from PIL import Image
import pytest
from pytest_homeassistant_custom_component.typing import ClientSessionGenerator
import yaml

from custom_components.tecoapi.config_flow import MAP_MENU
from custom_components.tecoapi.const import DeviceGrouping
from custom_components.tecoapi.options import PUSH_SCHEMA, options_schema
from custom_components.tecoapi.pyplc.core import registry
from custom_components.tecoapi.pyplc.core.descriptor import (
    Capability,
    FieldKind,
    SourceDescriptor,
)

REPO: Final = Path(__file__).resolve().parent.parent
INTEGRATION: Final = REPO / "custom_components" / "tecoapi"
TRANSLATIONS: Final = INTEGRATION / "translations"
BRAND: Final = INTEGRATION / "brand"

# The oldest Home Assistant the test suite runs on (the floor target).
TESTED_FLOOR: Final = "2026.2.0"

type KeyPath = tuple[str, ...]
type KeyTemplate = tuple[str | None, ...]
"""A key path with None where the translation key goes."""
type JsonObject = dict[str, Any]


# ---------------------------------------------------------------------------
# Shared helpers


def _load_json(path: Path) -> JsonObject:
    data = json.loads(path.read_text(encoding="utf-8"))
    assert isinstance(data, dict), f"{path.name} is not a JSON object"
    return data


def _load_yaml(path: Path) -> JsonObject:
    data = yaml.safe_load(path.read_text(encoding="utf-8")) or {}
    assert isinstance(data, dict), f"{path.name} is not a mapping"
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


ANY_KEY = "*"
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


def _dotted(path: KeyPath) -> str:
    return ".".join(path)


# ---------------------------------------------------------------------------
# hacs.json (HACS's integration checks)

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


# ---------------------------------------------------------------------------
# manifest.json (hassfest's manifest checks and the loader's version rule)

MANIFEST_KEYS: Final = frozenset(
    {
        "domain",
        "name",
        "after_dependencies",
        "bluetooth",
        "codeowners",
        "config_flow",
        "dependencies",
        "dhcp",
        "disabled",
        "documentation",
        "homekit",
        "import_executor",
        "integration_type",
        "iot_class",
        "issue_tracker",
        "loggers",
        "mqtt",
        "preview_features",
        "quality_scale",
        "requirements",
        "single_config_entry",
        "ssdp",
        "usb",
        "version",
        "zeroconf",
    }
)
INTEGRATION_TYPES: Final = frozenset(
    {"device", "entity", "hardware", "helper", "hub", "service", "system", "virtual"}
)
DHCP_MATCHER_KEYS: Final = frozenset({"hostname", "macaddress", "registered_devices"})
# Home Assistant's loader blocks a custom integration whose version is none of these.
VERSION_STRATEGIES: Final = [
    AwesomeVersionStrategy.CALVER,
    AwesomeVersionStrategy.SEMVER,
    AwesomeVersionStrategy.SIMPLEVER,
    AwesomeVersionStrategy.BUILDVER,
    AwesomeVersionStrategy.PEP440,
]


def _manifest_sort_key(key: str) -> tuple[int, str]:
    return {"domain": (0, ""), "name": (1, "")}.get(key, (2, key))


def manifest_problems(
    manifest: Mapping[str, Any], *, directory: str, const_domain: str | None
) -> list[str]:
    """What hassfest (or the loader, for the version) would reject in manifest.json."""
    problems: list[str] = []
    keys = list(manifest)
    if keys != sorted(keys, key=_manifest_sort_key):
        problems.append(
            f"keys are not 'domain', 'name', then alphabetical: {', '.join(keys)}"
        )
    problems += [
        f"key {key!r} is not a manifest key" for key in keys if key not in MANIFEST_KEYS
    ]

    required: dict[str, type] = {
        "domain": str,
        "name": str,
        "codeowners": list,
        "config_flow": bool,
        "documentation": str,
        "integration_type": str,
        "iot_class": str,
        "issue_tracker": str,
        "loggers": list,
        "requirements": list,
        "version": str,
    }
    for key, kind in required.items():
        if key not in manifest:
            problems.append(f"{key!r} is missing")
        elif not isinstance(manifest[key], kind):
            problems.append(f"{key!r} is not a {kind.__name__}")
    if not problems:
        problems += _manifest_value_problems(manifest, directory, const_domain)
    return problems


def _manifest_value_problems(
    manifest: Mapping[str, Any], directory: str, const_domain: str | None
) -> list[str]:
    problems: list[str] = []
    if manifest["domain"] != directory:
        problems.append(
            f"domain {manifest['domain']!r} is not the directory {directory!r}"
        )
    if const_domain is not None and manifest["domain"] != const_domain:
        problems.append(
            f"domain {manifest['domain']!r} is not const.DOMAIN {const_domain!r}"
        )
    if manifest["config_flow"] is not True:
        problems.append("'config_flow' is not true")
    if manifest["iot_class"] != "local_polling":
        problems.append(
            f"'iot_class' is {manifest['iot_class']!r}, not 'local_polling'"
        )
    if manifest["integration_type"] not in INTEGRATION_TYPES:
        problems.append(
            f"'integration_type' {manifest['integration_type']!r} is unknown"
        )
    problems += [
        f"{key!r} is not an https URL"
        for key in ("documentation", "issue_tracker")
        if not manifest[key].startswith("https://")
    ]
    if not manifest["codeowners"] or not all(
        isinstance(owner, str) and owner.startswith("@")
        for owner in manifest["codeowners"]
    ):
        problems.append("'codeowners' must name at least one @owner")
    problems += [
        f"{key!r} must be a list of non-empty strings"
        for key in ("loggers", "requirements")
        if not all(isinstance(item, str) and item for item in manifest[key])
    ]
    try:
        AwesomeVersion(manifest["version"], ensure_strategy=VERSION_STRATEGIES)
    except AwesomeVersionException:
        problems.append(f"version {manifest['version']!r} is not a valid version")
    for matcher in manifest.get("dhcp", []):
        problems += _dhcp_matcher_problems(matcher)
    return problems


def _dhcp_matcher_problems(matcher: Any) -> list[str]:
    if not isinstance(matcher, Mapping) or not matcher:
        return [f"dhcp matcher {matcher!r} is not a non-empty object"]
    problems = [
        f"dhcp matcher key {key!r} is unknown"
        for key in matcher
        if key not in DHCP_MATCHER_KEYS
    ]
    mac = matcher.get("macaddress")
    if mac is not None and not re.fullmatch(r"[0-9A-F]{6}[0-9A-F*?]*", str(mac)):
        problems.append(
            f"dhcp macaddress {mac!r} is not upper-case hex without separators"
        )
    hostname = matcher.get("hostname")
    if hostname is not None and hostname != str(hostname).lower():
        problems.append(f"dhcp hostname {hostname!r} is not lower case")
    return problems


def const_domain(const_py: Path) -> str | None:
    """The `DOMAIN` string assigned at module level in const.py, if there is one."""
    if not const_py.is_file():
        return None
    for node in ast.parse(const_py.read_text(encoding="utf-8")).body:
        target, value = _simple_assignment(node)
        if (
            target == "DOMAIN"
            and isinstance(value, ast.Constant)
            and isinstance(value.value, str)
        ):
            return value.value
    return None


def _simple_assignment(node: ast.stmt) -> tuple[str | None, ast.expr | None]:
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


# ---------------------------------------------------------------------------
# Translation files (hassfest's translation schema rules, en/cs parity)

# hassfest: lower case, digits, '-' and '_', not doubled, not at either end.
TRANSLATION_KEY: Final = re.compile(r"(?!.*[_-]{2})(?![_-])[a-z0-9_-]+(?<![_-])")
# Children of these keys name config fields or service fields, not translation keys.
FREE_KEY_PARENTS: Final = frozenset({"data", "data_description", "fields", "sections"})
PLACEHOLDER: Final = re.compile(r"\{(\w+)\}")
# The strings of a step, exception or issue that receive its placeholders.
TEXT_PARTS: Final = ("title", "description", "message")
SINGLE_QUOTED_PLACEHOLDER: Final = re.compile(r"'[^']*\{[^}]+\}[^']*'")
HTML_TAG: Final = re.compile(r"<[a-zA-Z/][^>]*>")


def structure_differences(
    left: Mapping[str, Any], right: Mapping[str, Any], left_name: str, right_name: str
) -> list[str]:
    """Keys one translation tree has and the other lacks (or has as a leaf)."""
    left_paths, right_paths = key_paths(left), key_paths(right)
    problems = [
        f"{_dotted(path)} is in {left_name} but not in {right_name}"
        for path in sorted(left_paths - right_paths)
    ]
    problems += [
        f"{_dotted(path)} is in {right_name} but not in {left_name}"
        for path in sorted(right_paths - left_paths)
    ]
    left_leaves, right_leaves = dict(leaves(left)), dict(leaves(right))
    problems += [
        f"{_dotted(path)} is a string in one file and an object in the other"
        for path in sorted(left_paths & right_paths)
        if (path in left_leaves) != (path in right_leaves)
    ]
    return problems


def translation_string_problems(tree: Mapping[str, Any], file_name: str) -> list[str]:
    """Keys hassfest would reject and strings a user would see broken."""
    problems = [
        f"{file_name}: key {_dotted(path)} is not a valid translation key"
        for path in sorted(key_paths(tree))
        if (len(path) < 2 or path[-2] not in FREE_KEY_PARENTS)
        and not TRANSLATION_KEY.fullmatch(path[-1])
    ]
    for path, value in leaves(tree):
        where = f"{file_name}: {_dotted(path)}"
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
                f"{_dotted(path)}: {left_name} has {sorted(mine)}, {right_name} has {sorted(theirs)}"
            )
    return problems


# ---------------------------------------------------------------------------
# What the Python code asks of the translations (read with `ast`)

_PLATFORM_BY_CAMEL: Final = {
    "".join(part.title() for part in platform.value.split("_")): platform.value
    for platform in Platform
}
_EXCEPTION_SUFFIXES: Final = ("Error", "Exception", "Failed", "NotReady", "Invalid")
_SCHEMA_MARKERS: Final = frozenset({"Required", "Optional", "Exclusive", "Inclusive"})
# Callee -> (position of the action name, position when the first argument is
# `hass`, keyword of the action name).
_SERVICE_REGISTRARS: Final = {
    "async_register": (1, 1, "service"),
    "async_register_admin_service": (2, 2, "service"),
    "async_register_entity_service": (0, 2, "name"),
    "async_register_platform_entity_service": (2, 2, "service_name"),
}


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


def _parameter(
    function: ast.FunctionDef | ast.AsyncFunctionDef, name: str
) -> Parameter | None:
    arguments = function.args
    positional = [
        argument.arg
        for argument in (*arguments.posonlyargs, *arguments.args)
        if argument.arg not in {"self", "cls"}
    ]
    if name in positional:
        return name, positional.index(name)
    if name in {argument.arg for argument in arguments.kwonlyargs}:
        return name, None
    return None


def _argument(call: ast.Call, parameter: Parameter) -> ast.expr | None:
    name, position = parameter
    for keyword in call.keywords:
        if keyword.arg == name:
            return keyword.value
    if position is not None and len(call.args) > position:
        return call.args[position]
    return None


def _fill(template: KeyTemplate, key: str) -> KeyPath:
    return tuple(key if part is None else part for part in template)


def _names_this_domain(domain: ast.expr) -> bool:
    """Whether a `translation_domain=` names this integration (DOMAIN, or its name)."""
    if isinstance(domain, ast.Name):
        return domain.id == "DOMAIN"
    return isinstance(domain, ast.Constant) and domain.value == INTEGRATION.name


def _terminal_name(node: ast.expr) -> str:
    if isinstance(node, ast.Name):
        return node.id
    if isinstance(node, ast.Attribute):
        return node.attr
    if isinstance(node, ast.Call):
        return _terminal_name(node.func)
    if isinstance(node, ast.Subscript):
        return _terminal_name(node.value)
    return ""


def _platform_of_name(name: str) -> str | None:
    for suffix in ("EntityDescription", "Description", "Entity"):
        name = name.removesuffix(suffix)
    matches = [camel for camel in _PLATFORM_BY_CAMEL if name.endswith(camel)]
    return _PLATFORM_BY_CAMEL[max(matches, key=len)] if matches else None


def _module_constants(trees: Mapping[str, ast.Module]) -> dict[str, str | None]:
    """Module-level string constants of all modules; None where modules disagree."""
    constants: dict[str, str | None] = {}
    for tree in trees.values():
        for node in tree.body:
            name, value = _simple_assignment(node)
            if (
                name
                and isinstance(value, ast.Constant)
                and isinstance(value.value, str)
            ):
                if name in constants and constants[name] != value.value:
                    constants[name] = None
                else:
                    constants[name] = value.value
    return constants


class _ModuleReader(ast.NodeVisitor):
    """Collects translation and action uses from one module."""

    def __init__(
        self,
        module: str,
        tree: ast.Module,
        constants: Mapping[str, str | None],
        usage: TranslationUsage,
    ) -> None:
        self._module = module
        self.module = module
        self.tree = tree
        self._constants = constants
        self._usage = usage
        self._classes: dict[str, ast.ClassDef] = {
            node.name: node for node in tree.body if isinstance(node, ast.ClassDef)
        }
        self._functions: dict[str, ast.FunctionDef | ast.AsyncFunctionDef] = {
            node.name: node
            for node in tree.body
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef)
        }
        self._module_values: dict[str, ast.expr] = {}
        for node in tree.body:
            name, value = _simple_assignment(node)
            if name and value is not None:
                self._module_values[name] = value
        self.module_values: Mapping[str, ast.expr] = self._module_values

    def import_values(self, values: Mapping[str, Mapping[str, ast.expr]]) -> None:
        """Know the module-level values this module imports from its siblings.

        A schema defined in one module (``from .options import OPTIONS_SCHEMA``)
        is read where a form shows it.
        """
        package = self._module.split(".")[:-1]
        for node in self.tree.body:
            if not isinstance(node, ast.ImportFrom) or node.level == 0:
                continue
            parts = package[: len(package) - (node.level - 1)]
            source = values.get(".".join([*parts, *(node.module or "").split(".")]))
            for alias in node.names:
                if source is not None and alias.name in source:
                    self._module_values.setdefault(
                        alias.asname or alias.name, source[alias.name]
                    )
        self._class_stack: list[ast.ClassDef] = []
        self._function_stack: list[ast.FunctionDef | ast.AsyncFunctionDef] = []

    # -- resolution -------------------------------------------------------

    def _string(self, node: ast.expr | None) -> str | None:
        if isinstance(node, ast.Constant) and isinstance(node.value, str):
            return node.value
        if isinstance(node, ast.Name):
            if node.id in self._constants:
                return self._constants[node.id]
            value = getattr(ha_const, node.id, None)
            return value if isinstance(value, str) else None
        if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name):
            owner = getattr(ha_const, node.value.id, None)
            value = getattr(owner, node.attr, None) if owner is not None else None
            return value if isinstance(value, str) else None
        return None

    def _where(self, node: ast.AST) -> str:
        return f"{self._module}:{getattr(node, 'lineno', '?')}"

    def _need(self, path: KeyPath, node: ast.AST) -> None:
        # A subentry flow's section is "config_subentries.*": one flow class may
        # serve several subentry types, and each needs the key.
        path = (*path[0].split("."), *path[1:]) if path else path
        self._usage.required.setdefault(path, self._where(node))

    def _problem(self, node: ast.AST, text: str) -> None:
        self._usage.problems.append(f"{self._where(node)}: {text}")

    def _bases(
        self, cls: ast.ClassDef, seen: frozenset[str] = frozenset()
    ) -> Iterator[str]:
        """Names of a class's bases, following classes of this module."""
        for base in cls.bases:
            name = _terminal_name(base)
            yield name
            if name in self._classes and name not in seen:
                yield from self._bases(self._classes[name], seen | {name})

    def _flow_section(self) -> str | None:
        if not self._class_stack:
            return None
        for name in self._bases(self._class_stack[-1]):
            if "OptionsFlow" in name:
                return "options"
            if "SubentryFlow" in name:
                return f"config_subentries.{ANY_KEY}"
            if "ConfigFlow" in name:
                return "config"
        return None

    def _entity_platform(self) -> str | None:
        if self._class_stack:
            for name in self._bases(self._class_stack[-1]):
                if name.endswith("Entity") and (platform := _platform_of_name(name)):
                    return platform
        stem = self._module.rpartition(".")[2]
        return stem if stem in _PLATFORM_BY_CAMEL.values() else None

    def _defines_step(self, step: str) -> bool:
        return self._method(f"async_step_{step}") is not None

    # -- visiting ---------------------------------------------------------

    def visit_ClassDef(self, node: ast.ClassDef) -> None:
        self._class_stack.append(node)
        self.generic_visit(node)
        self._class_stack.pop()

    def _visit_function(self, node: ast.FunctionDef | ast.AsyncFunctionDef) -> None:
        self._function_stack.append(node)
        self.generic_visit(node)
        self._function_stack.pop()

    def visit_FunctionDef(self, node: ast.FunctionDef) -> None:
        self._visit_function(node)

    def visit_AsyncFunctionDef(self, node: ast.AsyncFunctionDef) -> None:
        self._visit_function(node)

    def visit_Constant(self, node: ast.Constant) -> None:
        if isinstance(node.value, str):
            self._usage.literals.add(node.value)

    def visit_Assign(self, node: ast.Assign) -> None:
        for target in node.targets:
            self._assignment(target, node.value, node)
        self.generic_visit(node)

    def visit_AnnAssign(self, node: ast.AnnAssign) -> None:
        if node.value is not None:
            self._assignment(node.target, node.value, node)
        self.generic_visit(node)

    def _assignment(self, target: ast.expr, value: ast.expr, node: ast.AST) -> None:
        if _terminal_name(target) == "_attr_translation_key":
            self._entity_key(value, node)
        elif (
            isinstance(target, ast.Subscript)
            and _terminal_name(target.value) == "errors"
        ):
            self._flow_error(value, node)
        elif isinstance(target, ast.Name) and target.id == "errors":
            if isinstance(value, ast.Dict):
                for item in value.values:
                    self._flow_error(item, node)
            else:
                self._errors_returned_by(value, None)
        elif isinstance(target, ast.Tuple):
            for index, element in enumerate(target.elts):
                if isinstance(element, ast.Name) and element.id == "errors":
                    self._errors_returned_by(value, index)
        elif (
            isinstance(target, ast.Subscript)
            and _terminal_name(target.value) == "context"
            and self._string(target.slice) == "title_placeholders"
        ):
            self._need(("config", "flow_title"), node)
            self._provide(
                ("config", "flow_title"),
                self._dict_keys(value, self._local_values()),
                node,
            )

    def _errors_returned_by(self, value: ast.expr, index: int | None) -> None:
        """Errors in the dicts a flow helper returns (whole, or item `index`)."""
        if isinstance(value, ast.Await):
            value = value.value
        if not isinstance(value, ast.Call):
            return
        function = self._definition(value.func)
        if function is None:
            return
        for node in ast.walk(function):
            if not isinstance(node, ast.Return) or node.value is None:
                continue
            result = node.value
            if index is not None:
                if not isinstance(result, ast.Tuple) or len(result.elts) <= index:
                    continue
                result = result.elts[index]
            if isinstance(result, ast.Dict):
                for item in result.values:
                    self._flow_error(item, node)

    def _definition(
        self, callee: ast.expr
    ) -> ast.FunctionDef | ast.AsyncFunctionDef | None:
        """The function or method of this module that `callee` names."""
        if isinstance(callee, ast.Name):
            return self._functions.get(callee.id)
        if (
            isinstance(callee, ast.Attribute)
            and isinstance(callee.value, ast.Name)
            and callee.value.id == "self"
        ):
            return self._method(callee.attr)
        return None

    def _method(self, name: str) -> ast.FunctionDef | ast.AsyncFunctionDef | None:
        """A method of the enclosing class or of its bases in this module."""
        if not self._class_stack:
            return None
        classes = [self._class_stack[-1]]
        classes += [
            self._classes[base]
            for base in self._bases(self._class_stack[-1])
            if base in self._classes
        ]
        for cls in classes:
            for node in cls.body:
                if (
                    isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef)
                    and node.name == name
                ):
                    return node
        return None

    def _flow_error(self, value: ast.expr, node: ast.AST) -> None:
        if isinstance(value, ast.IfExp):  # "a" if plccoms else "b": both are shown
            self._flow_error(value.body, node)
            self._flow_error(value.orelse, node)
            return
        error = self._string(value)
        section = self._flow_section()
        if error is None:
            return
        if section is None:
            self._problem(node, f"error {error!r} set outside a config or options flow")
        else:
            self._need((section, "error", error), node)

    def _need_key(
        self,
        template: KeyTemplate,
        key: ast.expr,
        node: ast.AST,
        placeholders: ast.expr | None = None,
    ) -> None:
        """Need the key `key` evaluates to, or its callers' keys if a parameter.

        With `placeholders` (an exception's translation_placeholders, None when
        not passed), also record which placeholder names the message receives.
        """
        track = template[0] == "exceptions"
        if (value := self._string(key)) is not None:
            self._need(_fill(template, value), node)
            if track:
                self._provide(
                    _fill(template, value)[:2],
                    self._dict_keys(
                        placeholders or ast.Dict([], []), self._local_values()
                    ),
                    node,
                )
            return
        if not isinstance(key, ast.Name) or not self._function_stack:
            return  # chosen at runtime; unused_translations() accepts its literals
        function = self._function_stack[-1]
        if (parameter := _parameter(function, key.id)) is None:
            return
        forwarded_placeholders = None
        if track and isinstance(placeholders, ast.Name):
            forwarded_placeholders = _parameter(function, placeholders.id)
        self._usage.forwarded[function.name] = Forwarding(
            parameter, forwarded_placeholders, template
        )

    def _entity_key(
        self, key: ast.expr, node: ast.AST, platform: str | None = None
    ) -> None:
        platform = platform or self._entity_platform()
        if platform is not None:
            self._need_key(("entity", platform, None), key, node)
        elif (value := self._string(key)) is not None:
            self._problem(
                node, f"cannot tell the entity platform of translation_key {value!r}"
            )

    def need_forwarded_keys(self) -> None:
        """Need the keys this module passes to functions that forward them."""
        functions = [
            node
            for node in ast.walk(self.tree)
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef)
        ]
        scopes: list[tuple[ast.AST, Mapping[str, list[ast.expr]]]] = [(self.tree, {})]
        scopes += [(function, self._local_values(function)) for function in functions]
        for scope, local_values in scopes:
            for node in ast.walk(scope):
                if not isinstance(node, ast.Call):
                    continue
                forwarding = self._usage.forwarded.get(_terminal_name(node.func))
                if forwarding is None:
                    continue
                key = self._string(_argument(node, forwarding.key))
                if key is None:
                    continue
                path = _fill(forwarding.template, key)
                self._need(path, node)
                if forwarding.placeholders is not None and scope is not self.tree:
                    argument = _argument(node, forwarding.placeholders)
                    self._provide(
                        path[:2], self._dict_keys(argument, local_values), node
                    )

    def visit_Call(self, node: ast.Call) -> None:
        name = _terminal_name(node.func)
        keywords = {kw.arg: kw.value for kw in node.keywords if kw.arg}
        if name in _FLOW_CALLS:
            self._flow_call(name, node, keywords)
        elif name in _SERVICE_REGISTRARS:
            self._service_registration(name, node, keywords)
        elif "translation_key" in keywords:
            self._keyed_call(name, node, keywords)
        self.generic_visit(node)

    def _keyed_call(
        self, name: str, node: ast.Call, keywords: Mapping[str, ast.expr]
    ) -> None:
        key = keywords["translation_key"]
        if name == "async_create_issue":
            self._need_key(("issues", None, "title"), key, node)
        elif name == "DeviceInfo":
            self._need_key(("device", None, "name"), key, node)
        elif name.endswith("SelectorConfig"):
            self._selector_key(key, keywords.get("options"), node)
        elif "translation_domain" in keywords and not _names_this_domain(
            keywords["translation_domain"]
        ):
            pass  # another integration's strings: Home Assistant's own, say
        elif "translation_domain" in keywords or name.endswith(_EXCEPTION_SUFFIXES):
            self._need_key(
                ("exceptions", None, "message"),
                key,
                node,
                keywords.get("translation_placeholders"),
            )
        elif name.endswith("Description"):
            platform = _platform_of_name(name)
            if platform is None and name in self._classes:
                platform = next(
                    filter(
                        None, map(_platform_of_name, self._bases(self._classes[name]))
                    ),
                    None,
                )
            self._entity_key(key, node, platform)
        else:
            self._entity_key(key, node)

    def _selector_key(
        self, key: ast.expr, options: ast.expr | None, node: ast.AST
    ) -> None:
        self._need_key(("selector", None, "options"), key, node)
        if isinstance(options, ast.List | ast.Tuple):
            for option in options.elts:
                if (value := self._string(option)) is not None:
                    self._need_key(("selector", None, "options", value), key, node)

    def _service_registration(
        self, name: str, node: ast.Call, keywords: Mapping[str, ast.expr]
    ) -> None:
        position, position_after_hass, keyword = _SERVICE_REGISTRARS[name]
        if node.args and _terminal_name(node.args[0]) == "hass":
            position = position_after_hass
        value = keywords.get(keyword)
        if value is None and len(node.args) > position:
            value = node.args[position]
        action = self._string(value)
        if action is None:
            self._problem(node, f"cannot read the action name registered by {name}()")
        else:
            self._usage.services.setdefault(action, self._where(node))

    def _flow_call(
        self, name: str, node: ast.Call, keywords: Mapping[str, ast.expr]
    ) -> None:
        section = self._flow_section()
        if section is None:
            self._problem(node, f"{name}() outside a config or options flow")
            return
        for reason in _FLOW_CALLS[name](self, node, keywords):
            self._need((section, "abort", reason), node)

    def _show_form(self, node: ast.Call, keywords: Mapping[str, ast.expr]) -> list[str]:
        section = self._flow_section()
        assert section is not None
        step = self._step_id(node, keywords)
        if step is None:
            return []
        self._need((section, "step", step), node)
        self._provide(
            (section, "step", step),
            self._dict_keys(
                keywords.get("description_placeholders", ast.Dict([], [])),
                self._local_values(),
            ),
            node,
        )
        errors = keywords.get("errors")
        if isinstance(errors, ast.Dict):
            for value in errors.values:
                self._flow_error(value, node)
        schema = keywords.get("data_schema")
        if schema is not None:
            for path in sorted(self._schema_fields(schema)):
                # A field of a form section is under "sections" (see _schema_fields).
                *within, data_key = path
                self._need((section, "step", step, *within, "data", data_key), node)
        return []

    def _show_menu(self, node: ast.Call, keywords: Mapping[str, ast.expr]) -> list[str]:
        section = self._flow_section()
        assert section is not None
        step = self._step_id(node, keywords)
        options = keywords.get("menu_options")
        if step is not None and isinstance(options, ast.List | ast.Tuple):
            for option in options.elts:
                if (value := self._string(option)) is not None:
                    self._need((section, "step", step, "menu_options", value), node)
        return []

    def _step_id(self, node: ast.Call, keywords: Mapping[str, ast.expr]) -> str | None:
        if "step_id" in keywords:
            value = keywords["step_id"]
            if isinstance(value, ast.Attribute) and value.attr.endswith("step_id"):
                # A source's own form (``form.step_id``, its words'
                # ``options_step_id``): its keys come from the descriptors
                # themselves (see descriptor_usage).
                return None
            step = self._string(value)
            if step is None:
                self._problem(node, "cannot read step_id")
            return step
        function = self._function_stack[-1].name if self._function_stack else ""
        if function.startswith("async_step_"):
            return function.removeprefix("async_step_")
        self._problem(node, "a form without step_id outside an async_step_* method")
        return None

    def _reason(
        self, keywords: Mapping[str, ast.expr], node: ast.Call, keyword: str = "reason"
    ) -> str | None:
        value = keywords.get(keyword)
        if value is None and node.args:
            value = node.args[0]
        return self._string(value)

    def _abort(self, node: ast.Call, keywords: Mapping[str, ast.expr]) -> list[str]:
        reason = self._reason(keywords, node)
        return [reason] if reason else []

    def _update_and_abort(
        self, node: ast.Call, keywords: Mapping[str, ast.expr]
    ) -> list[str]:
        if "reason" in keywords:
            reason = self._string(keywords["reason"])
            return [reason] if reason else []
        # Home Assistant picks the reason from the flow's source; on the floor
        # release it is the integration's own string, not a shared one.
        function = self._function_stack[-1].name if self._function_stack else ""
        if "reconfigure" in function:
            return ["reconfigure_successful"]
        if "reauth" in function:
            return ["reauth_successful"]
        sources = {
            "reauth": "reauth_successful",
            "reconfigure": "reconfigure_successful",
        }
        return [reason for step, reason in sources.items() if self._defines_step(step)]

    def _schema_fields(self, expr: ast.expr) -> set[tuple[str, ...]]:
        """Keys of vol.Required/Optional markers reachable from a schema expression.

        A plain field is ``(key,)``; a field of a form section (``KEY: section(
        SCHEMA, ...)``) is ``("sections", KEY, field)``, as translations nest it.
        """
        fields: set[tuple[str, ...]] = set()
        pending: list[ast.AST] = [expr]
        seen: set[int] = set()
        local_values = self._local_values()
        while pending:
            current = pending.pop()
            if id(current) in seen:
                continue
            seen.add(id(current))
            for child in ast.walk(current):
                if isinstance(child, ast.Dict):
                    for key_node, value in zip(child.keys, child.values, strict=True):
                        if (
                            key_node is None
                            or not isinstance(value, ast.Call)
                            or _terminal_name(value.func) != "section"
                            or not value.args
                        ):
                            continue
                        marker = key_node
                        seen.update(id(node) for node in ast.walk(marker))
                        seen.update(id(node) for node in ast.walk(value))
                        name = (
                            self._string(marker.args[0])
                            if isinstance(marker, ast.Call) and marker.args
                            else None
                        )
                        if name is not None:
                            fields |= {
                                ("sections", name, *inner)
                                for inner in self._schema_fields(value.args[0])
                            }
                elif id(child) in seen and child is not current:
                    continue
                elif (
                    isinstance(child, ast.Call)
                    and _terminal_name(child.func) in _SCHEMA_MARKERS
                ):
                    if child.args and (key := self._string(child.args[0])) is not None:
                        fields.add((key,))
                elif isinstance(child, ast.Name):
                    pending += local_values.get(child.id, [])
                    if child.id in self._module_values:
                        pending.append(self._module_values[child.id])
                    if child.id in self._functions:
                        pending.append(self._functions[child.id])
                elif isinstance(child, ast.Attribute) and (
                    method := self._definition(child)
                ):
                    pending.append(method)
        return fields

    def _local_values(
        self, function: ast.FunctionDef | ast.AsyncFunctionDef | None = None
    ) -> dict[str, list[ast.expr]]:
        values: dict[str, list[ast.expr]] = {}
        function = function or (
            self._function_stack[-1] if self._function_stack else None
        )
        if function is None:
            return values
        for node in ast.walk(function):
            if isinstance(node, ast.Assign | ast.AnnAssign):
                targets = (
                    node.targets if isinstance(node, ast.Assign) else [node.target]
                )
                for target in targets:
                    if isinstance(target, ast.Name) and node.value is not None:
                        values.setdefault(target.id, []).append(node.value)
        return values

    def _dict_keys(
        self, expr: ast.expr | None, local_values: Mapping[str, list[ast.expr]]
    ) -> frozenset[str] | None:
        """The keys a placeholders mapping always has, or None if unreadable."""
        if isinstance(expr, ast.Dict):
            keys: set[str] = set()
            for key, value in zip(expr.keys, expr.values, strict=True):
                part = (
                    self._dict_keys(value, local_values)
                    if key is None
                    else frozenset(filter(None, [self._string(key)]))
                )
                if part is None or (key is not None and not part):
                    return None
                keys |= part
            return frozenset(keys)
        if isinstance(expr, ast.BinOp) and isinstance(expr.op, ast.BitOr):
            left = self._dict_keys(expr.left, local_values)
            right = self._dict_keys(expr.right, local_values)
            return None if left is None or right is None else left | right
        if isinstance(expr, ast.Name):
            assigned = local_values.get(expr.id, [])
            if len(assigned) == 1:
                return self._dict_keys(assigned[0], local_values)
            if not assigned and expr.id in self._module_values:
                return self._dict_keys(self._module_values[expr.id], {})
        return None

    def _provide(
        self, path: KeyPath, provided: frozenset[str] | None, node: ast.AST
    ) -> None:
        """Record the placeholders a call passes; several calls: the common ones."""
        if provided is None or not all(path):
            return
        if path in self._usage.placeholders:
            known, where = self._usage.placeholders[path]
            self._usage.placeholders[path] = (known & provided, where)
        else:
            self._usage.placeholders[path] = (provided, self._where(node))


def _fixed(*reasons: str) -> Any:
    return lambda _reader, _node, _keywords: list(reasons)


def _set_unique_id(
    _reader: _ModuleReader, _node: ast.Call, keywords: Mapping[str, ast.expr]
) -> list[str]:
    raises = keywords.get("raise_on_progress")
    if isinstance(raises, ast.Constant) and raises.value is False:
        return []
    return ["already_in_progress"]


# Flow calls -> the abort reasons they can end in (and, for forms, other keys).
_FLOW_CALLS: Final[dict[str, Any]] = {
    "async_show_form": _ModuleReader._show_form,
    "async_show_menu": _ModuleReader._show_menu,
    "async_abort": _ModuleReader._abort,
    "AbortFlow": _ModuleReader._abort,
    "async_update_reload_and_abort": _ModuleReader._update_and_abort,
    "async_update_and_abort": _ModuleReader._update_and_abort,
    "_abort_if_unique_id_configured": lambda reader, node, keywords: [
        reader._string(keywords["error"])
        if "error" in keywords
        else "already_configured"
    ],
    "_abort_if_unique_id_mismatch": lambda reader, node, keywords: [
        reader._string(keywords["reason"])
        if "reason" in keywords
        else "unique_id_mismatch"
    ],
    "_async_abort_entries_match": _fixed("already_configured"),
    "async_set_unique_id": _set_unique_id,
    "_async_handle_discovery_without_unique_id": _fixed(
        "already_in_progress", "already_configured"
    ),
}


def read_usage(sources: Mapping[str, str]) -> TranslationUsage:
    """What the modules (dotted name -> source) need from translations and services.yaml."""
    trees = {
        module: ast.parse(source, filename=module) for module, source in sources.items()
    }
    constants = _module_constants(trees)
    usage = TranslationUsage()
    readers = [
        _ModuleReader(module, tree, constants, usage) for module, tree in trees.items()
    ]
    values = {reader.module: dict(reader.module_values) for reader in readers}
    for reader in readers:
        reader.import_values(values)
    for reader in readers:
        reader.visit(reader.tree)
    for reader in readers:
        reader.need_forwarded_keys()
    usage.required = {
        path: where for path, where in usage.required.items() if all(path)
    }
    return usage


def descriptor_usage(
    usage: TranslationUsage, descriptors: Iterable[SourceDescriptor]
) -> None:
    """Add what each source's forms need: the config flow builds them from its descriptor.

    The first step's menu offers each source; its connect and reconfigure forms
    show its fields (and its form placeholders), reauthentication and a
    discovered device's confirmation its credentials; its errors are form errors
    (a push server's, the options' too), its probe's answers abort reasons. A
    form that uploads a point map shows the upload's errors, naming ``{error}``;
    the forms that check a connection show what an error rule's message names
    of its failure (``{code}``).
    """

    def need(path: KeyPath, where: str) -> None:
        usage.required.setdefault(path, where)

    def provide(path: KeyPath, names: Iterable[str], where: str) -> None:
        provided = frozenset(names)
        if path in usage.placeholders:
            known, first = usage.placeholders[path]
            usage.placeholders[path] = (known & provided, first)
        else:
            usage.placeholders[path] = (provided, where)

    by_name = {descriptor.name: descriptor for descriptor in descriptors}
    for descriptor in by_name.values():
        where = f"descriptor {descriptor.name}"
        connect, reconfigure = descriptor.connect, descriptor.reconfigure
        need(("config", "step", "user", "menu_options", connect.step_id), where)
        uploads = any(field.kind is FieldKind.POINT_MAP for field in connect.fields)
        shown = {name for rule in descriptor.errors for name in rule.placeholders}
        for form in (connect, reconfigure):
            for item in form.fields:
                need(("config", "step", form.step_id, "data", item.key), where)
            extra = shown | ({"error"} if uploads and form is connect else set())
            provide(
                ("config", "step", form.step_id), {*form.placeholders, *extra}, where
            )
        words = descriptor.words
        steps = [words.reauth_step_id] if descriptor.credentials else []
        if descriptor.probe is not None:
            steps.append("dhcp_confirm")
        for step in steps:
            for item in descriptor.credentials:
                need(("config", "step", step, "data", item.key), where)
            provide(("config", "step", step), {*connect.placeholders, "host"}, where)
        for rule in descriptor.errors:
            need(("config", "error", rule.key), where)
        if uploads:
            need(("config", "error", "point_map_invalid"), where)
            need(("config", "error", "point_map_missing"), where)
            # A new entry says how many points its file holds.
            need(("config", "create_entry", "point_map"), where)
            provide(
                ("config", "create_entry", "point_map"),
                {"points", "entities", "skipped"},
                where,
            )
        if Capability.POINT_MAP in descriptor.capabilities:
            # A newer file is checked on the device: its errors are the options'.
            # The failure's details go with its error, as in the config flow.
            for rule in descriptor.errors:
                need(("options", "error", rule.key), where)
                provide(("options", "error", rule.key), rule.placeholders, where)
            need(("options", "error", "point_map_other_device"), where)
        for reason in descriptor.probe_reasons:
            need(("config", "abort", reason), where)
        if descriptor.push_server is not None:
            for rule in by_name[descriptor.push_server].errors:
                need(("options", "error", rule.key), where)
        # Its abort reasons, in its own words.
        for reason in (
            words.already_configured,
            words.wrong_device,
            words.reconfigured,
        ):
            need(("config", "abort", reason), where)
        # The options form: the fields its capabilities use, on the first step
        # (or, for a source with a map, on its settings step behind its menu),
        # its device grouping's choices labelled in its words.
        step = words.options_step_id
        if Capability.POINT_MAP in descriptor.capabilities:
            for option in MAP_MENU:
                need(("options", "step", step, "menu_options", option), where)
            assert words.settings_step_id != step, where  # its own, behind the menu
        step = words.settings_step_id
        need(("options", "step", step, "title"), where)
        for marker in options_schema(descriptor).schema:
            need(("options", "step", step, "data", str(marker)), where)
        for grouping in DeviceGrouping:
            need(("selector", words.devices, "options", grouping.value), where)
        if descriptor.push_server is not None:
            for marker in PUSH_SCHEMA.schema:
                need(
                    ("options", "step", step, "sections", "push", "data", str(marker)),
                    where,
                )


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
        f"{_dotted(path)} (used at {where})"
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
        _dotted(path)
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
                    f"{_dotted(text_path)} uses {missing}, not passed at {where}"
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


# ---------------------------------------------------------------------------
# services.yaml, icons.json


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
        f"{_dotted(path)}: {value!r} is not an mdi: icon"
        for path, value in leaves(icons)
        if not isinstance(value, str) or not MDI_ICON.fullmatch(value)
    ]
    return problems


# ---------------------------------------------------------------------------
# Brand images (Home Assistant's brands rules)

BRAND_IMAGES: Final = frozenset(
    {
        "icon.png",
        "icon@2x.png",
        "logo.png",
        "logo@2x.png",
        "dark_icon.png",
        "dark_icon@2x.png",
        "dark_logo.png",
        "dark_logo@2x.png",
    }
)
REQUIRED_BRAND_IMAGES: Final = ("icon.png", "icon@2x.png", "logo.png", "logo@2x.png")
PNG_SIGNATURE: Final = b"\x89PNG\r\n\x1a\n"
# PNG colour types with an alpha channel: grey + alpha, RGBA.
PNG_ALPHA_TYPES: Final = frozenset({4, 6})


@dataclass(frozen=True, slots=True)
class PngHeader:
    """The IHDR facts of a PNG file."""

    width: int
    height: int
    colour_type: int


def png_header(data: bytes) -> PngHeader | None:
    """Width, height and colour type from a PNG's IHDR chunk, or None if not a PNG."""
    if len(data) < 33 or not data.startswith(PNG_SIGNATURE) or data[12:16] != b"IHDR":
        return None
    width, height, _depth, colour_type = struct.unpack(">IIBB", data[16:26])
    return PngHeader(width, height, colour_type)


def brand_problems(directory: Path) -> list[str]:
    """Missing, unknown, wrongly sized, opaque or untrimmed brand images."""
    present = (
        {path.name for path in directory.iterdir()} if directory.is_dir() else set()
    )
    problems = [
        f"{name} is missing" for name in REQUIRED_BRAND_IMAGES if name not in present
    ]
    problems += [
        f"{name} is not a brand image name" for name in sorted(present - BRAND_IMAGES)
    ]
    headers: dict[str, PngHeader] = {}
    for name in sorted(present & BRAND_IMAGES):
        header = png_header((directory / name).read_bytes())
        if header is None:
            problems.append(f"{name} is not a PNG")
            continue
        headers[name] = header
        problems += _brand_image_problems(name, header, directory / name)
    for name, header in headers.items():
        single = headers.get(name.replace("@2x", ""))
        if (
            "@2x" in name
            and single is not None
            and (
                abs(header.width - 2 * single.width) > 1
                or abs(header.height - 2 * single.height) > 1
            )
        ):
            problems.append(
                f"{name} is not twice the size of {name.replace('@2x', '')}"
            )
    return problems


def _brand_image_problems(name: str, header: PngHeader, path: Path) -> list[str]:
    problems: list[str] = []
    scale = 2 if "@2x" in name else 1
    size = f"{header.width}x{header.height}"
    if "icon" in name and (header.width, header.height) != (256 * scale, 256 * scale):
        problems.append(f"{name} is {size}, not {256 * scale}x{256 * scale}")
    if "logo" in name:
        shortest = min(header.width, header.height)
        if not 128 * scale <= shortest <= 256 * scale:
            problems.append(
                f"{name} is {size}; its shortest side must be {128 * scale}-{256 * scale} px"
            )
        if header.width < header.height:
            problems.append(f"{name} is {size}, not landscape")
    if header.colour_type not in PNG_ALPHA_TYPES:
        problems.append(f"{name} has no alpha channel")
        return problems
    with Image.open(path) as image:
        alpha = image.convert("RGBA").getchannel("A")
    low, _high = alpha.getextrema()
    if low != 0:
        problems.append(f"{name} has no transparent background")
    bbox = alpha.getbbox() or (0, 0, 0, 0)
    # Trimmed: the artwork reaches both edges along at least one axis (1 px slack
    # for antialiasing).
    spans_width = bbox[0] <= 1 and bbox[2] >= header.width - 1
    spans_height = bbox[1] <= 1 and bbox[3] >= header.height - 1
    if not (spans_width or spans_height):
        problems.append(f"{name} is not trimmed: artwork spans {bbox} of {size}")
    return problems


# ===========================================================================
# The repository's files


@pytest.fixture(scope="module")
def manifest() -> JsonObject:
    return _load_json(INTEGRATION / "manifest.json")


@pytest.fixture(scope="module")
def en() -> JsonObject:
    path = TRANSLATIONS / "en.json"
    assert path.is_file(), "translations/en.json is missing"
    return _load_json(path)


@pytest.fixture(scope="module")
def cs() -> JsonObject:
    path = TRANSLATIONS / "cs.json"
    assert path.is_file(), "translations/cs.json is missing"
    return _load_json(path)


@pytest.fixture(scope="module")
def usage() -> TranslationUsage:
    found = read_usage(integration_sources(INTEGRATION))
    descriptor_usage(found, registry.sources())
    return found


@pytest.fixture(scope="module")
def services_yaml() -> JsonObject:
    path = INTEGRATION / "services.yaml"
    return _load_yaml(path) if path.is_file() else {}


def test_hacs_json_has_only_accepted_keys_and_the_tested_floor() -> None:
    assert hacs_problems(_load_json(REPO / "hacs.json"), TESTED_FLOOR) == []


def test_hacs_finds_one_integration_and_a_readme() -> None:
    integrations = [
        path.name
        for path in (REPO / "custom_components").iterdir()
        if path.is_dir() and path.name != "__pycache__"
    ]
    assert integrations == ["tecoapi"]
    assert (REPO / "README.md").is_file()


def test_manifest_passes_hassfest_rules(manifest: JsonObject) -> None:
    assert (
        manifest_problems(
            manifest,
            directory=INTEGRATION.name,
            const_domain=const_domain(INTEGRATION / "const.py"),
        )
        == []
    )


def test_manifest_promises_a_config_flow_that_exists(manifest: JsonObject) -> None:
    assert manifest.get("config_flow") is True
    assert (INTEGRATION / "config_flow.py").is_file()


def test_translations_en_and_cs_have_the_same_keys(
    en: JsonObject, cs: JsonObject
) -> None:
    assert structure_differences(en, cs, "en.json", "cs.json") == []


def test_translation_strings_are_valid(en: JsonObject, cs: JsonObject) -> None:
    assert (
        translation_string_problems(en, "en.json")
        + translation_string_problems(cs, "cs.json")
        == []
    )


def test_translations_use_the_same_placeholders(en: JsonObject, cs: JsonObject) -> None:
    assert placeholder_differences(en, cs, "en.json", "cs.json") == []


def test_strings_json_matches_en(en: JsonObject) -> None:
    path = INTEGRATION / "strings.json"
    if not path.is_file():
        pytest.skip("no strings.json (optional for custom integrations)")
    assert structure_differences(_load_json(path), en, "strings.json", "en.json") == []


def test_code_reads_cleanly_for_translation_keys(usage: TranslationUsage) -> None:
    assert usage.problems == []


def test_every_translation_key_the_code_uses_exists(
    usage: TranslationUsage, en: JsonObject, cs: JsonObject
) -> None:
    assert missing_translations(usage, en) == []
    assert missing_translations(usage, cs) == []


def test_code_passes_every_placeholder_its_strings_use(
    usage: TranslationUsage, en: JsonObject, cs: JsonObject
) -> None:
    assert placeholder_gaps(usage, en) + placeholder_gaps(usage, cs) == []


def test_no_entity_exception_or_issue_translation_is_unused(
    usage: TranslationUsage, en: JsonObject
) -> None:
    assert unused_translations(en, usage) == []


def test_actions_agree_with_services_yaml_and_translations(
    usage: TranslationUsage, services_yaml: JsonObject, en: JsonObject
) -> None:
    if not services_yaml and not usage.services:
        pytest.skip("the integration registers no actions")
    assert service_problems(services_yaml, en, usage.services) == []


def test_icons_refer_to_existing_entities_and_actions(
    services_yaml: JsonObject, en: JsonObject
) -> None:
    path = INTEGRATION / "icons.json"
    if not path.is_file():
        pytest.skip("no icons.json")
    assert icon_problems(_load_json(path), en, services_yaml) == []


def test_brand_images_follow_the_brand_rules() -> None:
    assert brand_problems(BRAND) == []


# ===========================================================================
# The checkers fail on bad input


def test_checker_hacs_rejects_unknown_keys_missing_name_and_wrong_floor() -> None:
    assert hacs_problems({"name": "X", "homeassistant": "2026.2.0"}, "2026.2.0") == []
    assert hacs_problems(
        {"domains": ["sensor"], "homeassistant": "2025.1.0"}, "2026.2.0"
    ) == [
        "key 'domains' is not one HACS accepts",
        "'name' is missing or empty",
        "'homeassistant' is '2025.1.0', the tested floor is '2026.2.0'",
    ]


GOOD_MANIFEST: Final[JsonObject] = {
    "domain": "tecoapi",
    "name": "Tecomat TecoApi",
    "codeowners": ["@someone"],
    "config_flow": True,
    "dhcp": [{"macaddress": "F8DC7A*"}],
    "documentation": "https://example.org/docs",
    "integration_type": "device",
    "iot_class": "local_polling",
    "issue_tracker": "https://example.org/issues",
    "loggers": ["custom_components.tecoapi"],
    "requirements": [],
    "version": "0.1.0",
}


def test_checker_manifest_accepts_a_good_manifest() -> None:
    assert (
        manifest_problems(GOOD_MANIFEST, directory="tecoapi", const_domain="tecoapi")
        == []
    )


def test_checker_manifest_rejects_wrong_key_order() -> None:
    name_first = {"name": GOOD_MANIFEST["name"], **GOOD_MANIFEST}
    assert manifest_problems(name_first, directory="tecoapi", const_domain=None) == [
        (
            "keys are not 'domain', 'name', then alphabetical: name, domain, "
            "codeowners, config_flow, dhcp, documentation, integration_type, "
            "iot_class, issue_tracker, loggers, requirements, version"
        )
    ]
    unsorted = {**GOOD_MANIFEST}
    unsorted["codeowners"] = unsorted.pop("codeowners")
    assert any(
        "alphabetical" in problem
        for problem in manifest_problems(
            unsorted, directory="tecoapi", const_domain=None
        )
    )


def test_checker_manifest_rejects_missing_keys_and_bad_values() -> None:
    missing = {key: value for key, value in GOOD_MANIFEST.items() if key != "version"}
    assert manifest_problems(missing, directory="tecoapi", const_domain=None) == [
        "'version' is missing"
    ]
    bad = {
        **GOOD_MANIFEST,
        "dhcp": [{"macaddress": "f8:dc:7a:*", "vendor": "Teco"}],
        "iot_class": "cloud_polling",
        "version": "latest",
    }
    assert manifest_problems(bad, directory="teco", const_domain="other") == [
        "domain 'tecoapi' is not the directory 'teco'",
        "domain 'tecoapi' is not const.DOMAIN 'other'",
        "'iot_class' is 'cloud_polling', not 'local_polling'",
        "version 'latest' is not a valid version",
        "dhcp matcher key 'vendor' is unknown",
        "dhcp macaddress 'f8:dc:7a:*' is not upper-case hex without separators",
    ]
    assert manifest_problems(
        {**GOOD_MANIFEST, "colour": "blue"}, directory="tecoapi", const_domain=None
    ) == [
        "keys are not 'domain', 'name', then alphabetical: "
        + ", ".join([*GOOD_MANIFEST, "colour"]),
        "key 'colour' is not a manifest key",
    ]


def test_checker_const_domain_reads_the_module_constant(tmp_path: Path) -> None:
    const_py = tmp_path / "const.py"
    const_py.write_text(
        'from typing import Final\n\nDOMAIN: Final = "tecoapi"\n', encoding="utf-8"
    )
    assert const_domain(const_py) == "tecoapi"
    assert const_domain(tmp_path / "absent.py") is None


def test_checker_translation_trees_must_match() -> None:
    en_tree = {"config": {"error": {"cannot_connect": "x", "invalid_auth": "y"}}}
    cs_tree = {
        "config": {"error": {"cannot_connect": "x", "unknown": "z"}},
        "title": "t",
    }
    assert structure_differences(en_tree, cs_tree, "en", "cs") == [
        "config.error.invalid_auth is in en but not in cs",
        "config.error.unknown is in cs but not in en",
        "title is in cs but not in en",
    ]
    assert structure_differences({"a": "x"}, {"a": {"b": "x"}}, "en", "cs") == [
        "a.b is in cs but not in en",
        "a is a string in one file and an object in the other",
    ]


def test_checker_translation_strings_must_be_usable() -> None:
    tree = {
        "config": {
            "step": {
                "user": {"title": "", "description": " padded", "data": {"Host": "ok"}}
            },
            "error": {
                "Bad_Key": "x",
                "ref": "[%key:common::config_flow::error::cannot_connect%]",
            },
            "abort": {
                "quoted": "Device '{name}' exists",
                "html": "See <b>this</b>",
                "num": 3,
            },
        }
    }
    assert translation_string_problems(tree, "en.json") == [
        "en.json: key config.error.Bad_Key is not a valid translation key",
        "en.json: config.step.user.title is empty",
        "en.json: config.step.user.description has leading or trailing whitespace",
        "en.json: config.error.ref uses a [%key:…%] reference, which custom integrations do not resolve",
        "en.json: config.abort.quoted puts a placeholder in single quotes",
        "en.json: config.abort.html contains HTML",
        "en.json: config.abort.num is not a string",
    ]


def test_checker_placeholders_must_match_per_key() -> None:
    en_tree = {"a": "Connect to {host}", "b": "{count} points", "c": "plain"}
    cs_tree = {"a": "Připojit k {hostname}", "b": "{count} bodů", "c": "prostý"}
    assert placeholder_differences(en_tree, cs_tree, "en", "cs") == [
        "a: en has ['host'], cs has ['hostname']"
    ]


FLOW_SOURCE: Final = """
import voluptuous as vol
from homeassistant.config_entries import ConfigFlow, OptionsFlow
from homeassistant.const import CONF_HOST, CONF_PASSWORD

from .const import DOMAIN, ERROR_AUTH

STEP_USER = vol.Schema({vol.Required(CONF_HOST): str, vol.Required(CONF_PASSWORD): str})


class PlcConfigFlow(ConfigFlow, domain=DOMAIN):
    async def async_step_user(self, user_input=None):
        errors = {}
        if user_input is not None:
            await self.async_set_unique_id("serial")
            self._abort_if_unique_id_configured()
            errors["base"] = "cannot_connect"
            errors[CONF_PASSWORD] = ERROR_AUTH
        return self.async_show_form(step_id="user", data_schema=STEP_USER, errors=errors)

    async def async_step_dhcp(self, discovery_info):
        self.context["title_placeholders"] = {"name": "PLC"}
        return self.async_show_form(step_id="dhcp_confirm")

    async def async_step_reauth(self, entry_data):
        return await self.async_step_reauth_confirm()

    async def async_step_reauth_confirm(self, user_input=None):
        if user_input is not None:
            return self.async_update_reload_and_abort(self._entry, data_updates=user_input)
        return self.async_show_form(data_schema=vol.Schema({vol.Required("password"): str}))


class PlcOptionsFlow(OptionsFlow):
    async def async_step_init(self, user_input=None):
        return self.async_abort(reason="no_options")

    async def async_step_pick(self, user_input=None):
        choice = SelectSelectorConfig(options=["on", "off"], translation_key="mode")
        schema = vol.Schema({vol.Required("mode"): SelectSelector(choice)})
        return self.async_show_form(step_id="pick", data_schema=schema)


class SecondFlow(PlcConfigFlow):
    async def async_step_reconfigure(self, user_input=None):
        info, errors = await self._async_try(user_input)
        return self.async_show_form(step_id="reconfigure", errors=errors)

    async def _async_try(self, user_input):
        try:
            return await probe(user_input), {}
        except OSError:
            return None, {"base": "timeout"}
        except ValueError:
            return None, {"base": "refused_by_plc" if user_input else "no_input"}
"""

CONST_SOURCE: Final = """
from typing import Final

DOMAIN: Final = "tecoapi"
ERROR_AUTH: Final = "invalid_auth"
SERVICE_WRITE: Final = "write_variable"
"""

PLATFORM_SOURCE: Final = """
from homeassistant.components.sensor import SensorEntity, SensorEntityDescription
from homeassistant.components.switch import SwitchEntity
from homeassistant.exceptions import HomeAssistantError, ServiceValidationError
from homeassistant.helpers import issue_registry as ir

from .const import DOMAIN, SERVICE_WRITE

UPTIME = SensorEntityDescription(key="uptime", translation_key="uptime")
KINDS = {"temp": "temperature"}


class Boiler(SwitchEntity):
    _attr_translation_key = "boiler"


class Point(SensorEntity):
    def __init__(self, point):
        self._attr_translation_key = KINDS.get(point.kind)

    async def write(self):
        raise ServiceValidationError(translation_domain=DOMAIN, translation_key="read_only")


async def async_setup(hass):
    hass.services.async_register(DOMAIN, SERVICE_WRITE, handler)
    ir.async_create_issue(hass, DOMAIN, "x", translation_key="program_changed")
    raise HomeAssistantError(translation_domain=DOMAIN, translation_key="write_failed")


def _validation_error(translation_key, placeholders):
    return ServiceValidationError(
        translation_domain=DOMAIN,
        translation_key=translation_key,
        translation_placeholders=placeholders,
    )


def check(value):
    if value > 3:
        raise _validation_error("out_of_range", {"value": value})
"""


def _synthetic_usage() -> TranslationUsage:
    return read_usage(
        {"config_flow": FLOW_SOURCE, "const": CONST_SOURCE, "sensor": PLATFORM_SOURCE}
    )


def test_checker_reads_flows_entities_exceptions_issues_and_actions() -> None:
    usage = _synthetic_usage()
    assert usage.problems == []
    assert sorted(usage.required) == [
        ("config", "abort", "already_configured"),
        ("config", "abort", "already_in_progress"),
        ("config", "abort", "reauth_successful"),
        ("config", "error", "cannot_connect"),
        ("config", "error", "invalid_auth"),
        ("config", "error", "no_input"),
        ("config", "error", "refused_by_plc"),
        ("config", "error", "timeout"),
        ("config", "flow_title"),
        ("config", "step", "dhcp_confirm"),
        ("config", "step", "reauth_confirm"),
        ("config", "step", "reauth_confirm", "data", "password"),
        ("config", "step", "reconfigure"),
        ("config", "step", "user"),
        ("config", "step", "user", "data", "host"),
        ("config", "step", "user", "data", "password"),
        ("entity", "sensor", "uptime"),
        ("entity", "switch", "boiler"),
        ("exceptions", "out_of_range", "message"),
        ("exceptions", "read_only", "message"),
        ("exceptions", "write_failed", "message"),
        ("issues", "program_changed", "title"),
        ("options", "abort", "no_options"),
        ("options", "step", "pick"),
        ("options", "step", "pick", "data", "mode"),
        ("selector", "mode", "options"),
        ("selector", "mode", "options", "off"),
        ("selector", "mode", "options", "on"),
    ]
    # The key reaches ServiceValidationError through a helper's parameter.
    assert usage.forwarded == {
        "_validation_error": Forwarding(
            ("translation_key", 0),
            ("placeholders", 1),
            ("exceptions", None, "message"),
        )
    }
    assert set(usage.services) == {"write_variable"}
    assert usage.services["write_variable"].startswith("sensor:")


SECTION_FLOW_SOURCE: Final = """
import voluptuous as vol
from homeassistant.data_entry_flow import section

INNER = vol.Schema({vol.Optional("plccoms_host"): str})


class Options(OptionsFlow):
    async def async_step_init(self, user_input=None):
        schema = OUTER.extend({vol.Required("push"): section(INNER, {})})
        return self.async_show_form(step_id="init", data_schema=schema)


OUTER = vol.Schema({vol.Required("scan_interval"): int})
"""


def test_checker_puts_a_form_section_s_fields_under_sections() -> None:
    usage = read_usage({"config_flow": SECTION_FLOW_SOURCE})
    assert usage.problems == []
    assert sorted(usage.required) == [
        ("options", "step", "init"),
        ("options", "step", "init", "data", "scan_interval"),
        ("options", "step", "init", "sections", "push", "data", "plccoms_host"),
    ]


def test_checker_reads_a_schema_imported_from_a_sibling_module() -> None:
    usage = read_usage(
        {
            "options": 'import voluptuous as vol\nFORM = vol.Schema({vol.Required("devices"): str})\n',
            "config_flow": (
                "from .options import FORM\n\n\n"
                "class Options(OptionsFlow):\n"
                "    async def async_step_init(self, user_input=None):\n"
                '        return self.async_show_form(step_id="init", data_schema=FORM)\n'
            ),
        }
    )
    assert usage.problems == []
    assert sorted(usage.required) == [
        ("options", "step", "init"),
        ("options", "step", "init", "data", "devices"),
    ]


def test_checker_reports_missing_and_unused_translations() -> None:
    usage = _synthetic_usage()
    strings = {
        "config": {"step": {"user": {"data": {"host": "Host"}}}},
        "entity": {
            "sensor": {
                "uptime": {"name": "Uptime"},
                "temperature": {"name": "T"},
                "ghost": {"name": "G"},
            }
        },
        "exceptions": {"write_failed": {"message": "m"}, "stale": {"message": "s"}},
    }
    # Present: config.step.user(.data.host), entity.sensor.uptime, write_failed.
    assert missing_translations(usage, strings) == [
        "config.abort.already_configured (used at config_flow:16)",
        "config.abort.already_in_progress (used at config_flow:15)",
        "config.abort.reauth_successful (used at config_flow:30)",
        "config.error.cannot_connect (used at config_flow:17)",
        "config.error.invalid_auth (used at config_flow:18)",
        "config.error.no_input (used at config_flow:55)",
        "config.error.refused_by_plc (used at config_flow:55)",
        "config.error.timeout (used at config_flow:53)",
        "config.flow_title (used at config_flow:22)",
        "config.step.dhcp_confirm (used at config_flow:23)",
        "config.step.reauth_confirm (used at config_flow:31)",
        "config.step.reauth_confirm.data.password (used at config_flow:31)",
        "config.step.reconfigure (used at config_flow:47)",
        "config.step.user.data.password (used at config_flow:19)",
        "entity.switch.boiler (used at sensor:14)",
        "exceptions.out_of_range.message (used at sensor:41)",
        "exceptions.read_only.message (used at sensor:22)",
        "issues.program_changed.title (used at sensor:27)",
        "options.abort.no_options (used at config_flow:36)",
        "options.step.pick (used at config_flow:41)",
        "options.step.pick.data.mode (used at config_flow:41)",
        "selector.mode.options (used at config_flow:39)",
        "selector.mode.options.off (used at config_flow:39)",
        "selector.mode.options.on (used at config_flow:39)",
    ]
    # `temperature` is chosen at runtime from a mapping: its literal counts as a use.
    assert unused_translations(strings, usage) == [
        "entity.sensor.ghost",
        "exceptions.stale",
    ]


def test_checker_leaves_home_assistants_own_keys_to_it() -> None:
    """An error raised with Home Assistant's strings needs none of the integration's."""
    usage = read_usage(
        {
            "compat": (
                "def unload(done):\n"
                "    if not done:\n"
                "        raise ConfigEntryError(\n"
                "            translation_domain=HOMEASSISTANT_DOMAIN,\n"
                "            translation_key='unload_platforms_failed',\n"
                "        )\n"
                "    raise ConfigEntryError(translation_domain=DOMAIN, translation_key='ours')\n"
            )
        }
    )
    assert missing_translations(usage, {}) == [
        "exceptions.ours.message (used at compat:7)"
    ]


def test_checker_reports_placeholders_the_code_does_not_pass() -> None:
    usage = _synthetic_usage()
    assert usage.placeholders[("config", "flow_title")] == (
        frozenset({"name"}),
        "config_flow:22",
    )
    strings = {
        "config": {
            "flow_title": "{name} ({host})",
            "step": {"user": {"title": "PLC", "description": "Mark {public_api}"}},
            "error": {"timeout": "No answer in {seconds} s"},
        },
        "exceptions": {
            "out_of_range": {"message": "{value} is above {max_value}"},
            "read_only": {"message": "Read-only"},
        },
    }
    assert placeholder_gaps(usage, strings) == [
        "config.flow_title uses ['host'], not passed at config_flow:22",
        "config.step.user.description uses ['public_api'], not passed at config_flow:19",
        "exceptions.out_of_range.message uses ['max_value'], not passed at sensor:41",
        "config.error.timeout uses ['seconds'], not passed at config_flow:53",
    ]


def test_checker_reports_uses_it_cannot_place() -> None:
    usage = read_usage(
        {
            "helpers": 'def f(hass):\n    hass.services.async_register("d", name_of(), h)\n'
            '    return self.async_abort(reason="x")\n'
            'DESC = Something(translation_key="k")\n'
        }
    )
    assert usage.problems == [
        "helpers:2: cannot read the action name registered by async_register()",
        "helpers:3: async_abort() outside a config or options flow",
        "helpers:4: cannot tell the entity platform of translation_key 'k'",
    ]


def test_checker_services_must_agree_everywhere() -> None:
    services_yaml: JsonObject = {
        "write_variable": {
            "fields": {"name": {}, "value": {}, "advanced": {"fields": {"timeout": {}}}}
        },
        "orphan": {},
    }
    strings = {
        "services": {
            "write_variable": {
                "name": "Write",
                "description": "",
                "fields": {
                    "name": {"name": "N", "description": "D"},
                    "value": {"name": "V"},
                    "extra": {},
                },
            },
            "gone": {"name": "g", "description": "d"},
        }
    }
    registered = {"write_variable": "services:1", "refresh": "services:2"}
    assert service_problems(services_yaml, strings, registered) == [
        "action 'refresh' is registered but not in services.yaml",
        "action 'orphan' is in services.yaml but never registered",
        "action 'orphan' has no translation",
        "translated action 'gone' is not in services.yaml",
        "action 'write_variable' has no translated description",
        "field write_variable.timeout has no translation",
        "translated field write_variable.extra is not in services.yaml",
        "field write_variable.value has no translated description",
    ]


def test_checker_icons_must_refer_to_existing_keys() -> None:
    icons = {
        "entity": {
            "sensor": {
                "uptime": {"default": "mdi:timer"},
                "ghost": {"default": "timer"},
            }
        },
        "services": {"refresh": "mdi:refresh"},
        "unknown": {},
    }
    strings = {"entity": {"sensor": {"uptime": {"name": "Uptime"}}}}
    assert icon_problems(icons, strings, {"write_variable": {}}) == [
        "icons.json section 'unknown' is not checked here",
        "icon for entity.sensor.ghost has no entity translation",
        "icon for action 'refresh' that services.yaml lacks",
        "action 'write_variable' has no icon",
        "entity.sensor.ghost.default: 'timer' is not an mdi: icon",
    ]


def _png(
    path: Path,
    size: tuple[int, int],
    *,
    mode: str = "RGBA",
    box: tuple[int, int, int, int] | None = None,
) -> None:
    image = Image.new(mode, size)
    fill = (30, 90, 160, 255) if mode == "RGBA" else (30, 90, 160)
    image.paste(fill, box or (0, 0, *size))
    image.save(path)


def test_checker_png_header_is_read_without_decoding(tmp_path: Path) -> None:
    _png(tmp_path / "a.png", (300, 120))
    assert png_header((tmp_path / "a.png").read_bytes()) == PngHeader(300, 120, 6)
    assert png_header(b"GIF89a" + bytes(40)) is None


def test_checker_brand_images_must_have_the_right_sizes_and_transparency(
    tmp_path: Path,
) -> None:
    _png(tmp_path / "icon.png", (256, 256), box=(0, 40, 256, 216))
    _png(tmp_path / "icon@2x.png", (512, 512), box=(0, 80, 512, 432))
    _png(tmp_path / "logo.png", (400, 128), box=(0, 0, 400, 100))
    _png(tmp_path / "logo@2x.png", (800, 256), box=(0, 0, 800, 200))
    assert brand_problems(tmp_path) == []

    _png(tmp_path / "icon.png", (200, 200), mode="RGB")
    _png(tmp_path / "icon@2x.png", (512, 512), box=(10, 10, 500, 500))
    _png(tmp_path / "logo@2x.png", (256, 300))
    (tmp_path / "logo.png").unlink()
    (tmp_path / "banner.png").write_bytes(b"not a png")
    assert brand_problems(tmp_path) == [
        "logo.png is missing",
        "banner.png is not a brand image name",
        "icon.png is 200x200, not 256x256",
        "icon.png has no alpha channel",
        "icon@2x.png is not trimmed: artwork spans (10, 10, 500, 500) of 512x512",
        "logo@2x.png is 256x300, not landscape",
        "logo@2x.png has no transparent background",
        "icon@2x.png is not twice the size of icon.png",
    ]


async def test_home_assistant_serves_the_brand_images(
    hass: HomeAssistant,
    enable_custom_integrations: None,
    hass_client: ClientSessionGenerator,
) -> None:
    """Home Assistant's own brands endpoint serves the files, not the CDN."""
    pytest.importorskip(
        "homeassistant.components.brands",
        reason="this Home Assistant does not serve brand images of custom integrations",
    )
    assert await async_setup_component(hass, "brands", {})
    client = await hass_client()
    shipped = sorted(path.name for path in BRAND.iterdir())
    # dark_icon.png is not shipped: Home Assistant falls back to icon.png.
    for name, source in [(name, name) for name in shipped] + [
        ("dark_icon.png", "icon.png")
    ]:
        response = await client.get(
            f"/api/brands/integration/tecoapi/{name}", params={"placeholder": "no"}
        )
        assert response.status == HTTPStatus.OK, name
        assert await response.read() == (BRAND / source).read_bytes(), name


def test_checker_reads_what_a_descriptor_s_forms_need() -> None:
    """A source's forms are built from its descriptor: the checker asks for their keys."""
    from tests.fake_source import MEMORY

    usage = TranslationUsage()
    descriptor_usage(usage, [MEMORY])
    needed = {_dotted(path) for path in usage.required}
    assert {
        "config.step.user.menu_options.memory",
        "config.step.memory.data.host",
        "config.step.memory.data.point_map",
        "config.step.reconfigure_memory.data.host",
        "config.error.cannot_connect",
        "config.error.point_map_invalid",
        "options.step.settings.data.scan_interval",
    } <= needed
    assert "options.step.settings.data.attribute_interval" not in needed
    assert usage.placeholders[("config", "step", "memory")][0] == {"error"}
