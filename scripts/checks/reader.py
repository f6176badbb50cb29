"""What the integration's Python code asks of its translations and services.yaml.

The code is read with `ast`, never imported: config and options flows (steps,
their fields and placeholders, errors, abort reasons), entities' translation
keys by platform, exceptions, repair issues, selectors and registered actions.
"""

import ast
from collections.abc import Callable, Mapping
from typing import ClassVar, Final

from .common import KeyPath, KeyTemplate, simple_assignment
from .scope import ModuleScope, platform_of_name, terminal_name
from .usage import Forwarding, Parameter, TranslationUsage

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


def _module_constants(trees: Mapping[str, ast.Module]) -> dict[str, str | None]:
    """Module-level string constants of all modules; None where modules disagree."""
    constants: dict[str, str | None] = {}
    for tree in trees.values():
        for node in tree.body:
            name, value = simple_assignment(node)
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


type FlowCall = Callable[[ModuleReader, ast.Call, Mapping[str, ast.expr]], list[str]]
"""What a flow call can end in, read from the call: its abort reasons."""


def _fixed(*reasons: str) -> FlowCall:
    return lambda _reader, _node, _keywords: list(reasons)


def _set_unique_id(
    _reader: "ModuleReader", _node: ast.Call, keywords: Mapping[str, ast.expr]
) -> list[str]:
    raises = keywords.get("raise_on_progress")
    if isinstance(raises, ast.Constant) and raises.value is False:
        return []
    return ["already_in_progress"]


class ModuleReader(ModuleScope, ast.NodeVisitor):
    """Collects translation and action uses from one module."""

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
        if terminal_name(target) == "_attr_translation_key":
            self._entity_key(value, node)
        elif (
            isinstance(target, ast.Subscript)
            and terminal_name(target.value) == "errors"
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
            and terminal_name(target.value) == "context"
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
                forwarding = self._usage.forwarded.get(terminal_name(node.func))
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
        name = terminal_name(node.func)
        keywords = {kw.arg: kw.value for kw in node.keywords if kw.arg}
        if name in self._FLOW_CALLS:
            self._flow_call(name, node, keywords)
        elif name in _SERVICE_REGISTRARS:
            self._service_registration(name, node, keywords)
        elif "translation_key" in keywords:
            self._keyed_call(name, node, keywords)
        self.generic_visit(node)

    def _names_this_domain(self, domain: ast.expr) -> bool:
        """Whether a `translation_domain=` names this integration (DOMAIN, or its name)."""
        if isinstance(domain, ast.Name):
            return domain.id == "DOMAIN"
        return isinstance(domain, ast.Constant) and domain.value == self._domain

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
        elif "translation_domain" in keywords and not self._names_this_domain(
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
            platform = platform_of_name(name)
            if platform is None and name in self._classes:
                platform = next(
                    filter(
                        None, map(platform_of_name, self._bases(self._classes[name]))
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
        if node.args and terminal_name(node.args[0]) == "hass":
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
        for reason in self._FLOW_CALLS[name](self, node, keywords):
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

    def _unique_id_configured(
        self, _node: ast.Call, keywords: Mapping[str, ast.expr]
    ) -> list[str]:
        reason = (
            self._string(keywords["error"])
            if "error" in keywords
            else "already_configured"
        )
        return [reason] if reason else []

    def _unique_id_mismatch(
        self, _node: ast.Call, keywords: Mapping[str, ast.expr]
    ) -> list[str]:
        reason = (
            self._string(keywords["reason"])
            if "reason" in keywords
            else "unique_id_mismatch"
        )
        return [reason] if reason else []

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
                            or terminal_name(value.func) != "section"
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
                    and terminal_name(child.func) in _SCHEMA_MARKERS
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

    # Flow calls -> the abort reasons they can end in (and, for forms, other keys).
    _FLOW_CALLS: ClassVar[Mapping[str, FlowCall]] = {
        "async_show_form": _show_form,
        "async_show_menu": _show_menu,
        "async_abort": _abort,
        "AbortFlow": _abort,
        "async_update_reload_and_abort": _update_and_abort,
        "async_update_and_abort": _update_and_abort,
        "_abort_if_unique_id_configured": _unique_id_configured,
        "_abort_if_unique_id_mismatch": _unique_id_mismatch,
        "_async_abort_entries_match": _fixed("already_configured"),
        "async_set_unique_id": _set_unique_id,
        "_async_handle_discovery_without_unique_id": _fixed(
            "already_in_progress", "already_configured"
        ),
    }


def read_usage(sources: Mapping[str, str], *, domain: str) -> TranslationUsage:
    """What the modules (dotted name -> source) need from translations and services.yaml.

    `domain` is the integration's: an error raised with `translation_domain=`
    another one's (Home Assistant's own, say) needs none of its strings.
    """
    trees = {
        module: ast.parse(source, filename=module) for module, source in sources.items()
    }
    constants = _module_constants(trees)
    usage = TranslationUsage()
    readers = [
        ModuleReader(module, tree, constants, usage, domain=domain)
        for module, tree in trees.items()
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
