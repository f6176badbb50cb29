"""Tests mirror the code: each test file sits where its module does, and is named after it.

A test file (``test_*.py``) under a folder of tests mirroring a source folder sits
in the folder that mirrors a package of the source (one with an ``__init__.py``)
and is named ``test_<name>.py`` or ``test_<name>_<topic>.py``, where ``<name>`` is
a module of that package (``init`` for its ``__init__.py``), a subpackage, or
another file of it (``quality_scale.yaml``). Helpers (``conftest.py``, plugins,
shared programs) are not test files and may sit anywhere. A subpackage tested in a
mirror of its own (the library, beside the Home Assistant layer) is ``apart``: no
test file sits in its place.
"""

from collections.abc import Collection
from pathlib import Path


def package_names(package: Path) -> set[str]:
    """What a test in the mirror of `package` may be named after."""
    names = {"init"}
    for child in package.iterdir():
        if child.is_dir():
            if (child / "__init__.py").is_file():
                names.add(child.name)
        elif child.name != "__init__.py":
            names.add(child.name.split(".", 1)[0])
    return names


def mirror_problems(
    root: Path, source: str, tests: str, *, apart: Collection[str] = ()
) -> list[str]:
    """Test files under `tests` that sit where `source` has no module of their name.

    `source` and `tests` are folders of the repository at `root`; each problem
    names the test file by its path there.
    """
    problems: list[str] = []
    for test in sorted((root / tests).rglob("test_*.py")):
        where = test.relative_to(root).as_posix()
        folder = test.parent.relative_to(root / tests)
        inside = "/".join((source, *folder.parts))
        if folder.parts and folder.parts[0] in apart:
            problems.append(f"{where}: {inside} is tested apart, not under {tests}")
            continue
        package = root / inside
        if not (package / "__init__.py").is_file():
            problems.append(f"{where}: {inside} is no package to mirror")
            continue
        stem = test.stem.removeprefix("test_")
        if not any(
            stem == name or stem.startswith(f"{name}_")
            for name in package_names(package)
        ):
            problems.append(f"{where}: {inside} has no module named like {stem!r}")
    return problems
