"""Home Assistant figures for one program: discovery, CPU and state writes per poll,
memory per entity and write latency, with a real `hass` and every entity enabled.

CPU is the CPU time of Home Assistant's event-loop thread (`time.thread_time`) from
the start of a coordinator refresh until Home Assistant is idle again: the poll's
client work, the coordinator and the entities' state writes. The simulated PLC runs on
its own thread and is not counted; `time.process_time` (which would count it) is
recorded alongside. The transport floor is the CPU of the same requests the poll sent,
alone: its plan's GetObject requests and, where the poll read GetInfo too (a quiet poll
checks the PLC still runs), a GetInfo; each sent and decoded by the client as the poll
sends and decodes it, nothing mapped to points. It is what any client reading the same
values in as few requests pays, before Home Assistant sees a value; the GetObject
requests' part of it is recorded alongside.
Times are means per poll, with the garbage collector paused while a poll is measured
(it runs between polls), so a collection does not land on one side of the comparison.
"""

from collections.abc import Iterator
from contextlib import contextmanager, nullcontext
from dataclasses import dataclass, field, replace
import gc
import statistics
import time
from typing import Any, Final
from unittest.mock import patch

from homeassistant.components.number import (
    ATTR_MAX,
    ATTR_MIN,
    ATTR_VALUE,
    DOMAIN as NUMBER_DOMAIN,
)
from homeassistant.components.number.const import SERVICE_SET_VALUE
from homeassistant.const import ATTR_ENTITY_ID, EVENT_STATE_CHANGED
from homeassistant.core import Event, HomeAssistant, callback
from homeassistant.helpers import entity_registry as er
from homeassistant.helpers.entity_platform import async_get_platforms
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.tecoapi import coordinator as coordinator_module
from custom_components.tecoapi.const import DOMAIN, STATUS_KEYS
from custom_components.tecoapi.coordinator import PlcCoordinator
from custom_components.tecoapi.data import PlcData, updated_data
from custom_components.tecoapi.pyplc import ValueKind
from custom_components.tecoapi.pyplc.tecomat.points import value_path
from custom_components.tecoapi.pyplc.tecomat.tecoapi.source import TecoApiSession

from .changes import ValueChanger, changes_in_poll
from .home_assistant import (
    StateWrites,
    all_entities_enabled,
    bench_entry,
    bench_home_assistant,
    counting_state_writes,
)
from .plc_thread import PlcThread


@dataclass(frozen=True, slots=True, kw_only=True)
class DiscoveryFigures:
    """From an empty config entry to every entity created."""

    requests: int
    ms: float
    entities: int
    point_entities: int


@dataclass(frozen=True, slots=True, kw_only=True)
class PollCost:
    """What one way of telling entities about a poll costs, per poll."""

    cpu_ms: float
    update_cpu_ms: float
    process_cpu_ms: float
    wall_ms: float
    state_writes: float
    state_changes: float
    requests: float


@dataclass(frozen=True, slots=True, kw_only=True)
class CpuFigures:
    """Ours (per-key updates) and the every-entity baseline at one change rate."""

    percent: float
    changed_points: float
    # Entities that show one of the changed points (a typed entity and the raw entity
    # of the same variable both do): what a poll that tells only them writes.
    fed_entities: float
    ours: PollCost
    baseline: PollCost
    transport_cpu_ms: float
    """The floor: the poll's requests alone (its GetObject requests, and its GetInfo)."""
    get_object_cpu_ms: float
    """The floor's GetObject requests alone."""

    @property
    def floor_ratio(self) -> float:
        """Our CPU per poll against the transport floor's (1.0: the floor itself)."""
        return self.ours.cpu_ms / self.transport_cpu_ms

    @property
    def cpu_ratio(self) -> float:
        """Our CPU per poll as a share of the baseline's."""
        return self.ours.cpu_ms / self.baseline.cpu_ms

    @property
    def update_cpu_ratio(self) -> float:
        """Our CPU telling entities about a poll as a share of the baseline's."""
        return self.ours.update_cpu_ms / self.baseline.update_cpu_ms


@dataclass(frozen=True, slots=True, kw_only=True)
class WriteFigures:
    """A `number.set_value` call until the PLC and the entity hold the new value."""

    entity_id: str
    samples: int
    shown_requests: float
    shown_ms: float
    call_requests: float
    call_ms: float
    plc_held_every_value: bool


@dataclass(frozen=True, slots=True, kw_only=True)
class MemoryFigures:
    """Memory the entry's setup added, in a fresh process (see `memory`).

    The traced Python heap it kept, and how far it raised the process's peak
    resident set size (never negative).
    """

    entities: int
    traced_bytes: int
    peak_resident_growth_bytes: int

    def per_thousand(self, amount: int) -> float:
        """MiB per 1000 entities."""
        return amount / max(1, self.entities) * 1000 / 2**20


@dataclass(frozen=True, slots=True, kw_only=True)
class IntegrationFigures:
    """Everything measured with Home Assistant for one program."""

    discovery: DiscoveryFigures
    cpu: tuple[CpuFigures, ...]
    write: WriteFigures | None
    memory: MemoryFigures


@dataclass(frozen=True, slots=True, kw_only=True)
class Credentials:
    """The simulated PLC's TecoApi user."""

    username: str
    password: str


CREDENTIALS: Final = Credentials(username="bench", password="bench-Pa55word")


@contextmanager
def every_entity_told() -> Iterator[None]:
    """The baseline: every entity writes its state on every poll.

    That is what a plain `CoordinatorEntity` does. Here each poll's data says that
    every key changed, so every entity passes its check and writes its state (the
    check itself, a set lookup, is the only difference left to a plain one).
    """
    every_key: dict[int, frozenset[str]] = {}

    def everything_changed(*args: Any, **kwargs: Any) -> PlcData:
        data = updated_data(*args, **kwargs)
        keys = every_key.get(id(data.selection))
        if keys is None:
            keys = every_key[id(data.selection)] = data.selection.watched | STATUS_KEYS
        return replace(data, changed=keys)

    with patch.object(coordinator_module, "updated_data", everything_changed):
        yield


@contextmanager
def timing_entity_updates(coordinator: PlcCoordinator) -> Iterator[list[float]]:
    """CPU seconds of each `async_update_listeners` call: the entities' share of a poll.

    It is where entities are told and write their state; it dispatches to whatever
    the class holds, so it measures the baseline too.
    """
    spent: list[float] = []

    @callback
    def timed() -> None:
        started = time.thread_time()
        type(coordinator).async_update_listeners(coordinator)
        spent.append(time.thread_time() - started)

    with patch.object(coordinator, "async_update_listeners", timed):
        yield spent


@contextmanager
def collector_paused() -> Iterator[None]:
    """Pause the garbage collector while a measurement runs (it runs between them)."""
    gc.disable()
    try:
        yield
    finally:
        gc.enable()


async def setup_bench_entry(
    hass: HomeAssistant, plc: PlcThread, credentials: Credentials
) -> MockConfigEntry:
    serial = await plc.call(lambda simulator: simulator.serial_number)
    entry = bench_entry(plc.url, credentials.username, credentials.password, serial)
    entry.add_to_hass(hass)
    with all_entities_enabled():
        if not await hass.config_entries.async_setup(entry.entry_id):
            raise RuntimeError(f"the entry did not set up: {entry.state}")
        await hass.async_block_till_done()
    return entry


async def _refresh(hass: HomeAssistant, coordinator: PlcCoordinator) -> None:
    await coordinator.async_refresh()
    await hass.async_block_till_done()
    if not coordinator.last_update_success:
        raise RuntimeError(f"a poll failed: {coordinator.last_exception}")


@dataclass(slots=True)
class _Series:
    """Samples of one way of telling entities about polls."""

    cpu: list[float] = field(default_factory=list)
    update_cpu: list[float] = field(default_factory=list)
    process_cpu: list[float] = field(default_factory=list)
    wall: list[float] = field(default_factory=list)
    changed: int = 0
    fed: int = 0
    writes: int = 0
    changes: int = 0
    requests: int = 0

    def cost(self) -> PollCost:
        """Means per poll (a fractional change rate makes polls differ on purpose)."""
        polls = len(self.wall)
        return PollCost(
            cpu_ms=statistics.fmean(self.cpu) * 1000,
            update_cpu_ms=statistics.fmean(self.update_cpu) * 1000,
            process_cpu_ms=statistics.fmean(self.process_cpu) * 1000,
            wall_ms=statistics.fmean(self.wall) * 1000,
            state_writes=self.writes / polls,
            state_changes=self.changes / polls,
            requests=self.requests / polls,
        )


def _entities_showing(hass: HomeAssistant, keys: frozenset[str]) -> int:
    """How many of the integration's entities show one of the points `keys`."""
    return sum(
        not keys.isdisjoint(getattr(entity, "_watched", frozenset()))
        for platform in async_get_platforms(hass, DOMAIN)
        for entity in platform.entities.values()
    )


async def _poll_once(
    hass: HomeAssistant,
    plc: PlcThread,
    coordinator: PlcCoordinator,
    *,
    changer: ValueChanger,
    count: int,
    counts: StateWrites,
    series: _Series,
) -> int:
    """Change `count` values in the PLC, then poll once and add the sample.

    Returns the requests the poll sent.
    """
    change = await plc.call(lambda simulator: changer.change(simulator, count))
    if len(change.written) != count:
        raise RuntimeError(f"changed {len(change.written)} values, wanted {count}")
    before = (counts.writes, counts.changes, len(plc.requests))
    # The entity updates' timer is put in place (a mock's patch) before the clocks
    # start and taken away after they stop: the benchmark's own tools are not the
    # poll's cost.
    with collector_paused(), timing_entity_updates(coordinator) as updates:
        started = (time.thread_time(), time.process_time(), time.perf_counter())
        await _refresh(hass, coordinator)
        # Read the clocks before the collector runs again: the collection the poll's
        # garbage triggers belongs between polls, not to whichever poll ran last.
        ended = (time.thread_time(), time.process_time(), time.perf_counter())
    series.update_cpu.append(sum(updates))
    series.cpu.append(ended[0] - started[0])
    series.process_cpu.append(ended[1] - started[1])
    series.wall.append(ended[2] - started[2])
    series.changed += count
    series.fed += _entities_showing(hass, change.changed)
    series.writes += counts.writes - before[0]
    series.changes += counts.changes - before[1]
    requests = len(plc.requests) - before[2]
    series.requests += requests
    return requests


async def _cpu_figures(
    hass: HomeAssistant,
    plc: PlcThread,
    coordinator: PlcCoordinator,
    *,
    percents: tuple[float, ...],
    polls: int,
    seed: int,
) -> tuple[CpuFigures, ...]:
    """Ours and the baseline at each change rate, their polls interleaved.

    Interleaving (and alternating which goes first) keeps drift in the process --
    caches warming, the heap growing -- from favouring either.
    """
    changer = ValueChanger(coordinator.data.points.values(), seed=seed)
    points = len(coordinator.data.points)
    figures = []
    with counting_state_writes(hass) as counts:
        for percent in percents:
            ours, baseline = _Series(), _Series()
            transport: list[tuple[float, float]] = []
            gc.collect()
            for index in range(polls):
                count = min(changer.changeable, changes_in_poll(points, percent, index))
                turns = [(ours, False), (baseline, True)]
                sent = {}
                for series, every_entity in turns[:: 1 if index % 2 == 0 else -1]:
                    with every_entity_told() if every_entity else nullcontext():
                        sent[every_entity] = await _poll_once(
                            hass,
                            plc,
                            coordinator,
                            changer=changer,
                            count=count,
                            counts=counts,
                            series=series,
                        )
                transport.append(await transport_cpu(coordinator, sent[False]))
            figures.append(
                CpuFigures(
                    percent=percent,
                    changed_points=ours.changed / polls,
                    fed_entities=ours.fed / polls,
                    ours=ours.cost(),
                    baseline=baseline.cost(),
                    transport_cpu_ms=statistics.fmean(t for t, _ in transport) * 1000,
                    get_object_cpu_ms=statistics.fmean(g for _, g in transport) * 1000,
                )
            )
    return tuple(figures)


async def transport_cpu(
    coordinator: PlcCoordinator, requests: int
) -> tuple[float, float]:
    """CPU seconds of the requests a poll sent, alone; and of its GetObject requests.

    The value plan's GetObject requests, each sent and decoded as the poll does
    (:meth:`TecoApiClient.get_planned`), then a GetInfo where the poll sent
    ``requests`` one more than the plan (a quiet poll's check that the PLC
    runs), until Home Assistant is idle, as a poll is measured. The floor of any
    client reading these values in this many requests; nothing is mapped to
    points and Home Assistant is not told.
    """
    source = coordinator.source
    if not isinstance(source, TecoApiSession):
        raise TypeError("the transport floor is measured for TecoApi")
    plan = source.read_plan
    if plan is None:
        raise RuntimeError("no read plan yet: poll before measuring the transport")
    extra = requests - len(plan.requests)
    if extra not in (0, 1):
        raise RuntimeError(
            f"a poll sent {requests} requests for a plan of {len(plan.requests)}"
        )
    client = source.client
    with collector_paused():
        started = time.thread_time()
        for request in plan.requests:
            await client.get_planned(request)
        read = time.thread_time()
        if extra:
            await client.get_info()
        await coordinator.hass.async_block_till_done()
        return time.thread_time() - started, read - started


def _number_to_write(
    hass: HomeAssistant, entry: MockConfigEntry
) -> tuple[str, str] | None:
    """A number entity with a numeric state, and its point's key."""
    registry = er.async_get(hass)
    prefix = f"{entry.unique_id}_"
    for registry_entry in er.async_entries_for_config_entry(registry, entry.entry_id):
        if registry_entry.domain != NUMBER_DOMAIN:
            continue
        state = hass.states.get(registry_entry.entity_id)
        if state is None:
            continue
        try:
            float(state.state)
        except ValueError:
            continue
        return registry_entry.entity_id, registry_entry.unique_id.removeprefix(prefix)
    return None


async def _write_figures(
    hass: HomeAssistant,
    plc: PlcThread,
    entry: MockConfigEntry,
    coordinator: PlcCoordinator,
    samples: int,
) -> WriteFigures | None:
    """Time `number.set_value` until the entity shows the value and until it returns.

    The call returns after the coordinator's write path: the write, the entity
    showing the acknowledged value, and the refresh it requests.
    """
    target = _number_to_write(hass, entry)
    if target is None:
        return None
    entity_id, key = target
    point = coordinator.data.points[key]
    shown: list[tuple[float, int]] = []
    wanted: list[float] = []

    @callback
    def state_changed(event: Event[Any]) -> None:
        new_state = event.data["new_state"]
        if event.data["entity_id"] != entity_id or new_state is None:
            return
        try:
            if float(new_state.state) == wanted[-1]:
                shown.append((time.perf_counter(), len(plc.requests)))
        except ValueError:
            return

    shown_ms: list[float] = []
    shown_requests: list[int] = []
    call_ms: list[float] = []
    call_requests: list[int] = []
    held = True
    unsubscribe = hass.bus.async_listen(EVENT_STATE_CHANGED, state_changed)
    try:
        for _ in range(samples):
            state = hass.states.get(entity_id)
            assert state is not None
            minimum, maximum = state.attributes[ATTR_MIN], state.attributes[ATTR_MAX]
            value = maximum if float(state.state) != maximum else minimum
            if point.kind is ValueKind.INTEGER:
                value = int(value)
            wanted.append(float(value))
            shown.clear()
            # Each sample starts outside the refresh debouncer's cooldown.
            coordinator._debounced_refresh.async_cancel()
            requests = len(plc.requests)
            started = time.perf_counter()
            await hass.services.async_call(
                NUMBER_DOMAIN,
                SERVICE_SET_VALUE,
                {ATTR_ENTITY_ID: entity_id, ATTR_VALUE: value},
                blocking=True,
            )
            call_ms.append((time.perf_counter() - started) * 1000)
            call_requests.append(len(plc.requests) - requests)
            await hass.async_block_till_done()
            if not shown:
                raise RuntimeError(f"{entity_id} never showed {value}")
            shown_ms.append((shown[0][0] - started) * 1000)
            shown_requests.append(shown[0][1] - requests)
            plc_value = await plc.call(
                lambda simulator: simulator.get_value(value_path(point))
            )
            held = held and float(plc_value) == float(value)
    finally:
        unsubscribe()
    return WriteFigures(
        entity_id=entity_id,
        samples=samples,
        shown_requests=statistics.fmean(shown_requests),
        shown_ms=statistics.median(shown_ms),
        call_requests=statistics.fmean(call_requests),
        call_ms=statistics.median(call_ms),
        plc_held_every_value=held,
    )


async def measure_integration(
    plc: PlcThread,
    credentials: Credentials,
    *,
    polls: int,
    percents: tuple[float, ...],
    write_samples: int,
    memory: MemoryFigures,
    seed: int = 0,
) -> IntegrationFigures:
    """Set up the PLC's entry in a real Home Assistant and measure it.

    ``memory`` is measured beforehand in a fresh process (`memory.measure`).
    """
    async with bench_home_assistant() as hass:
        gc.collect()
        requests = len(plc.requests)
        started = time.perf_counter()
        entry = await setup_bench_entry(hass, plc, credentials)
        discovery_ms = (time.perf_counter() - started) * 1000
        discovery_requests = len(plc.requests) - requests
        coordinator: PlcCoordinator = entry.runtime_data
        entities = len(
            er.async_entries_for_config_entry(er.async_get(hass), entry.entry_id)
        )
        discovery = DiscoveryFigures(
            requests=discovery_requests,
            ms=discovery_ms,
            entities=entities,
            point_entities=len(coordinator.data.points),
        )
        # The first refresh shows discovery's values; the next ones poll the plan.
        await _refresh(hass, coordinator)
        await _refresh(hass, coordinator)
        cpu = await _cpu_figures(
            hass, plc, coordinator, percents=percents, polls=polls, seed=seed
        )
        write = await _write_figures(hass, plc, entry, coordinator, write_samples)
    return IntegrationFigures(discovery=discovery, cpu=cpu, write=write, memory=memory)


async def warm_up(plc: PlcThread, credentials: Credentials) -> None:
    """Set up an entry once, so imports and caches do not count as the first's cost."""
    async with bench_home_assistant() as hass:
        entry = await setup_bench_entry(hass, plc, credentials)
        await _refresh(hass, entry.runtime_data)
