"""scripts/mutate's runner on a toy module: it finds a survivor, a killed and an equivalent."""

import ast
from pathlib import Path
import textwrap

import pytest

from tests.mutation import runner

TOY = '''\
"""A toy module."""

LIMIT: int = 10
UNUSED = 3
STEP = 1  # mutate: equivalent — never read


def fits(value: int) -> bool:
    """At most LIMIT."""
    return value <= LIMIT
'''

TOY_TESTS = """\
from toy import fits


def test_fits() -> None:
    assert fits(10)
    assert not fits(11)
"""

CONFIG = """\
[module.toy]
path = "{module}"
tests = ["{tests}"]

[[module.toy.equivalent]]
line = "return value"
mutant = "x"
reason = "no such mutant: the entry never matches"
"""

PYTEST_INI = """\
[pytest]
asyncio_mode = auto
asyncio_default_fixture_loop_scope = function
"""
# The runner forks this test process, which Home Assistant's test plugin has made
# multi-threaded; the child only runs pytest and exits (or is killed on its timeout).
pytestmark = pytest.mark.filterwarnings(
    "ignore:This process .* is multi-threaded:DeprecationWarning"
)


@pytest.fixture
def toy(tmp_path: Path) -> runner.Target:
    (tmp_path / "toy.py").write_text(TOY, encoding="utf-8")
    tests = tmp_path / "test_toy.py"
    tests.write_text(TOY_TESTS, encoding="utf-8")
    config = tmp_path / "modules.toml"
    config.write_text(
        CONFIG.format(module=tmp_path / "toy.py", tests=tests), encoding="utf-8"
    )
    (tmp_path / "pytest.ini").write_text(PYTEST_INI, encoding="utf-8")
    return runner.load_targets(config, root=tmp_path)["toy"]


def test_mutants_change_one_token_and_leave_docs_and_types_alone() -> None:
    source = textwrap.dedent('''\
        """Doc 1."""
        from typing import Final
        X: Final[int] = 2
        def f(a: int = 4, *, b: bool = True) -> list[int]:
            """Doc 2."""
            if a < 1 and not b or a in (1, 2) or a is None:
                return [a + 1, a * 3, a // 2, a << 1, a & 1, a % 2]
            logger.debug("x %s", 5)
            return []
        ''')
    labels = sorted(m.label for m in runner.mutants(source))
    assert labels == sorted(
        [
            "2 → 3", "2 → 1",  # X
            "4 → 5", "4 → 3",  # a default
            "True → False",
            "< → <=", "1 → 2", "1 → 0",
            "and → or", "or → and", "not x → x",
            "in → not in", "1 → 2", "1 → 0", "2 → 3", "2 → 1",
            "is → is not",
            "+ → -", "1 → 2", "1 → 0",
            "* → //", "3 → 4", "3 → 2",
            "// → *", "2 → 3", "2 → 1",
            "<< → >>", "1 → 2", "1 → 0",
            "& → |", "1 → 2", "1 → 0",
            "% → //", "2 → 3", "2 → 1",
        ]
    )  # fmt: skip
    # every mutant compiles, and only the function restricted to is changed
    for mutant in runner.mutants(source):
        compile(runner.mutate(source, mutant), "m.py", "exec")
    assert {m.line for m in runner.mutants(source, only=["f"])} == {4, 6, 7}


def test_a_planted_survivor_is_found_and_a_boundary_test_kills(
    toy: runner.Target,
) -> None:
    reported: list[str] = []
    result = runner.run_target(toy, reported.append)
    survived = sorted(m.label for m in result.survived)
    assert survived == ["3 → 2", "3 → 4"]  # UNUSED: no test reads it
    killed = {m.label for m in result.killed}
    assert killed == {"<= → <", "10 → 11", "10 → 9"}
    assert [(m.label, why) for m, why in result.equivalent] == [
        ("1 → 2", "never read"),
        ("1 → 0", "never read"),
    ]
    assert result.score == pytest.approx(100 * len(killed) / (len(killed) + 2))
    assert any("toy.py:4  3 → 4  in  UNUSED = 3" in line for line in reported)
    assert runner.summary([result])[2].startswith("| toy | ")
    # a survivor checked again alone: only its line's mutants run
    again = runner.run_target(toy, reported.append, lines={4})
    assert (len(again.survived), again.killed, again.equivalent) == (2, [], [])
    # the worktree's copy is never touched: the mutants live in memory
    assert toy.path.read_text(encoding="utf-8") == TOY


def test_a_child_past_its_timeout_is_killed_with_its_group(
    tmp_path: Path,
) -> None:
    tests = tmp_path / "test_hang.py"
    tests.write_text(
        "import threading\n\ndef test_hang() -> None:\n    threading.Event().wait()\n",
        encoding="utf-8",
    )
    (tmp_path / "pytest.ini").write_text(PYTEST_INI, encoding="utf-8")
    target = runner.Target("hang", tmp_path / "none.py", (str(tests),))
    assert runner.run_child(target, None, timeout=3.0) is None


def test_the_command_lists_and_scores(
    toy: runner.Target, capsys: pytest.CaptureFixture[str]
) -> None:
    config = toy.path.with_name("modules.toml")
    assert runner.main(["--config", str(config), "--list", "toy"]) == 0
    listed = capsys.readouterr().out.splitlines()
    assert len(listed) == 7
    assert any("(equivalent: never read)" in line for line in listed)
    assert runner.main(["--config", str(config), "--list", "--line", "4", "toy"]) == 0
    assert [line.split("  ")[1] for line in capsys.readouterr().out.splitlines()] == [
        "3 → 4",
        "3 → 2",
    ]
    with pytest.raises(SystemExit):
        runner.main(["--config", str(config), "nothing"])


def test_two_mutants_of_one_label_on_a_line_are_told_apart(tmp_path: Path) -> None:
    source = "def f(a: int) -> int:\n    return a - 1 - a\n"
    found = runner.mutants(source)
    places = runner.occurrences(found)
    minus = sorted((m for m in found if m.label == "- → +"), key=lambda m: places[m][0])
    assert [places[m] for m in minus] == [(1, 2), (2, 2)]
    # the leftmost is the inner subtraction (a - 1): its change gives a + 1 - a
    first = ast.unparse(runner.mutate(source, minus[0]))
    assert "a + 1 - a" in first
    assert "a - 1 + a" in ast.unparse(runner.mutate(source, minus[1]))
    module = tmp_path / "two.py"
    module.write_text(source, encoding="utf-8")
    config = tmp_path / "modules.toml"
    config.write_text(
        f'[module.two]\npath = "{module}"\ntests = []\n\n'
        '[[module.two.equivalent]]\nline = "return a - 1 - a"\n'
        'mutant = "- → +"\noccurrence = 2\nreason = "only the second"\n',
        encoding="utf-8",
    )
    target = runner.load_targets(config, root=tmp_path)["two"]
    lines = source.splitlines()
    reasons = [runner.equivalent_reason(lines, m, target, places[m][0]) for m in minus]
    assert reasons == [None, "only the second"]
    # the list names each by its place; a label alone on its line has none
    assert runner.describe(target, minus[1], place=places[minus[1]]).endswith(
        "2  - → + #2  in  return a - 1 - a"
    )
    one = next(m for m in found if m.label == "1 → 2")
    assert "  1 → 2  in  " in runner.describe(target, one, place=places[one])
    # without an occurrence an entry names every mutant of its label on the line
    unnamed = runner.Target(
        "two", module, (), equivalent=(runner.Equivalent("a - 1", "- → +", "all"),)
    )
    assert [
        runner.equivalent_reason(lines, m, unnamed, places[m][0]) for m in minus
    ] == ["all", "all"]


def test_a_sample_is_spread_evenly_and_the_same_each_time(
    toy: runner.Target, capsys: pytest.CaptureFixture[str]
) -> None:
    items = [runner.Mutant(n, 0, n, str(n)) for n in range(10)]
    assert [m.node for m in runner.spread(items, 4)] == [0, 2, 5, 7]
    assert [m.node for m in runner.spread(items, 1)] == [0]
    assert runner.spread(items, 10) == runner.spread(items, 11) == items
    assert runner.spread(items, 0) == items
    # the toy's five mutants not known equivalent: LIMIT's two, UNUSED's two, <=
    reported: list[str] = []
    result = runner.run_target(toy, reported.append, sample=2)
    assert [m.label for m in result.killed] == ["10 → 11"]
    assert [m.label for m in result.survived] == ["3 → 4"]
    assert result.equivalent == []
    config = toy.path.with_name("modules.toml")
    assert runner.main(["--config", str(config), "--list", "--sample", "3", "toy"]) == 0
    assert [line.split("  ")[1] for line in capsys.readouterr().out.splitlines()] == [
        "10 → 11",
        "10 → 9",
        "3 → 2",
    ]
