"""pyplc stands on its own: nothing of Home Assistant in it."""

import ast
from pathlib import Path
import subprocess
import sys

from custom_components.tecoapi import pyplc
from custom_components.tecoapi.pyplc import tecomat

PACKAGE_DIR = Path(pyplc.__file__).parent

_LOAD_ALONE = f"""
import importlib.util, sys
spec = importlib.util.spec_from_file_location(
    "pyplc", {str(PACKAGE_DIR / "__init__.py")!r},
    submodule_search_locations=[{str(PACKAGE_DIR)!r}],
)
module = importlib.util.module_from_spec(spec)
sys.modules["pyplc"] = module
spec.loader.exec_module(module)
import pyplc.tecomat
module.normalize_host, pyplc.tecomat.TecoApiClient, pyplc.tecomat.plan_reads
loaded = sorted(name for name in sys.modules if name.split(".")[0] == "homeassistant")
print(",".join(loaded) or "none")
"""


def test_package_imports_without_home_assistant() -> None:
    """Loaded as a top-level package of its own, it pulls in no homeassistant module."""
    result = subprocess.run(  # noqa: S603 - our own interpreter and code
        [sys.executable, "-c", _LOAD_ALONE],
        capture_output=True,
        text=True,
        check=True,
        timeout=60,
    )
    assert result.stdout.strip() == "none"


def test_no_source_file_imports_home_assistant() -> None:
    sources = sorted(PACKAGE_DIR.rglob("*.py"))
    assert len(sources) > 5
    for source in sources:
        tree = ast.parse(source.read_text(encoding="utf-8"))
        for node in ast.walk(tree):
            if isinstance(node, ast.Import):
                modules = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom):
                modules = [node.module or ""]
            else:
                continue
            for module in modules:
                assert not module.startswith("homeassistant"), source.name


def test_public_api_is_re_exported() -> None:
    for package in (pyplc, tecomat):
        for name in package.__all__:
            assert getattr(package, name) is not None
    assert {
        "TecoApiClient",
        "ValueKind",
        "PlcMode",
        "SourceInfo",
        "PointAttributes",
        "Point",
        "Catalogue",
        "PlannedRequest",
        "ReadPlan",
        "PlcSource",
        "Snapshot",
        "TecoApiSession",
        "normalize_host",
        "plan_reads",
        "ValueRejectedError",
    } <= {*pyplc.__all__, *tecomat.__all__}
