"""Home Assistant's quality-scale validators: the same rules, read in the same places.

hassfest (home-assistant/core, ``script/hassfest/quality_scale_validation/``)
checks each rule an integration's ``quality_scale.yaml`` marks done that has a
validator, by reading the integration's files with ``ast`` (never importing
them) in fixed places: a step of the config flow only counts when it is
defined in ``config_flow.py``, whatever module it delegates to; the typed
config entry only when a parameter's annotation is a bare name ending in
``ConfigEntry``. hassfest does not run here (it needs core's tree), so this
module applies the same rules to a custom integration's folder; where core
reads a file a custom integration has no copy of (``.strict-typing``), the
rule reads the project's own equivalent (its mypy settings in pyproject.toml).

Each rule returns its problems in words; :func:`quality_scale_problems` runs
those of the rules marked done.
"""

import ast
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path
import re
import tomllib
from typing import Any, Final, Self

from homeassistant.const import Platform

from .common import load_json, load_yaml

TYPED_ENTRY: Final = re.compile(r"^[A-Za-z]+ConfigEntry$")
"""What core takes for a typed config entry: a bare name, ``PlcConfigEntry``."""

# The module functions core reads a config entry parameter of, and its position.
ENTRY_PARAMETERS: Final[dict[str, dict[str, int]]] = {
    "__init__": {
        "async_migrate_entry": 2,
        "async_remove_config_entry_device": 2,
        "async_remove_entry": 2,
        "async_setup_entry": 2,
        "async_unload_entry": 2,
    },
    "diagnostics": {
        "async_get_config_entry_diagnostics": 2,
        "async_get_device_diagnostics": 2,
    },
    **{platform.value: {"async_setup_entry": 2} for platform in Platform},
}
DISCOVERY_KEYS: Final = (
    "bluetooth",
    "dhcp",
    "homekit",
    "mqtt",
    "ssdp",
    "usb",
    "zeroconf",
)
DISCOVERY_STEPS: Final = frozenset(
    {
        "async_step_bluetooth",
        "async_step_discovery",
        "async_step_dhcp",
        "async_step_hassio",
        "async_step_homekit",
        "async_step_mqtt",
        "async_step_ssdp",
        "async_step_usb",
        "async_step_zeroconf",
    }
)
DIAGNOSTICS_FUNCTIONS: Final = frozenset(
    {"async_get_config_entry_diagnostics", "async_get_device_diagnostics"}
)
SETUP_ERRORS: Final = frozenset(
    {"ConfigEntryNotReady", "ConfigEntryAuthFailed", "ConfigEntryError"}
)


@dataclass(frozen=True, slots=True)
class Integration:
    """An integration's folder, as the validators see it."""

    path: Path
    manifest: Mapping[str, Any]
    rules_done: frozenset[str]
    pyproject: Mapping[str, Any] = field(default_factory=dict)
    """The project's pyproject.toml (strict typing), empty where there is none."""

    @classmethod
    def read(cls, path: Path, pyproject: Path | None = None) -> Self:
        """Read an integration's manifest and quality_scale.yaml (and the project's)."""
        scale = path / "quality_scale.yaml"
        return cls(
            path=path,
            manifest=load_json(path / "manifest.json"),
            rules_done=rules_done(load_yaml(scale)) if scale.is_file() else frozenset(),
            pyproject={}
            if pyproject is None or not pyproject.is_file()
            else tomllib.loads(pyproject.read_text(encoding="utf-8")),
        )

    def module(self, name: str) -> ast.Module | None:
        """A module of the integration's folder, parsed; None where it has none."""
        return _parsed(self.path / f"{name}.py")


@cache
def _parsed_text(text: str) -> ast.Module:
    return ast.parse(text)


def _parsed(path: Path) -> ast.Module | None:
    if not path.is_file():
        return None
    return _parsed_text(path.read_text(encoding="utf-8"))


def rules_done(scale: Mapping[str, Any]) -> frozenset[str]:
    """The rules a quality_scale.yaml marks done (``done``, or a status of done)."""
    return frozenset(
        rule
        for rule, value in (scale.get("rules") or {}).items()
        if (value if isinstance(value, str) else value.get("status")) == "done"
    )


def defines_async(module: ast.Module, name: str) -> bool:
    """Whether an ``async def`` of that name is anywhere in the module (a method too)."""
    return any(
        isinstance(node, ast.AsyncFunctionDef) and node.name == name
        for node in ast.walk(module)
    )


def calls_method(tree: ast.AST, name: str) -> bool:
    """Whether the code calls ``something.<name>(...)`` anywhere in it."""
    return any(
        isinstance(node, ast.Call)
        and isinstance(node.func, ast.Attribute)
        and node.func.attr == name
        for node in ast.walk(tree)
    )


def module_function(module: ast.Module, name: str) -> ast.AsyncFunctionDef | None:
    """The module's own top-level ``async def`` of that name."""
    return next(
        (
            node
            for node in module.body
            if isinstance(node, ast.AsyncFunctionDef) and node.name == name
        ),
        None,
    )


def _config_flow(integration: Integration) -> tuple[ast.Module | None, list[str]]:
    """config_flow.py parsed, or the problem that it is missing."""
    module = integration.module("config_flow")
    if module is None:
        return None, ["config_flow.py is missing"]
    return module, []


def _flow_step(step: str) -> Callable[[Integration], list[str]]:
    """A rule that a step of the config flow is defined in config_flow.py."""

    def check(integration: Integration) -> list[str]:
        module, problems = _config_flow(integration)
        if module is not None and not defines_async(module, step):
            problems.append(f"config_flow.py defines no `{step}`")
        return problems

    return check


def config_flow_rule(integration: Integration) -> list[str]:
    """config-flow: the manifest says so and config_flow.py exists.

    Core asks no more; a flow the user starts from the UI needs its first step,
    ``async_step_user``, so it is read where core reads the others.
    """
    problems = []
    if integration.manifest.get("config_flow") is not True:
        problems.append("manifest.json does not set config_flow")
    return problems + _flow_step("async_step_user")(integration)


def unique_config_entry_rule(integration: Integration) -> list[str]:
    """unique-config-entry: config_flow.py aborts a device configured twice.

    Either ``_async_abort_entries_match``, or both ``async_set_unique_id`` and
    ``_abort_if_unique_id_configured``, called in config_flow.py; an
    integration of a single config entry needs neither.
    """
    if integration.manifest.get("single_config_entry"):
        return []
    module, problems = _config_flow(integration)
    if module is None:
        return problems
    if calls_method(module, "_async_abort_entries_match") or (
        calls_method(module, "async_set_unique_id")
        and calls_method(module, "_abort_if_unique_id_configured")
    ):
        return []
    return [
        (
            "config_flow.py calls neither _async_abort_entries_match nor both "
            "async_set_unique_id and _abort_if_unique_id_configured"
        )
    ]


def _annotation_problem(
    function: ast.AsyncFunctionDef | ast.FunctionDef, position: int
) -> str | None:
    """Whether a parameter (1-based) is annotated with a typed config entry."""
    arguments = function.args.args
    if len(arguments) < position:
        return f"{function.name} has too few parameters"
    annotation = arguments[position - 1].annotation
    if isinstance(annotation, ast.Name) and TYPED_ENTRY.match(annotation.id):
        return None
    return f"{function.name} does not take a typed config entry (XxxConfigEntry)"


def _typed_entry_problems(integration: Integration) -> Iterator[str]:
    """Where core reads a config entry parameter, and it is not a typed one."""
    for name, functions in ENTRY_PARAMETERS.items():
        if (module := integration.module(name)) is None:
            continue
        for function_name, position in functions.items():
            function = module_function(module, function_name)
            if function is not None and (
                problem := _annotation_problem(function, position)
            ):
                yield f"{problem} in {name}.py"
    if (flow := integration.module("config_flow")) is None:
        return
    for node in flow.body:
        if not isinstance(node, ast.ClassDef):
            continue
        for item in node.body:
            if (
                isinstance(item, ast.FunctionDef)
                and item.name == "async_get_options_flow"
                and (problem := _annotation_problem(item, 1))
            ):
                yield f"{problem} in config_flow.py ({node.name})"


def runtime_data_rule(integration: Integration) -> list[str]:
    """runtime-data: async_setup_entry stores ``<entry>.runtime_data``.

    With strict-typing done, every function core knows takes the typed entry
    (``__init__``, diagnostics, each platform's ``async_setup_entry``, the
    options flow's factory in config_flow.py).
    """
    init = integration.module("__init__")
    setup = None if init is None else module_function(init, "async_setup_entry")
    if setup is None:
        return ["__init__.py defines no async_setup_entry"]
    if len(setup.args.args) != 2:
        return ["async_setup_entry in __init__.py does not take (hass, entry)"]
    entry = setup.args.args[1].arg
    problems = []
    if not any(
        isinstance(node, ast.Attribute)
        and isinstance(node.value, ast.Name)
        and node.value.id == entry
        and node.attr == "runtime_data"
        and isinstance(node.ctx, ast.Store)
        for node in ast.walk(setup)
    ):
        problems.append(f"async_setup_entry does not set {entry}.runtime_data")
    if "strict-typing" in integration.rules_done:
        problems += _typed_entry_problems(integration)
    return problems


def _name_of(node: ast.expr | None) -> str | None:
    """The name an expression ends in: ``X``, ``X(...)``, ``module.X``, ``X[T]``.

    What core reads of a raised exception and of a class's base alike.
    """
    if isinstance(node, ast.Call):
        return _name_of(node.func)
    if isinstance(node, ast.Subscript):
        return _name_of(node.value)
    if isinstance(node, ast.Attribute):
        return node.attr
    if isinstance(node, ast.Name):
        return node.id
    return None


def test_before_setup_rule(integration: Integration) -> list[str]:
    """test-before-setup: the first refresh in async_setup_entry, or a setup error raised.

    ``async_config_entry_first_refresh`` called in ``__init__.async_setup_entry``,
    or any module of the integration raising ConfigEntryNotReady,
    ConfigEntryAuthFailed or ConfigEntryError.
    """
    init = integration.module("__init__")
    setup = None if init is None else module_function(init, "async_setup_entry")
    if setup is None:
        return ["__init__.py defines no async_setup_entry"]
    if calls_method(setup, "async_config_entry_first_refresh"):
        return []
    for path in sorted(integration.path.rglob("*.py")):
        module = _parsed(path)
        if module is not None and any(
            isinstance(node, ast.Raise) and _name_of(node.exc) in SETUP_ERRORS
            for node in ast.walk(module)
        ):
            return []
    return [f"the integration raises none of {', '.join(sorted(SETUP_ERRORS))}"]


def discovery_rule(integration: Integration) -> list[str]:
    """discovery: a discovery key in the manifest, or a discovery step in config_flow.py."""
    module, problems = _config_flow(integration)
    if module is None or any(key in integration.manifest for key in DISCOVERY_KEYS):
        return problems
    if any(defines_async(module, step) for step in DISCOVERY_STEPS):
        return []
    return ["neither the manifest nor config_flow.py declares a way of discovery"]


def diagnostics_rule(integration: Integration) -> list[str]:
    """diagnostics: diagnostics.py defines a config entry's or a device's diagnostics."""
    module = integration.module("diagnostics")
    if module is None:
        return ["diagnostics.py is missing"]
    if any(defines_async(module, name) for name in DIAGNOSTICS_FUNCTIONS):
        return []
    return [
        f"diagnostics.py defines none of {', '.join(sorted(DIAGNOSTICS_FUNCTIONS))}"
    ]


def _registers_actions(function: ast.AsyncFunctionDef) -> bool:
    """Whether a function registers an action (an entity's, or hass.services')."""
    for node in ast.walk(function):
        if not (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute)):
            continue
        if node.func.attr == "async_register_entity_service":
            return True
        owner = node.func.value
        if (
            node.func.attr in {"async_register", "register"}
            and isinstance(owner, ast.Attribute)
            and owner.attr == "services"
            and isinstance(owner.value, ast.Name)
            and owner.value.id == "hass"
        ):
            return True
    return False


def action_setup_rule(integration: Integration) -> list[str]:
    """action-setup: no action registered in an async_setup_entry (only in async_setup)."""
    problems = []
    for name in ("__init__", *(platform.value for platform in Platform)):
        module = integration.module(name)
        setup = None if module is None else module_function(module, "async_setup_entry")
        if setup is not None and _registers_actions(setup):
            problems.append(f"{name}.py registers actions in async_setup_entry")
    return problems


def config_entry_unloading_rule(integration: Integration) -> list[str]:
    """config-entry-unloading: __init__.py defines async_unload_entry at its top level."""
    init = integration.module("__init__")
    if init is None or module_function(init, "async_unload_entry") is None:
        return ["__init__.py defines no async_unload_entry"]
    return []


def parallel_updates_rule(integration: Integration) -> list[str]:
    """parallel-updates: each platform module assigns PARALLEL_UPDATES at its top level.

    A plain assignment, as core reads it (``PARALLEL_UPDATES = 0``): an annotated
    one is not seen.
    """
    problems = []
    for platform in Platform:
        module = integration.module(platform.value)
        if module is not None and not any(
            isinstance(node, ast.Assign)
            and any(
                isinstance(target, ast.Name) and target.id == "PARALLEL_UPDATES"
                for target in node.targets
            )
            for node in module.body
        ):
            problems.append(f"{platform.value}.py does not set PARALLEL_UPDATES")
    return problems


def has_entity_name_rule(integration: Integration) -> list[str]:
    """has-entity-name: every entity class sets ``_attr_has_entity_name = True``.

    An entity class is one of the integration's top-level modules named ``…Entity``
    or with such a base; the assignment counts in it or in a base those modules
    define.
    """
    classes: dict[str, tuple[bool, list[str]]] = {}
    for path in sorted(integration.path.glob("*.py")):
        module = _parsed(path)
        for node in [] if module is None else ast.walk(module):
            if not isinstance(node, ast.ClassDef) or node.name in classes:
                continue
            sets = any(
                isinstance(item, ast.Assign)
                and any(
                    isinstance(target, ast.Name)
                    and target.id == "_attr_has_entity_name"
                    for target in item.targets
                )
                and isinstance(item.value, ast.Constant)
                and item.value.value is True
                for item in node.body
            )
            bases = [name for base in node.bases if (name := _name_of(base))]
            classes[node.name] = (sets, bases)

    def named(name: str, seen: frozenset[str] = frozenset()) -> bool:
        if name not in classes or name in seen:
            return False
        sets, bases = classes[name]
        return sets or any(named(base, seen | {name}) for base in bases)

    return [
        f"{name} does not set _attr_has_entity_name = True"
        for name, (_sets, bases) in classes.items()
        if (name.endswith("Entity") or any(b.endswith("Entity") for b in bases))
        and not named(name)
    ]


def strict_typing_rule(integration: Integration) -> list[str]:
    """strict-typing: mypy --strict over the integration's package.

    Core reads its ``.strict-typing`` list; a custom integration's equivalent is
    the project's ``[tool.mypy]``: ``strict = true``, the integration's package
    among its ``packages`` (or its folder among its ``files``), and no override
    that relaxes it.
    """
    mypy = integration.pyproject.get("tool", {}).get("mypy", {})
    package = ".".join(integration.path.parts[-2:])
    folder = "/".join(integration.path.parts[-2:])
    problems = []
    if mypy.get("strict") is not True:
        problems.append("pyproject.toml's [tool.mypy] is not strict = true")
    if package not in mypy.get("packages", []) and not any(
        str(item).rstrip("/") in {folder, integration.path.parts[-2]}
        for item in mypy.get("files", [])
    ):
        problems.append(f"mypy does not check {package}")
    for override in mypy.get("overrides", []):
        modules = override.get("module", [])
        modules = [modules] if isinstance(modules, str) else modules
        relaxes = (
            override.get("ignore_errors") is True or override.get("strict") is False
        )
        if relaxes and any(str(m).startswith(package) for m in modules):
            problems.append(f"a mypy override relaxes {', '.join(modules)}")
    return problems


VALIDATORS: Final[dict[str, Callable[[Integration], list[str]]]] = {
    "action-setup": action_setup_rule,
    "config-entry-unloading": config_entry_unloading_rule,
    "config-flow": config_flow_rule,
    "diagnostics": diagnostics_rule,
    "discovery": discovery_rule,
    "has-entity-name": has_entity_name_rule,
    "parallel-updates": parallel_updates_rule,
    "reauthentication-flow": _flow_step("async_step_reauth"),
    "reconfiguration-flow": _flow_step("async_step_reconfigure"),
    "runtime-data": runtime_data_rule,
    "strict-typing": strict_typing_rule,
    "test-before-setup": test_before_setup_rule,
    "unique-config-entry": unique_config_entry_rule,
}
"""The rules core has a validator module for, each read as core reads it."""


def quality_scale_problems(integration: Integration) -> list[str]:
    """What core's validators would report for the rules marked done."""
    return [
        f"{rule}: {problem}"
        for rule in sorted(integration.rules_done & VALIDATORS.keys())
        for problem in VALIDATORS[rule](integration)
    ]
