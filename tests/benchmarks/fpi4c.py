"""The FP-I4C benchmark (issue 24): POSTs, bytes and CPU per poll, and a write's delay.

    scripts/bench fpi4c                 maps of 50, 300 and 1,000 points, 10 polls each
    scripts/bench fpi4c --quick         3 polls, 5 write samples

For each map (three stations, registers in blocks with realistic gaps, bits,
double words, a few strings; :func:`bench_map`, seeded), the source polls every
point: its POSTs and bytes per poll against the planner's bound, and the
*naive client*'s (one POST per point) side by side, with the CPU each takes per
poll on its own thread (the gateway runs on a thread of its own, so its work is
not counted). Then a real Home Assistant with the demo's map: the time from a
number's ``set_value`` to the state showing the written value, against 100 ms.
The deterministic counts (POSTs at the bound) are asserted in
``tests/test_bench_counts_fpi4c.py``; only timings live here.
"""

import argparse
import asyncio
from collections.abc import Callable, Coroutine
from dataclasses import asdict, dataclass
import json
import logging
from pathlib import Path
import random
import statistics
import time
from typing import Any, Final

import aiohttp
from homeassistant.const import CONF_HOST, CONF_SCAN_INTERVAL, EVENT_STATE_CHANGED
from homeassistant.core import Event, HomeAssistant, callback
from homeassistant.helpers import entity_registry as er
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.tecoapi.const import CONF_TRANSPORT, DOMAIN, MAX_SCAN_INTERVAL
from custom_components.tecoapi.point_maps import async_save_point_map
from custom_components.tecoapi.pyplc.core.descriptor import CONF_POINT_MAP
from custom_components.tecoapi.pyplc.core.pointmap import PointMap, load_csv
from custom_components.tecoapi.pyplc.panasonic import (
    FpI4cClient,
    FpI4cSource,
    check_point,
    plan_reads,
)
from custom_components.tecoapi.pyplc.panasonic.mapping import address_identity
from tests.simulator.fpi4c import (
    EXAMPLE_CSV,
    FpI4cSimulator,
    StationMemory,
    demo_stations,
)

from .home_assistant import bench_home_assistant
from .plc_thread import SimulatorThread

SIZES: Final = (50, 300, 1000)
STATIONS: Final = (1, 2, 3)
WRITE_TARGET_MS: Final = 100.0
DEFAULT_OUTPUT: Final = Path("bench-results/fpi4c.json")
HEADER: Final = (
    "id,name,address,type,length,unit,scale,offset,writable,min,max,step,device"
)
# How far apart blocks of registers lie: mostly close, sometimes far (another
# part of the program's memory).
GAPS: Final = (0, 0, 1, 2, 3, 5, 8, 15, 40, 120)


def bench_map(points: int, seed: int = 0) -> tuple[PointMap, dict[int, StationMemory]]:
    """Return a map of ``points`` points on three stations, and PLCs holding them.

    Registers come in blocks of 3 to 24 (INT and UINT mostly, double words and
    REALs in a fifth, tenths of a degree scaled) a gap apart; bits in blocks of 2
    to 12 on R, X and Y; a string now and then (one block in twenty).
    """
    rng = random.Random(seed)
    memory = {station: StationMemory() for station in STATIONS}
    registers = dict.fromkeys(STATIONS, 0)
    bits = {(station, area): 0 for station in STATIONS for area in "RXY"}
    rows: list[str] = []

    def row(address: str, type_: str, station: int, extra: str = ",,,,no") -> None:
        rows.append(
            f"p{len(rows)},Point {len(rows)},{address},{type_},{extra},,,,{station}"
        )

    while len(rows) < points:
        station = rng.choice(STATIONS)
        choice = rng.random()
        if choice < 0.05:
            word = registers[station] + rng.choice(GAPS)
            text = f"text {len(rows)}"
            memory[station].write_string("DT", word, text)
            row(f"DT{word}", "STRING", station, "16,,,,no")
            registers[station] = word + 2 + 8
        elif choice < 0.8:
            word = registers[station] + rng.choice(GAPS)
            double = rng.random() < 0.2
            type_ = (
                rng.choice(("DINT", "REAL", "UDINT"))
                if double
                else rng.choice(("INT", "INT", "INT", "UINT"))
            )
            width = 2 if double else 1
            for _ in range(rng.randint(3, 24)):
                if len(rows) >= points:
                    break
                value: Any = (
                    round(rng.uniform(-50, 150), 2)
                    if type_ == "REAL"
                    else rng.randint(0, 30_000)
                )
                memory[station].write("DT", type_, word, [value])
                scaled = ",°C,0.1,,yes" if type_ == "INT" else ",,,,no"
                row(f"DT{word}", type_, station, scaled)
                word += width
            registers[station] = word
        else:
            area = rng.choice("RXY")
            index = bits[station, area] + rng.choice((0, 0, 1, 3, 16))
            for _ in range(rng.randint(2, 12)):
                if len(rows) >= points:
                    break
                memory[station].write(area, "BOOL", index, [rng.random() < 0.5])
                word, bit = divmod(index, 16)
                row(f"{area}{word}{bit:X}", "BOOL", station)
                index += 1
            bits[station, area] = index
    return load_csv("\n".join((HEADER, *rows)) + "\n", check_point), memory


class GatewayThread(SimulatorThread[FpI4cSimulator]):
    """A simulated gateway serving from a thread and event loop of its own."""

    def __init__(self, stations: dict[int, StationMemory]) -> None:
        async def start() -> FpI4cSimulator:
            simulator = FpI4cSimulator(stations, station=1)
            await simulator.start()
            return simulator

        super().__init__("simulated-fp-i4c", start)

    @property
    def url(self) -> str:
        return self.served.url


@dataclass(frozen=True, slots=True)
class PollFigures:
    """One way of polling a map: per poll, on average."""

    posts: float
    bytes: float
    cpu_ms: float


@dataclass(frozen=True, slots=True)
class MapFigures:
    """A map's figures: ours against the bound, and the naive client's."""

    points: int
    stations: int
    lower_bound: int
    requests: int
    unused_values: int
    ours: PollFigures
    naive: PollFigures


async def _measured(
    client: FpI4cClient, polls: int, poll: Callable[[], Coroutine[Any, Any, object]]
) -> PollFigures:
    """POSTs, bytes and thread CPU per poll, over ``polls`` polls."""
    before = (
        client.statistics.posts,
        client.statistics.bytes_sent + (client.statistics.bytes_received),
    )
    started = time.thread_time()
    for _ in range(polls):
        await poll()
    cpu = time.thread_time() - started
    after = (
        client.statistics.posts,
        client.statistics.bytes_sent + (client.statistics.bytes_received),
    )
    return PollFigures(
        posts=(after[0] - before[0]) / polls,
        bytes=(after[1] - before[1]) / polls,
        cpu_ms=cpu * 1000 / polls,
    )


async def measure_map(points: int, polls: int, seed: int = 0) -> MapFigures:
    """Poll a generated map ours and the naive way; return the figures."""
    point_map, stations = bench_map(points, seed)
    async with GatewayThread(stations) as gateway, aiohttp.ClientSession() as http:
        client = FpI4cClient(http, gateway.url)
        source = FpI4cSource(client, point_map, identity="bench")
        snapshot = await source.poll(())
        keys = frozenset(snapshot.catalogue.points)
        await source.poll(keys)  # planned once, as Home Assistant's first poll
        ours = await _measured(client, polls, lambda: source.poll(keys))
        plan = source.plan(keys)
        naive_client = FpI4cClient(http, gateway.url)
        singles = [
            (post.station, [request.body() for request in post.requests])
            for target in source._targets.values()
            for post in plan_reads([target]).posts
        ]

        async def naive_poll() -> None:
            for station, requests in singles:
                await naive_client.post(requests, station)

        naive = await _measured(naive_client, polls, naive_poll)
    return MapFigures(
        points=points,
        stations=len({post.station for post in plan.posts}),
        lower_bound=plan.lower_bound,
        requests=plan.requests,
        unused_values=plan.unused_values,
        ours=ours,
        naive=naive,
    )


@dataclass(frozen=True, slots=True)
class WriteFigures:
    """Milliseconds from a number's set_value to its state showing the value."""

    samples: int
    median_ms: float
    max_ms: float
    target_ms: float = WRITE_TARGET_MS


async def measure_writes(samples: int) -> WriteFigures:
    """Write the demo's room setpoint ``samples`` times through Home Assistant."""
    point_map = load_csv(EXAMPLE_CSV.read_text(encoding="utf-8"), check_point)
    async with (
        GatewayThread(demo_stations()) as gateway,
        bench_home_assistant() as hass,
    ):
        entry = MockConfigEntry(
            domain=DOMAIN,
            title="FP-I4C",
            unique_id=address_identity(gateway.url, None, None),
            data={
                CONF_HOST: gateway.url,
                CONF_TRANSPORT: "fpi4c",
                CONF_POINT_MAP: await async_save_point_map(hass, point_map),
            },
            options={CONF_SCAN_INTERVAL: int(MAX_SCAN_INTERVAL.total_seconds())},
        )
        entry.add_to_hass(hass)
        assert await hass.config_entries.async_setup(entry.entry_id)
        await hass.async_block_till_done()
        entity_id = er.async_get(hass).async_get_entity_id(
            "number", DOMAIN, f"{entry.unique_id}_room_setpoint"
        )
        assert entity_id is not None
        delays = [
            await _write_delay(hass, entity_id, 15.0 + n % 20 * 0.5)
            for n in range(samples)
        ]
    return WriteFigures(
        samples=samples,
        median_ms=statistics.median(delays),
        max_ms=max(delays),
    )


async def _write_delay(hass: HomeAssistant, entity_id: str, value: float) -> float:
    """Milliseconds from the service call to the state showing ``value``."""
    shown = asyncio.Event()

    @callback
    def changed(event: Event[Any]) -> None:
        state = event.data.get("new_state")
        if (
            event.data.get("entity_id") == entity_id
            and state is not None
            and state.state == str(value)
        ):
            shown.set()

    unsubscribe = hass.bus.async_listen(EVENT_STATE_CHANGED, changed)
    started = time.perf_counter()
    try:
        if hass.states.get(entity_id).state == str(value):  # type: ignore[union-attr]
            return 0.0
        await hass.services.async_call(
            "number", "set_value", {"entity_id": entity_id, "value": value}
        )
        await asyncio.wait_for(shown.wait(), 10)
    finally:
        unsubscribe()
    return (time.perf_counter() - started) * 1000


def markdown(maps: list[MapFigures], writes: WriteFigures) -> str:
    """The report: POSTs and bytes per poll side by side, CPU, the write's delay."""
    lines = [
        "## FP-I4C: a poll of every point (per poll)",
        "",
        (
            "| points | stations | bound (POSTs) | ours: POSTs | ours: requests | "
            "ours: bytes | ours: CPU ms | naive: POSTs | naive: bytes | naive: CPU ms |"
        ),
        "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    lines += [
        f"| {item.points} | {item.stations} | {item.lower_bound} | "
        f"{item.ours.posts:g} | {item.requests} | {item.ours.bytes:,.0f} | "
        f"{item.ours.cpu_ms:.2f} | {item.naive.posts:g} | {item.naive.bytes:,.0f} | "
        f"{item.naive.cpu_ms:.2f} |"
        for item in maps
    ]
    lines += [
        "",
        "## FP-I4C: a write shown in Home Assistant",
        "",
        "| samples | median ms | max ms | target ms |",
        "|---:|---:|---:|---:|",
        (
            f"| {writes.samples} | {writes.median_ms:.1f} | {writes.max_ms:.1f} | "
            f"{writes.target_ms:g} |"
        ),
    ]
    return "\n".join(lines)


async def run(
    polls: int, samples: int, sizes: tuple[int, ...]
) -> tuple[list[MapFigures], WriteFigures]:
    """Measure every map, then the writes."""
    maps = [await measure_map(size, polls) for size in sizes]
    return maps, await measure_writes(samples)


def main(argv: list[str]) -> int:
    """``scripts/bench fpi4c [--quick] [--polls N] [--sizes 50,300]``."""
    parser = argparse.ArgumentParser(prog="scripts/bench fpi4c", description=__doc__)
    parser.add_argument("--quick", action="store_true", help="3 polls, 5 writes")
    parser.add_argument("--polls", type=int, help="polls per map (default 10)")
    parser.add_argument(
        "--sizes",
        type=lambda text: tuple(int(part) for part in text.split(",")),
        default=SIZES,
        help="points of the maps (default 50,300,1000)",
    )
    parser.add_argument("--output", type=Path, default=DEFAULT_OUTPUT)
    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.WARNING)
    logging.getLogger("homeassistant.loader").setLevel(logging.ERROR)
    polls = args.polls or (3 if args.quick else 10)
    samples = 5 if args.quick else 20
    maps, writes = asyncio.run(run(polls, samples, args.sizes))
    print(markdown(maps, writes))
    args.output.parent.mkdir(parents=True, exist_ok=True)
    args.output.write_text(
        json.dumps(
            {"maps": [asdict(item) for item in maps], "writes": asdict(writes)},
            indent=2,
        ),
        encoding="utf-8",
    )
    print(f"Figures written to {args.output}")
    return 0
