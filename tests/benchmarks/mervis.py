"""``scripts/bench mervis``: the Mervis source's figures of issue 23.

- **Requests per poll** for generated projects of 50, 300 and 1,000 variables
  with a realistic structure (function blocks of a few members, structs,
  arrays, ``hw`` variables, top-level ones; ``tests.simulator.mervis.generated``):
  ours (one range per CommUid, packed under the limits: 64 IDs per request, as
  the naive client sends) against the naive client (one ID per variable, 64 IDs
  per request, as a public Mervis client does), both over real HTTP against the
  simulated controller, with the planner's lower bound beside them; and the CPU
  one poll costs on the polling thread (the simulator runs on a thread of its
  own, so its work is not counted), median of the polls.
- **A write shown in Home Assistant**: a real Home Assistant with a Mervis entry
  of the simulated cottage, a relay marked writable; the time from the
  ``switch.turn_on``/``turn_off`` call to the entity's new state, over samples.
  The issue asks for at most 100 ms.

Deterministic counts (requests per poll) are asserted in
``tests/test_bench_counts_mervis.py``; only this module measures time.
"""

import argparse
import asyncio
from collections.abc import Awaitable, Callable, Sequence
from dataclasses import dataclass, replace
import math
import statistics
import time
from typing import Any, Final

import aiohttp
from homeassistant.const import CONF_SCAN_INTERVAL, EVENT_STATE_CHANGED
from homeassistant.core import Event, HomeAssistant, callback
from homeassistant.helpers import entity_registry as er
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.tecoapi.const import DOMAIN, MAX_SCAN_INTERVAL
from custom_components.tecoapi.point_maps import async_save_point_map
from custom_components.tecoapi.pyplc.core.descriptor import (
    CONF_HOST,
    CONF_PASSWORD,
    CONF_POINT_MAP,
    CONF_USERNAME,
    CONF_VERIFY_SSL,
)
from custom_components.tecoapi.pyplc.core.models import Access
from custom_components.tecoapi.pyplc.core.pointmap import (
    PointMap,
    map_catalogue,
)
from custom_components.tecoapi.pyplc.mervis import Address, MervisClient, MervisSource
from custom_components.tecoapi.pyplc.mervis.codec import decode
from custom_components.tecoapi.pyplc.mervis.vlist import load_vlist
from tests.simulator.mervis import (
    HOUSE_NAME,
    MervisSimulator,
    Project,
    generated,
    house,
)

from .home_assistant import bench_home_assistant
from .plc_thread import SimulatorThread

SIZES: Final = (50, 300, 1000)
NAIVE_IDS_PER_REQUEST: Final = 64
USER: Final = "bench"
PASSWORD: Final = "bench-pass"
RELAY: Final = "hw.neuron_l203_ro_2.01"
WRITE_BUDGET_MS: Final = 100.0


class MervisThread(SimulatorThread[MervisSimulator]):
    """A simulated Mervis controller serving from a thread and event loop of its own."""

    def __init__(self, project: Project) -> None:
        """Prepare the controller of a project (with credentials)."""
        self.simulator = MervisSimulator(project, username=USER, password=PASSWORD)
        simulator = self.simulator

        async def start() -> MervisSimulator:
            await simulator.start()
            return simulator

        super().__init__("simulated-mervis", start)

    def requests(self) -> int:
        """How many requests arrived so far (read between requests)."""
        return len(self.simulator.requests)


@dataclass(frozen=True, slots=True)
class PollFigures:
    """What one project's polls cost, ours against the naive client's."""

    variables: int
    commuids: int
    ours: int
    lower_bound: int
    naive: int
    ours_cpu_ms: float
    naive_cpu_ms: float


async def naive_poll(
    client: MervisClient, points: Sequence[tuple[Any, Address]]
) -> int:
    """Read every variable by its own ID, 64 IDs a request (a public client's way).

    Returns the requests sent; the values are decoded as ours are.
    """
    requests = 0
    for start in range(0, len(points), NAIVE_IDS_PER_REQUEST):
        batch = points[start : start + NAIVE_IDS_PER_REQUEST]
        items = await client.values([address for _, address in batch])
        requests += 1
        for data_type, address in batch:
            item = items.get(address)
            if item is not None and item.value is not None:
                decode(data_type, item.value)
    return requests


async def _cpu_ms(poll: Callable[[], Awaitable[Any]], polls: int) -> float:
    """The median CPU (this thread's) one poll takes, in milliseconds."""
    spent = []
    for _ in range(polls):
        started = time.thread_time()
        await poll()
        spent.append((time.thread_time() - started) * 1000)
    return statistics.median(spent)


async def measure_polls(size: int, polls: int, seed: int = 0) -> PollFigures:
    """Poll a generated project of ``size`` variables both ways (see the module)."""
    project = generated(size, seed=seed)
    point_map = load_vlist(project.vlist())
    async with MervisThread(project) as controller, aiohttp.ClientSession() as http:
        url = controller.simulator.url
        source = MervisSource(MervisClient(http, url, USER, PASSWORD), point_map)
        polled = frozenset((await source.poll(())).catalogue.points)
        await source.poll(polled)
        plan = source.read_plan
        assert plan is not None
        before = controller.requests()
        ours_cpu = await _cpu_ms(lambda: source.poll(polled), polls)
        ours = (controller.requests() - before) // polls
        naive_client = MervisClient(http, url, USER, PASSWORD)
        await naive_client.login()
        points = [
            (point.type, Address.parse(point.address))
            for point in map_catalogue(point_map).points.values()
        ]
        before = controller.requests()
        naive_cpu = await _cpu_ms(lambda: naive_poll(naive_client, points), polls)
        naive = (controller.requests() - before) // polls
    return PollFigures(
        variables=size,
        commuids=plan.ids,
        ours=ours,
        lower_bound=plan.lower_bound,
        naive=naive,
        ours_cpu_ms=ours_cpu,
        naive_cpu_ms=naive_cpu,
    )


def naive_requests(variables: int) -> int:
    """The requests a naive client's poll takes: one ID per variable, 64 a request."""
    return math.ceil(variables / NAIVE_IDS_PER_REQUEST)


def cottage_map() -> PointMap:
    """The cottage's map with its first relay marked writable (as a user marks it)."""
    point_map = load_vlist(house().vlist())
    relay = point_map.by_key()[RELAY]
    return point_map.with_point(replace(relay, access=Access.READ_WRITE))


async def mervis_entry(
    hass: HomeAssistant, url: str, point_map: PointMap, credentials: tuple[str, str]
) -> MockConfigEntry:
    """An entry of the cottage's controller with a map, polled only when told to."""
    username, password = credentials
    return MockConfigEntry(
        domain=DOMAIN,
        title=f"Mervis · {HOUSE_NAME}",
        unique_id=f"Mervis {HOUSE_NAME}",
        data={
            CONF_HOST: url,
            CONF_USERNAME: username,
            CONF_PASSWORD: password,
            CONF_VERIFY_SSL: True,
            "transport": "mervis",
            CONF_POINT_MAP: await async_save_point_map(hass, point_map),
        },
        options={CONF_SCAN_INTERVAL: int(MAX_SCAN_INTERVAL.total_seconds())},
    )


async def measure_writes(samples: int) -> list[float]:
    """Milliseconds from a switch's turn_on/turn_off to its new state in Home Assistant."""
    async with MervisThread(house()) as controller, bench_home_assistant() as hass:
        entry = await mervis_entry(
            hass, controller.simulator.url, cottage_map(), (USER, PASSWORD)
        )
        entry.add_to_hass(hass)
        assert await hass.config_entries.async_setup(entry.entry_id)
        await hass.async_block_till_done()
        entity_id = er.async_get(hass).async_get_entity_id(
            "switch", DOMAIN, f"{entry.unique_id}_{RELAY}"
        )
        assert entity_id is not None
        return [
            await _write_ms(hass, entity_id, on=index % 2 == 0)
            for index in range(samples)
        ]


async def _write_ms(hass: HomeAssistant, entity_id: str, *, on: bool) -> float:
    """One switch call, timed until the state machine shows the new state."""
    wanted = "on" if on else "off"
    shown = asyncio.Event()

    @callback
    def changed(event: Event[Any]) -> None:
        new = event.data.get("new_state")
        if event.data.get("entity_id") == entity_id and new and new.state == wanted:
            shown.set()

    unsubscribe = hass.bus.async_listen(EVENT_STATE_CHANGED, changed)
    started = time.perf_counter()
    try:
        await hass.services.async_call(
            "switch", "turn_on" if on else "turn_off", {"entity_id": entity_id}
        )
        await shown.wait()
        return (time.perf_counter() - started) * 1000
    finally:
        unsubscribe()


def report(figures: Sequence[PollFigures], writes: Sequence[float]) -> str:
    """The figures as markdown."""
    lines = [
        "### Mervis: requests and CPU per poll (ours vs a naive client)",
        "",
        (
            "| variables | CommUids | ours: requests/poll | lower bound "
            "| naive: requests/poll | ours: CPU ms/poll | naive: CPU ms/poll |"
        ),
        "|---:|---:|---:|---:|---:|---:|---:|",
    ]
    lines.extend(
        f"| {item.variables} | {item.commuids} | {item.ours} | {item.lower_bound} "
        f"| {item.naive} | {item.ours_cpu_ms:.2f} | {item.naive_cpu_ms:.2f} |"
        for item in figures
    )
    if writes:
        ordered = sorted(writes)
        lines += [
            "",
            "### Mervis: a write shown in Home Assistant",
            "",
            (
                f"{len(writes)} switch writes: median "
                f"{statistics.median(ordered):.1f} ms, max {ordered[-1]:.1f} ms "
                f"(budget {WRITE_BUDGET_MS:.0f} ms: "
                f"{'met' if ordered[-1] <= WRITE_BUDGET_MS else 'NOT met'})"
            ),
        ]
    return "\n".join(lines)


async def run(sizes: Sequence[int], polls: int, samples: int) -> str:
    """Measure everything; return the report."""
    figures = [await measure_polls(size, polls) for size in sizes]
    writes = await measure_writes(samples) if samples else []
    return report(figures, writes)


def main(argv: Sequence[str]) -> int:
    """Entry point of ``scripts/bench mervis``."""
    parser = argparse.ArgumentParser(
        prog="scripts/bench mervis",
        description="Mervis: requests and CPU per poll against a naive client, "
        "and the time a write takes to show in Home Assistant.",
    )
    parser.add_argument("--quick", action="store_true", help="50 variables, 3 polls")
    parser.add_argument("--polls", type=int, default=None, help="polls per figure (20)")
    parser.add_argument("--writes", type=int, default=None, help="write samples (20)")
    args = parser.parse_args(argv)
    sizes = (50,) if args.quick else SIZES
    polls = args.polls or (3 if args.quick else 20)
    samples = args.writes if args.writes is not None else (3 if args.quick else 20)
    print(asyncio.run(run(sizes, polls, samples)))
    return 0
