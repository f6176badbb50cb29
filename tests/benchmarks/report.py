"""The benchmark's report: markdown tables, the issues' targets, and the JSON file."""

from dataclasses import asdict, dataclass
import json
from pathlib import Path
from typing import Final

from .integration import CpuFigures
from .results import BenchResults, ProgramResult

POLL_INTERVAL_MS: Final = 5000.0
"""The integration's default polling interval; a poll must fit well inside it."""
WELL_INSIDE: Final = 0.5
"""'Well inside' the interval, read as: at most half of it."""
FLOOR_TARGET: Final = 1.2
"""A poll's CPU at most this many times the transport floor's (issue 41)."""


@dataclass(frozen=True, slots=True)
class Target:
    """One benchmark target (issues 6, 13, 41) and whether this run met it."""

    name: str
    met: bool | None
    measured: str


def _fmt(value: float, digits: int = 1) -> str:
    return f"{value:,.{digits}f}".rstrip("0").rstrip(".") if digits else f"{value:,.0f}"


def _cpu(program: ProgramResult, percent: float) -> CpuFigures | None:
    return next(
        (cpu for cpu in program.integration.cpu if cpu.percent == percent), None
    )


def _at_percent(
    programs: list[ProgramResult], percent: float
) -> list[tuple[str, CpuFigures]]:
    """Each program's CPU figures at one change rate (programs without it left out)."""
    found = [(program.label, _cpu(program, percent)) for program in programs]
    return [(label, cpu) for label, cpu in found if cpu is not None]


def evaluate_targets(results: BenchResults) -> list[Target]:
    """Check every target against the figures (None: not measured)."""
    programs = results.programs
    targets = []
    over = {
        p.label: (p.polling.requests_per_poll, p.polling.lower_bound) for p in programs
    }
    targets.append(
        Target(
            "Requests per poll = lower bound (within one) at every size",
            all(ours <= bound + 1 for ours, bound in over.values()) if over else None,
            ", ".join(f"{k}: {_fmt(o)} vs {b}" for k, (o, b) in over.items()),
        )
    )
    at_300 = results.by_label("300")
    if at_300 is None:
        targets.append(Target("≥ 20x fewer requests than the peer at 300", None, "-"))
        targets.append(Target("≥ 10x less wall time than the peer at 300", None, "-"))
    else:
        polling = at_300.polling
        targets.append(
            Target(
                "≥ 20x fewer requests than the peer at 300",
                polling.request_ratio >= 20,
                f"{polling.request_ratio:.1f}x ({_fmt(polling.requests_per_poll)} vs "
                f"{_fmt(polling.peer_requests_per_poll)})",
            )
        )
        targets.append(
            Target(
                "≥ 10x less wall time than the peer at 300",
                polling.time_ratio >= 10,
                f"{polling.time_ratio:.1f}x ({_fmt(polling.poll_ms, 0)} ms vs "
                f"{_fmt(polling.peer_poll_ms, 0)} ms)",
            )
        )
    trips = {
        p.label: (p.polling.round_trips_per_request, p.polling.challenges_after_first)
        for p in programs
    }
    targets.append(
        Target(
            "Exactly one round trip per request after the first challenge",
            all(r == 1 and c == 0 for r, c in trips.values()) if trips else None,
            ", ".join(
                f"{k}: {r:.3f} ({c} later challenges)" for k, (r, c) in trips.items()
            ),
        )
    )
    zero = _at_percent(programs, 0)
    targets.append(
        Target(
            "0 % changing: zero state writes per poll",
            all(cpu.ours.state_writes == 0 for _, cpu in zero) if zero else None,
            ", ".join(f"{k}: {_fmt(cpu.ours.state_writes)}" for k, cpu in zero),
        )
    )
    one = _at_percent(programs, 1)
    targets.append(
        Target(
            "1 % changing: state writes = entities showing a changed value",
            all(cpu.ours.state_writes == cpu.fed_entities for _, cpu in one)
            if one
            else None,
            ", ".join(
                f"{k}: {_fmt(cpu.ours.state_writes)} of {_fmt(cpu.fed_entities)}"
                f" ({_fmt(cpu.changed_points)} values)"
                for k, cpu in one
            ),
        )
    )
    targets.append(
        Target(
            "1 % changing: CPU telling entities ≤ 10 % of the every-entity baseline",
            all(cpu.update_cpu_ratio <= 0.10 for _, cpu in one) if one else None,
            ", ".join(f"{k}: {cpu.update_cpu_ratio:.1%}" for k, cpu in one),
        )
    )
    targets.append(floor_target(zero))
    at_1000 = results.by_label("1000")
    if at_1000 is None:
        targets.append(Target("A 1000-point poll well inside 5 s", None, "-"))
    else:
        refresh = _cpu(at_1000, 0)
        slowest = max(at_1000.polling.poll_ms, refresh.ours.wall_ms if refresh else 0.0)
        targets.append(
            Target(
                "A 1000-point poll well inside 5 s (≤ 2.5 s)",
                slowest <= POLL_INTERVAL_MS * WELL_INSIDE,
                f"client {_fmt(at_1000.polling.poll_ms, 0)} ms"
                + (
                    f", coordinator {_fmt(refresh.ours.wall_ms, 0)} ms"
                    if refresh
                    else ""
                )
                + f" ({_fmt(at_1000.polling.poll_with_attrs_ms, 0)} ms with attributes)",
            )
        )
    writes = [(p.label, p.integration.write) for p in programs if p.integration.write]
    targets.append(
        Target(
            "Write: one request plus at most one confirming read",
            all(w.call_requests <= 2 for _, w in writes) if writes else None,
            ", ".join(
                f"{k}: {_fmt(w.shown_requests)} to show, {_fmt(w.call_requests)} "
                "until the call returned"
                for k, w in writes
            ),
        )
    )
    return targets


def floor_figures(cpu: CpuFigures) -> str:
    """Our CPU against the floor's, as the target reads it: ``1.14x (4.1 / 3.6 ms)``."""
    return (
        f"{cpu.floor_ratio:.2f}× ({_fmt(cpu.ours.cpu_ms, 2)} / "
        f"{_fmt(cpu.transport_cpu_ms, 2)} ms)"
    )


def floor_target(zero: list[tuple[str, CpuFigures]]) -> Target:
    """Whether the whole poll stays within the floor's target at every size (0 %)."""
    return Target(
        f"0 % changing: whole poll CPU ≤ {FLOOR_TARGET}× the transport floor "
        "at every size",
        all(cpu.floor_ratio <= FLOOR_TARGET for _, cpu in zero) if zero else None,
        ", ".join(f"{label}: {floor_figures(cpu)}" for label, cpu in zero),
    )


def markdown_table(header: list[str], rows: list[list[str]]) -> list[str]:
    """A markdown table: the first column left-aligned, the others right."""
    lines = ["| " + " | ".join(header) + " |"]
    lines.append(
        "|" + "|".join("---:" if i else "---" for i in range(len(header))) + "|"
    )
    lines.extend("| " + " | ".join(row) + " |" for row in rows)
    return lines


def _cpu_row(program: ProgramResult, cpu: CpuFigures) -> list[str]:
    """One row of the Home Assistant table."""
    return [
        program.label,
        f"{program.integration.discovery.entities}",
        f"{_fmt(cpu.percent)} % ({_fmt(cpu.changed_points)})",
        _fmt(cpu.ours.state_writes),
        _fmt(cpu.baseline.state_writes),
        _fmt(cpu.ours.cpu_ms, 2),
        _fmt(cpu.baseline.cpu_ms, 2),
        f"{cpu.cpu_ratio:.0%}",
        (f"{_fmt(cpu.ours.update_cpu_ms, 2)} / {_fmt(cpu.baseline.update_cpu_ms, 2)}"),
        f"{cpu.update_cpu_ratio:.1%}",
        f"{_fmt(cpu.transport_cpu_ms, 2)} ({_fmt(cpu.get_object_cpu_ms, 2)})",
        f"{cpu.floor_ratio:.2f}×",
        _fmt(cpu.ours.wall_ms, 0),
    ]


def markdown(results: BenchResults) -> str:
    """The report as markdown: the machine, three tables and the targets."""
    settings, machine = results.settings, results.machine
    lines = [
        "## TecoApi benchmark",
        "",
        (
            f"Machine: {machine['cpu']}, {machine['cores']} cores, {machine['os']}; "
            f"Python {machine['python']}, Home Assistant {machine['homeassistant']}, "
            f"aiohttp {machine['aiohttp']}."
        ),
        (
            f"Latency model: {_fmt(settings.latency_ms, 2)} ms per request + "
            f"{_fmt(settings.per_item_ms, 3)} ms per returned item; {settings.polls} "
            f"polls per figure ({settings.peer_polls} for the peer); "
            f"run took {results.seconds:.0f} s."
        ),
        "",
        "### Requests and wall time per poll (every point polled)",
        "",
    ]
    lines += markdown_table(
        [
            "program",
            "points",
            "ours",
            "lower bound",
            "ours with attrs",
            "peer",
            "fewer requests",
            "ours ms",
            "peer ms",
            "faster",
            "round trips / request",
        ],
        [
            [
                p.label,
                f"{p.polling.points}",
                _fmt(p.polling.requests_per_poll),
                f"{p.polling.lower_bound}",
                (
                    f"{_fmt(p.polling.requests_per_poll_with_attrs)} "
                    f"(bound {p.polling.lower_bound_with_attrs})"
                ),
                _fmt(p.polling.peer_requests_per_poll),
                f"{p.polling.request_ratio:.1f}x",
                _fmt(p.polling.poll_ms, 0),
                _fmt(p.polling.peer_poll_ms, 0),
                f"{p.polling.time_ratio:.1f}x",
                f"{p.polling.round_trips_per_request:.2f}",
            ]
            for p in results.programs
        ],
    )
    lines += [
        "",
        (
            "### Home Assistant per poll (all entities enabled; ours vs every entity "
            "writing its state)"
        ),
        "",
    ]
    rows = [
        _cpu_row(program, cpu)
        for program in results.programs
        for cpu in program.integration.cpu
    ]
    lines += [
        (
            "CPU: Home Assistant's event-loop thread from the start of a coordinator "
            "refresh until idle (the client's HTTP and JSON work included; the simulated "
            "PLC runs on another thread); entity updates: the part spent telling entities "
            "and writing their states; transport floor: the same requests the poll "
            "sent, alone (its GetObject requests, and the GetInfo a quiet poll reads "
            "to see that the program still runs; HTTP, Digest, JSON decoding, as the "
            "client does them), which any client pays; in brackets its GetObject "
            "requests alone; ours / floor: our whole poll against it. Changing: "
            "the share of values changed before each poll (values per poll, on "
            "average: 1 % of 50 is one value every second poll). Means per poll."
        ),
        "",
    ]
    lines += markdown_table(
        [
            "program",
            "entities",
            "changing",
            "state writes ours",
            "state writes baseline",
            "CPU ms ours",
            "CPU ms baseline",
            "ours / baseline",
            "entity updates CPU ms ours / baseline",
            "ours / baseline (updates)",
            "transport floor CPU ms (GetObject alone)",
            "ours / floor",
            "poll ms",
        ],
        rows,
    )
    zero = _at_percent(results.programs, 0)
    if zero:
        lines += [
            "",
            (
                "### Whole poll against the transport floor, 0 % changing "
                f"(target ≤ {FLOOR_TARGET}×)"
            ),
            "",
        ]
        lines += markdown_table(
            [
                "program",
                "whole poll CPU ms",
                "transport floor CPU ms",
                "of it GetObject alone",
                "ours / floor",
                "met",
            ],
            [
                [
                    label,
                    _fmt(cpu.ours.cpu_ms, 2),
                    _fmt(cpu.transport_cpu_ms, 2),
                    _fmt(cpu.get_object_cpu_ms, 2),
                    f"{cpu.floor_ratio:.2f}×",
                    "yes" if floor_target([(label, cpu)]).met else "**no**",
                ]
                for label, cpu in zero
            ],
        )
    lines += ["", "### Discovery, memory, write latency", ""]
    rows = []
    for program in results.programs:
        integration = program.integration
        memory, write = integration.memory, integration.write
        rows.append(
            [
                program.label,
                f"{integration.discovery.requests}",
                _fmt(integration.discovery.ms, 0),
                f"{integration.discovery.entities}",
                f"{memory.per_thousand(memory.traced_bytes):.1f}",
                f"{memory.per_thousand(memory.peak_resident_growth_bytes):.1f}",
                "-"
                if write is None
                else f"{_fmt(write.shown_requests)} / {_fmt(write.shown_ms, 0)} ms",
                "-"
                if write is None
                else f"{_fmt(write.call_requests)} / {_fmt(write.call_ms, 0)} ms",
            ]
        )
    lines += markdown_table(
        [
            "program",
            "discovery requests",
            "discovery ms",
            "entities",
            "heap MiB / 1000 entities",
            "peak RSS growth MiB / 1000 entities",
            "write → entity shows (requests / ms)",
            "write → call returns (requests / ms)",
        ],
        rows,
    )
    lines += ["", "### Targets (issues 6 and 41)", ""]
    lines += markdown_table(
        ["target", "met", "measured"],
        [
            [
                target.name,
                "n/a" if target.met is None else ("yes" if target.met else "**no**"),
                target.measured,
            ]
            for target in evaluate_targets(results)
        ],
    )
    return "\n".join(lines) + "\n"


def write_json(results: BenchResults, path: Path) -> None:
    """Write every figure, the settings, the machine and the targets to `path`."""
    data = results.as_dict()
    data["targets"] = [asdict(target) for target in evaluate_targets(results)]
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(data, indent=2, ensure_ascii=False) + "\n")
