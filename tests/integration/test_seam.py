"""The seam: Home Assistant's side depends on the neutral part of the library only."""

import ast
from pathlib import Path
import re
from typing import Final

from custom_components.tecoapi import pyplc
from custom_components.tecoapi.pyplc.core import exceptions, models, source

INTEGRATION = Path(pyplc.__file__).parent.parent

# Modules that must not know which protocol reaches the PLC.
TRANSPORT_NEUTRAL: Final = (
    "__init__.py",
    "binary_sensor.py",
    "coordinator.py",
    "data.py",
    "diagnostics.py",
    "entity.py",
    "helpers.py",
    "mapping.py",
    "number.py",
    "reconcile.py",
    "sensor.py",
    "services.py",
    "switch.py",
    "text.py",
)
NEUTRAL_MODULES: Final = {
    "core.devices",
    "core.exceptions",
    "core.models",
    "core.source",
    "core.values",
}
NEUTRAL_NAMES: Final = {
    name
    for module in (exceptions, models, source)
    for name, value in vars(module).items()
    if not name.startswith("_") and getattr(value, "__module__", "") == module.__name__
}
# What the neutral models define for TecoApi alone: the item limit of a CPU type.
TECOAPI_MODELS: Final[set[str]] = set()


def library_imports(path: Path) -> list[tuple[str, str]]:
    """(module, name) of every import a file makes from the library."""
    imports: list[tuple[str, str]] = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("pyplc"):
            imports += [(node.module or "", alias.name) for alias in node.names]
    return imports


def test_the_check_sees_imports() -> None:
    """The scan finds what a TecoApi-specific module imports (it is not blind)."""
    assert ("pyplc.tecomat", "TecoApiSession") in library_imports(
        INTEGRATION / "connection.py"
    )
    assert "TecoApiClient" not in NEUTRAL_NAMES
    assert {"PlcSource", "Snapshot", "VariableNotFoundError", "Point"} <= NEUTRAL_NAMES


def test_coordinator_and_platforms_import_only_the_neutral_library() -> None:
    for name in TRANSPORT_NEUTRAL:
        for module, imported in library_imports(INTEGRATION / name):
            if module == "pyplc":
                assert imported in (NEUTRAL_NAMES - TECOAPI_MODELS) | NEUTRAL_MODULES, (
                    name,
                    imported,
                )
            elif module == "pyplc.core":
                assert f"core.{imported}" in NEUTRAL_MODULES, (name, imported)
            else:
                assert module.removeprefix("pyplc.") in NEUTRAL_MODULES, (
                    name,
                    module,
                )


def test_no_protocol_error_code_outside_the_library() -> None:
    """No TecoApi code (``"400.005"``) or made-up one is decoded by Home Assistant's side."""
    code = re.compile(r"\"[0-9]{3}\.[0-9]{3}\"")
    for path in sorted(INTEGRATION.glob("*.py")):
        assert code.search(path.read_text(encoding="utf-8")) is None, path.name
