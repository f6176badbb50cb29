"""The soak run (`scripts/bench soak`): thousands of polls with random faults.

A real Home Assistant polls a simulated device through the integration's
coordinator (every entity enabled) while, between polls, the device changes
values and faults are switched on at random, one at a time, each for one to
three polls; now and then a `number.set_value` call writes a value. One engine
runs every source; a per-source adapter (:class:`SoakAdapter`, the sources in
:mod:`.soak_sources`) starts the source's simulator, makes its entry, changes
its values, switches each of its documented faults on and off, and tells what
the device holds and how many writes it applied.

After every good poll each value the coordinator reports is compared with what
the device holds; a write that returned without error must be held by the
device and applied once (not lost, not doubled). After each fault the entities
must come back: every entity available before the faults is available again
within a few polls of the fault's end, and the fault's log lines are counted
(the integration logs an outage once, and its end once). It reports, per
source, cycles, faults by kind, failed polls, recoveries, wrong values, lost
and doubled writes, log lines per fault, and resident memory, Python heap
blocks and asyncio tasks at start and end.
"""

from abc import ABC, abstractmethod
import argparse
import asyncio
from collections import Counter, deque
from collections.abc import Awaitable, Callable
from dataclasses import asdict, dataclass, field
from datetime import datetime
import gc
import json
import logging
import math
from pathlib import Path
import random
import sys
import time
from typing import Any, ClassVar, Final

from homeassistant.components.number import (
    ATTR_VALUE,
    DOMAIN as NUMBER_DOMAIN,
)
from homeassistant.components.number.const import SERVICE_SET_VALUE
from homeassistant.const import ATTR_ENTITY_ID, STATE_UNAVAILABLE
from homeassistant.core import HomeAssistant
from homeassistant.exceptions import HomeAssistantError
from homeassistant.helpers import entity_registry as er
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.tecoapi.coordinator import PlcCoordinator
from custom_components.tecoapi.pyplc import Point, ValueKind

from .home_assistant import all_entities_enabled, bench_home_assistant
from .machine import machine_info, resident_memory
from .programs import parse_program_labels

DEFAULT_OUTPUT: Final = Path("bench-results/soak.json")
SOURCES: Final = ("tecoapi", "mervis", "fpi4c", "tekon", "plccoms")
RECOVERY_POLLS: Final = 3
"""Good polls after a fault's end within which every entity must be back."""
LOG_EXAMPLES: Final = 6
"""Log lines of a fault shown in the report (of its first time)."""
UNCHECKED: Final = object()
"""What :meth:`SoakAdapter.held` answers for a value the soak does not compare."""

type EndFault = Callable[[], Awaitable[None]]


@dataclass(frozen=True, slots=True, kw_only=True)
class SoakSettings:
    """The knobs of a soak run (see `scripts/bench soak --help`)."""

    program: str
    cycles: int
    fault_rate: float
    change_percent: float
    write_rate: float
    latency_ms: float
    seed: int
    source: str = "tecoapi"


@dataclass(slots=True, kw_only=True)
class SoakResults:
    """What a soak run of one source saw."""

    settings: SoakSettings
    machine: dict[str, Any]
    source: str = "tecoapi"
    device: str = ""
    entities: int = 0
    cycles: int = 0
    faults: Counter[str] = field(default_factory=Counter)
    failed_polls: int = 0
    recoveries: int = 0
    faults_recovered: int = 0
    faults_not_recovered: int = 0
    not_recovered_examples: list[str] = field(default_factory=list)
    fault_log_lines: dict[str, list[int]] = field(default_factory=dict)
    fault_log_examples: dict[str, list[str]] = field(default_factory=dict)
    values_checked: int = 0
    wrong_values: int = 0
    wrong_examples: list[str] = field(default_factory=list)
    missing_values: int = 0
    writes: int = 0
    writes_skipped: int = 0
    writes_refused: int = 0
    writes_lost: int = 0
    writes_doubled: int = 0
    requests: int = 0
    extras: Counter[str] = field(default_factory=Counter)
    unhandled_exceptions: int = 0
    integration_log: Counter[str] = field(default_factory=Counter)
    resident_start: int = 0
    resident_end: int = 0
    heap_blocks_start: int = 0
    heap_blocks_end: int = 0
    tasks_start: int = 0
    tasks_end: int = 0
    tasks_after_unload: int = 0
    seconds: float = 0.0

    @property
    def bad(self) -> int:
        """Everything that must be zero."""
        return (
            self.wrong_values
            + self.writes_lost
            + self.writes_doubled
            + self.unhandled_exceptions
            + self.faults_not_recovered
        )

    def as_dict(self) -> dict[str, Any]:
        """Everything, JSON-serialisable."""
        data = asdict(self)
        # asdict rebuilds a Counter from (key, count) pairs, counting the pairs.
        for name in ("faults", "integration_log", "extras"):
            data[name] = dict(getattr(self, name))
        return data


class SoakAdapter(ABC):
    """What the engine needs of one source: its device, entry, values and faults."""

    source: ClassVar[str]
    faults: ClassVar[tuple[str, ...]]
    """The faults it switches on (the simulator's documented ones)."""

    def __init__(self, settings: SoakSettings) -> None:
        """Prepare the device; nothing runs until :meth:`start`."""
        self.settings = settings
        self.extras: Counter[str] = Counter()
        """Source-specific figures for the report (Digest challenges, ...)."""

    @property
    @abstractmethod
    def device(self) -> str:
        """What the soak polls, for the report (a program, a project, a map)."""

    @abstractmethod
    async def start(self) -> None:
        """Start the simulator."""

    @abstractmethod
    async def stop(self) -> None:
        """Stop the simulator (idempotent)."""

    @abstractmethod
    async def entry(self, hass: HomeAssistant) -> MockConfigEntry:
        """The config entry of the device, as its config flow stores it."""

    def prepare(self, coordinator: PlcCoordinator, rng: random.Random) -> None:  # noqa: B027
        """Learn the device's points once the entry is set up (default: nothing)."""

    @abstractmethod
    def change(self, rng: random.Random) -> None:
        """Change a share of the device's values, as its program would."""

    @abstractmethod
    async def inject(self, fault: str, rng: random.Random) -> EndFault | None:
        """Switch a fault on; return what switches it off (None: it ends by itself)."""

    async def before_poll(self) -> None:  # noqa: B027
        """What the device does just before a poll (default: nothing)."""

    async def after_fault(self, coordinator: PlcCoordinator) -> None:  # noqa: B027
        """Wait for what a source does by itself after a fault (default: nothing)."""

    @abstractmethod
    def held(self, point: Point) -> Any:
        """The value the device holds for a point as the source shows it, or UNCHECKED."""

    @abstractmethod
    def settle(self) -> tuple[int, int]:
        """Requests and applied writes since the last call; forget their records."""


@dataclass(slots=True)
class _Episode:
    """A fault switched on: until its end, then until the entities are back."""

    kind: str
    polls_left: int
    end: EndFault | None
    log_start: int
    polls_after: int = 0
    ended: bool = False


class _LogCounter(logging.Handler):
    """Counts the integration's log records by level (and keeps them off the screen).

    The last few lines are kept, to show what a fault logged.
    """

    def __init__(self, counts: Counter[str]) -> None:
        super().__init__(logging.DEBUG)
        self.counts = counts
        self.last: deque[str] = deque(maxlen=LOG_EXAMPLES)

    def emit(self, record: logging.LogRecord) -> None:
        self.counts[record.levelname] += 1
        if record.levelno >= logging.INFO:
            self.last.append(f"{record.levelname} {record.getMessage()}"[:160])


def _measure(results: SoakResults, *, start: bool) -> None:
    gc.collect()
    resident, blocks, tasks = (
        resident_memory(),
        sys.getallocatedblocks(),
        len(asyncio.all_tasks()),
    )
    if start:
        results.resident_start, results.heap_blocks_start = resident, blocks
        results.tasks_start = tasks
    else:
        results.resident_end, results.heap_blocks_end = resident, blocks
        results.tasks_end = tasks


def same_value(reported: Any, held: Any) -> bool:
    """Whether a reported value is the one held (numbers to a float's precision)."""
    numbers = (int, float)
    if (
        isinstance(reported, numbers)
        and isinstance(held, numbers)
        and not isinstance(reported, bool)
        and not isinstance(held, bool)
    ):
        return math.isclose(reported, held, rel_tol=1e-6, abs_tol=1e-6)
    if isinstance(reported, datetime) and isinstance(held, datetime):
        # PLCComS tells a DT to the second (the simulator's README).
        return reported.replace(microsecond=0) == held.replace(microsecond=0)
    return reported == held and type(reported) is type(held)


def _check_values(
    adapter: SoakAdapter, coordinator: PlcCoordinator, results: SoakResults
) -> None:
    """Compare every reported value with the device's; count what differs."""
    data = coordinator.data
    for key in coordinator.polled_keys:
        point = data.points[key]
        if not data.point_available(key):
            # Not shown: bad quality, or its device (a station) offline.
            results.missing_values += 1
            continue
        held = adapter.held(point)
        if held is UNCHECKED:
            continue
        results.values_checked += 1
        reported = data.values.get(key)
        if not same_value(reported, held):
            results.wrong_values += 1
            if len(results.wrong_examples) < 10:
                results.wrong_examples.append(
                    f"{point.path}: reported {reported!r}, the device holds {held!r}"
                )


def _writable_numbers(
    hass: HomeAssistant, entry: MockConfigEntry, coordinator: PlcCoordinator
) -> list[tuple[str, Point]]:
    """The number entities of single points, with their points."""
    prefix = f"{coordinator.data.info.identity}_"
    numbers = []
    for registry_entry in er.async_entries_for_config_entry(
        er.async_get(hass), entry.entry_id
    ):
        key = registry_entry.unique_id.removeprefix(prefix)
        point = coordinator.data.points.get(key)
        if registry_entry.domain == NUMBER_DOMAIN and point and point.attributes:
            numbers.append((registry_entry.entity_id, point))
    return numbers


def _value_to_write(point: Point, rng: random.Random) -> float:
    """A random value within the point's range (0 to 100 without one)."""
    assert point.attributes is not None
    low = point.attributes.minimum
    high = point.attributes.maximum
    low = 0.0 if low is None else low
    high = 100.0 if high is None else high
    if point.kind is ValueKind.INTEGER and point.scale == 1:
        return rng.randint(math.ceil(low), math.floor(high))
    return round(rng.uniform(low, high), 1)


async def _write(
    hass: HomeAssistant,
    adapter: SoakAdapter,
    number: tuple[str, Point],
    rng: random.Random,
    results: SoakResults,
) -> None:
    """Write a random in-range value: held by the device, applied once, if it returns."""
    entity_id, point = number
    state = hass.states.get(entity_id)
    if state is None or state.state == STATE_UNAVAILABLE:
        # Home Assistant skips a service call on an unavailable entity (with a
        # warning) and returns: that is not a write, lost or otherwise.
        results.writes_skipped += 1
        return
    value = _value_to_write(point, rng)
    results.requests += adapter.settle()[0]
    results.writes += 1
    try:
        await hass.services.async_call(
            NUMBER_DOMAIN,
            SERVICE_SET_VALUE,
            {ATTR_ENTITY_ID: entity_id, ATTR_VALUE: value},
            blocking=True,
        )
    except HomeAssistantError:
        results.requests += adapter.settle()[0]
        results.writes_refused += 1
        return
    requests, applied = adapter.settle()
    results.requests += requests
    if applied > 1:
        results.writes_doubled += 1
    held = adapter.held(point)
    if held is not UNCHECKED and not same_value(float(held), float(value)):
        results.writes_lost += 1


def _unavailable(hass: HomeAssistant, entity_ids: set[str]) -> set[str]:
    """The entities among ``entity_ids`` that are unavailable (or gone)."""
    return {
        entity_id
        for entity_id in entity_ids
        if (state := hass.states.get(entity_id)) is None
        or state.state == STATE_UNAVAILABLE
    }


async def run_soak(settings: SoakSettings) -> SoakResults:
    """Run the soak of one source and return what it saw."""
    from .soak_sources import ADAPTERS  # they import this module: here, not above

    adapter = ADAPTERS[settings.source](settings)
    rng = random.Random(settings.seed)
    results = SoakResults(
        settings=settings, machine=machine_info(), source=settings.source
    )
    log_counter = _LogCounter(results.integration_log)
    integration_logger = logging.getLogger("custom_components.tecoapi")
    integration_logger.addHandler(log_counter)
    integration_logger.propagate = False
    integration_level = integration_logger.level
    integration_logger.setLevel(logging.INFO)
    loop = asyncio.get_running_loop()
    exception_handler = loop.get_exception_handler()

    def count_exception(loop: asyncio.AbstractEventLoop, context: Any) -> None:
        results.unhandled_exceptions += 1

    loop.set_exception_handler(count_exception)
    started = time.perf_counter()
    await adapter.start()
    results.device = adapter.device
    try:
        async with bench_home_assistant() as hass:
            entry = await adapter.entry(hass)
            entry.add_to_hass(hass)
            with all_entities_enabled():
                await hass.config_entries.async_setup(entry.entry_id)
                await hass.async_block_till_done()
            coordinator: PlcCoordinator = entry.runtime_data
            results.entities = len(
                er.async_entries_for_config_entry(er.async_get(hass), entry.entry_id)
            )
            await adapter.before_poll()
            await coordinator.async_refresh()
            await hass.async_block_till_done()
            adapter.prepare(coordinator, rng)
            await _soak(
                hass,
                adapter,
                entry=entry,
                coordinator=coordinator,
                rng=rng,
                results=results,
                log=log_counter,
            )
            _measure(results, start=False)
            await hass.config_entries.async_unload(entry.entry_id)
            await hass.async_block_till_done()
            results.tasks_after_unload = len(asyncio.all_tasks())
    finally:
        await adapter.stop()
        loop.set_exception_handler(exception_handler)
        integration_logger.removeHandler(log_counter)
        integration_logger.propagate = True
        integration_logger.setLevel(integration_level)
    results.requests += adapter.settle()[0]
    results.extras.update(adapter.extras)
    results.seconds = time.perf_counter() - started
    return results


async def _soak(
    hass: HomeAssistant,
    adapter: SoakAdapter,
    *,
    entry: MockConfigEntry,
    coordinator: PlcCoordinator,
    rng: random.Random,
    results: SoakResults,
    log: _LogCounter,
) -> None:
    settings = results.settings
    numbers = _writable_numbers(hass, entry, coordinator)
    # The entities to come back after every fault: those shown before any.
    shown = {
        registry_entry.entity_id
        for registry_entry in er.async_entries_for_config_entry(
            er.async_get(hass), entry.entry_id
        )
    }
    shown -= _unavailable(hass, shown)
    results.requests += adapter.settle()[0]
    _measure(results, start=True)
    previous_ok = True
    episode: _Episode | None = None
    for _ in range(settings.cycles):
        results.cycles += 1
        adapter.change(rng)
        if episode is None and rng.random() < settings.fault_rate:
            kind = rng.choice(adapter.faults)
            results.faults[kind] += 1
            episode = _Episode(
                kind=kind,
                polls_left=rng.randint(1, 3),
                end=await adapter.inject(kind, rng),
                log_start=_logged(results),
            )
        # Each write starts outside the refresh debouncer's cooldown.
        coordinator._debounced_refresh.async_cancel()
        if numbers and rng.random() < settings.write_rate:
            await _write(hass, adapter, rng.choice(numbers), rng, results)
        await adapter.before_poll()
        await coordinator.async_refresh()
        await hass.async_block_till_done()
        results.requests += adapter.settle()[0]
        ok = coordinator.last_update_success
        if ok:
            _check_values(adapter, coordinator, results)
            results.recoveries += not previous_ok
        else:
            results.failed_polls += 1
        previous_ok = ok
        if episode is not None and await _follow_episode(
            hass, adapter, coordinator, episode, shown, results, log, ok=ok
        ):
            episode = None
    if episode is not None and episode.end is not None and not episode.ended:
        await episode.end()


async def _follow_episode(  # noqa: PLR0917 (the episode's parts)
    hass: HomeAssistant,
    adapter: SoakAdapter,
    coordinator: PlcCoordinator,
    episode: _Episode,
    shown: set[str],
    results: SoakResults,
    log: _LogCounter,
    *,
    ok: bool,
) -> bool:
    """End a fault after its polls; then see the entities back. Whether it is over."""
    if not episode.ended:
        episode.polls_left -= 1
        if episode.polls_left > 0:
            return False
        if episode.end is not None:
            await episode.end()
        episode.ended = True
        await adapter.after_fault(coordinator)
        return False
    episode.polls_after += 1
    down = _unavailable(hass, shown)
    if ok and not down:
        results.faults_recovered += 1
    elif episode.polls_after >= RECOVERY_POLLS:
        results.faults_not_recovered += 1
        if len(results.not_recovered_examples) < 10:
            results.not_recovered_examples.append(
                f"{episode.kind}: {'poll failing' if not ok else ''} "
                f"{len(down)} entities down ({', '.join(sorted(down)[:3])})"
            )
    else:
        return False
    lines = _logged(results) - episode.log_start
    results.fault_log_lines.setdefault(episode.kind, []).append(lines)
    if lines and episode.kind not in results.fault_log_examples:
        results.fault_log_examples[episode.kind] = list(log.last)[-lines:]
    return True


def _logged(results: SoakResults) -> int:
    """The integration's log records so far (INFO and above)."""
    log = results.integration_log
    return log.total() - log["DEBUG"]


def report(results: SoakResults) -> str:
    """The soak's figures as markdown."""
    mib = 2**20
    settings = results.settings
    lines_per_fault = ", ".join(
        f"{kind} {sum(lines)}/{len(lines)} (max {max(lines)})"
        for kind, lines in sorted(results.fault_log_lines.items())
    )
    rows = [
        ("device", f"{results.device} ({results.entities} entities)"),
        ("cycles (polls)", f"{results.cycles}"),
        (
            "faults injected",
            f"{results.faults.total()} ("
            + ", ".join(f"{k} {v}" for k, v in sorted(results.faults.items()))
            + ")",
        ),
        ("failed polls", f"{results.failed_polls}"),
        ("recoveries (failed → good poll)", f"{results.recoveries}"),
        (
            (
                "faults with every entity back (not back within "
                f"{RECOVERY_POLLS} polls of the end)"
            ),
            f"{results.faults_recovered} ({results.faults_not_recovered})",
        ),
        (
            "log lines per fault: lines/faults (max one fault)",
            lines_per_fault or "no fault",
        ),
        ("values checked against the device", f"{results.values_checked}"),
        ("wrong values reported", f"{results.wrong_values}"),
        ("values not shown (unavailable)", f"{results.missing_values}"),
        (
            "writes (raised an error / lost silently / applied twice)",
            (
                f"{results.writes} ({results.writes_refused} / {results.writes_lost}"
                f" / {results.writes_doubled})"
            ),
        ),
        (
            "writes not attempted (entity unavailable)",
            f"{results.writes_skipped}",
        ),
        ("requests", f"{results.requests}"),
        *((name, f"{count}") for name, count in sorted(results.extras.items())),
        ("unhandled exceptions", f"{results.unhandled_exceptions}"),
        (
            "integration log records",
            ", ".join(f"{k} {v}" for k, v in sorted(results.integration_log.items()))
            or "none",
        ),
        (
            "resident memory start → end",
            f"{results.resident_start / mib:.1f} → {results.resident_end / mib:.1f} MiB",
        ),
        (
            "Python heap blocks start → end",
            f"{results.heap_blocks_start} → {results.heap_blocks_end}",
        ),
        (
            "asyncio tasks start → end (after unload)",
            (
                f"{results.tasks_start} → {results.tasks_end} "
                f"({results.tasks_after_unload})"
            ),
        ),
        ("wall time", f"{results.seconds:.0f} s"),
    ]
    machine = results.machine
    lines = [
        f"## Soak run: {results.source}",
        "",
        (
            f"Machine: {machine['cpu']}, {machine['cores']} cores; Python "
            f"{machine['python']}, Home Assistant {machine['homeassistant']}. Fault rate "
            f"{settings.fault_rate:.0%} of cycles, {settings.change_percent:g} % of values "
            f"changing per cycle, writes in {settings.write_rate:.0%} of cycles, latency "
            f"{settings.latency_ms:g} ms, seed {settings.seed}."
        ),
        "",
        "| figure | value |",
        "|---|---:|",
        *(f"| {name} | {value} |" for name, value in rows),
    ]
    lines += [f"- {example}" for example in results.wrong_examples]
    lines += [f"- not back: {example}" for example in results.not_recovered_examples]
    lines += [
        f"- {kind} logged: " + " / ".join(logged)
        for kind, logged in sorted(results.fault_log_examples.items())
    ]
    return "\n".join(lines) + "\n"


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="scripts/bench soak",
        description="Soak run: thousands of coordinator polls with random faults.",
    )
    parser.add_argument(
        "--source",
        choices=(*SOURCES, "all"),
        default="tecoapi",
        help="the source soaked, or all of them one after another (default tecoapi)",
    )
    parser.add_argument(
        "--program",
        default="300",
        help="TecoApi and PLCComS: a point count or a shipped program (default 300)",
    )
    parser.add_argument("--cycles", type=int, default=3000, help="polls (default 3000)")
    parser.add_argument(
        "--fault-rate",
        type=float,
        default=0.05,
        help="share of cycles that switch a fault on (default 0.05)",
    )
    parser.add_argument(
        "--change-percent",
        type=float,
        default=5.0,
        help="percent of values the device changes each cycle (default 5)",
    )
    parser.add_argument(
        "--write-rate",
        type=float,
        default=0.02,
        help="share of cycles with a number.set_value write (default 0.02)",
    )
    parser.add_argument(
        "--latency-ms",
        type=float,
        default=0.0,
        help="TecoApi: PLC latency per request in ms (default 0: as many polls "
        "as possible)",
    )
    parser.add_argument("--seed", type=int, default=0, help="random seed")
    parser.add_argument(
        "--output",
        type=Path,
        default=DEFAULT_OUTPUT,
        help=f"JSON results file (default {DEFAULT_OUTPUT})",
    )
    return parser


def main(argv: list[str]) -> int:
    """Run the soak, print its report, write its JSON; non-zero if anything was wrong."""
    args = _parser().parse_args(argv)
    (program,) = parse_program_labels(args.program)
    if args.cycles < 1:
        raise SystemExit("--cycles must be at least 1")
    logging.basicConfig(level=logging.WARNING, format="%(asctime)s %(message)s")
    logging.getLogger("homeassistant.loader").setLevel(logging.ERROR)
    sources = SOURCES if args.source == "all" else (args.source,)
    every: list[SoakResults] = []
    for source in sources:
        settings = SoakSettings(
            program=program,
            cycles=args.cycles,
            fault_rate=args.fault_rate,
            change_percent=args.change_percent,
            write_rate=args.write_rate,
            latency_ms=args.latency_ms,
            seed=args.seed,
            source=source,
        )
        results = asyncio.run(run_soak(settings))
        print(report(results))
        every.append(results)
    args.output.parent.mkdir(parents=True, exist_ok=True)
    figures: Any = (
        every[0].as_dict()
        if len(every) == 1
        else {results.source: results.as_dict() for results in every}
    )
    args.output.write_text(json.dumps(figures, indent=2) + "\n")
    print(f"Figures written to {args.output}")
    return 1 if any(results.bad for results in every) else 0
