"""mirror_problems: a test file where no package is, named after no module, or apart."""

from pathlib import Path

from scripts.checks.layout import mirror_problems, package_names


def plant(root: Path, *files: str) -> None:
    for name in files:
        path = root / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text("", encoding="utf-8")


def test_checker_names_a_package_by_its_modules_subpackages_and_files(
    tmp_path: Path,
) -> None:
    plant(
        tmp_path,
        "pkg/__init__.py",
        "pkg/client.py",
        "pkg/quality_scale.yaml",
        "pkg/sub/__init__.py",
        "pkg/brand/icon.png",
    )
    (tmp_path / "pkg" / "__pycache__").mkdir()
    assert package_names(tmp_path / "pkg") == {"init", "client", "quality_scale", "sub"}


def test_checker_finds_each_planted_misplaced_test(tmp_path: Path) -> None:
    plant(
        tmp_path,
        "src/lib/__init__.py",
        "src/lib/client.py",
        "src/lib/core/__init__.py",
        "src/lib/core/codec.py",
        "src/lib/apart/__init__.py",
        "src/lib/apart/thing.py",
        "src/lib/notes/readme.md",
        # In their places: a module's, a topic of it, the package's, a subpackage's.
        "tests/lib/test_client.py",
        "tests/lib/test_client_bounds.py",
        "tests/lib/test_init.py",
        "tests/lib/test_core.py",
        "tests/lib/core/test_codec.py",
        "tests/lib/core/test_init_registry.py",
        # Helpers are no test files.
        "tests/lib/conftest.py",
        "tests/lib/core/programs.py",
        # Planted: no such module, a module of another package, a prefix of a
        # name only, no package to mirror, a package tested apart.
        "tests/lib/test_gateway.py",
        "tests/lib/core/test_client.py",
        "tests/lib/test_clients.py",
        "tests/lib/notes/test_readme.py",
        "tests/lib/elsewhere/test_client.py",
        "tests/lib/apart/test_thing.py",
    )
    assert mirror_problems(tmp_path, "src/lib", "tests/lib", apart={"apart"}) == [
        "tests/lib/apart/test_thing.py: src/lib/apart is tested apart, not under tests/lib",
        "tests/lib/core/test_client.py: src/lib/core has no module named like 'client'",
        "tests/lib/elsewhere/test_client.py: src/lib/elsewhere is no package to mirror",
        "tests/lib/notes/test_readme.py: src/lib/notes is no package to mirror",
        "tests/lib/test_clients.py: src/lib has no module named like 'clients'",
        "tests/lib/test_gateway.py: src/lib has no module named like 'gateway'",
    ]
    assert mirror_problems(tmp_path, "src/lib", "tests/lib") == [
        "tests/lib/core/test_client.py: src/lib/core has no module named like 'client'",
        "tests/lib/elsewhere/test_client.py: src/lib/elsewhere is no package to mirror",
        "tests/lib/notes/test_readme.py: src/lib/notes is no package to mirror",
        "tests/lib/test_clients.py: src/lib has no module named like 'clients'",
        "tests/lib/test_gateway.py: src/lib has no module named like 'gateway'",
    ]
