"""The contract every source passes: TecoApi, PLCComS, Mervis, the FP-I4C, Tekon, memory.

Whatever a source speaks, a caller (Home Assistant) relies on the same things:

- ``identify()`` tells who the device is (an identity, a name, a manufacturer);
- the first ``poll()`` lists the catalogue: every point has a key, a path, an
  address and a data type, and each value it read has the Python type of its
  kind (a source that subscribes reads only what is polled);
- a later ``poll(polled)`` reads the polled points and nothing else, and shows
  what the device holds now;
- ``write()`` checks a value before anything is sent (read-only, range, kind:
  each its own exception, the device unchanged), writes a good one, tells its
  subscribers at once and shows it in the next poll;
- ``write_many()`` checks every value of a batch first (one refused: that
  error, nothing sent, the source's public ``check_write`` refusing it alone),
  writes them all in the requests its protocol allows (counted), tells its
  subscribers and shows them in the next poll;
- a source that pushes (``Capability.PUSH``) tells its subscribers of a change
  on the device without a poll;
- ``check_points()`` on a source not polled yet reads the points it is given:
  a source of a map passes its map's points, every source refuses a key it does
  not have, as not found;
- failures are exceptions of the core by class: nothing answering is a
  ``PlcConnectionError``.

Each source runs against its real peer: the simulated PLC over HTTP, its
PLCComS server over TCP, the simulated Mervis controller over HTTP (its map the
house's ``.vlist``, a setpoint marked writable as a user marks it), the simulated
FP-I4C and Tekon gateways over HTTP, a memory device.
"""

from collections.abc import AsyncIterator, Awaitable, Callable
import contextlib
from dataclasses import dataclass, replace
from datetime import date, datetime, timedelta
import socket
from typing import Any

import aiohttp
import pytest

from custom_components.tecoapi.pyplc import (
    Access,
    InvalidValueError,
    OutOfRangeError,
    PlcConnectionError,
    PlcSource,
    Point,
    ReadOnlyError,
    Record,
    Snapshot,
    ValueKind,
)
from custom_components.tecoapi.pyplc.core.codec import to_raw
from custom_components.tecoapi.pyplc.core.descriptor import Capability
from custom_components.tecoapi.pyplc.core.pointmap import load_csv
from custom_components.tecoapi.pyplc.core.registry import sources
from custom_components.tecoapi.pyplc.core.source import NOT_FOUND, BaseSource
from custom_components.tecoapi.pyplc.mervis import MervisClient, MervisSource
from custom_components.tecoapi.pyplc.mervis.vlist import load_vlist
from custom_components.tecoapi.pyplc.panasonic import (
    FpI4cClient,
    FpI4cSource,
    check_point,
)
from custom_components.tecoapi.pyplc.panasonic.address import wire_type
from custom_components.tecoapi.pyplc.panasonic.descriptor import FPI4C
from custom_components.tecoapi.pyplc.tecomat import (
    PlcComsClient,
    PlcComsSource,
    TecoApiClient,
    TecoApiSession,
)
from custom_components.tecoapi.pyplc.tecomat.points import value_path
from custom_components.tecoapi.pyplc.tekon import TekonClient, TekonSource
from tests.conftest import SIM_PASSWORD, SIM_USERNAME
from tests.fake_source import (
    MEMORY,
    MemoryDevice,
    MemorySource,
    house_device,
    house_map,
)
from tests.pyplc.conftest import Heard
from tests.simulator import Simulator
from tests.simulator.fpi4c import EXAMPLE_CSV, FpI4cSimulator, demo_stations
from tests.simulator.mervis import MervisSimulator
from tests.simulator.plccoms import PlcComsServer
from tests.simulator.tekon import TekonGateway

PYTHON_TYPES: dict[ValueKind, tuple[type, ...]] = {
    ValueKind.BOOL: (bool,),
    ValueKind.INTEGER: (int,),
    ValueKind.REAL: (float,),
    ValueKind.STRING: (str,),
    ValueKind.DATE: (date,),
    ValueKind.TIME: (timedelta,),
    ValueKind.DATETIME: (datetime,),
    ValueKind.DURATION: (timedelta,),
    ValueKind.RECORD: (Record,),
}


@dataclass
class Harness:
    """A source under test and what the test needs to know of its device."""

    source: PlcSource
    capabilities: frozenset[Capability]
    set_raw: Callable[[Point, Any], Awaitable[None]]
    """Change a point's value on the device (as the device itself would; the
    value as shown, the device's own units being the harness's business)."""
    get_raw: Callable[[Point], Any]
    """What the device holds for a point."""
    unreachable: Callable[[], PlcSource]
    """A source of the same kind where nothing answers."""
    requests: Callable[[], int]
    """The requests the source sent so far, as it counts them on its wire."""
    batch_requests: int
    """The requests a batch of two writes takes, read-backs included (native)."""


def _closed_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        port: int = probe.getsockname()[1]
    return port


def _capabilities(name: str) -> frozenset[Capability]:
    return next(item.capabilities for item in sources() if item.name == name)


@contextlib.asynccontextmanager
async def _tecoapi() -> AsyncIterator[Harness]:
    async with aiohttp.ClientSession() as http:
        sim = Simulator("demo", username=SIM_USERNAME, password=SIM_PASSWORD)
        await sim.start()
        try:
            source = TecoApiSession(
                TecoApiClient(http, sim.url, SIM_USERNAME, SIM_PASSWORD)
            )

            async def set_raw(point: Point, value: Any) -> None:
                sim.set_value(value_path(point), value)

            def unreachable() -> PlcSource:
                return TecoApiSession(
                    TecoApiClient(
                        http,
                        f"127.0.0.1:{_closed_port()}",
                        SIM_USERNAME,
                        SIM_PASSWORD,
                        timeout=2,
                    )
                )

            yield Harness(
                source,
                _capabilities("tecoapi"),
                set_raw,
                lambda point: sim.get_value(value_path(point)),
                unreachable,
                lambda: source.client.request_count,
                # One SetObject of both members, one GetObject of both.
                2,
            )
            await source.close()
        finally:
            await sim.stop()


@contextlib.asynccontextmanager
async def _plccoms() -> AsyncIterator[Harness]:
    sim = Simulator("demo", username=SIM_USERNAME, password=SIM_PASSWORD)
    async with PlcComsServer(sim, scan_interval=None) as coms:
        source = PlcComsSource(
            PlcComsClient("127.0.0.1", coms.port, timeout=2, reconnect_delay=0.01)
        )

        async def set_raw(point: Point, value: Any) -> None:
            sim.set_value(value_path(point), value)
            await coms.scan()

        def unreachable() -> PlcSource:
            return PlcComsSource(PlcComsClient("127.0.0.1", _closed_port(), timeout=2))

        try:
            yield Harness(
                source,
                _capabilities("plccoms"),
                set_raw,
                lambda point: sim.get_value(value_path(point)),
                unreachable,
                lambda: source.client.health.lines_sent,
                # Two SET: lines and their barrier in one exchange, two GET: back.
                5,
            )
        finally:
            await source.close()


@contextlib.asynccontextmanager
async def _memory() -> AsyncIterator[Harness]:
    device = house_device("MEM-CONTRACT")
    source = MemorySource(device, house_map())

    async def set_raw(point: Point, value: Any) -> None:
        source.push_value(point.address, to_raw(point, value))

    def unreachable() -> PlcSource:
        return MemorySource(
            MemoryDevice(fail=PlcConnectionError("nothing answers")), house_map()
        )

    yield Harness(
        source,
        MEMORY.capabilities,
        set_raw,
        lambda point: device.values[point.address],  # raw: compared with itself
        unreachable,
        lambda: device.requests,
        # A memory device takes each write in a request of its own.
        2,
    )
    await source.close()


@contextlib.asynccontextmanager
async def _fpi4c() -> AsyncIterator[Harness]:
    async with (
        aiohttp.ClientSession() as http,
        FpI4cSimulator(demo_stations(), station=1) as gateway,
    ):
        point_map = load_csv(EXAMPLE_CSV.read_text(encoding="utf-8"), check_point)
        source = FpI4cSource(
            FpI4cClient(http, gateway.url), point_map, identity="contract"
        )

        def where(point: Point) -> tuple[int, str, str]:
            wire = wire_type(point.type)
            assert wire is not None
            return int(point.device.removeprefix("station_")), point.address, wire

        async def set_raw(point: Point, value: Any) -> None:
            station, address, wire = where(point)
            gateway.set(station, address, wire, to_raw(point, value))

        def unreachable() -> PlcSource:
            client = FpI4cClient(http, f"127.0.0.1:{_closed_port()}", timeout=2)
            return FpI4cSource(client, point_map, identity="contract")

        yield Harness(
            source,
            FPI4C.capabilities,
            set_raw,
            lambda point: gateway.get(*where(point)),
            unreachable,
            lambda: source.client.statistics.posts,
            # Both writes, their read-backs and DT0 in one POST.
            1,
        )
        await source.close()


@contextlib.asynccontextmanager
async def _tekon() -> AsyncIterator[Harness]:
    async with aiohttp.ClientSession() as http, TekonGateway() as gateway:
        source = TekonSource(TekonClient(http, gateway.url))

        async def set_raw(point: Point, value: Any) -> None:
            gateway.set_value(point.address, str(value))

        def unreachable() -> PlcSource:
            return TekonSource(
                TekonClient(http, f"127.0.0.1:{_closed_port()}", timeout=2)
            )

        try:
            yield Harness(
                source,
                _capabilities("tekon"),
                set_raw,
                lambda point: gateway.value(point.address),
                unreachable,
                lambda: source.client.request_count,
                # One WriteItemsValuesText of both (the values come with updates).
                1,
            )
        finally:
            await source.close()


@contextlib.asynccontextmanager
async def _mervis() -> AsyncIterator[Harness]:
    async with (
        aiohttp.ClientSession() as http,
        MervisSimulator(username=SIM_USERNAME, password=SIM_PASSWORD) as sim,
    ):
        point_map = load_vlist(sim.project.vlist())
        setpoint = point_map.by_key()["koupelna.setpoint"]
        point_map = point_map.with_point(
            replace(setpoint, access=Access.READ_WRITE, minimum=15.0, maximum=28.0)
        )
        # A second one marked writable, for a batch of two writes.
        other = point_map.by_key()["jidelna.setpoint"]
        point_map = point_map.with_point(
            replace(other, access=Access.READ_WRITE, minimum=15.0, maximum=28.0)
        )
        source = MervisSource(
            MervisClient(http, sim.url, SIM_USERNAME, SIM_PASSWORD), point_map
        )

        async def set_raw(point: Point, value: Any) -> None:
            sim.project.set(point.path, value)

        def unreachable() -> PlcSource:
            return MervisSource(
                MervisClient(http, f"127.0.0.1:{_closed_port()}", timeout=2), point_map
            )

        yield Harness(
            source,
            _capabilities("mervis"),
            set_raw,
            lambda point: sim.project.get(point.path),
            unreachable,
            lambda: source.client.request_count,
            # command.cgi takes one variable a request; one read of both back.
            3,
        )
        await source.close()


HARNESSES = {
    "tecoapi": _tecoapi,
    "plccoms": _plccoms,
    "memory": _memory,
    "fpi4c": _fpi4c,
    "tekon": _tekon,
    "mervis": _mervis,
}


@pytest.fixture(params=list(HARNESSES))
async def harness(
    request: pytest.FixtureRequest, socket_enabled: None
) -> AsyncIterator[Harness]:
    async with HARNESSES[request.param]() as found:
        yield found


async def _discovered(harness: Harness) -> Snapshot:
    await harness.source.identify()
    return await harness.source.poll(())


def _writable_number(snapshot: Snapshot) -> Point:
    """A writable number with a range (every source under test has one)."""
    return next(
        point
        for point in snapshot.catalogue.points.values()
        if point.writable
        and point.kind in (ValueKind.REAL, ValueKind.INTEGER)
        and point.attributes is not None
        and point.attributes.has_range
    )


def _read_only(snapshot: Snapshot) -> Point:
    return next(
        point
        for point in snapshot.catalogue.points.values()
        if point.attributes is not None and not point.attributes.writable
    )


async def _current(harness: Harness, snapshot: Snapshot, point: Point) -> Any:
    """What the device holds for a point: discovery's value, else a poll's."""
    if point.key in snapshot.values:
        return snapshot.values[point.key]
    return (await harness.source.poll(frozenset({point.key}))).values[point.key]


def _in_range(point: Point, current: float) -> float:
    assert point.attributes is not None
    assert point.attributes.minimum is not None
    assert point.attributes.maximum is not None
    low, high = point.attributes.minimum, point.attributes.maximum
    candidate = low if current != low else high
    return int(candidate) if point.kind is ValueKind.INTEGER else float(candidate)


async def test_identify_tells_who_the_device_is(harness: Harness) -> None:
    info = await harness.source.identify()
    assert info.identity
    assert info.name
    assert info.manufacturer
    assert info.running


async def test_the_first_poll_lists_typed_points(harness: Harness) -> None:
    snapshot = await _discovered(harness)
    points = snapshot.catalogue.points
    assert points
    for key, point in points.items():
        assert point.key == key
        assert point.path
        assert point.address
        assert point.type.kind is point.kind or point.scaled
        value = snapshot.values.get(key)
        if value is not None:
            assert isinstance(value, PYTHON_TYPES[point.kind]), (key, value)
    assert snapshot.missing == frozenset()


async def test_a_poll_reads_the_polled_points_as_the_device_holds_them(
    harness: Harness,
) -> None:
    snapshot = await _discovered(harness)
    point = _writable_number(snapshot)
    polled = frozenset({point.key})
    current = await _current(harness, snapshot, point)
    raw = _in_range(point, current)
    await harness.set_raw(point, raw)
    after = await harness.source.poll(polled)
    assert set(after.values) <= polled
    assert after.values[point.key] == pytest.approx(raw)


async def test_a_write_is_checked_sent_told_and_shown(harness: Harness) -> None:
    snapshot = await _discovered(harness)
    point = _writable_number(snapshot)
    polled = frozenset({point.key})
    current = await _current(harness, snapshot, point)
    told: list[Snapshot] = []
    unsubscribe = harness.source.subscribe(told.append)
    value = _in_range(point, current)
    await harness.source.write(point.key, value)
    unsubscribe()
    assert any(item.values.get(point.key) == pytest.approx(value) for item in told), (
        "a write tells the subscribers at once"
    )
    after = await harness.source.poll(polled)
    assert after.values[point.key] == pytest.approx(value)


async def test_a_refused_write_sends_nothing(harness: Harness) -> None:
    snapshot = await _discovered(harness)
    number, read_only = _writable_number(snapshot), _read_only(snapshot)
    before = (harness.get_raw(number), harness.get_raw(read_only))
    assert number.attributes is not None
    assert number.attributes.maximum is not None
    with pytest.raises(OutOfRangeError):
        await harness.source.write(number.key, number.attributes.maximum + 1000)
    with pytest.raises(InvalidValueError):
        await harness.source.write(number.key, "not a number")
    with pytest.raises(ReadOnlyError):
        await harness.source.write(
            read_only.key, await _current(harness, snapshot, read_only)
        )
    assert (harness.get_raw(number), harness.get_raw(read_only)) == before


def _second_writable(snapshot: Snapshot, first: Point) -> Point:
    """Another writable point: a number with a range, else a switch."""
    others = [
        point
        for point in snapshot.catalogue.points.values()
        if point.writable and point.key != first.key
    ]
    numbers = [
        point
        for point in others
        if point.kind in (ValueKind.REAL, ValueKind.INTEGER)
        and point.attributes is not None
        and point.attributes.has_range
    ]
    switches = [point for point in others if point.kind is ValueKind.BOOL]
    return [*numbers, *switches][0]


def _another(point: Point, current: Any) -> Any:
    """A value the point takes that differs from its current one."""
    if point.kind is ValueKind.BOOL:
        return not current
    return _in_range(point, current)


async def test_a_batch_writes_every_value_in_the_native_requests(
    harness: Harness,
) -> None:
    snapshot = await _discovered(harness)
    first = _writable_number(snapshot)
    second = _second_writable(snapshot, first)
    polled = frozenset({first.key, second.key})
    batch = {
        first.key: _another(first, await _current(harness, snapshot, first)),
        second.key: _another(second, await _current(harness, snapshot, second)),
    }
    told: list[Snapshot] = []
    unsubscribe = harness.source.subscribe(told.append)
    requests = harness.requests()
    confirmed = await harness.source.write_many(batch)
    assert harness.requests() - requests == harness.batch_requests
    unsubscribe()
    for key, value in batch.items():
        assert any(item.values.get(key) == pytest.approx(value) for item in told), (
            f"the batch tells the subscribers of {key} at once"
        )
    if confirmed is not None:
        assert {key: confirmed.values[key] for key in batch} == pytest.approx(batch)
    after = await harness.source.poll(polled)
    assert {key: after.values[key] for key in batch} == pytest.approx(batch)


@pytest.mark.parametrize("refusal", ["out_of_range", "wrong_kind", "read_only"])
async def test_a_batch_with_one_refused_value_sends_nothing(
    harness: Harness, refusal: str
) -> None:
    snapshot = await _discovered(harness)
    number, read_only = _writable_number(snapshot), _read_only(snapshot)
    other = _second_writable(snapshot, number)
    assert number.attributes is not None
    assert number.attributes.maximum is not None
    good = _another(other, await _current(harness, snapshot, other))
    error, batch = {
        "out_of_range": (
            OutOfRangeError,
            {other.key: good, number.key: number.attributes.maximum + 1000},
        ),
        "wrong_kind": (
            InvalidValueError,
            {other.key: good, number.key: "not a number"},
        ),
        "read_only": (
            ReadOnlyError,
            {
                number.key: _another(number, await _current(harness, snapshot, number)),
                read_only.key: await _current(harness, snapshot, read_only),
            },
        ),
    }[refusal]
    points = [snapshot.catalogue.points[key] for key in batch]
    before = [harness.get_raw(point) for point in points]
    requests = harness.requests()
    # The good value first: a batch that wrote in order would have sent it.
    with pytest.raises(error) as raised:
        await harness.source.write_many(batch)
    assert getattr(raised.value, "path", None), "the refusal names its point"
    # The source's own check refuses it alone, as its write does.
    source = harness.source
    assert isinstance(source, BaseSource)
    refused_key = next(reversed(batch))
    with pytest.raises(error):
        source.check_write(refused_key, batch[refused_key])
    with pytest.raises(error):
        await source.write(refused_key, batch[refused_key])
    for key, value in batch.items():
        if key != refused_key:
            source.check_write(key, value)
    assert harness.requests() == requests, "nothing was sent"
    assert [harness.get_raw(point) for point in points] == before


async def test_a_pushing_source_tells_of_a_change_without_a_poll(
    harness: Harness,
) -> None:
    if Capability.PUSH not in harness.capabilities:
        pytest.skip("the source does not push")
    snapshot = await _discovered(harness)
    point = _writable_number(snapshot)
    polled = frozenset({point.key})
    await harness.source.poll(polled)
    await harness.source.follow(polled)
    heard = Heard[Snapshot](harness.source.subscribe)
    polls = harness.source.statistics.polls
    raw = _in_range(point, snapshot.values[point.key])
    await harness.set_raw(point, raw)
    await heard.wait_for(lambda item: item.values.get(point.key) == pytest.approx(raw))
    heard.unsubscribe()
    assert harness.source.statistics.polls == polls


async def test_a_check_passes_the_device_s_points_and_refuses_others(
    harness: Harness,
) -> None:
    source = harness.source
    point_map = getattr(source, "point_map", None)
    keys = {point.key for point in point_map.points} if point_map else set()
    refused = await source.check_points({*keys, "no_such_point"})
    assert refused == {"no_such_point": NOT_FOUND}
    assert (Capability.POINT_MAP in harness.capabilities) == bool(keys)


async def test_nothing_answering_is_a_connection_error(harness: Harness) -> None:
    source = harness.unreachable()
    try:
        with pytest.raises(PlcConnectionError):
            await source.identify()
    finally:
        await source.close()
