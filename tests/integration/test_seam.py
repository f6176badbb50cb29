"""The seam: Home Assistant's side knows the library's core, and no system in it.

Every module of the integration outside the library imports from the library's
core (``pyplc`` re-exports it, ``pyplc.core.*``) and nothing else: not a
system's subpackage (``pyplc.tecomat``, and those to come). A source reaches
Home Assistant through its descriptor, found in the core's registry.
"""

import ast
from pathlib import Path
import re
from typing import Final

from custom_components.tecoapi import pyplc

LIBRARY = Path(pyplc.__file__).parent
INTEGRATION = LIBRARY.parent
HOME_ASSISTANT_MODULES: Final = sorted(
    path
    for path in INTEGRATION.rglob("*.py")
    if path.relative_to(INTEGRATION).parts[0] != "pyplc"
)


def library_imports(source: str) -> list[str]:
    """The library modules a module's source imports from (``pyplc``, ``pyplc.x``)."""
    modules: list[str] = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.ImportFrom):
            module = node.module or ""
            if module == "pyplc" or module.startswith("pyplc."):
                modules.append(module)
            elif node.level and not module:
                # from . import pyplc / from .pyplc import tecomat
                modules += [alias.name for alias in node.names if alias.name == "pyplc"]
        elif isinstance(node, ast.Import):
            modules += [
                alias.name.partition("custom_components.tecoapi.")[2]
                for alias in node.names
                if ".pyplc" in alias.name
            ]
    return modules


def only_the_core(module: str) -> bool:
    """Whether a library module is the core's (the package root re-exports it)."""
    return module in {"pyplc", "pyplc.core"} or module.startswith("pyplc.core.")


def test_the_check_sees_a_system_import() -> None:
    """The scan finds what a module would import from a system (it is not blind)."""
    imports = library_imports(
        "from .pyplc.tecomat import TecoApiSession\n"
        "from .pyplc.core.models import Point\n"
        "from .pyplc import Snapshot\n"
    )
    assert imports == ["pyplc.tecomat", "pyplc.core.models", "pyplc"]
    assert [only_the_core(module) for module in imports] == [False, True, True]


def test_home_assistant_modules_import_only_the_core() -> None:
    assert len(HOME_ASSISTANT_MODULES) > 20
    for path in HOME_ASSISTANT_MODULES:
        for module in library_imports(path.read_text(encoding="utf-8")):
            assert only_the_core(module), (path.name, module)


def test_the_package_root_re_exports_the_core_only() -> None:
    """``from .pyplc import X`` brings nothing of a system: the root imports the core."""
    root = (LIBRARY / "__init__.py").read_text(encoding="utf-8")
    for node in ast.walk(ast.parse(root)):
        if isinstance(node, ast.ImportFrom):
            assert (node.module or "").startswith("core"), node.module


def test_the_core_imports_no_system() -> None:
    """The core names the built-in systems' modules as text only (the registry)."""
    for path in sorted((LIBRARY / "core").glob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom) and node.level:
                assert node.level == 1, (path.name, node.module)


def test_no_protocol_error_code_outside_the_library() -> None:
    """No TecoApi code (``"400.005"``) or made-up one is decoded by Home Assistant's side."""
    code = re.compile(r"\"[0-9]{3}\.[0-9]{3}\"")
    for path in HOME_ASSISTANT_MODULES:
        assert code.search(path.read_text(encoding="utf-8")) is None, path.name


def test_no_home_assistant_module_names_a_source() -> None:
    """No module branches on a source's name: the names live in the descriptors."""
    names = re.compile(r"[\"'](tecoapi|plccoms)[\"']")
    for path in HOME_ASSISTANT_MODULES:
        if path.name == "const.py":
            continue  # DOMAIN is "tecoapi": the integration's name, not a source's
        assert names.search(path.read_text(encoding="utf-8")) is None, path.name
