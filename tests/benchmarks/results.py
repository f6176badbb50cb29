"""What one benchmark run measured, and the settings it ran with."""

from dataclasses import asdict, dataclass, field
from typing import Any

from .integration import IntegrationFigures
from .polling import PollingFigures


@dataclass(frozen=True, slots=True, kw_only=True)
class BenchSettings:
    """The knobs of a run (see `python -m tests.benchmarks --help`)."""

    programs: tuple[str, ...]
    latency_ms: float
    per_item_ms: float
    polls: int
    peer_polls: int
    percents: tuple[float, ...]
    write_samples: int
    seed: int


@dataclass(frozen=True, slots=True, kw_only=True)
class ProgramResult:
    """Client-level and Home Assistant figures for one program."""

    label: str
    polling: PollingFigures
    integration: IntegrationFigures


@dataclass(slots=True, kw_only=True)
class BenchResults:
    """A whole run: the machine, the settings, each program's figures."""

    machine: dict[str, Any]
    settings: BenchSettings
    programs: list[ProgramResult] = field(default_factory=list)
    seconds: float = 0.0

    def by_label(self, label: str) -> ProgramResult | None:
        """The figures of one program, if it ran."""
        return next((p for p in self.programs if p.label == label), None)

    def as_dict(self) -> dict[str, Any]:
        """Everything, JSON-serialisable (ratios included)."""
        programs = {}
        for program in self.programs:
            entry = asdict(program)
            entry["polling"]["request_ratio"] = program.polling.request_ratio
            entry["polling"]["time_ratio"] = program.polling.time_ratio
            for cpu, figures in zip(
                entry["integration"]["cpu"], program.integration.cpu, strict=True
            ):
                cpu["cpu_ratio"] = figures.cpu_ratio
                cpu["update_cpu_ratio"] = figures.update_cpu_ratio
                cpu["floor_ratio"] = figures.floor_ratio
            memory = program.integration.memory
            entry["integration"]["memory"]["traced_mib_per_1000_entities"] = (
                memory.per_thousand(memory.traced_bytes)
            )
            entry["integration"]["memory"]["peak_rss_growth_mib_per_1000_entities"] = (
                memory.per_thousand(memory.peak_resident_growth_bytes)
            )
            programs[program.label] = entry
        return {
            "machine": self.machine,
            "settings": asdict(self.settings),
            "seconds": self.seconds,
            "programs": programs,
        }
