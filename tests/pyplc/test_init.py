"""pyplc stands on its own: nothing of Home Assistant in it, a version, an example.

``PACKAGE_DIR`` is the package under test: the vendored folder in the Home Assistant
runs, the installed copy in ``scripts/test_library``'s (tests/pyplc/standalone.py).
``SOURCE_DIR`` is the folder in the repository, with its pyproject.toml and README.
"""

import ast
import asyncio
import os
from pathlib import Path
import re
import subprocess
import sys
import tomllib

import aiohttp

from custom_components.tecoapi import pyplc
from custom_components.tecoapi.pyplc import tecomat
from tests.conftest import SIM_PASSWORD, SIM_USERNAME
from tests.simulator import Simulator

PACKAGE_DIR = Path(pyplc.__file__).parent
SOURCE_DIR = Path(__file__).parents[2] / "custom_components" / "tecoapi" / "pyplc"
EXAMPLE_HEADING = "## Example: reading points"

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


def test_the_version_is_the_pyproject_s() -> None:
    project = tomllib.loads((SOURCE_DIR / "pyproject.toml").read_text(encoding="utf-8"))
    assert project["project"]["name"] == "pyplc"
    assert project["project"]["version"] == pyplc.__version__
    assert re.fullmatch(r"\d+\.\d+\.\d+", pyplc.__version__)


def test_the_package_is_the_folder_s_modules_and_py_typed() -> None:
    """Installed (scripts/test_library), the build shipped every module, typed."""

    def shipped(root: Path) -> set[str]:
        return {
            path.relative_to(root).as_posix()
            for path in root.rglob("*")
            if path.suffix == ".py" or path.name == "py.typed"
        }

    assert shipped(PACKAGE_DIR) == shipped(SOURCE_DIR)
    assert "py.typed" in shipped(PACKAGE_DIR)
    assert "tekon/catalogue.py" in shipped(PACKAGE_DIR)


def readme_example() -> str:
    """The README's example: the first Python block under its heading."""
    readme = (SOURCE_DIR / "README.md").read_text(encoding="utf-8")
    section = readme.split(f"\n{EXAMPLE_HEADING}\n", 1)[1]
    found = re.search(r"^```python\n(.*?)^```$", section, re.MULTILINE | re.DOTALL)
    assert found is not None, "no python block under the example's heading"
    return found.group(1)


def test_the_readme_example_is_short_and_imports_only_pyplc_and_aiohttp() -> None:
    example = readme_example()
    assert len(example.splitlines()) <= 20
    imported = {
        name.split(".")[0]
        for node in ast.walk(ast.parse(example))
        for name in (
            [alias.name for alias in node.names]
            if isinstance(node, ast.Import)
            else [node.module or ""]
            if isinstance(node, ast.ImportFrom)
            else []
        )
    }
    assert imported == {"asyncio", "sys", "aiohttp", "pyplc"}


async def test_the_readme_example_reads_the_simulated_plc(
    simulator: Simulator, tmp_path: Path
) -> None:
    """The block runs as a user runs it: a script of its own, ``pyplc`` top-level."""
    async with aiohttp.ClientSession() as http:
        client = tecomat.TecoApiClient(http, simulator.url, SIM_USERNAME, SIM_PASSWORD)
        discovered = await tecomat.TecoApiSession(client).poll(())
    script = tmp_path / "example.py"
    script.write_text(readme_example(), encoding="utf-8")
    # Only the package on the path: the integration's folder has modules named like
    # the standard library's (time.py, datetime.py).
    (tmp_path / "path").mkdir()
    (tmp_path / "path" / "pyplc").symlink_to(PACKAGE_DIR, target_is_directory=True)
    env = {**os.environ, "PYTHONPATH": str(tmp_path / "path")}
    process = await asyncio.create_subprocess_exec(
        sys.executable,
        str(script),
        simulator.url,
        SIM_USERNAME,
        SIM_PASSWORD,
        env=env,
        cwd=tmp_path,
        stdout=asyncio.subprocess.PIPE,
        stderr=asyncio.subprocess.PIPE,
    )
    async with asyncio.timeout(60):
        out, err = await process.communicate()
    assert process.returncode == 0, err.decode()
    lines = out.decode().splitlines()
    assert lines[0] == "CP-2080 SD 2080 FAMILY_HOUSE v1.3 RUN"
    points = lines[1:-1]
    assert len(points) > 50
    assert points == [
        f"{key} = {discovered.values.get(key)}"
        for key in sorted(discovered.catalogue.points)
    ]
    assert "outsidetemp = 4.5" in points
    assert "heating.livingsetpoint = 21.5" in points
    assert ast.literal_eval(lines[-1]) == {
        "outsidetemp": 4.5,
        "heating.livingsetpoint": 21.5,
    }
    # The last poll: one GetObject of the two points, and GetInfo as its values are
    # the previous poll's (a stopped PLC's tell, README "HALT/ERR within one poll").
    assert [(r.service, r.items) for r in simulator.requests[-2:]] == [
        ("GetObject", 2),
        ("GetInfo", 0),
    ]
