"""What one module of the integration defines, and how its names resolve.

`ModuleScope` knows a module's classes, functions and module-level values (and
those it imports from its siblings), the class and function being read, and the
flow or entity platform they belong to. `reader.ModuleReader` walks the module
with it and records what the code asks of the translations.
"""

import ast
from collections.abc import Iterator, Mapping
from typing import Final

import homeassistant.const as ha_const
from homeassistant.const import Platform

from .common import ANY_KEY, KeyPath, simple_assignment
from .usage import TranslationUsage

PLATFORM_BY_CAMEL: Final = {
    "".join(part.title() for part in platform.value.split("_")): platform.value
    for platform in Platform
}


def terminal_name(node: ast.expr) -> str:
    """The last name of a name, attribute, call or subscript: `b` of `a.b(c)[0]`."""
    if isinstance(node, ast.Name):
        return node.id
    if isinstance(node, ast.Attribute):
        return node.attr
    if isinstance(node, ast.Call):
        return terminal_name(node.func)
    if isinstance(node, ast.Subscript):
        return terminal_name(node.value)
    return ""


def platform_of_name(name: str) -> str | None:
    """The entity platform a class name ends in: `sensor` of `PlcSensorEntity`."""
    for suffix in ("EntityDescription", "Description", "Entity"):
        name = name.removesuffix(suffix)
    matches = [camel for camel in PLATFORM_BY_CAMEL if name.endswith(camel)]
    return PLATFORM_BY_CAMEL[max(matches, key=len)] if matches else None


class ModuleScope:
    """One module's definitions, and where in them the reading is."""

    def __init__(
        self,
        module: str,
        tree: ast.Module,
        constants: Mapping[str, str | None],
        usage: TranslationUsage,
        *,
        domain: str,
    ) -> None:
        self._module = module
        self.module = module
        self.tree = tree
        self._constants = constants
        self._usage = usage
        self._domain = domain
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
            name, value = simple_assignment(node)
            if name and value is not None:
                self._module_values[name] = value
        self.module_values: Mapping[str, ast.expr] = self._module_values
        self._class_stack: list[ast.ClassDef] = []
        self._function_stack: list[ast.FunctionDef | ast.AsyncFunctionDef] = []

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
            name = terminal_name(base)
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
                if name.endswith("Entity") and (platform := platform_of_name(name)):
                    return platform
        stem = self._module.rpartition(".")[2]
        return stem if stem in PLATFORM_BY_CAMEL.values() else None

    def _defines_step(self, step: str) -> bool:
        return self._method(f"async_step_{step}") is not None

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
