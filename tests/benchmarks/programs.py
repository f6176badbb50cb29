"""The PLC programs the benchmark runs: generated ones of N T_ApiObjects, and shipped ones."""

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Final

from tests.simulator import Program, generate_program, load_program

DEFAULT_PROGRAMS: Final = ("50", "300", "1000", "demo")
SHIPPED_PROGRAMS: Final = ("demo", "manual")


@dataclass(frozen=True, slots=True)
class BenchProgram:
    """A program under test and its label in the report (`300`, `demo`)."""

    label: str
    program: Program


def parse_program_labels(text: str) -> tuple[str, ...]:
    """`50,300,demo` -> its labels; a label is a point count or a shipped program."""
    labels = tuple(part.strip() for part in text.split(",") if part.strip())
    if not labels:
        raise ValueError("name at least one program size or shipped program")
    for label in labels:
        if label not in SHIPPED_PROGRAMS and not (label.isdigit() and int(label) > 0):
            raise ValueError(
                f"{label!r} is neither a point count nor one of "
                f"{', '.join(SHIPPED_PROGRAMS)}"
            )
    return labels


def bench_program(label: str, *, seed: int = 0) -> BenchProgram:
    """The program for a label: `generate_program(N, seed=seed)` or a shipped one."""
    if label in SHIPPED_PROGRAMS:
        return BenchProgram(label, load_program(label))
    return BenchProgram(label, generate_program(int(label), seed=seed))


def bench_programs(labels: Sequence[str], *, seed: int = 0) -> list[BenchProgram]:
    """The programs for several labels, in order."""
    return [bench_program(label, seed=seed) for label in labels]
