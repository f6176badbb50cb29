"""Tests mirror the code: the library's, the Home Assistant layer's and the checkers'.

``tests/pyplc`` mirrors the library (``custom_components/tecoapi/pyplc``),
``tests/components/tecoapi`` the Home Assistant layer around it (Home Assistant's
own layout; the library is tested apart), ``tests/checks`` the checkers of
``scripts/checks``: a test file sits in the folder of its module's package and is
named after the module (``scripts/checks/layout.py`` says how exactly).
"""

from pathlib import Path
from typing import Final

import pytest

from scripts.checks.layout import mirror_problems

REPO: Final = Path(__file__).resolve().parent.parent
MIRRORS: Final = [
    ("custom_components/tecoapi/pyplc", "tests/pyplc", ()),
    ("custom_components/tecoapi", "tests/components/tecoapi", ("pyplc",)),
    ("scripts/checks", "tests/checks", ()),
]


@pytest.mark.parametrize(("source", "tests", "apart"), MIRRORS)
def test_every_test_file_sits_where_its_module_does(
    source: str, tests: str, apart: tuple[str, ...]
) -> None:
    assert len(list((REPO / tests).rglob("test_*.py"))) >= 10
    assert mirror_problems(REPO, source, tests, apart=apart) == []


def test_no_test_file_sits_outside_the_mirrors_but_the_repository_s_own() -> None:
    """Tests of no one module (simulators, contract, e2e…) have folders of their own."""
    mirrored = [REPO / tests for _, tests, _ in MIRRORS]
    assert sorted(
        {
            path.parent.relative_to(REPO).as_posix()
            for path in (REPO / "tests").rglob("test_*.py")
            if not any(path.is_relative_to(folder) for folder in mirrored)
        }
    ) == [
        "tests",
        "tests/contract",
        "tests/e2e",
        "tests/mutation",
        "tests/simulator_tests",
    ]
