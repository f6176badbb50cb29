"""Run tests/pyplc against an installed ``pyplc``, without Home Assistant.

``scripts/test_library`` loads this plugin (``-p tests.pyplc.standalone``) in a
plain environment where ``pip install custom_components/tecoapi/pyplc`` put the
library as the top-level ``pyplc``, and Home Assistant is not installed.

The library's tests name it as the integration vendors it
(``custom_components.tecoapi.pyplc``), the name mypy knows it by. Here that name is
the installed package: every module of ``pyplc`` is imported and entered in
``sys.modules`` under the vendored name too (the same module objects, so a class is
one class by either name), and ``custom_components`` and
``custom_components.tecoapi`` are empty packages holding it: the integration's own
modules, which need Home Assistant, are never imported. ``tests/conftest.py``
imports ``custom_components.tecoapi`` (for Home Assistant's loader) and gets the
empty one. What pytest-homeassistant-custom-component gives every test and the
library's tests rely on is given here alike: ``caplog`` at DEBUG.

The run refuses to start where Home Assistant is importable, or where ``pyplc`` is
the repository's folder rather than an installed copy: it proves nothing then.
"""

import importlib
import importlib.metadata
import importlib.util
import logging
from pathlib import Path
import pkgutil
import sys
import types

import pytest

VENDORED = "custom_components.tecoapi.pyplc"
"""The name the integration, and the tests, import the library by."""

REPO = Path(__file__).resolve().parents[2]


def alias_installed() -> types.ModuleType:
    """Enter the installed ``pyplc`` under the vendored name; return it."""
    pyplc = importlib.import_module("pyplc")
    for found in pkgutil.walk_packages(pyplc.__path__, "pyplc."):
        importlib.import_module(found.name)
    for name, module in list(sys.modules.items()):
        if name == "pyplc" or name.startswith("pyplc."):
            sys.modules[VENDORED + name.removeprefix("pyplc")] = module
    parent: types.ModuleType | None = None
    for name in ("custom_components", "custom_components.tecoapi"):
        package = types.ModuleType(name, "an empty stand-in: Home Assistant is absent")
        package.__path__ = []
        sys.modules[name] = package
        if parent is not None:
            parent.tecoapi = package  # type: ignore[attr-defined]
        parent = package
    assert parent is not None
    parent.pyplc = pyplc  # type: ignore[attr-defined]
    return pyplc


def check_environment(pyplc: types.ModuleType) -> None:
    """Refuse a run that would not test the installed library alone."""
    if importlib.util.find_spec("homeassistant") is not None:
        raise pytest.UsageError("Home Assistant is installed: not a run without it")
    location = Path(pyplc.__file__ or "").resolve()
    if location.is_relative_to(REPO):
        raise pytest.UsageError(f"pyplc is imported from the repository: {location}")
    installed = importlib.metadata.version("pyplc")
    if installed != pyplc.__version__:
        raise pytest.UsageError(
            f"pyplc {installed} is installed, its __version__ says {pyplc.__version__}"
        )


@pytest.hookimpl(tryfirst=True)
def pytest_load_initial_conftests() -> None:
    """Before any conftest imports the library by its vendored name."""
    check_environment(alias_installed())


def pytest_report_header() -> str:
    """Which pyplc the run tests."""
    pyplc = sys.modules["pyplc"]
    return f"pyplc {pyplc.__version__} installed at {Path(pyplc.__file__ or '').parent}"


@pytest.fixture(name="caplog")
def caplog_fixture(caplog: pytest.LogCaptureFixture) -> pytest.LogCaptureFixture:
    """At DEBUG, as in the Home Assistant runs (their plugin sets it so)."""
    caplog.set_level(logging.DEBUG)
    return caplog
