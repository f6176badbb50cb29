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


def test_no_protocol_error_code_outside_the_library() -> None:
    """No TecoApi code (``"400.005"``) or made-up one is decoded by Home Assistant's side."""
    code = re.compile(r"\"[0-9]{3}\.[0-9]{3}\"")
    for path in HOME_ASSISTANT_MODULES:
        assert code.search(path.read_text(encoding="utf-8")) is None, path.name


# --- the vocabulary: no system's or convention's word in the kernel -------------
#
# Built from what every registered descriptor names: its source's name, the words of
# its title, its manufacturer, its push companion's title, its recognisers' names and
# the formats of the point-map loaders it brings (the core's own CSV is neutral).
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
        words.update(recogniser.name for recogniser in descriptor.recognisers)
        words.update(
            key
            for key, loader in descriptor.point_map_loaders.items()
            if not loader.__module__.startswith(f"{LIBRARY.name}.core")
            and ".pyplc.core." not in loader.__module__
        )
    return frozenset(words)


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
    assert {"tecomat", "teco", "plccoms", "gtsap1", "struct", "vlist"} <= words
    assert {"unipi", "panasonic", "asudscada"} <= words
    # The core's own CSV map is no system's word:
    assert "csv" not in words
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
