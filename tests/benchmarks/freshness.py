"""The freshness run (`scripts/bench freshness`): how soon Home Assistant shows a change.

A real Home Assistant runs the integration against a simulated PLC on its own thread
(the TecoApi latency model of the main benchmark, and a PLCComS server detecting
changes every 100 ms as the real one polls the PLC). At random moments (gaps drawn
uniformly around `--gap`) the PLC's program changes the value of a random point; the
delay is from that change inside the PLC until Home Assistant's state machine shows
the entity's new state (`state_changed`). Each way into the PLC runs for the same
window:

- `tecoapi-5s`, `tecoapi-1s`: TecoApi polling at 5 s and 1 s (the integration as
  shipped: `TecoApiSession`);
- `tecoapi+plccoms`: TecoApi with PLCComS push (`PushedTecoApiSession`; the
  coordinator still polls every 5 s, which costs no TecoApi request while PLCComS is
  healthy), switched on in the entry's options as a user would;
- `plccoms`: PLCComS alone (`PlcComsSource`), an entry as the config flow stores it;
- `peer-5s`: the peer approach (one Digest-challenged GetObject per object, one after
  the other, `peer.py`) polling every 5 s after the previous poll ended, as a data
  update coordinator schedules; a change counts as shown when the poll that read it
  ends (where that coordinator would tell its entities). It runs without Home
  Assistant.

The PLC web server's load is read from the simulator's request records over the
window: requests per minute, and the share of the window it was busy, from its latency
model (each request costs `--latency-ms` plus `--per-item-ms` per item returned; the
simulator, like the PLC, serves one request at a time).

`... freshness --mode-check` measures issue 13's HALT check without PLCComS instead: a
quiet poll (no value changed) reads GetInfo as well. It reports requests and Home
Assistant CPU per poll with the check off and on, with no value changing and with one
value changing per poll, and after how many polls a HALT shows.
"""

import argparse
import asyncio
from collections import Counter
from collections.abc import Callable, Iterator
import contextlib
from contextlib import contextmanager
from dataclasses import asdict, dataclass, field
from datetime import timedelta
from functools import partial
import gc
import json
import logging
import math
from pathlib import Path
import random
import statistics
import sys
import time
from typing import Any, Final
from unittest.mock import patch

import aiohttp
from homeassistant.const import (
    CONF_HOST,
    CONF_PASSWORD,
    CONF_PORT,
    CONF_USERNAME,
    CONF_VERIFY_SSL,
    EVENT_STATE_CHANGED,
    STATE_UNAVAILABLE,
    STATE_UNKNOWN,
)
from homeassistant.core import Event, HomeAssistant, callback
from homeassistant.helpers import entity_registry as er
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.tecoapi.const import (
    CONF_TRANSPORT,
    DOMAIN,
    MAX_ATTRIBUTE_INTERVAL,
    MAX_SCAN_INTERVAL,
    PlainVariables,
)
from custom_components.tecoapi.coordinator import PlcCoordinator
from custom_components.tecoapi.options import PlcOptions
from custom_components.tecoapi.pyplc import PlcMode, Point
from custom_components.tecoapi.pyplc.core.source import PlcSource, Snapshot
from custom_components.tecoapi.pyplc.tecomat import (
    PlcComsSource,
    PushedTecoApiSession,
    TecoApiClient,
    TecoApiSession,
)
from custom_components.tecoapi.pyplc.tecomat.points import value_path
from custom_components.tecoapi.pyplc.tecomat.tecoapi.paths import MISSING, lookup_path
from tests.simulator import RequestRecord, Simulator

from .changes import CHANGEABLE_KINDS, set_new_value
from .home_assistant import all_entities_enabled, bench_home_assistant
from .integration import CREDENTIALS, collector_paused
from .machine import machine_info
from .peer import PeerClient
from .plc_thread import PlcThread
from .programs import bench_program, parse_program_labels
from .report import Target, markdown_table

_LOGGER: Final = logging.getLogger(__name__)

DEFAULT_OUTPUT: Final = Path("bench-results/freshness.json")
SCENARIOS: Final = ("tecoapi-5s", "tecoapi-1s", "tecoapi+plccoms", "plccoms", "peer-5s")
DESCRIPTIONS: Final = {
    "tecoapi-5s": "TecoApi polling, 5 s",
    "tecoapi-1s": "TecoApi polling, 1 s",
    "tecoapi+plccoms": "TecoApi + PLCComS push (HA polls 5 s)",
    "plccoms": "PLCComS alone (HA polls 5 s)",
    "peer-5s": "peer: one GetObject per object, 5 s",
}
INTERVALS: Final = {
    "tecoapi-5s": 5,
    "tecoapi-1s": 1,
    "tecoapi+plccoms": 5,
    "plccoms": 5,
    "peer-5s": 5,
}
PUSH_P95_MS: Final = 250.0
REQUEST_REDUCTION: Final = 10.0
# How long a change may take to show before it counts as never shown.
SETTLE_SECONDS: Final = 30.0
# One reconciliation period of the PLCComS way (5 min) and one poll (5 s), a little
# more: measured from just after a reconciliation, the window holds exactly one.
DEFAULT_DURATION: Final = 308.0


@dataclass(frozen=True, slots=True, kw_only=True)
class FreshnessSettings:
    """The knobs of a freshness run (see `scripts/bench freshness --help`)."""

    program: str
    duration: float
    gap: float
    latency_ms: float
    per_item_ms: float
    scenarios: tuple[str, ...]
    seed: int


@dataclass(frozen=True, slots=True, kw_only=True)
class ScenarioFigures:
    """One way into the PLC: how fresh Home Assistant's states were, what it cost."""

    scenario: str
    description: str
    interval_s: float
    points: int
    changes: int
    shown: int
    p50_ms: float
    p95_ms: float
    max_ms: float
    slowest: list[tuple[float, str]]
    """The five slowest changes: milliseconds and point key."""
    not_shown: list[str]
    """Point keys of changes never shown (within 30 s after the window)."""
    window_s: float
    requests: int
    requests_by_service: dict[str, int]
    requests_per_minute: float
    busy_share: float
    tecoapi_polls: int
    mean_poll_ms: float | None
    max_poll_ms: float | None


@dataclass(frozen=True, slots=True, kw_only=True)
class ModeCheckFigures:
    """TecoApi polling without PLCComS, GetInfo on quiet polls off or on."""

    check_quiet_polls: bool
    quiet_requests_per_poll: float
    changing_requests_per_poll: float
    quiet_cpu_ms: float
    changing_cpu_ms: float
    halt_shown_after_polls: int | None


@dataclass(slots=True, kw_only=True)
class FreshnessResults:
    """A whole freshness run."""

    machine: dict[str, Any]
    settings: FreshnessSettings
    scenarios: list[ScenarioFigures] = field(default_factory=list)
    mode_check: list[ModeCheckFigures] = field(default_factory=list)
    seconds: float = 0.0

    def by_name(self, name: str) -> ScenarioFigures | None:
        """The figures of one scenario, if it ran."""
        return next((s for s in self.scenarios if s.scenario == name), None)

    def as_dict(self) -> dict[str, Any]:
        """Everything, JSON-serialisable, with the targets."""
        return {
            "machine": self.machine,
            "settings": asdict(self.settings),
            "seconds": self.seconds,
            "scenarios": {s.scenario: asdict(s) for s in self.scenarios},
            "mode_check": [asdict(figures) for figures in self.mode_check],
            "targets": [asdict(target) for target in evaluate_targets(self)],
        }


# --- what the PLC's web server did --------------------------------------------------------


def busy_seconds(
    requests: list[RequestRecord], latency: float, per_item: float
) -> float:
    """Seconds the web server spent on requests, from the simulator's latency model."""
    return sum(latency + per_item * request.items for request in requests)


def percentile(samples: list[float], share: float) -> float:
    """The nearest-rank percentile of samples (share in 0..1)."""
    ordered = sorted(samples)
    rank = max(1, math.ceil(share * len(ordered)))
    return ordered[rank - 1]


# --- the changes --------------------------------------------------------------------------


@dataclass(slots=True)
class _Change:
    key: str
    at: float
    value: Any


@dataclass(slots=True)
class _Tracker:
    """Changes under way and the delays of those shown."""

    pending: dict[str, _Change] = field(default_factory=dict)
    delays: list[float] = field(default_factory=list)
    slowest: list[tuple[float, str]] = field(default_factory=list)
    changes: int = 0
    settled: asyncio.Event = field(default_factory=asyncio.Event)

    def shown(self, target: str, at: float) -> None:
        change = self.pending.pop(target, None)
        if change is not None:
            self.delays.append(at - change.at)
            self.slowest = sorted([*self.slowest, (at - change.at, change.key)])[-5:]
        if not self.pending:
            self.settled.set()


def _change(simulator: Simulator, point: Point) -> tuple[float, Any] | None:
    """Give a point a new value inside the PLC (on its thread): when, and the value."""
    if not set_new_value(simulator, point):
        return None
    return time.perf_counter(), simulator.get_value(value_path(point))


async def _drive_changes(
    plc: PlcThread,
    points: dict[str, Point],
    tracker: _Tracker,
    *,
    duration: float,
    gap: float,
    rng: random.Random,
) -> None:
    """Change random points at random moments for `duration` seconds.

    `points` are by target (entity ID or point key); a point is not changed again
    while its previous change has not shown.
    """
    targets = sorted(points)
    ends = time.perf_counter() + duration
    while True:
        await asyncio.sleep(rng.uniform(gap / 3, gap * 5 / 3))
        if time.perf_counter() >= ends:
            return
        free = [target for target in targets if target not in tracker.pending]
        if not free:
            continue
        target = rng.choice(free)
        point = points[target]
        changed = await plc.call(partial(_change, point=point))
        if changed is not None:
            tracker.pending[target] = _Change(point.key, changed[0], changed[1])
            tracker.changes += 1


async def _window(
    plc: PlcThread,
    points: dict[str, Point],
    tracker: _Tracker,
    settings: FreshnessSettings,
    rng: random.Random,
) -> tuple[float, list[RequestRecord]]:
    """Drive the changes of one measured window, then let the last ones show.

    Returns the window's length in seconds and the requests the PLC served in it.
    """
    first = len(plc.requests)
    started = time.perf_counter()
    await _drive_changes(
        plc, points, tracker, duration=settings.duration, gap=settings.gap, rng=rng
    )
    window = time.perf_counter() - started
    requests = list(plc.requests[first:])
    await _settle(tracker)
    return window, requests


async def _settle(tracker: _Tracker) -> None:
    """Give the last changes time to show (they count as not shown after that)."""
    if not tracker.pending:
        return
    tracker.settled.clear()
    with contextlib.suppress(TimeoutError):
        async with asyncio.timeout(SETTLE_SECONDS):
            await tracker.settled.wait()


# --- Home Assistant -----------------------------------------------------------------------


def _entry(
    scenario: str,
    url: str,
    serial: str,
    coms_port: int | None,
    *,
    scan_interval: timedelta | None = None,
    attribute_interval: timedelta = timedelta(seconds=60),
) -> MockConfigEntry:
    """The scenario's entry, as the config flow and the options would store it.

    Polling every `INTERVALS[scenario]` s (or `scan_interval`), attributes every 60 s
    (or `attribute_interval`), every variable; push
    switched on in the options (`tecoapi+plccoms`) or PLCComS alone from the config
    flow (`plccoms`).
    """
    options: dict[str, Any] = PlcOptions(
        scan_interval=scan_interval or timedelta(seconds=INTERVALS[scenario]),
        attribute_interval=attribute_interval,
        plain_variables=PlainVariables.ENABLED,
        push={CONF_HOST: "127.0.0.1", CONF_PORT: coms_port}
        if scenario == "tecoapi+plccoms"
        else {},
    ).as_dict()
    if scenario == "plccoms":
        assert coms_port is not None
        data: dict[str, Any] = {
            CONF_TRANSPORT: "plccoms",
            CONF_HOST: "127.0.0.1",
            CONF_PORT: coms_port,
        }
    else:
        data = {
            CONF_HOST: url,
            CONF_USERNAME: CREDENTIALS.username,
            CONF_PASSWORD: CREDENTIALS.password,
            CONF_VERIFY_SSL: True,
        }
    return MockConfigEntry(
        domain=DOMAIN,
        title="Freshness PLC",
        unique_id=serial,
        data=data,
        options=options,
    )


@contextmanager
def _timed_polls(source: PlcSource) -> Iterator[list[tuple[float, int]]]:
    """Wall seconds and TecoApi requests of each poll of a TecoApi source."""
    polls: list[tuple[float, int]] = []
    original = source.poll

    async def timed(polled: Any) -> Snapshot:
        started = time.perf_counter()
        snapshot = await original(polled)
        requests = source.statistics.last_poll_requests or 0
        polls.append((time.perf_counter() - started, requests))
        return snapshot

    with patch.object(source, "poll", timed):
        yield polls


async def _until(condition: Callable[[], bool], limit: float = 60.0) -> None:
    """Wait until a source's counter says it is ready (a benchmark may poll it)."""
    async with asyncio.timeout(limit):
        while not condition():  # noqa: ASYNC110 - nothing to await but a counter
            await asyncio.sleep(0.05)


def _point_entities(
    hass: HomeAssistant, entry: MockConfigEntry, coordinator: PlcCoordinator
) -> dict[str, Point]:
    """The entities of points whose values the changer can change, by entity ID."""
    # Entities are named by the PLC's identity (PLCComS alone has its own).
    prefix = f"{coordinator.data.info.serial_number}_"
    points = coordinator.data.points
    found: dict[str, Point] = {}
    for registry_entry in er.async_entries_for_config_entry(
        er.async_get(hass), entry.entry_id
    ):
        key = registry_entry.unique_id.removeprefix(prefix)
        point = points.get(key)
        state = hass.states.get(registry_entry.entity_id)
        if (
            point is not None
            and point.kind in CHANGEABLE_KINDS
            # An entity whose T_ApiObject says `enable: false` shows no value.
            and state is not None
            and state.state != STATE_UNAVAILABLE
        ):
            found[registry_entry.entity_id] = point
    return found


async def _home_assistant_scenario(
    scenario: str, settings: FreshnessSettings, rng: random.Random
) -> ScenarioFigures:
    """Run one way into the PLC under Home Assistant and measure it."""
    async with _plc(settings) as plc:
        port = (
            await plc.start_plccoms()
            if scenario in {"tecoapi+plccoms", "plccoms"}
            else None
        )
        serial = await plc.call(lambda simulator: simulator.serial_number)
        async with bench_home_assistant() as hass:
            entry = _entry(scenario, plc.url, serial, port)
            entry.add_to_hass(hass)
            with all_entities_enabled():
                if not await hass.config_entries.async_setup(entry.entry_id):
                    raise RuntimeError(f"the entry did not set up: {entry.state}")
                await hass.async_block_till_done()
            coordinator: PlcCoordinator = entry.runtime_data
            source = coordinator.source
            # Measure from the first poll after discovery on: it enables the polled
            # points on PLCComS (and, with TecoApi, reads them once more).
            await _until(lambda: source.statistics.polls >= 1)
            if isinstance(source, PushedTecoApiSession):
                await _until(
                    lambda: source.diagnostics()["push"]["reconciliations"] >= 1
                )
            points = _point_entities(hass, entry, coordinator)
            tracker = _Tracker()

            @callback
            def state_changed(event: Event[Any]) -> None:
                new, old = event.data["new_state"], event.data["old_state"]
                if (
                    new is None
                    or new.state in (STATE_UNAVAILABLE, STATE_UNKNOWN)
                    or (old is not None and old.state == new.state)
                ):
                    return
                tracker.shown(event.data["entity_id"], time.perf_counter())

            unsubscribe = hass.bus.async_listen(EVENT_STATE_CHANGED, state_changed)
            try:
                with _timed_polls(source) as polls:
                    window, requests = await _window(
                        plc, points, tracker, settings, rng
                    )
            finally:
                unsubscribe()
    # Polls that asked TecoApi for something (a PLCComS source asks it nothing).
    tecoapi_polls = (
        []
        if isinstance(source, PlcComsSource)
        else [seconds for seconds, count in polls if count]
    )
    return _figures(
        scenario,
        settings,
        points=len(points),
        tracker=tracker,
        window=window,
        requests=requests,
        poll_seconds=tecoapi_polls,
    )


# --- the peer -----------------------------------------------------------------------------


def _same(read: Any, expected: Any) -> bool:
    """Whether a JSON value read equals what the PLC holds (REALs to 6 decimals)."""
    if isinstance(expected, float) and isinstance(read, int | float):
        return round(float(read), 6) == round(expected, 6)
    return bool(read == expected)


async def _peer_scenario(
    settings: FreshnessSettings, rng: random.Random
) -> ScenarioFigures:
    """Poll with the peer approach every 5 s after the previous poll ended."""
    interval = INTERVALS["peer-5s"]
    async with _plc(settings) as plc, aiohttp.ClientSession() as session:
        client = TecoApiClient(
            session, plc.url, CREDENTIALS.username, CREDENTIALS.password
        )
        await client.get_info()
        catalogue = await client.discover()
        peer = PeerClient(session, plc.url, CREDENTIALS.username, CREDENTIALS.password)
        names = [point.path for point in catalogue.points.values()]
        points = {
            key: point
            for key, point in catalogue.points.items()
            if point.kind in CHANGEABLE_KINDS
        }
        tracker = _Tracker()
        poll_seconds: list[float] = []

        async def polling() -> None:
            while True:
                started = time.perf_counter()
                read = await peer.poll(names)
                ended = time.perf_counter()
                poll_seconds.append(ended - started)
                for target, change in list(tracker.pending.items()):
                    point = points[target]
                    value = lookup_path(read.get(point.path, {}), value_path(point))
                    if value is not MISSING and _same(value, change.value):
                        tracker.shown(target, ended)
                await asyncio.sleep(interval)

        poller = asyncio.create_task(polling())
        try:
            window, requests = await _window(plc, points, tracker, settings, rng)
        finally:
            poller.cancel()
            await asyncio.gather(poller, return_exceptions=True)
    return _figures(
        "peer-5s",
        settings,
        points=len(points),
        tracker=tracker,
        window=window,
        requests=requests,
        poll_seconds=poll_seconds,
    )


# --- figures ------------------------------------------------------------------------------


def _plc(settings: FreshnessSettings) -> PlcThread:
    return PlcThread(
        bench_program(settings.program, seed=settings.seed).program,
        username=CREDENTIALS.username,
        password=CREDENTIALS.password,
        latency=settings.latency_ms / 1000,
        latency_per_item=settings.per_item_ms / 1000,
    )


def _figures(
    scenario: str,
    settings: FreshnessSettings,
    *,
    points: int,
    tracker: _Tracker,
    window: float,
    requests: list[RequestRecord],
    poll_seconds: list[float],
) -> ScenarioFigures:
    delays = [delay * 1000 for delay in tracker.delays] or [math.nan]
    busy = busy_seconds(
        requests, settings.latency_ms / 1000, settings.per_item_ms / 1000
    )
    return ScenarioFigures(
        scenario=scenario,
        description=DESCRIPTIONS[scenario],
        interval_s=INTERVALS[scenario],
        points=points,
        changes=tracker.changes,
        shown=len(tracker.delays),
        p50_ms=percentile(delays, 0.5),
        p95_ms=percentile(delays, 0.95),
        max_ms=max(delays),
        slowest=[(delay * 1000, key) for delay, key in reversed(tracker.slowest)],
        not_shown=sorted(change.key for change in tracker.pending.values()),
        window_s=window,
        requests=len(requests),
        requests_by_service=dict(
            Counter(request.service or "other" for request in requests)
        ),
        requests_per_minute=len(requests) / window * 60,
        busy_share=busy / window,
        tecoapi_polls=len(poll_seconds),
        mean_poll_ms=statistics.fmean(poll_seconds) * 1000 if poll_seconds else None,
        max_poll_ms=max(poll_seconds) * 1000 if poll_seconds else None,
    )


# --- the HALT check without PLCComS -------------------------------------------------------


async def measure_mode_check(
    settings: FreshnessSettings, polls: int = 10
) -> list[ModeCheckFigures]:
    """Requests and CPU per poll with GetInfo on quiet polls off and on; HALT polls."""
    figures: list[ModeCheckFigures] = []
    async with _plc(settings) as plc, bench_home_assistant() as hass:
        serial = await plc.call(lambda simulator: simulator.serial_number)
        entry = _entry(
            "tecoapi-5s",
            plc.url,
            serial,
            None,
            scan_interval=MAX_SCAN_INTERVAL,
            attribute_interval=MAX_ATTRIBUTE_INTERVAL,
        )
        entry.add_to_hass(hass)
        with all_entities_enabled():
            await hass.config_entries.async_setup(entry.entry_id)
            await hass.async_block_till_done()
        coordinator: PlcCoordinator = entry.runtime_data
        source = coordinator.source
        assert isinstance(source, TecoApiSession)
        changing = sorted(
            (p for p in coordinator.data.points.values() if p.kind in CHANGEABLE_KINDS),
            key=lambda point: point.key,
        )
        await _refresh(hass, coordinator)
        for check in (False, True):
            source.check_quiet_polls = check
            quiet = [await _measured_poll(hass, plc, coordinator) for _ in range(polls)]
            moving = []
            for index in range(polls):
                point = changing[index % len(changing)]
                await plc.call(partial(set_new_value, point=point))
                moving.append(await _measured_poll(hass, plc, coordinator))
            await plc.call(lambda simulator: setattr(simulator, "mode", "HALT"))
            halt_polls = None
            for count in range(1, polls + 1):
                await _refresh(hass, coordinator)
                if coordinator.data.info.mode is PlcMode.STOPPED:
                    halt_polls = count
                    break
            await plc.call(lambda simulator: setattr(simulator, "mode", "RUN"))
            # Back in RUN: the check's GetInfo (or the failed-HALT poll) sees it.
            source.check_quiet_polls = True
            await _refresh(hass, coordinator)
            await _refresh(hass, coordinator)
            figures.append(
                ModeCheckFigures(
                    check_quiet_polls=check,
                    quiet_requests_per_poll=statistics.fmean(r for r, _ in quiet),
                    changing_requests_per_poll=statistics.fmean(r for r, _ in moving),
                    quiet_cpu_ms=statistics.fmean(c for _, c in quiet) * 1000,
                    changing_cpu_ms=statistics.fmean(c for _, c in moving) * 1000,
                    halt_shown_after_polls=halt_polls,
                )
            )
    return figures


async def _refresh(hass: HomeAssistant, coordinator: PlcCoordinator) -> None:
    await coordinator.async_refresh()
    await hass.async_block_till_done()
    if not coordinator.last_update_success:
        raise RuntimeError(f"a poll failed: {coordinator.last_exception}")


async def _measured_poll(
    hass: HomeAssistant, plc: PlcThread, coordinator: PlcCoordinator
) -> tuple[int, float]:
    """Requests and Home Assistant CPU seconds of one refresh."""
    before = len(plc.requests)
    gc.collect()
    with collector_paused():
        started = time.thread_time()
        await _refresh(hass, coordinator)
        spent = time.thread_time() - started
    return len(plc.requests) - before, spent


# --- the run ------------------------------------------------------------------------------


async def run_freshness(
    settings: FreshnessSettings, *, mode_check: bool
) -> FreshnessResults:
    """Run the scenarios (or the HALT check) and return what they measured."""
    started = time.perf_counter()
    results = FreshnessResults(machine=machine_info(), settings=settings)
    rng = random.Random(settings.seed)
    if mode_check:
        results.mode_check = await measure_mode_check(settings)
    else:
        for scenario in settings.scenarios:
            _LOGGER.info("Scenario %s for %g s", scenario, settings.duration)
            if scenario == "peer-5s":
                figures = await _peer_scenario(settings, rng)
            else:
                figures = await _home_assistant_scenario(scenario, settings, rng)
            results.scenarios.append(figures)
    results.seconds = time.perf_counter() - started
    return results


def evaluate_targets(results: FreshnessResults) -> list[Target]:
    """Issue 13's targets, for the scenarios that ran."""
    targets: list[Target] = []
    pushed, polled = results.by_name("tecoapi+plccoms"), results.by_name("tecoapi-5s")
    if pushed is not None:
        targets.append(
            Target(
                name=f"with PLCComS, p95 <= {PUSH_P95_MS:g} ms",
                met=pushed.p95_ms <= PUSH_P95_MS,
                measured=f"{pushed.p95_ms:.0f} ms",
            )
        )
    if pushed is not None and polled is not None:
        ratio = (
            polled.requests_per_minute / pushed.requests_per_minute
            if pushed.requests_per_minute
            else math.inf
        )
        targets.append(
            Target(
                name=(
                    f"with PLCComS, >= {REQUEST_REDUCTION:g}x fewer TecoApi "
                    "requests/min than polling at 5 s"
                ),
                met=ratio >= REQUEST_REDUCTION,
                measured=f"{ratio:.1f}x ({polled.requests_per_minute:.1f} vs "
                f"{pushed.requests_per_minute:.2f}/min)",
            )
        )
    for name in ("tecoapi-5s", "tecoapi-1s"):
        figures = results.by_name(name)
        if figures is None or figures.mean_poll_ms is None:
            continue
        bound = figures.interval_s * 1000 + figures.mean_poll_ms
        targets.append(
            Target(
                name=f"{figures.description}: p95 <= interval + one poll",
                met=figures.p95_ms <= bound,
                measured=f"{figures.p95_ms:.0f} ms <= {bound:.0f} ms",
            )
        )
    return targets


def markdown(results: FreshnessResults) -> str:
    """The report: the machine, the freshness table (or the HALT check), the targets."""
    settings, machine = results.settings, results.machine
    lines = [
        "## Freshness",
        "",
        (
            f"Machine: {machine['cpu']}, {machine['cores']} cores "
            f"({machine['usable_cores']} usable), {machine['os']}; Python "
            f"{machine['python']}, Home Assistant {machine['homeassistant']}."
        ),
        (
            f"Program {settings.program}; PLC latency {settings.latency_ms:g} ms per "
            f"request + {settings.per_item_ms:g} ms per item; "
            + (
                "10 polls per figure, every entity enabled"
                if results.mode_check
                else f"a change every {settings.gap / 3:.1f}-"
                f"{settings.gap * 5 / 3:.1f} s, for {settings.duration:g} s per way"
            )
            + f"; seed {settings.seed}. Run took {results.seconds:.0f} s."
        ),
        "",
    ]
    if results.scenarios:
        lines += markdown_table(
            [
                "way into the PLC",
                "changes shown",
                "p50 ms",
                "p95 ms",
                "max ms",
                "TecoApi requests/min",
                "web server busy",
                "TecoApi poll ms (mean)",
            ],
            [
                [
                    s.description,
                    f"{s.shown}/{s.changes}",
                    f"{s.p50_ms:.0f}",
                    f"{s.p95_ms:.0f}",
                    f"{s.max_ms:.0f}",
                    f"{s.requests_per_minute:.1f}",
                    f"{s.busy_share:.1%}",
                    "-" if s.mean_poll_ms is None else f"{s.mean_poll_ms:.0f}",
                ]
                for s in results.scenarios
            ],
        )
    if results.mode_check:
        lines += markdown_table(
            [
                "GetInfo on quiet polls",
                "requests/poll, nothing changed",
                "requests/poll, one value changed",
                "HA CPU ms/poll, nothing changed",
                "HA CPU ms/poll, one changed",
                "HALT shown after",
            ],
            [
                [
                    "on" if f.check_quiet_polls else "off (before issue 13)",
                    f"{f.quiet_requests_per_poll:.1f}",
                    f"{f.changing_requests_per_poll:.1f}",
                    f"{f.quiet_cpu_ms:.2f}",
                    f"{f.changing_cpu_ms:.2f}",
                    (
                        f"{f.halt_shown_after_polls} poll(s)"
                        if f.halt_shown_after_polls is not None
                        else "the next GetInfo on the cadence"
                    ),
                ]
                for f in results.mode_check
            ],
        )
    targets = evaluate_targets(results)
    if targets:
        lines += ["", "Targets:", ""]
        lines += markdown_table(
            ["target", "met", "measured"],
            [[t.name, "yes" if t.met else "NO", t.measured] for t in targets],
        )
    return "\n".join(lines) + "\n"


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="scripts/bench freshness",
        description=(
            "Freshness: the delay from a change inside the PLC to Home Assistant's "
            "state, and the PLC web server's load, for each way into the PLC."
        ),
    )
    parser.add_argument(
        "--program", default="demo", help="a point count or a shipped program"
    )
    parser.add_argument(
        "--duration",
        type=float,
        default=DEFAULT_DURATION,
        help=f"seconds of changes per way (default {DEFAULT_DURATION:g}: the window "
        "starts right after a reconciliation of the PLCComS way and holds exactly "
        "one more, so its TecoApi load is the long-run rate)",
    )
    parser.add_argument(
        "--quick", action="store_true", help="60 s per way (no reconciliation inside)"
    )
    parser.add_argument(
        "--gap", type=float, default=1.5, help="mean seconds between changes"
    )
    parser.add_argument(
        "--scenarios",
        type=lambda text: tuple(part for part in text.split(",") if part),
        default=SCENARIOS,
        help=f"comma-separated, of {','.join(SCENARIOS)} (default all)",
    )
    parser.add_argument(
        "--mode-check",
        action="store_true",
        help="measure the HALT check of polling without PLCComS instead",
    )
    parser.add_argument("--latency-ms", type=float, default=20.0)
    parser.add_argument("--per-item-ms", type=float, default=0.05)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--output", type=Path, default=DEFAULT_OUTPUT)
    parser.add_argument("--verbose", action="store_true")
    return parser


def main(argv: list[str]) -> int:
    """Run the freshness benchmark, print its table, write its JSON."""
    args = _parser().parse_args(argv)
    unknown = set(args.scenarios) - set(SCENARIOS)
    if unknown:
        raise SystemExit(f"unknown scenarios: {', '.join(sorted(unknown))}")
    (program,) = parse_program_labels(args.program)
    logging.basicConfig(level=logging.WARNING, format="%(asctime)s %(message)s")
    logging.getLogger("homeassistant.loader").setLevel(logging.ERROR)
    if args.verbose:
        logging.getLogger(__package__).setLevel(logging.INFO)
    settings = FreshnessSettings(
        program=program,
        duration=60.0 if args.quick else args.duration,
        gap=args.gap,
        latency_ms=args.latency_ms,
        per_item_ms=args.per_item_ms,
        scenarios=args.scenarios,
        seed=args.seed,
    )
    results = asyncio.run(run_freshness(settings, mode_check=args.mode_check))
    print(markdown(results))
    output = args.output
    if args.mode_check and output == DEFAULT_OUTPUT:
        output = output.with_name("mode-check.json")
    output.parent.mkdir(parents=True, exist_ok=True)
    output.write_text(json.dumps(results.as_dict(), indent=2) + "\n")
    print(f"Figures written to {output}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
