"""Mutation testing: does a module's own test suite notice a one-token change?

    scripts/mutate                      every module of tests/mutation/modules.toml
    scripts/mutate mervis.codec ...     the named ones
    scripts/mutate --list mervis.codec  the mutants only, nothing run
    scripts/mutate --sample 12 mervis.codec   12 of its mutants, spread evenly

A mutant is the module with ONE change: an arithmetic or bitwise operator swapped
(``+``/``-``, ``*``/``//``, ``<<``/``>>``, ``&``/``|``), a comparison moved by one
(``<``/``<=``, ``>``/``>=``, ``==``/``!=``, ``in``/``not in``, ``is``/``is not``), an
integer changed by one either way, a boolean flipped, ``and``/``or`` swapped or a
``not`` dropped. Docstrings, annotations, decorators and logging calls are left
alone (their mutants tell nothing of behaviour); strings and floats too.

Each mutant runs the tests that own the module (the config's ``tests``, with ``-x``,
no coverage) in a forked child of this process: the heavy imports (pytest, Home
Assistant, hypothesis, aiohttp) happen once here, the project's own modules are
imported afresh in each child, and the mutated module is served from memory by an
import hook, so no file of the working tree is ever written. A child that runs
longer than its timeout is killed with its process group and counts as killed.

A mutant that cannot change behaviour is *equivalent*: mark its line in the source
with ``# mutate: equivalent — <reason>``, or name it in the config's ``equivalent``
list (the line's text, the mutant's label and the reason), which survives edits
around it. The score is killed / (mutants - equivalent).
"""

import argparse
import ast
from collections.abc import Callable, Collection, Iterator, Sequence
import contextlib
from dataclasses import dataclass, field
import gc
import importlib
import importlib.abc
import importlib.machinery
import os
from pathlib import Path
import signal
import sys
import time
import tomllib
from types import CodeType, ModuleType
from typing import Final

import pytest

REPO_ROOT: Final = Path(__file__).resolve().parents[2]
CONFIG: Final = Path(__file__).with_name("modules.toml")
MARKER: Final = "# mutate: equivalent"
WARM_IMPORTS: Final = (
    "pytest_homeassistant_custom_component.plugins",
    "pytest",
    "hypothesis",
    "aiohttp",
    "yarl",
    "homeassistant.core",
    "homeassistant.helpers.entity",
)
"""Imported once by the runner, before any fork: what every child would import."""
PROJECT_PACKAGES: Final = ("custom_components", "tests", "pyplc")
"""Imported afresh in each child, so the mutated module is the one they see."""
PYTEST_ARGS: Final = ("-x", "-q", "-p", "no:cov", "-p", "no:randomly", "--no-header")

_BINARY: Final[dict[type[ast.operator], type[ast.operator]]] = {
    ast.Add: ast.Sub,
    ast.Sub: ast.Add,
    ast.Mult: ast.FloorDiv,
    ast.FloorDiv: ast.Mult,
    ast.Div: ast.Mult,
    ast.Mod: ast.FloorDiv,
    ast.Pow: ast.Mult,
    ast.LShift: ast.RShift,
    ast.RShift: ast.LShift,
    ast.BitAnd: ast.BitOr,
    ast.BitOr: ast.BitAnd,
    ast.BitXor: ast.BitOr,
}
_COMPARE: Final[dict[type[ast.cmpop], type[ast.cmpop]]] = {
    ast.Lt: ast.LtE,
    ast.LtE: ast.Lt,
    ast.Gt: ast.GtE,
    ast.GtE: ast.Gt,
    ast.Eq: ast.NotEq,
    ast.NotEq: ast.Eq,
    ast.In: ast.NotIn,
    ast.NotIn: ast.In,
    ast.Is: ast.IsNot,
    ast.IsNot: ast.Is,
}
_SYMBOL: Final[dict[type[ast.AST], str]] = {
    ast.Add: "+",
    ast.Sub: "-",
    ast.Mult: "*",
    ast.Div: "/",
    ast.FloorDiv: "//",
    ast.Mod: "%",
    ast.Pow: "**",
    ast.LShift: "<<",
    ast.RShift: ">>",
    ast.BitAnd: "&",
    ast.BitOr: "|",
    ast.BitXor: "^",
    ast.Lt: "<",
    ast.LtE: "<=",
    ast.Gt: ">",
    ast.GtE: ">=",
    ast.Eq: "==",
    ast.NotEq: "!=",
    ast.In: "in",
    ast.NotIn: "not in",
    ast.Is: "is",
    ast.IsNot: "is not",
    ast.And: "and",
    ast.Or: "or",
}


@dataclass(frozen=True, slots=True)
class Mutant:
    """One change to a module: which node (its place in ast.walk order) and how."""

    node: int
    variant: int
    line: int
    label: str
    """What changed, e.g. ``> → >=`` or ``16383 → 16384``."""
    column: int = 0
    """Where on its line, to tell apart two changes of the same label there."""


@dataclass(frozen=True, slots=True)
class Equivalent:
    """A mutant the config says cannot change behaviour, found by its line's text."""

    line: str
    mutant: str
    reason: str
    occurrence: int | None = None
    """Which of its line's mutants of that label (1: the leftmost); None: all."""


@dataclass(frozen=True, slots=True)
class Target:
    """A module under test and the tests that own it."""

    name: str
    path: Path
    tests: tuple[str, ...]
    keyword: str = ""
    only: tuple[str, ...] = ()
    """Mutate only inside these functions (their names), when given."""
    equivalent: tuple[Equivalent, ...] = ()


@dataclass(slots=True)
class Result:
    """How a module's mutants fared."""

    target: Target
    killed: list[Mutant] = field(default_factory=list)
    survived: list[Mutant] = field(default_factory=list)
    equivalent: list[tuple[Mutant, str]] = field(default_factory=list)
    baseline: float = 0.0

    @property
    def score(self) -> float:
        """Killed of the non-equivalent mutants, in percent (100 with none)."""
        counted = len(self.killed) + len(self.survived)
        return 100.0 * len(self.killed) / counted if counted else 100.0


def _skipped_nodes(tree: ast.Module) -> set[int]:
    """Ids of the nodes no mutant touches: docstrings, annotations, decorators, logs."""
    skipped: set[int] = set()

    def skip(node: ast.AST | None) -> None:
        if node is not None:
            skipped.update(id(child) for child in ast.walk(node))

    for node in ast.walk(tree):
        if isinstance(
            node, ast.Module | ast.ClassDef | ast.FunctionDef | ast.AsyncFunctionDef
        ):
            body = node.body
            if (
                body
                and isinstance(body[0], ast.Expr)
                and isinstance(body[0].value, ast.Constant)
            ):
                skip(body[0])
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef):
            for decorator in node.decorator_list:
                skip(decorator)
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            skip(node.returns)
            for arg in (*node.args.posonlyargs, *node.args.args, *node.args.kwonlyargs):
                skip(arg.annotation)
            skip(node.args.vararg and node.args.vararg.annotation)
            skip(node.args.kwarg and node.args.kwarg.annotation)
        if isinstance(node, ast.AnnAssign):
            skip(node.annotation)
        if isinstance(node, ast.Expr) and isinstance(node.value, ast.Constant):
            skip(node)  # an attribute's docstring
        if (
            isinstance(node, ast.Call)
            and isinstance(node.func, ast.Attribute)
            and isinstance(node.func.value, ast.Name)
            and "log" in node.func.value.id.lower()
        ):
            skip(node)
        if isinstance(node, ast.If) and ast.unparse(node.test) == "TYPE_CHECKING":
            skip(node)
    return skipped


def _within(tree: ast.Module, names: Sequence[str]) -> set[int] | None:
    """Ids of the nodes inside the named functions; None: no restriction."""
    if not names:
        return None
    inside: set[int] = set()
    for node in ast.walk(tree):
        if (
            isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef)
            and node.name in names
        ):
            inside.update(id(child) for child in ast.walk(node))
    return inside


def _variants(
    node: ast.AST,
) -> list[tuple[str, Callable[[ast.AST], None], tuple[int, int]]]:
    """The ways to change one node: (label, how, line and column of the change)."""
    out: list[tuple[str, Callable[[ast.AST], None], tuple[int, int]]] = []
    if isinstance(node, ast.BinOp | ast.AugAssign) and type(node.op) in _BINARY:
        operands = (
            (node.left, node.right) if isinstance(node, ast.BinOp) else (node.value,)
        )
        if not any(
            isinstance(o, ast.JoinedStr)
            or (isinstance(o, ast.Constant) and isinstance(o.value, str | bytes))
            for o in operands
        ):
            new = _BINARY[type(node.op)]
            changed = node.right if isinstance(node, ast.BinOp) else node
            line = (changed.lineno, changed.col_offset)

            def swap_op(n: ast.AST, new: type[ast.operator] = new) -> None:
                n.op = new()  # type: ignore[attr-defined]

            out.append((f"{_SYMBOL[type(node.op)]} → {_SYMBOL[new]}", swap_op, line))
    elif isinstance(node, ast.Compare):
        for index, op in enumerate(node.ops):
            if type(op) in _COMPARE:
                cmp_new = _COMPARE[type(op)]

                def swap_cmp(
                    n: ast.AST, i: int = index, new: type[ast.cmpop] = cmp_new
                ) -> None:
                    n.ops[i] = new()  # type: ignore[attr-defined]

                out.append(
                    (
                        f"{_SYMBOL[type(op)]} → {_SYMBOL[cmp_new]}",
                        swap_cmp,
                        (
                            node.comparators[index].lineno,
                            node.comparators[index].col_offset,
                        ),
                    )
                )
    elif isinstance(node, ast.BoolOp):
        other = ast.Or if isinstance(node.op, ast.And) else ast.And

        def swap_bool(n: ast.AST, new: type[ast.boolop] = other) -> None:
            n.op = new()  # type: ignore[attr-defined]

        out.append(
            (
                f"{_SYMBOL[type(node.op)]} → {_SYMBOL[other]}",
                swap_bool,
                (node.values[1].lineno, node.values[1].col_offset),
            )
        )
    elif isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.Not):

        def drop_not(n: ast.AST) -> None:
            n.operand = ast.UnaryOp(ast.Not(), n.operand)  # type: ignore[attr-defined]

        out.append(("not x → x", drop_not, (node.lineno, node.col_offset)))
    elif isinstance(node, ast.Constant) and isinstance(node.value, bool):

        def flip(n: ast.AST) -> None:
            n.value = not n.value  # type: ignore[attr-defined]

        out.append(
            (f"{node.value} → {not node.value}", flip, (node.lineno, node.col_offset))
        )
    elif isinstance(node, ast.Constant) and type(node.value) is int:
        for step in (1, -1):

            def shift(n: ast.AST, step: int = step) -> None:
                n.value += step  # type: ignore[attr-defined]

            out.append(
                (
                    f"{node.value} → {node.value + step}",
                    shift,
                    (node.lineno, node.col_offset),
                )
            )
    return out


def mutants(source: str, only: Sequence[str] = ()) -> list[Mutant]:
    """Every mutant of a module's source, in a stable order."""
    tree = ast.parse(source)
    skipped = _skipped_nodes(tree)
    inside = _within(tree, only)
    found: list[Mutant] = []
    for index, node in enumerate(ast.walk(tree)):
        if id(node) in skipped or (inside is not None and id(node) not in inside):
            continue
        for variant, (label, _, (line, column)) in enumerate(_variants(node)):
            found.append(Mutant(index, variant, line, label, column))
    return sorted(found, key=lambda m: (m.line, m.node, m.variant))


def occurrences(found: Sequence[Mutant]) -> dict[Mutant, tuple[int, int]]:
    """Each mutant's place among its line's mutants of the same label, left to
    right, and how many there are: (1, 1) for a label alone on its line."""
    same: dict[tuple[int, str], list[Mutant]] = {}
    for mutant in found:
        same.setdefault((mutant.line, mutant.label), []).append(mutant)
    places: dict[Mutant, tuple[int, int]] = {}
    for group in same.values():
        ordered = sorted(group, key=lambda m: (m.column, m.node, m.variant))
        for place, mutant in enumerate(ordered, 1):
            places[mutant] = (place, len(group))
    return places


def mutate(source: str, mutant: Mutant) -> ast.Module:
    """The module's tree with the one change a mutant names."""
    tree = ast.parse(source)
    node = next(n for i, n in enumerate(ast.walk(tree)) if i == mutant.node)
    _variants(node)[mutant.variant][1](node)
    return ast.fix_missing_locations(tree)


def equivalent_reason(
    source_lines: Sequence[str], mutant: Mutant, target: Target, occurrence: int = 1
) -> str | None:
    """Why a mutant is equivalent, if its line or the config says so.

    ``occurrence`` is the mutant's place among its line's mutants of the same
    label (see ``occurrences``); an entry naming one matches only that one.
    """
    text = source_lines[mutant.line - 1]
    if MARKER in text:
        reason = text.split(MARKER, 1)[1].lstrip(" —-:")
        return reason or "marked in the source"
    for entry in target.equivalent:
        if (
            entry.line in text
            and entry.mutant == mutant.label
            and entry.occurrence in (None, occurrence)
        ):
            return entry.reason
    return None


def load_targets(config: Path = CONFIG, root: Path = REPO_ROOT) -> dict[str, Target]:
    """The modules of a config file, by name."""
    data = tomllib.loads(config.read_text(encoding="utf-8"))
    targets: dict[str, Target] = {}
    for name, entry in data["module"].items():
        targets[name] = Target(
            name=name,
            path=(root / entry["path"]).resolve(),
            tests=tuple(entry["tests"]),
            keyword=entry.get("keyword", ""),
            only=tuple(entry.get("only", ())),
            equivalent=tuple(
                Equivalent(e["line"], e["mutant"], e["reason"], e.get("occurrence"))
                for e in entry.get("equivalent", ())
            ),
        )
    return targets


class _MutantLoader(importlib.machinery.SourceFileLoader):
    """Loads the mutated module from memory, never from its .pyc."""

    def __init__(self, fullname: str, path: str, code: CodeType) -> None:
        super().__init__(fullname, path)
        self._code = code

    def get_code(self, fullname: str) -> CodeType:
        return self._code


class _MutantFinder(importlib.abc.MetaPathFinder):
    """Serves one file, under whatever name it is imported, from a compiled tree."""

    def __init__(self, path: Path, code: CodeType) -> None:
        self._path = path
        self._code = code

    def find_spec(
        self,
        fullname: str,
        path: Sequence[str] | None,
        target: ModuleType | None = None,
    ) -> importlib.machinery.ModuleSpec | None:
        spec = importlib.machinery.PathFinder.find_spec(fullname, path)
        if (
            spec is None
            or spec.origin is None
            or Path(spec.origin).resolve() != self._path
        ):
            return None
        spec.loader = _MutantLoader(fullname, spec.origin, self._code)
        return spec


def _child(target: Target, code: CodeType | None, quiet: bool) -> int:
    """In a forked child: import the project afresh (mutated where given), run the tests."""
    os.setpgid(0, 0)
    sys.dont_write_bytecode = True
    for name in list(sys.modules):
        if name.split(".")[0] in PROJECT_PACKAGES:
            del sys.modules[name]
    if code is not None:
        sys.meta_path.insert(0, _MutantFinder(target.path, code))
    if quiet:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, 1)
        os.dup2(devnull, 2)
        sys.stdout = sys.stderr = os.fdopen(devnull, "w", encoding="utf-8")
    args = [*PYTEST_ARGS, "-p", "tests.mutation.profile", *target.tests]
    if target.keyword:
        args += ["-k", target.keyword]
    return int(pytest.main(args))


def run_child(
    target: Target, code: CodeType | None, timeout: float, quiet: bool = True
) -> int | None:
    """Run the target's tests in a forked child; its exit status, None on a timeout."""
    sys.stdout.flush()
    sys.stderr.flush()
    pid = os.fork()
    if pid == 0:  # pragma: no cover - the child; its status tells the parent
        status = 3
        try:
            status = _child(target, code, quiet)
        finally:
            os._exit(status)
    deadline = time.monotonic() + timeout
    while True:
        done, status = os.waitpid(pid, os.WNOHANG)
        if done:
            return os.waitstatus_to_exitcode(status)
        if time.monotonic() > deadline:
            with contextlib.suppress(ProcessLookupError):
                os.killpg(pid, signal.SIGKILL)
            os.waitpid(pid, 0)
            return None
        time.sleep(0.02)


def warm_up(targets: Sequence[Target] = ()) -> None:
    """Import once what every child needs, so a fork starts with it.

    The project's own modules are imported too (its tests' and their conftests'),
    for the third-party modules they pull in, then forgotten: each child imports
    them afresh.
    """
    os.environ.setdefault("PYTHONDONTWRITEBYTECODE", "1")
    sys.dont_write_bytecode = True
    if str(REPO_ROOT) not in sys.path:
        sys.path.insert(0, str(REPO_ROOT))
    names = list(WARM_IMPORTS)
    for target in targets:
        for test in target.tests:
            path = Path(test)
            names.extend(
                ".".join((*parent.parts, "conftest"))
                for parent in reversed(path.parents[:-1])
                if (REPO_ROOT / parent / "conftest.py").exists()
            )
            names.append(".".join(path.with_suffix("").parts))
    for name in names:
        with contextlib.suppress(ImportError):
            importlib.import_module(name)
    for name in list(sys.modules):
        if name.split(".")[0] in PROJECT_PACKAGES:
            del sys.modules[name]
    # What is imported now lives as long as every child: the collector need not look
    # at it again (pytest collects hard after each session, and the heap is large).
    gc.collect()
    gc.freeze()


def spread(items: Sequence[Mutant], count: int) -> list[Mutant]:
    """``count`` of the items spread evenly from the first (all of them when fewer).

    The same items every time: a sample for a quick run, not a random one.
    """
    if count <= 0 or count >= len(items):
        return list(items)
    return [items[index * len(items) // count] for index in range(count)]


def iter_results(
    target: Target,
    report: Callable[[str], None],
    timeout_factor: float = 4.0,
    lines: Collection[int] = (),
    sample: int = 0,
) -> Iterator[tuple[Mutant, str]]:
    """Run every mutant of a target; yield each with its outcome.

    ``sample`` > 0 runs only that many of the mutants not known equivalent, spread
    over the module (:func:`spread`), and yields no equivalent.
    """
    source = target.path.read_text(encoding="utf-8")
    text_lines = source.splitlines()
    started = time.monotonic()
    status = run_child(target, None, timeout=600.0)
    baseline = time.monotonic() - started
    if status != 0:
        raise SystemExit(
            f"{target.name}: the tests fail without a mutant (exit status {status})"
        )
    timeout = max(10.0, timeout_factor * baseline)
    report(
        f"{target.name}: tests pass unmutated in {baseline:.1f} s; timeout {timeout:.0f} s"
    )
    found = mutants(source, target.only)
    places = occurrences(found)
    chosen = [mutant for mutant in found if not lines or mutant.line in lines]
    if sample > 0:
        chosen = spread(
            [
                m
                for m in chosen
                if equivalent_reason(text_lines, m, target, places[m][0]) is None
            ],
            sample,
        )
    for mutant in chosen:
        reason = equivalent_reason(text_lines, mutant, target, places[mutant][0])
        if reason is not None:
            yield mutant, "equivalent: " + reason
            continue
        code = compile(mutate(source, mutant), str(target.path), "exec")
        status = run_child(target, code, timeout)
        if status is None:
            yield mutant, "killed (timeout)"
        elif status == 0:
            yield mutant, "survived"
        elif status == 5:
            raise SystemExit(f"{target.name}: no test was collected")
        else:
            yield mutant, "killed"


def run_target(
    target: Target,
    report: Callable[[str], None],
    lines: Collection[int] = (),
    sample: int = 0,
) -> Result:
    """All mutants of one module (those on `lines`, `sample` of them), with the score."""
    result = Result(target)
    places = occurrences(mutants(target.path.read_text(encoding="utf-8"), target.only))
    for mutant, outcome in iter_results(target, report, lines=lines, sample=sample):
        if outcome.startswith("equivalent"):
            result.equivalent.append((mutant, outcome.split(": ", 1)[1]))
        elif outcome.startswith("killed"):
            result.killed.append(mutant)
        else:
            result.survived.append(mutant)
            report("  survived: " + describe(target, mutant, place=places[mutant]))
    return result


def describe(
    target: Target,
    mutant: Mutant,
    root: Path = REPO_ROOT,
    place: tuple[int, int] = (1, 1),
) -> str:
    """``file:line  label  in  source line`` for a survivor.

    A label its line has more than once is followed by `` #N``, its place from
    the left (what an equivalent entry's ``occurrence`` names).
    """
    text = target.path.read_text(encoding="utf-8").splitlines()[mutant.line - 1].strip()
    try:
        where = target.path.relative_to(root)
    except ValueError:
        where = target.path
    label = mutant.label if place[1] == 1 else f"{mutant.label} #{place[0]}"
    return f"{where}:{mutant.line}  {label}  in  {text}"


def summary(results: Sequence[Result]) -> list[str]:
    """The table: module, mutants, equivalent, killed, survived, score."""
    rows = [
        "| module | mutants | equivalent | killed | survived | score |",
        "|---|---:|---:|---:|---:|---:|",
    ]
    for r in results:
        total = len(r.killed) + len(r.survived) + len(r.equivalent)
        rows.append(
            f"| {r.target.name} | {total} | {len(r.equivalent)} | {len(r.killed)} "
            f"| {len(r.survived)} | {r.score:.1f} % |"
        )
    return rows


def _print(line: str) -> None:
    print(line, flush=True)


def main(argv: Sequence[str] | None = None) -> int:
    """Command line: run the named modules (all without names), print the table."""
    parser = argparse.ArgumentParser(
        prog="scripts/mutate", description=__doc__.split("\n")[0]
    )
    parser.add_argument(
        "modules", nargs="*", help="names from tests/mutation/modules.toml"
    )
    parser.add_argument(
        "--list", action="store_true", help="list the mutants, run nothing"
    )
    parser.add_argument("--config", type=Path, default=CONFIG)
    parser.add_argument(
        "--line",
        type=int,
        action="append",
        default=[],
        help="only the mutants on this line (repeatable): to check survivors again",
    )
    parser.add_argument(
        "--min-score", type=float, default=0.0, help="exit 1 below this score"
    )
    parser.add_argument(
        "--sample",
        type=int,
        default=0,
        metavar="N",
        help="run only N mutants of each module, spread evenly (the same N each time)",
    )
    args = parser.parse_args(argv)
    targets = load_targets(args.config)
    unknown = [name for name in args.modules if name not in targets]
    if unknown:
        parser.error(
            f"unknown module(s) {', '.join(unknown)}; known: {', '.join(targets)}"
        )
    chosen = (
        [targets[name] for name in args.modules]
        if args.modules
        else list(targets.values())
    )
    if args.list:
        for target in chosen:
            source = target.path.read_text(encoding="utf-8")
            lines = source.splitlines()
            found = mutants(source, target.only)
            places = occurrences(found)
            listed = [m for m in found if not args.line or m.line in args.line]
            if args.sample > 0:
                listed = spread(
                    [
                        m
                        for m in listed
                        if not equivalent_reason(lines, m, target, places[m][0])
                    ],
                    args.sample,
                )
            for mutant in listed:
                place = places[mutant]
                reason = equivalent_reason(lines, mutant, target, place[0])
                note = f"  (equivalent: {reason})" if reason else ""
                print(describe(target, mutant, place=place) + note)
        return 0
    warm_up(chosen)
    results: list[Result] = []
    for target in chosen:
        result = run_target(target, _print, args.line, args.sample)
        results.append(result)
        print(f"{target.name}: {result.score:.1f} % killed", flush=True)
    print()
    print("\n".join(summary(results)))
    return 0 if all(r.score >= args.min_score for r in results) else 1


if __name__ == "__main__":
    sys.exit(main())
