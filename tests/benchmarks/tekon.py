"""The Tekon gateway run (`scripts/bench tekon`): freshness, load, the naive way, setup.

The simulated gateway serves from a thread of its own (its work is not counted as
Home Assistant's or the client's). Four measurements:

- **freshness** -- a real Home Assistant runs an entry of the gateway as the config
  flow makes it (polled every second, its default) over a building of ``--items``
  channels, every one enabled. At random moments (gaps drawn uniformly around
  ``--gap``) the gateway changes a random channel; the delay is from that change to
  Home Assistant's ``state_changed`` of its entity (as the freshness run measures
  push). Then a quiet window: what the gateway was asked while nothing changed, and
  what one reconnect (the sessions expired) cost;
- **naive** -- the way a script would do it, ``ReadItemValueSync`` per item per poll,
  beside ours (one ``GetUpdatesText`` per poll, after subscribing), both with the
  library's client on this thread for ``--naive-seconds`` with a poll every second:
  requests per minute and this thread's CPU per minute;
- **setup** -- an entry of a gateway with a ``--large`` item address space set up in
  Home Assistant: its wall time, the memory Python allocated meanwhile (its peak)
  and what stays allocated once it is set up (tracemalloc), the first time (the
  address space read from the gateway and kept) and after a restart (kept: only
  its hash is read).
"""

import argparse
import asyncio
from collections import Counter
from collections.abc import Callable, Coroutine, Iterator
from contextlib import contextmanager
from dataclasses import asdict, dataclass
import gc
import json
import logging
import math
from pathlib import Path
import random
import statistics
import sys
import time
import tracemalloc
from typing import Any, Final

import aiohttp
from homeassistant.const import (
    CONF_HOST,
    CONF_VERIFY_SSL,
    EVENT_STATE_CHANGED,
    STATE_UNAVAILABLE,
    STATE_UNKNOWN,
)
from homeassistant.core import Event, HomeAssistant, callback
from homeassistant.helpers import entity_registry as er
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.tecoapi.const import CONF_TRANSPORT, DOMAIN
from custom_components.tecoapi.coordinator import PlcCoordinator
from custom_components.tecoapi.pyplc.tekon import TekonClient, TekonSource
from custom_components.tecoapi.pyplc.tekon.catalogue import KEPT_PROPERTIES
from tests.simulator.tekon import Building, Item, TekonGateway, large_building

from .home_assistant import all_entities_enabled, bench_home_assistant
from .machine import machine_info
from .plc_thread import SimulatorThread
from .report import markdown_table

_LOGGER: Final = logging.getLogger(__name__)

DEFAULT_OUTPUT: Final = Path("bench-results/tekon.json")
INTERVAL: Final = 1.0
"""The entry's update interval: the source's default."""
TARGET_MARGIN_MS: Final = 150.0
SETTLE_SECONDS: Final = 10.0
CHANGED: Final = frozenset({(3000, 19), (3060, 4)})
"""Channels the run changes (type, value type): discrete inputs, real sensors."""


class GatewayThread(SimulatorThread[TekonGateway]):
    """A :class:`TekonGateway` serving on 127.0.0.1 from a thread of its own."""

    def __init__(self, building: Building) -> None:
        """Prepare a gateway of ``building``."""

        async def start() -> TekonGateway:
            gateway = TekonGateway(building)
            await gateway.start()
            return gateway

        super().__init__("simulated-gateway", start)

    @property
    def gateway(self) -> TekonGateway:
        """The gateway; touch it only through :meth:`call`."""
        return self.served


@dataclass(frozen=True, slots=True, kw_only=True)
class TekonSettings:
    """The knobs of a run (see `scripts/bench tekon --help`)."""

    items: int
    duration: float
    gap: float
    naive_seconds: float
    large: int
    seed: int


@dataclass(frozen=True, slots=True, kw_only=True)
class Freshness:
    """Change to Home Assistant state, and what the gateway was asked."""

    entities: int
    changes: int
    shown: int
    p50_ms: float
    p95_ms: float
    max_ms: float
    window_s: float
    requests_per_minute: float
    requests_by_call: dict[str, int]
    quiet_polls: int
    quiet_requests_by_call: dict[str, int]
    reconnect_requests_by_call: dict[str, int]
    subscribed: int


@dataclass(frozen=True, slots=True, kw_only=True)
class Way:
    """One way of reading ``items`` items every second."""

    way: str
    items: int
    polls: int
    requests_per_minute: float
    cpu_ms_per_minute: float
    mean_poll_ms: float
    max_poll_ms: float


@dataclass(frozen=True, slots=True, kw_only=True)
class Setup:
    """Setting up an entry of a large address space."""

    items: int
    kept: bool
    """The address space was kept beside the entry (only its hash read)."""
    seconds: float
    requests_by_call: dict[str, int]


@dataclass(frozen=True, slots=True, kw_only=True)
class Memory:
    """What Python allocated for a large address space (MiB, tracemalloc).

    Home Assistant's setup of the entry (every entity enabled); the source alone
    (its discovery: the catalogue it keeps); the address space as the client
    parses it (what would be kept twice if the source kept it beside its
    catalogue).
    """

    items: int
    home_assistant_peak_mib: float
    home_assistant_retained_mib: float
    source_peak_mib: float
    source_retained_mib: float
    parsed_address_space_mib: float


def percentile(samples: list[float], share: float) -> float:
    """The nearest-rank percentile (share in 0..1)."""
    ordered = sorted(samples)
    return ordered[max(1, math.ceil(share * len(ordered))) - 1]


def _entry(url: str) -> MockConfigEntry:
    """An entry as the config flow stores it (no options: the source's defaults)."""
    return MockConfigEntry(
        domain=DOMAIN,
        title="ASUD.SCADA OPC-HTTP",
        data={CONF_HOST: url, CONF_VERIFY_SSL: True, CONF_TRANSPORT: "tekon"},
    )


async def _set_up(hass: HomeAssistant, entry: MockConfigEntry) -> PlcCoordinator:
    """Set an entry up, every entity enabled."""
    with all_entities_enabled():
        if not await hass.config_entries.async_setup(entry.entry_id):
            raise RuntimeError(f"the entry did not set up: {entry.state}")
        await hass.async_block_till_done()
    coordinator: PlcCoordinator = entry.runtime_data
    return coordinator


def _changeable(hass: HomeAssistant, entry: MockConfigEntry) -> dict[str, str]:
    """Item names by entity ID of the entities whose channels the run changes."""
    coordinator: PlcCoordinator = entry.runtime_data
    points = coordinator.data.catalogue.points
    prefix = f"{coordinator.data.info.identity}_"
    found: dict[str, str] = {}
    for registry_entry in er.async_entries_for_config_entry(
        er.async_get(hass), entry.entry_id
    ):
        point = points.get(registry_entry.unique_id.removeprefix(prefix))
        if point is not None and point.attributes is not None:
            state = hass.states.get(registry_entry.entity_id)
            if state is not None and state.state not in (
                STATE_UNAVAILABLE,
                STATE_UNKNOWN,
            ):
                found[registry_entry.entity_id] = point.address
    return found


def _new_value(item: Item, rng: random.Random) -> str:
    """Another value for a channel the run changes."""
    if item.channel_type == 3000:
        return "0" if item.value == "1" else "1"
    return f"{float(item.value) + rng.choice([-1, 1]) * rng.randint(1, 50) / 10:.1f}"


async def measure_freshness(settings: TekonSettings) -> Freshness:
    """Changes to states under Home Assistant; the quiet window; a reconnect."""
    rng = random.Random(settings.seed)
    async with (
        GatewayThread(large_building(settings.items)) as plc,
        bench_home_assistant() as hass,
    ):
        entry = _entry(plc.gateway.url)
        entry.add_to_hass(hass)
        coordinator = await _set_up(hass, entry)
        # Everything subscribed: a poll after the entities listen.
        await asyncio.sleep(3 * INTERVAL)
        building = plc.gateway.building
        names = {
            entity_id: name
            for entity_id, name in _changeable(hass, entry).items()
            if (building.by_name[name].channel_type, building.by_name[name].vartype)
            in CHANGED
        }
        pending: dict[str, float] = {}
        delays: list[float] = []
        settled = asyncio.Event()

        @callback
        def state_changed(event: Event[Any]) -> None:
            new, old = event.data["new_state"], event.data["old_state"]
            if new is None or (old is not None and old.state == new.state):
                return
            if (started := pending.pop(event.data["entity_id"], None)) is not None:
                delays.append(time.perf_counter() - started)
                if not pending:
                    settled.set()

        unsubscribe = hass.bus.async_listen(EVENT_STATE_CHANGED, state_changed)
        await plc.call(lambda gateway: gateway.clear_requests())
        changes = 0
        started = time.perf_counter()
        ends = started + settings.duration
        targets = sorted(names)
        while True:
            await asyncio.sleep(rng.uniform(settings.gap / 3, settings.gap * 5 / 3))
            if time.perf_counter() >= ends:
                break
            free = [target for target in targets if target not in pending]
            target = rng.choice(free)
            name = names[target]

            def change(gateway: TekonGateway, name: str = name) -> None:
                item = gateway.building.by_name[name]
                gateway.set_value(name, _new_value(item, rng))

            await plc.call(change)
            pending[target] = time.perf_counter()
            changes += 1
        window = time.perf_counter() - started
        calls = await plc.call(lambda gateway: Counter(gateway.calls))
        if pending:
            settled.clear()
            async with asyncio.timeout(SETTLE_SECONDS):
                await settled.wait()
        unsubscribe()
        # Quiet: nothing changes for ten intervals.
        await plc.call(lambda gateway: gateway.clear_requests())
        polls_before = coordinator.source.statistics.polls
        await asyncio.sleep(10 * INTERVAL)
        quiet_polls = coordinator.source.statistics.polls - polls_before
        quiet = await plc.call(lambda gateway: dict(gateway.calls))
        subscribed = await plc.call(
            lambda gateway: sum(
                len(session.subscribed) for session in gateway.sessions.values()
            )
        )
        # A reconnect: every session gone (configuration mode, the same
        # address space), then one poll.
        await plc.call(lambda gateway: gateway.configuration_mode())
        await plc.call(lambda gateway: gateway.clear_requests())
        await coordinator.async_refresh()
        reconnect = await plc.call(lambda gateway: dict(gateway.calls))
    delays_ms = [delay * 1000 for delay in delays] or [math.nan]
    return Freshness(
        entities=len(names),
        changes=changes,
        shown=len(delays),
        p50_ms=percentile(delays_ms, 0.5),
        p95_ms=percentile(delays_ms, 0.95),
        max_ms=max(delays_ms),
        window_s=window,
        requests_per_minute=calls.total() / window * 60,
        requests_by_call=dict(calls),
        quiet_polls=quiet_polls,
        quiet_requests_by_call=quiet,
        reconnect_requests_by_call=reconnect,
        subscribed=subscribed,
    )


async def _every_second(
    seconds: float, poll: Callable[[], Coroutine[Any, Any, None]]
) -> tuple[int, float, list[float]]:
    """Poll every second (or right after a poll longer than that) for ``seconds``.

    Returns the polls, this thread's CPU seconds and each poll's wall seconds.
    """
    durations: list[float] = []
    cpu = time.thread_time()
    ends = time.perf_counter() + seconds
    while (now := time.perf_counter()) < ends:
        await poll()
        took = time.perf_counter() - now
        durations.append(took)
        await asyncio.sleep(max(0.0, INTERVAL - took))
    return len(durations), time.thread_time() - cpu, durations


async def measure_naive(settings: TekonSettings) -> list[Way]:
    """``ReadItemValueSync`` per item per poll, beside one ``GetUpdatesText``."""
    ways: list[Way] = []
    async with (
        GatewayThread(large_building(settings.items)) as plc,
        aiohttp.ClientSession() as http,
    ):
        names = [item.name for item in plc.gateway.building.items]
        # Ours: the source, every item polled.
        source = TekonSource(TekonClient(http, plc.gateway.url))
        catalogue = (await source.poll(())).catalogue
        polled = frozenset(catalogue.points)
        await source.poll(polled)
        requests = source.client.request_count

        async def ours() -> None:
            await source.poll(polled)

        polls, cpu, durations = await _every_second(settings.naive_seconds, ours)
        ways.append(
            _way(
                "ours: GetUpdatesText",
                len(names),
                polls,
                cpu,
                durations,
                source.client.request_count - requests,
                settings.naive_seconds,
            )
        )
        await source.close()
        # The naive way: a session, then every item read on every poll.
        client = TekonClient(http, plc.gateway.url)
        await client.open_session()
        requests = client.request_count

        async def naive() -> None:
            for name in names:
                await client.read(name)

        polls, cpu, durations = await _every_second(settings.naive_seconds, naive)
        ways.append(
            _way(
                "naive: ReadItemValueSync per item",
                len(names),
                polls,
                cpu,
                durations,
                client.request_count - requests,
                settings.naive_seconds,
            )
        )
        await client.close_session()
    return ways


def _way(  # noqa: PLR0917 (one row's figures)
    way: str,
    items: int,
    polls: int,
    cpu: float,
    durations: list[float],
    requests: int,
    seconds: float,
) -> Way:
    return Way(
        way=way,
        items=items,
        polls=polls,
        requests_per_minute=requests / seconds * 60,
        cpu_ms_per_minute=cpu / seconds * 60 * 1000,
        mean_poll_ms=statistics.fmean(durations) * 1000,
        max_poll_ms=max(durations) * 1000,
    )


async def measure_setup(settings: TekonSettings) -> tuple[list[Setup], Memory]:
    """Set up a large address space's entry: the first time, then after a restart.

    Timed without tracemalloc (it slows Python down several times); the memory is
    measured apart: Home Assistant's whole setup of the entry (address space kept),
    and the source alone, against the address space as the client parses it.
    """
    figures: list[Setup] = []
    async with (
        GatewayThread(large_building(settings.large)) as plc,
        bench_home_assistant() as hass,
    ):
        entry = _entry(plc.gateway.url)
        entry.add_to_hass(hass)
        for kept in (False, True):
            await plc.call(lambda gateway: gateway.clear_requests())
            started = time.perf_counter()
            with all_entities_enabled():
                await hass.config_entries.async_setup(entry.entry_id)
                await hass.async_block_till_done(wait_background_tasks=True)
            seconds = time.perf_counter() - started
            calls = await plc.call(lambda gateway: dict(gateway.calls))
            figures.append(
                Setup(
                    items=settings.large,
                    kept=kept,
                    seconds=seconds,
                    requests_by_call=calls,
                )
            )
            await hass.config_entries.async_unload(entry.entry_id)
            await hass.async_block_till_done()
        with _traced() as home_assistant, all_entities_enabled():
            await hass.config_entries.async_setup(entry.entry_id)
            await hass.async_block_till_done(wait_background_tasks=True)
        await hass.config_entries.async_unload(entry.entry_id)
        await hass.async_block_till_done()
        async with aiohttp.ClientSession() as http:
            source = TekonSource(TekonClient(http, plc.gateway.url))
            with _traced() as alone:
                await source.poll(())
            await source.close()
            with _traced() as parsed:
                client = TekonClient(http, plc.gateway.url)
                await client.open_session()
                items = await client.address_space(KEPT_PROPERTIES)
                await client.close_session()
            del items
    return figures, Memory(
        items=settings.large,
        home_assistant_peak_mib=home_assistant.peak,
        home_assistant_retained_mib=home_assistant.retained,
        source_peak_mib=alone.peak,
        source_retained_mib=alone.retained,
        parsed_address_space_mib=parsed.retained,
    )


@dataclass(slots=True)
class _Traced:
    peak: float = 0.0
    retained: float = 0.0


@contextmanager
def _traced() -> Iterator[_Traced]:
    """What Python allocated inside the block: its peak and what stays (MiB)."""
    traced = _Traced()
    gc.collect()
    tracemalloc.start()
    baseline = tracemalloc.get_traced_memory()[0]
    try:
        yield traced
    finally:
        gc.collect()
        current, peak = tracemalloc.get_traced_memory()
        tracemalloc.stop()
        traced.peak = (peak - baseline) / 2**20
        traced.retained = (current - baseline) / 2**20


def report(
    freshness: Freshness | None,
    ways: list[Way],
    setups: list[Setup],
    memory: Memory | None,
) -> list[str]:
    """The run as markdown tables."""
    lines: list[str] = []
    if freshness is not None:
        target = INTERVAL * 1000 + TARGET_MARGIN_MS
        lines += [
            "## Freshness (change to Home Assistant state, update interval 1 s)",
            "",
            *markdown_table(
                [
                    "entities",
                    "changes",
                    "shown",
                    "p50 ms",
                    "p95 ms",
                    "max ms",
                    "target p95",
                    "requests/min",
                ],
                [
                    [
                        str(freshness.entities),
                        str(freshness.changes),
                        str(freshness.shown),
                        f"{freshness.p50_ms:.0f}",
                        f"{freshness.p95_ms:.0f}",
                        f"{freshness.max_ms:.0f}",
                        f"<= {target:.0f} ({'met' if freshness.p95_ms <= target else 'NOT met'})",
                        f"{freshness.requests_per_minute:.1f}",
                    ]
                ],
            ),
            "",
            (
                f"While nothing changed: {freshness.quiet_polls} polls asked "
                f"{freshness.quiet_requests_by_call} ({freshness.subscribed} items "
                "subscribed)."
            ),
            (
                "A reconnect (every session closed, the same address space) asked "
                f"{freshness.reconnect_requests_by_call}."
            ),
            "",
        ]
    if ways:
        lines += [
            "## Ours against the naive way (every item, a poll a second)",
            "",
            *markdown_table(
                [
                    "way",
                    "items",
                    "polls",
                    "requests/min",
                    "client CPU ms/min",
                    "mean poll ms",
                    "max poll ms",
                ],
                [
                    [
                        way.way,
                        str(way.items),
                        str(way.polls),
                        f"{way.requests_per_minute:,.0f}",
                        f"{way.cpu_ms_per_minute:,.0f}",
                        f"{way.mean_poll_ms:,.1f}",
                        f"{way.max_poll_ms:,.1f}",
                    ]
                    for way in ways
                ],
            ),
            "",
        ]
    if setups:
        lines += [
            "## Setup with a large address space",
            "",
            *markdown_table(
                ["items", "address space", "seconds", "requests"],
                [
                    [
                        str(setup.items),
                        "kept (hash only)" if setup.kept else "read and kept",
                        f"{setup.seconds:.2f}",
                        ", ".join(
                            f"{k} {v}"
                            for k, v in sorted(setup.requests_by_call.items())
                        ),
                    ]
                    for setup in setups
                ],
            ),
            "",
        ]
    if memory is not None:
        lines += [
            f"## Memory for {memory.items} items (MiB allocated, tracemalloc)",
            "",
            *markdown_table(
                ["what", "peak", "retained"],
                [
                    [
                        "Home Assistant: the entry set up, every entity enabled",
                        f"{memory.home_assistant_peak_mib:.1f}",
                        f"{memory.home_assistant_retained_mib:.1f}",
                    ],
                    [
                        "the source alone: discovery, its catalogue kept",
                        f"{memory.source_peak_mib:.1f}",
                        f"{memory.source_retained_mib:.1f}",
                    ],
                    [
                        "the address space as parsed (not kept by the source)",
                        "",
                        f"{memory.parsed_address_space_mib:.1f}",
                    ],
                ],
            ),
        ]
    return lines


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="scripts/bench tekon",
        description="The Tekon gateway: freshness, load, the naive way, setup.",
    )
    parser.add_argument("--quick", action="store_true", help="a short run")
    parser.add_argument("--items", type=int, default=1000, help="enabled items (1000)")
    parser.add_argument(
        "--duration", type=float, help="seconds of changes (60; quick 15)"
    )
    parser.add_argument(
        "--gap", type=float, default=0.7, help="seconds between changes"
    )
    parser.add_argument(
        "--naive-seconds", type=float, help="seconds per way (60; quick 15)"
    )
    parser.add_argument(
        "--large", type=int, default=10_000, help="the large address space's items"
    )
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument(
        "--only", choices=("freshness", "naive", "setup"), help="one measurement"
    )
    parser.add_argument("--output", type=Path, default=DEFAULT_OUTPUT)
    return parser


async def run(settings: TekonSettings, only: str | None) -> dict[str, Any]:
    """Run the measurements; return them JSON-serialisable."""
    freshness = (
        await measure_freshness(settings) if only in (None, "freshness") else None
    )
    ways = await measure_naive(settings) if only in (None, "naive") else []
    setups, memory = (
        await measure_setup(settings) if only in (None, "setup") else ([], None)
    )
    print("\n".join(report(freshness, ways, setups, memory)))
    return {
        "machine": machine_info(),
        "settings": asdict(settings),
        "freshness": asdict(freshness) if freshness else None,
        "naive": [asdict(way) for way in ways],
        "setup": [asdict(setup) for setup in setups],
        "memory": asdict(memory) if memory else None,
    }


def main(argv: list[str]) -> int:
    """Entry point of `scripts/bench tekon`."""
    args = _parser().parse_args(argv)
    logging.basicConfig(level=logging.WARNING, format="%(asctime)s %(message)s")
    logging.getLogger("homeassistant.loader").setLevel(logging.ERROR)
    settings = TekonSettings(
        items=args.items,
        duration=args.duration or (15.0 if args.quick else 60.0),
        gap=args.gap,
        naive_seconds=args.naive_seconds or (15.0 if args.quick else 60.0),
        large=args.large,
        seed=args.seed,
    )
    results = asyncio.run(run(settings, args.only))
    args.output.parent.mkdir(parents=True, exist_ok=True)
    args.output.write_text(json.dumps(results, indent=2, ensure_ascii=False))
    print(f"Figures written to {args.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
