"""The soak run (`scripts/bench soak`): thousands of polls with random faults.

A real Home Assistant polls a simulated PLC through the integration's coordinator
(every entity enabled) while, between polls, the PLC's program changes values and
faults are switched on at random: HTTP 500, dropped connections, truncated and
malformed JSON (each for 1-3 requests), latency spikes, and Digest nonces that go
stale every few dozen uses. Now and then a `number.set_value` call writes a value.
After every poll each value the coordinator reports is compared with what the PLC
holds; a write that returned without error must be held by the PLC. It reports
cycles, faults, failed polls, recoveries, wrong values, lost writes, and resident
memory, Python heap blocks and asyncio tasks at start and end.
"""

import argparse
import asyncio
from collections import Counter
from dataclasses import asdict, dataclass, field
import gc
import json
import logging
from pathlib import Path
import random
import sys
import time
from typing import Any, Final

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

from custom_components.tecoapi.coordinator import TecoApiCoordinator
from custom_components.tecoapi.pyplc import Point, ValueKind
from custom_components.tecoapi.pyplc.core.values import parse_value
from custom_components.tecoapi.pyplc.tecomat.points import value_path
from tests.simulator import Simulator

from .changes import ValueChanger, changed_count
from .home_assistant import all_entities_enabled, bench_entry, bench_home_assistant
from .machine import machine_info, resident_memory
from .programs import bench_program, parse_program_labels

DEFAULT_OUTPUT: Final = Path("bench-results/soak.json")
USERNAME: Final = "soak"
PASSWORD: Final = "soak-Pa55word"
TRANSPORT_FAULTS: Final = (
    "http_500",
    "drop_connection",
    "truncated_json",
    "malformed_json",
)
FAULTS: Final = (*TRANSPORT_FAULTS, "latency_spike")
LATENCY_SPIKE: Final = 0.2
NONCE_MAX_USES: Final = 40


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


@dataclass(slots=True, kw_only=True)
class SoakResults:
    """What a soak run saw."""

    settings: SoakSettings
    machine: dict[str, Any]
    entities: int = 0
    cycles: int = 0
    faults: Counter[str] = field(default_factory=Counter)
    failed_polls: int = 0
    recoveries: int = 0
    values_checked: int = 0
    wrong_values: int = 0
    wrong_examples: list[str] = field(default_factory=list)
    missing_values: int = 0
    availability_mismatches: int = 0
    writes: int = 0
    writes_skipped: int = 0
    writes_refused: int = 0
    writes_lost: int = 0
    challenges: int = 0
    requests: int = 0
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

    def as_dict(self) -> dict[str, Any]:
        """Everything, JSON-serialisable."""
        data = asdict(self)
        # asdict rebuilds a Counter from (key, count) pairs, counting the pairs.
        data["faults"] = dict(self.faults)
        data["integration_log"] = dict(self.integration_log)
        return data


class _LogCounter(logging.Handler):
    """Counts the integration's log records by level (and keeps them off the screen)."""

    def __init__(self, counts: Counter[str]) -> None:
        super().__init__(logging.DEBUG)
        self.counts = counts

    def emit(self, record: logging.LogRecord) -> None:
        self.counts[record.levelname] += 1


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


def _inject(simulator: Simulator, rng: random.Random, results: SoakResults) -> None:
    """Switch one random fault on."""
    fault = rng.choice(FAULTS)
    results.faults[fault] += 1
    if fault == "latency_spike":
        simulator.faults.latency = LATENCY_SPIKE
        return
    setattr(simulator.faults, fault, True)
    simulator.faults.remaining = rng.randint(1, 3)


def _check_values(
    simulator: Simulator, coordinator: TecoApiCoordinator, results: SoakResults
) -> None:
    """Compare every reported value with the PLC's; count what differs."""
    data = coordinator.data
    for key in coordinator.polled_keys:
        point = coordinator.data.points[key]
        if key in data.missing:
            results.missing_values += 1
            continue
        results.values_checked += 1
        held = parse_value(point.kind, simulator.get_value(value_path(point)))
        reported = data.values.get(key)
        if reported != held or type(reported) is not type(held):
            results.wrong_values += 1
            if len(results.wrong_examples) < 10:
                results.wrong_examples.append(
                    f"{point.path}: reported {reported!r}, PLC holds {held!r}"
                )


def _count_requests(simulator: Simulator, results: SoakResults) -> None:
    """Count the PLC's requests so far and forget them (their records use memory)."""
    results.requests += len(simulator.requests)
    results.challenges += sum(
        1 for record in simulator.requests if record.status == 401
    )
    simulator.clear_requests()


def _writable_numbers(
    hass: HomeAssistant, entry: MockConfigEntry, coordinator: TecoApiCoordinator
) -> list[tuple[str, Point]]:
    prefix = f"{entry.unique_id}_"
    numbers = []
    for registry_entry in er.async_entries_for_config_entry(
        er.async_get(hass), entry.entry_id
    ):
        key = registry_entry.unique_id.removeprefix(prefix)
        point = coordinator.data.points.get(key)
        if registry_entry.domain == NUMBER_DOMAIN and point and point.attributes:
            numbers.append((registry_entry.entity_id, point))
    return numbers


async def _write(
    hass: HomeAssistant,
    simulator: Simulator,
    number: tuple[str, Point],
    rng: random.Random,
    results: SoakResults,
) -> None:
    """Write a random in-range value; a write that returns must be held by the PLC."""
    entity_id, point = number
    assert point.attributes is not None
    state = hass.states.get(entity_id)
    if state is None or state.state == STATE_UNAVAILABLE:
        # Home Assistant skips a service call on an unavailable entity (with a
        # warning) and returns: that is not a write, lost or otherwise.
        results.writes_skipped += 1
        return
    low, high = point.attributes.minimum, point.attributes.maximum
    assert low is not None
    assert high is not None
    value: float = (
        rng.randint(int(low), int(high))
        if point.kind is ValueKind.INTEGER
        else round(rng.uniform(low, high), 1)
    )
    results.writes += 1
    try:
        await hass.services.async_call(
            NUMBER_DOMAIN,
            SERVICE_SET_VALUE,
            {ATTR_ENTITY_ID: entity_id, ATTR_VALUE: value},
            blocking=True,
        )
    except HomeAssistantError:
        results.writes_refused += 1
        return
    if float(simulator.get_value(value_path(point))) != float(value):
        results.writes_lost += 1


async def run_soak(settings: SoakSettings) -> SoakResults:
    """Run the soak and return what it saw."""
    rng = random.Random(settings.seed)
    results = SoakResults(settings=settings, machine=machine_info())
    log_counter = _LogCounter(results.integration_log)
    integration_logger = logging.getLogger("custom_components.tecoapi")
    integration_logger.addHandler(log_counter)
    integration_logger.propagate = False
    integration_level = integration_logger.level
    integration_logger.setLevel(logging.INFO)
    loop = asyncio.get_running_loop()

    def count_exception(loop: asyncio.AbstractEventLoop, context: Any) -> None:
        results.unhandled_exceptions += 1

    loop.set_exception_handler(count_exception)
    started = time.perf_counter()
    simulator = Simulator(
        bench_program(settings.program, seed=settings.seed).program,
        username=USERNAME,
        password=PASSWORD,
        nonce_max_uses=NONCE_MAX_USES,
    )
    await simulator.start()
    try:
        async with bench_home_assistant() as hass:
            entry = bench_entry(
                simulator.url, USERNAME, PASSWORD, simulator.serial_number
            )
            entry.add_to_hass(hass)
            with all_entities_enabled():
                await hass.config_entries.async_setup(entry.entry_id)
                await hass.async_block_till_done()
            coordinator: TecoApiCoordinator = entry.runtime_data
            results.entities = len(
                er.async_entries_for_config_entry(er.async_get(hass), entry.entry_id)
            )
            await coordinator.async_refresh()
            await hass.async_block_till_done()
            await _soak(
                hass,
                simulator,
                entry=entry,
                coordinator=coordinator,
                rng=rng,
                results=results,
            )
            _measure(results, start=False)
            await hass.config_entries.async_unload(entry.entry_id)
            await hass.async_block_till_done()
            results.tasks_after_unload = len(asyncio.all_tasks())
    finally:
        await simulator.stop()
        integration_logger.removeHandler(log_counter)
        integration_logger.propagate = True
        integration_logger.setLevel(integration_level)
    _count_requests(simulator, results)
    results.seconds = time.perf_counter() - started
    return results


async def _soak(
    hass: HomeAssistant,
    simulator: Simulator,
    *,
    entry: MockConfigEntry,
    coordinator: TecoApiCoordinator,
    rng: random.Random,
    results: SoakResults,
) -> None:
    settings = results.settings
    changer = ValueChanger(coordinator.data.points.values(), seed=settings.seed)
    count = min(
        changer.changeable,
        changed_count(len(coordinator.data.points), settings.change_percent),
    )
    numbers = _writable_numbers(hass, entry, coordinator)
    probe = numbers[0] if numbers else None
    latency = settings.latency_ms / 1000
    simulator.faults.latency = latency
    _count_requests(simulator, results)
    _measure(results, start=True)
    previous_ok = True
    for _ in range(settings.cycles):
        results.cycles += 1
        simulator.faults.latency = latency
        changer.change(simulator, count)
        if rng.random() < settings.fault_rate:
            _inject(simulator, rng, results)
        # Each write starts outside the refresh debouncer's cooldown.
        coordinator._debounced_refresh.async_cancel()
        if numbers and rng.random() < settings.write_rate:
            await _write(hass, simulator, rng.choice(numbers), rng, results)
        await coordinator.async_refresh()
        await hass.async_block_till_done()
        _count_requests(simulator, results)
        ok = coordinator.last_update_success
        if ok:
            _check_values(simulator, coordinator, results)
            results.recoveries += not previous_ok
        else:
            results.failed_polls += 1
        if probe is not None:
            state = hass.states.get(probe[0])
            unavailable = state is None or state.state == STATE_UNAVAILABLE
            attributes = coordinator.data.point_attributes(probe[1].key)
            point_down = probe[1].key in coordinator.data.missing or not (
                attributes is None or attributes.enabled
            )
            if unavailable != (not ok or point_down):
                results.availability_mismatches += 1
        previous_ok = ok
    simulator.faults.clear()


def report(results: SoakResults) -> str:
    """The soak's figures as markdown."""
    mib = 2**20
    settings = results.settings
    rows = [
        ("program", f"{settings.program} ({results.entities} entities)"),
        ("cycles (polls)", f"{results.cycles}"),
        (
            "faults injected",
            f"{results.faults.total()} ("
            + ", ".join(f"{k} {v}" for k, v in sorted(results.faults.items()))
            + ")",
        ),
        ("failed polls", f"{results.failed_polls}"),
        ("recoveries (failed → good poll)", f"{results.recoveries}"),
        ("values checked against the PLC", f"{results.values_checked}"),
        ("wrong values reported", f"{results.wrong_values}"),
        ("values reported missing", f"{results.missing_values}"),
        ("availability mismatches", f"{results.availability_mismatches}"),
        (
            "writes (raised an error / lost silently)",
            f"{results.writes} ({results.writes_refused} / {results.writes_lost})",
        ),
        (
            "writes not attempted (entity unavailable)",
            f"{results.writes_skipped}",
        ),
        (
            "requests (Digest challenges)",
            f"{results.requests} ({results.challenges})",
        ),
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
        "## TecoApi soak run",
        "",
        (
            f"Machine: {machine['cpu']}, {machine['cores']} cores; Python "
            f"{machine['python']}, Home Assistant {machine['homeassistant']}. Fault rate "
            f"{settings.fault_rate:.0%} of cycles, {settings.change_percent:g} % of values "
            f"changing per cycle, writes in {settings.write_rate:.0%} of cycles, latency "
            f"{settings.latency_ms:g} ms, nonces stale after {NONCE_MAX_USES} uses."
        ),
        "",
        "| figure | value |",
        "|---|---:|",
        *(f"| {name} | {value} |" for name, value in rows),
    ]
    lines += [f"- {example}" for example in results.wrong_examples]
    return "\n".join(lines) + "\n"


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="scripts/bench soak",
        description="Soak run: thousands of coordinator polls with random faults.",
    )
    parser.add_argument(
        "--program",
        default="300",
        help="a point count or a shipped program (default 300)",
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
        help="percent of values the PLC changes each cycle (default 5)",
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
        help="PLC latency per request in ms (default 0: as many polls as possible)",
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
    settings = SoakSettings(
        program=program,
        cycles=args.cycles,
        fault_rate=args.fault_rate,
        change_percent=args.change_percent,
        write_rate=args.write_rate,
        latency_ms=args.latency_ms,
        seed=args.seed,
    )
    results = asyncio.run(run_soak(settings))
    print(report(results))
    args.output.parent.mkdir(parents=True, exist_ok=True)
    args.output.write_text(json.dumps(results.as_dict(), indent=2) + "\n")
    print(f"Figures written to {args.output}")
    bad = (
        results.wrong_values
        + results.writes_lost
        + results.unhandled_exceptions
        + results.availability_mismatches
    )
    return 1 if bad else 0
