"""The seam: Home Assistant's side knows the library's core, and no system in it.

Every module of the integration outside the library imports from the library's
core (``pyplc`` re-exports it, ``pyplc.core.*``) and nothing else: not a
system's subpackage (``pyplc.tecomat``, and those to come). A source reaches
Home Assistant through its descriptor, found in the core's registry.
"""

import ast
from dataclasses import replace
from pathlib import Path
import re
from typing import Final

from custom_components.tecoapi import pyplc
from custom_components.tecoapi.pyplc.core import registry
from custom_components.tecoapi.pyplc.core.descriptor import SourceDescriptor
from tests.fake_source import MEMORY

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


SYSTEM_PACKAGES: Final = sorted(
    path.name
    for path in LIBRARY.iterdir()
    if (path / "__init__.py").is_file() and path.name != "core"
)


def packages_imported(source: str, package: tuple[str, ...]) -> list[str]:
    """The library's top-level packages a module imports from (``core``, ``tecomat``).

    ``package`` is the module's package below the library (``("tecomat",
    "plccoms")``); a relative import is resolved against it. An import that
    climbs out of the library is ``..``, the library's root itself ``""``.
    """
    found: list[str] = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.ImportFrom) and node.level:
            if node.level - 1 > len(package):
                found.append("..")
                continue
            target = [
                *package[: len(package) - node.level + 1],
                *(node.module or "").split("."),
            ]
            target = [part for part in target if part]
            found += target[:1] if target else [alias.name for alias in node.names]
        else:
            names = (
                [node.module or ""]
                if isinstance(node, ast.ImportFrom)
                else [alias.name for alias in node.names]
                if isinstance(node, ast.Import)
                else []
            )
            for name in names:
                parts = name.split(".")
                if "pyplc" in parts:
                    found += parts[parts.index("pyplc") + 1 :][:1] or [""]
    return found


def test_the_package_scan_sees_another_system() -> None:
    """Relative imports resolve from the module's package; absolute ones count too."""
    imports = packages_imported(
        "from ..tecomat.conventions import RECOGNISERS\n"
        "from ..core.models import Point\n"
        "from .client import MervisClient\n"
        "from .. import tekon\n"
        "from ... import const\n"
        "import pyplc.panasonic.address\n",
        ("mervis",),
    )
    assert imports == ["tecomat", "core", "mervis", "tekon", "..", "panasonic"]
    plccoms = ("tecomat", "plccoms")
    assert packages_imported("from ..points import tecomat_point\n", plccoms) == [
        "tecomat"
    ]


def test_no_system_package_imports_another() -> None:
    """A system's modules import the core and their own package, nothing else of the library.

    What several systems share (the struct convention, the backoff, the cache
    beside an entry) lives in the core; a system's own conventions (Teco's
    GTSAP1) stay in its package.
    """
    assert SYSTEM_PACKAGES == ["mervis", "panasonic", "tecomat", "tekon"]
    found = [
        (path.relative_to(LIBRARY).as_posix(), imported)
        for system in SYSTEM_PACKAGES
        for path in sorted((LIBRARY / system).rglob("*.py"))
        for imported in packages_imported(
            path.read_text(encoding="utf-8"), path.relative_to(LIBRARY).parent.parts
        )
        if imported not in {"core", system}
    ]
    assert found == []


def test_no_protocol_error_code_outside_the_library() -> None:
    """No TecoApi code (``"400.005"``) or made-up one is decoded by Home Assistant's side."""
    code = re.compile(r"\"[0-9]{3}\.[0-9]{3}\"")
    for path in HOME_ASSISTANT_MODULES:
        assert code.search(path.read_text(encoding="utf-8")) is None, path.name


# --- the vocabulary: no system's or convention's word in the kernel -------------
#
# Built from what every registered descriptor names: its source's name, the words of
# its title, its manufacturer, its push companion's title, the names of the recognisers
# and the formats of the point-map loaders it brings (the core's own struct convention
# and CSV are neutral).
# A fifth system's words are denied the day its descriptor is registered.

CORE_MODULES: Final = sorted((LIBRARY / "core").rglob("*.py"))

ALLOWED: Final = {
    ("const.py", 'DOMAIN: Final = "tecoapi"'): (
        "the integration's domain: its config entries, unique IDs and HACS name"
        " (it is also the first source's name, for history's sake)"
    ),
    (
        "registry.py",
        '"..tecomat.descriptor",',
    ): "the registry line of a built-in system",
    ("registry.py", '"..mervis.descriptor",'): "the registry line of a built-in system",
    (
        "registry.py",
        '"..panasonic.descriptor",',
    ): "the registry line of a built-in system",
    ("registry.py", '"..tekon.descriptor",'): "the registry line of a built-in system",
    (
        "diagnostics.py",
        '{"roots", "skipped_roots", "points", "read_plans", "requests"}',
    ): "the diagnostics keys downloads have had since the first (Catalogue.groups)",
    (
        "diagnostics.py",
        'CATALOGUED: Final = ("roots", "skipped_roots")',
    ): "the diagnostics keys downloads have had since the first (Catalogue.groups)",
    ("models.py", 'STOPPED = "HALT"'): (
        "the value a stopped device's mode has always shown and stored (its state)"
    ),
}
"""The lines that may say a system's word, each with its reason."""

RETIRED: Final = frozenset({"roots", "halt"})
"""Words the kernel once spoke for one system, now said in neutral words.

Tecomat's top-level ``roots`` are the catalogue's ``groups``, its ``HALT`` mode
is ``PlcMode.STOPPED``: neither comes back into the kernel or Home Assistant's
code (``RUN`` and ``ERR`` are too common to deny: ``run()``, ``err``).
"""


def _words(text: str) -> list[str]:
    """A text's words, folded: ``FP-I4C`` is ``fpi4c``, ``ASUD.SCADA`` ``asudscada``."""
    return [
        word.lower().replace("-", "").replace(".", "")
        for word in re.findall(r"[A-Za-z0-9][A-Za-z0-9.\-]*", text)
    ]


def _parts(identifier: str) -> list[str]:
    """An identifier's words and their runs.

    ``TecoApiSession`` has ``teco``, ``api``, ``session``, ``tecoapi``, ...;
    ``fp_i4c`` has ``fpi4c``; ``PLCComS`` has ``plccoms``.
    """
    pieces = [
        part.lower()
        for piece in identifier.split("_")
        for part in re.findall(r"[A-Z]+(?![a-z])|[A-Z]?[a-z0-9]+", piece)
    ]
    return [
        "".join(pieces[start:end])
        for start in range(len(pieces))
        for end in range(start + 1, len(pieces) + 1)
    ]


def vocabulary(descriptors: tuple[SourceDescriptor, ...]) -> frozenset[str]:
    """The words of the systems these descriptors describe (folded, lower case)."""
    words: set[str] = set()
    for descriptor in descriptors:
        words.add(descriptor.name)
        words.update(_words(descriptor.title))
        words.update(_words(descriptor.manufacturer)[:1])
        if descriptor.companion is not None:
            words.update(_words(descriptor.companion.title))
        words.update(
            recogniser.name
            for recogniser in descriptor.recognisers
            if not _of_the_core(recogniser.find)
        )
        words.update(
            key
            for key, loader in descriptor.point_map_loaders.items()
            if not _of_the_core(loader)
        )
    return frozenset(words)


def _of_the_core(plug_in: object) -> bool:
    """Whether a descriptor's plug-in (a loader, a recogniser's ``find``) is the core's."""
    module = getattr(plug_in, "__module__", "")
    return module.startswith(f"{LIBRARY.name}.core") or ".pyplc.core." in module


def _documentation(tree: ast.Module) -> set[int]:
    """The string constants that document (docstrings, attribute docstrings)."""
    found: set[int] = set()
    for node in ast.walk(tree):
        body = getattr(node, "body", None)
        if not isinstance(body, list):
            continue
        for before, item in zip([None, *body], body, strict=False):
            documents = before is None or isinstance(
                before, ast.Assign | ast.AnnAssign | ast.TypeAlias
            )
            if (
                documents
                and isinstance(item, ast.Expr)
                and isinstance(item.value, ast.Constant)
                and isinstance(item.value.value, str)
            ):
                found.add(id(item.value))
    return found


def spoken(source: str, words: frozenset[str]) -> list[tuple[int, str]]:
    """Where a module's code says one of the words: (line, word).

    Identifiers (names, attributes, definitions, arguments, imports) and string
    constants count; docstrings and comments may give examples.
    """
    tree = ast.parse(source)
    documentation = _documentation(tree)
    found: list[tuple[int, str]] = []
    for node in ast.walk(tree):
        names: list[str] = []
        match node:
            case ast.Name(id=name) | ast.Attribute(attr=name):
                names = [name]
            case ast.FunctionDef(name=name) | ast.AsyncFunctionDef(name=name):
                names = [name]
            case ast.ClassDef(name=name) | ast.arg(arg=name):
                names = [name]
            case ast.alias(name=name, asname=asname):
                names = [name, asname or ""]
            case ast.keyword(arg=str() as name):
                names = [name]
            case ast.ImportFrom(module=module):
                names = [module or ""]
            case ast.Constant(value=str() as text) if id(node) not in documentation:
                names = [text]
                found += [(node.lineno, word) for word in _words(text) if word in words]
        found += [
            (getattr(node, "lineno", 0), part)
            for name in names
            for word in re.findall(r"\w+", name)
            for part in _parts(word)
            if part in words
        ]
    return sorted(set(found))


def test_the_vocabulary_is_every_descriptors() -> None:
    """Each built-in system's names and conventions are in it; a new one's join."""
    words = vocabulary(registry.sources())
    assert {descriptor.name for descriptor in registry.sources()} <= words
    # Titles, manufacturers, the companion, recognisers, a system's own map format:
    assert {"tecomat", "teco", "plccoms", "gtsap1", "vlist"} <= words
    assert {"unipi", "panasonic", "asudscada"} <= words
    # The core's own CSV map and struct convention are no system's words:
    assert {"csv", "struct"}.isdisjoint(words)
    other = replace(
        MEMORY, name="acme", title="Acme (AcmeNet)", manufacturer="Acme Ltd"
    )
    assert {"acme", "acmenet"} <= vocabulary((other,))


def test_the_deny_list_finds_a_planted_word() -> None:
    """It finds a word in an identifier, a string and an import, not in a docstring."""
    words = vocabulary(registry.sources())
    planted = (
        '"""A module; the TecoApi and the .vlist may be named in a docstring."""\n'
        "from .pyplc.mervis import thing\n"
        "class TecoApiCoordinator:\n"
        '    """Like GTSAP1\'s light (an example)."""\n'
        '    kind = "gtsap1:socket:"\n'
        "    def read_vlist(self, fp_i4c): ...\n"
        'LABEL = "FP-I4C gateway"\n'
        '"""An attribute docstring that says PLCComS."""\n'
    )
    assert spoken(planted, words) == [
        (2, "mervis"),
        (3, "teco"),
        (3, "tecoapi"),
        (5, "gtsap1"),
        (6, "fpi4c"),
        (6, "vlist"),
        (7, "fpi4c"),
    ]
    # And in a real module: one word more is one finding more.
    coordinator = (INTEGRATION / "coordinator.py").read_text(encoding="utf-8")
    assert spoken(coordinator, words) == []
    assert spoken(coordinator + '\nSERVER = "plccoms"\n', words) != []


def test_a_retired_word_is_found() -> None:
    """The retired words are denied as a system's are: in identifiers and strings."""
    planted = 'skipped = catalogue.skipped_roots\nMODE = "HALT"\n'
    assert spoken(planted, RETIRED) == [(1, "roots"), (2, "halt")]
    assert spoken("skipped = catalogue.skipped_groups\n", RETIRED) == []


def test_no_home_assistant_or_core_module_speaks_a_system() -> None:
    """No system's or convention's word in the kernel's or Home Assistant's code.

    The names live in the systems' subpackages and their descriptors; what is
    allowed (the domain, the registry's lines, the retired words' stored
    values) is listed with its reason.
    """
    words = vocabulary(registry.sources()) | RETIRED
    found: list[tuple[str, int, str]] = []
    for path in (*HOME_ASSISTANT_MODULES, *CORE_MODULES):
        text = path.read_text(encoding="utf-8")
        lines = text.splitlines()
        for line, word in spoken(text, words):
            if (path.name, lines[line - 1].strip()) not in ALLOWED:
                found.append((str(path.relative_to(INTEGRATION)), line, word))
    assert len(HOME_ASSISTANT_MODULES) > 30
    assert len(CORE_MODULES) > 10
    assert found == []


def test_every_allowed_line_is_there() -> None:
    """An allowed line that went is taken off the list (no stale exemptions)."""
    for name, line in ALLOWED:
        paths = [*INTEGRATION.glob(name), *(LIBRARY / "core").glob(name)]
        assert any(line in path.read_text(encoding="utf-8") for path in paths), name


# --- the tests use public behaviour: no private name reached from a test ---------------
#
# A test of our code asserts what a caller sees (requests a simulator received, a
# snapshot, the diagnostics, the statistics, states), not a private attribute: one that
# is renamed or reshaped must not break a test while the behaviour stays. What cannot
# be avoided is listed with its reason.

ROOT: Final = INTEGRATION.parent.parent
TESTS_OF_OUR_CODE: Final = ("tests/pyplc", "tests/components", "tests/contract")
NAMED_ACCESS: Final = frozenset({"getattr", "setattr", "hasattr", "delattr", "object"})

PRIVATE_ALLOWED: Final = {
    ("tests/pyplc/conftest.py", "_arrived"): "the test helper Heard's own attribute",
    ("tests/pyplc/conftest.py", "_take"): "the test helper Heard's own method",
    ("tests/pyplc/conftest.py", "_sent"): "the test helper HeaderLog's own method",
    (
        "tests/components/tecoapi/test_forms_system_words.py",
        "_add",
    ): "the test's own collector class",
    ("tests/components/tecoapi/test_coordinator_faults.py", "_debounced_refresh"): (
        "Home Assistant's coordinator: no public way to find its debouncer's timer"
    ),
    ("tests/components/tecoapi/test_coordinator_faults.py", "_callback"): (
        "asyncio's TimerHandle: no public accessor of a timer's callback"
    ),
    ("tests/components/tecoapi/test_motion.py", "_async_update_data"): (
        "the DataUpdateCoordinator hook Home Assistant calls on each refresh: the"
        " only place a scheduled refresh is seen to start before it takes the lock"
    ),
    (
        "tests/components/tecoapi/test_climate.py",
        "_attr_native_temperature_unit",
    ): (
        "Home Assistant's _attr_ shorthand: 2026.11's native_temperature_unit reads"
        " it, and no release tested has that property"
    ),
}


def private(name: str) -> bool:
    """Whether a name is private: a leading underscore, not a dunder."""
    return name.startswith("_") and not (name.startswith("__") and name.endswith("__"))


def private_names(source: str) -> list[tuple[int, str]]:
    """The private names a module's code reaches, with their lines.

    An attribute (``x._name``), or one named by a string to ``getattr``,
    ``setattr``, ``hasattr``, ``delattr``, ``patch.object`` or
    ``monkeypatch.setattr`` (``getattr(x, "_name")``).
    """
    found: list[tuple[int, str]] = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Attribute) and private(node.attr):
            found.append((node.lineno, node.attr))
        elif isinstance(node, ast.Call) and len(node.args) >= 2:
            function = node.func
            called = (
                function.id
                if isinstance(function, ast.Name)
                else function.attr
                if isinstance(function, ast.Attribute)
                else ""
            )
            named = node.args[1]
            if (
                called in NAMED_ACCESS
                and isinstance(named, ast.Constant)
                and isinstance(named.value, str)
                and private(named.value)
            ):
                found.append((node.lineno, named.value))
    return sorted(found)


def private_reaches(root: Path) -> list[tuple[str, int, str]]:
    """The private names the tests of our code under ``root`` reach, not allowed."""
    found: list[tuple[str, int, str]] = []
    for folder in TESTS_OF_OUR_CODE:
        for path in sorted((root / folder).rglob("*.py")):
            relative = path.relative_to(root).as_posix()
            for line, name in private_names(path.read_text(encoding="utf-8")):
                if (relative, name) not in PRIVATE_ALLOWED:
                    found.append((relative, line, name))
    return found


def test_the_private_scan_sees_what_a_test_reaches() -> None:
    """Attributes and names given as strings; dunders and public names are not private."""
    planted = (
        "client._session_id = 'S'\n"
        "source._quality['away']\n"
        "getattr(client, '_taken')\n"
        "patch.object(coordinator, '_async_update_data', spy)\n"
        "monkeypatch.setattr(client, '__mangled', 1)\n"
        "type(x).__name__, client.session_id, getattr(x, 'name'), x.__dict__\n"
    )
    assert private_names(planted) == [
        (1, "_session_id"),
        (2, "_quality"),
        (3, "_taken"),
        (4, "_async_update_data"),
        (5, "__mangled"),
    ]


def test_the_private_scan_finds_a_planted_reach(tmp_path: Path) -> None:
    """A test file reaching a private attribute is caught; an allowed one is not."""
    folder = tmp_path / "tests" / "pyplc" / "tekon"
    folder.mkdir(parents=True)
    (folder / "test_planted.py").write_text(
        "def test_it(client):\n    client._session_id = 'S'\n", encoding="utf-8"
    )
    helper = tmp_path / "tests" / "pyplc" / "conftest.py"
    helper.write_text("self._arrived = None\n", encoding="utf-8")
    assert private_reaches(tmp_path) == [
        ("tests/pyplc/tekon/test_planted.py", 2, "_session_id")
    ]


def test_tests_reach_no_private_name() -> None:
    """Tests of our code assert through public behaviour (issue #30, item 5)."""
    assert len(list((ROOT / "tests" / "pyplc").rglob("test_*.py"))) > 50
    assert private_reaches(ROOT) == []


def test_every_allowed_private_name_is_reached() -> None:
    """An allowance no test needs any more is taken off the list."""
    for (relative, name), reason in PRIVATE_ALLOWED.items():
        assert reason
        source = (ROOT / relative).read_text(encoding="utf-8")
        assert name in {found for _, found in private_names(source)}, relative
