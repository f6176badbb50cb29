"""The soak's sources: each one's simulator, entry, changing values and faults.

Each adapter switches on the faults its simulator documents
(``tests/simulator/README.md``), one at a time, and off again when the engine
(:mod:`.soak`) ends them:

- TecoApi: HTTP 500, dropped connections, truncated and malformed JSON (each for
  1-3 requests), latency spikes; Digest nonces go stale every few dozen uses.
- Mervis: limit refusals (the seed's uPLC limits, 5 variables and 1,500 bytes a
  request, while the fault lasts), session loss (every session expired), item
  errors (a CommUid answered with ``e``).
- FP-I4C: an offline station (it does not answer), a per-item error (61 on a
  register), lenient JSON (answers printed as the manual prints them), a limit
  error (a gateway taking one request a POST: every larger POST refused).
- Tekon: 409 (every session expired), 503 (the OPC server unavailable),
  configuration mode (every session closed, the address space described again),
  lost answers (carried out, the answer never arrives), bad quality (an item's
  quality 0x18, communication failure).
- PLCComS alone: a dropped connection (the server restarts), a program download
  (a new stamp), the PLC out of the server's reach (``ERROR:10`` to everything but
  ``GETINFO:``, as Teco's server 6.1 answers then).
"""

import asyncio
import csv
from dataclasses import replace
import random
from typing import Any, ClassVar, Final

from homeassistant.const import CONF_HOST, CONF_PORT, CONF_SCAN_INTERVAL
from homeassistant.core import HomeAssistant
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.tecoapi.const import CONF_TRANSPORT, DOMAIN, MAX_SCAN_INTERVAL
from custom_components.tecoapi.coordinator import PlcCoordinator
from custom_components.tecoapi.point_maps import async_save_point_map
from custom_components.tecoapi.pyplc import Point, ValueKind
from custom_components.tecoapi.pyplc.core.descriptor import (
    CONF_POINT_MAP,
    CONF_VERIFY_SSL,
)
from custom_components.tecoapi.pyplc.core.models import Access
from custom_components.tecoapi.pyplc.core.pointmap import PointMap, load_csv
from custom_components.tecoapi.pyplc.mervis.vlist import load_vlist
from custom_components.tecoapi.pyplc.panasonic import check_point
from custom_components.tecoapi.pyplc.panasonic.mapping import (
    address_identity,
    parse_station,
)
from custom_components.tecoapi.pyplc.tecomat import PlcComsSource
from custom_components.tecoapi.pyplc.tecomat.points import value_path
from custom_components.tecoapi.pyplc.tecomat.tecoapi.values import parse_value
from tests.simulator import Program, Simulator
from tests.simulator.fpi4c import EXAMPLE_CSV, FpI4cSimulator, demo_stations
from tests.simulator.fpi4c.server import MAX_REQUESTS
from tests.simulator.mervis import MervisSimulator, house
from tests.simulator.plccoms import PlcComsServer
from tests.simulator.tekon import TekonGateway
from tests.simulator.tekon.building import GOOD, VT_I4, VT_R4, VT_R8, VT_UI2, VT_UI4
from tests.waits import connected

from .changes import ValueChanger, changed_count
from .home_assistant import BENCH_OPTIONS, bench_entry
from .mervis import mervis_entry
from .programs import bench_program
from .soak import UNCHECKED, EndFault, SoakAdapter, SoakSettings

USERNAME: Final = "soak"
PASSWORD: Final = "soak-Pa55word"
NONCE_MAX_USES: Final = 40
LATENCY_SPIKE: Final = 0.2
TRANSPORT_FAULTS: Final = (
    "http_500",
    "drop_connection",
    "truncated_json",
    "malformed_json",
)
RECONNECT_WAIT: Final = 30.0
"""Seconds a PLCComS client may take to reconnect after a fault (its backoff)."""
BAD_QUALITY: Final = 0x18
"""OPC DA's bad quality, communication failure."""
UPLC_VARIABLES: Final = 5
UPLC_REQUEST_BYTES: Final = 1500
"""The seed's uPLC limits: variables a request, bytes a request."""
NUMBERS: Final = frozenset({VT_R4, VT_R8, VT_I4, VT_UI2, VT_UI4})
"""The Tekon value types the soak compares (as numbers)."""
QUIET_OPTIONS: Final = {CONF_SCAN_INTERVAL: int(MAX_SCAN_INTERVAL.total_seconds())}
"""A map source's options: polled only when the soak says so."""


def scaled(point: Point, raw: Any) -> Any:
    """A device's raw bool or number as a map source shows it (scale and offset)."""
    if isinstance(raw, bool):
        return raw if point.kind is ValueKind.BOOL else UNCHECKED
    if isinstance(raw, int | float) and point.kind in (
        ValueKind.INTEGER,
        ValueKind.REAL,
    ):
        return raw * point.scale + point.offset
    return UNCHECKED


def _changed_share(points: int, settings: SoakSettings) -> int:
    return changed_count(points, settings.change_percent)


# --- Tecomat: TecoApi, and PLCComS alone -------------------------------------------


class _Tecomat(SoakAdapter):
    """A simulated Tecomat PLC running a benchmark program (its values change)."""

    def __init__(self, settings: SoakSettings) -> None:
        super().__init__(settings)
        self.program = bench_program(settings.program, seed=settings.seed).program
        self.simulator = Simulator(
            self.program,
            username=USERNAME,
            password=PASSWORD,
            nonce_max_uses=NONCE_MAX_USES,
        )
        self._changer: ValueChanger | None = None
        self._count = 0

    @property
    def device(self) -> str:
        return f"program {self.settings.program}"

    def prepare(self, coordinator: PlcCoordinator, rng: random.Random) -> None:
        points = coordinator.data.points
        self._changer = ValueChanger(points.values(), seed=self.settings.seed)
        self._count = min(
            self._changer.changeable, _changed_share(len(points), self.settings)
        )

    def change(self, rng: random.Random) -> None:
        if self._changer is not None:
            self._changer.change(self.simulator, self._count)

    def held(self, point: Point) -> Any:
        return parse_value(point.kind, self.simulator.get_value(value_path(point)))


class TecoApiAdapter(_Tecomat):
    """TecoApi over HTTP with Digest, its transport faults and latency spikes."""

    source: ClassVar[str] = "tecoapi"
    faults: ClassVar[tuple[str, ...]] = (*TRANSPORT_FAULTS, "latency_spike")

    async def start(self) -> None:
        self.simulator.faults.latency = self.settings.latency_ms / 1000
        await self.simulator.start()

    async def stop(self) -> None:
        await self.simulator.stop()

    async def entry(self, hass: HomeAssistant) -> MockConfigEntry:
        simulator = self.simulator
        return bench_entry(simulator.url, USERNAME, PASSWORD, simulator.serial_number)

    async def inject(self, fault: str, rng: random.Random) -> EndFault | None:
        faults = self.simulator.faults
        if fault == "latency_spike":
            faults.latency = LATENCY_SPIKE
        else:
            setattr(faults, fault, True)
            faults.remaining = rng.randint(1, 3)
        return self._end

    async def _end(self) -> None:
        self.simulator.faults.clear()
        self.simulator.faults.latency = self.settings.latency_ms / 1000

    def settle(self) -> tuple[int, int]:
        requests = self.simulator.requests
        self.extras["Digest challenges"] += sum(
            1 for record in requests if record.status == 401
        )
        writes = sum(
            1
            for record in requests
            if record.service in ("SetObject", "PutObject")
            and record.status in (200, 204)
        )
        count = len(requests)
        self.simulator.clear_requests()
        return count, writes


class PlcComsAdapter(_Tecomat):
    """PLCComS alone (no TecoApi): its values pushed, its connection at fault."""

    source: ClassVar[str] = "plccoms"
    faults: ClassVar[tuple[str, ...]] = (
        "plc_unreachable",
        "program_download",
        "dropped_connection",
    )

    def __init__(self, settings: SoakSettings) -> None:
        super().__init__(settings)
        self.coms = PlcComsServer(self.simulator, scan_interval=None)
        # A download alternates between the program and a copy of another name
        # (another stamp): the same variables, their values back to the start.
        renamed = self.program.to_mapping()
        renamed["program"] = {**renamed.get("program", {}), "name": "SOAK_RELOADED"}
        self._programs = (Program.from_mapping(renamed), self.program)
        self._downloads = 0

    async def start(self) -> None:
        await self.coms.start()

    async def stop(self) -> None:
        await self.coms.stop()

    async def entry(self, hass: HomeAssistant) -> MockConfigEntry:
        return MockConfigEntry(
            domain=DOMAIN,
            title="Soak PLCComS",
            data={
                CONF_TRANSPORT: "plccoms",
                CONF_HOST: self.coms.host,
                CONF_PORT: self.coms.port,
            },
            options=dict(BENCH_OPTIONS),
        )

    async def before_poll(self) -> None:
        # PLCComS looks for changes (and pushes them) before each poll.
        await self.coms.scan()

    async def inject(self, fault: str, rng: random.Random) -> EndFault | None:
        if fault == "program_download":
            self.simulator.load_program(self._programs[self._downloads % 2])
            self._downloads += 1
            return None
        if fault == "plc_unreachable":
            self.coms.faults.plc_unreachable = True
            return self._end
        await self.coms.restart()
        return None

    async def _end(self) -> None:
        self.coms.faults.plc_unreachable = False

    async def after_fault(self, coordinator: PlcCoordinator) -> None:
        source = coordinator.source
        assert isinstance(source, PlcComsSource)
        await connected(source.client, RECONNECT_WAIT)

    def settle(self) -> tuple[int, int]:
        commands = self.coms.commands
        writes = sum(1 for line in commands if line.upper().startswith("SET:"))
        count = len(commands)
        commands.clear()
        return count, writes


# --- Mervis -------------------------------------------------------------------------


class MervisAdapter(SoakAdapter):
    """The demo cottage on a simulated Mervis controller, its setpoints writable."""

    source: ClassVar[str] = "mervis"
    faults: ClassVar[tuple[str, ...]] = ("limit_refusal", "session_loss", "item_error")

    def __init__(self, settings: SoakSettings) -> None:
        super().__init__(settings)
        self.simulator = MervisSimulator(house(), username=USERNAME, password=PASSWORD)
        self._changeable: list[Point] = []
        self._commuids: list[int] = []

    @property
    def device(self) -> str:
        return f"Mervis project {self.simulator.project.name}"

    async def start(self) -> None:
        await self.simulator.start()

    async def stop(self) -> None:
        await self.simulator.stop()

    def point_map(self) -> PointMap:
        """The project's map, its rooms' setpoints writable (as a user marks them)."""
        point_map = load_vlist(self.simulator.project.vlist())
        for point in point_map.points:
            if point.id.endswith(".setpoint"):
                point_map = point_map.with_point(
                    replace(point, access=Access.READ_WRITE)
                )
        return point_map

    async def entry(self, hass: HomeAssistant) -> MockConfigEntry:
        return await mervis_entry(
            hass, self.simulator.url, self.point_map(), (USERNAME, PASSWORD)
        )

    def prepare(self, coordinator: PlcCoordinator, rng: random.Random) -> None:
        points = coordinator.data.points.values()
        self._changeable = [
            point
            for point in points
            if point.kind is ValueKind.REAL
            and point.attributes is not None
            and point.attributes.access is not Access.READ_WRITE
        ]
        self._commuids = sorted(
            {int(point.details["commuid"]) for point in points if point.details}
        )

    def change(self, rng: random.Random) -> None:
        count = _changed_share(len(self._changeable), self.settings)
        for point in rng.sample(self._changeable, count):
            self.simulator.project.set(point.path, round(rng.uniform(-10, 40), 1))

    async def inject(self, fault: str, rng: random.Random) -> EndFault | None:
        switches = self.simulator.switches
        if fault == "session_loss":
            self.simulator.expire_sessions()
            return None
        if fault == "limit_refusal":
            switches.max_variables = UPLC_VARIABLES
            switches.max_request_size = UPLC_REQUEST_BYTES

            async def end_limits() -> None:
                switches.max_variables = switches.max_request_size = None

            return end_limits
        commuid = rng.choice(self._commuids)
        switches.item_errors.add(commuid)

        async def end_item_error() -> None:
            switches.item_errors.discard(commuid)

        return end_item_error

    def held(self, point: Point) -> Any:
        return scaled(point, self.simulator.project.get(point.path))

    def settle(self) -> tuple[int, int]:
        count, writes = len(self.simulator.requests), len(self.simulator.writes)
        self.simulator.clear_requests()
        self.simulator.writes.clear()
        return count, writes


# --- Panasonic FP-I4C ---------------------------------------------------------------


class FpI4cAdapter(SoakAdapter):
    """The demo's heating plant and garage door behind a simulated FP-I4C."""

    source: ClassVar[str] = "fpi4c"
    faults: ClassVar[tuple[str, ...]] = (
        "offline_station",
        "item_error",
        "lenient_json",
        "limit_error",
    )

    def __init__(self, settings: SoakSettings) -> None:
        super().__init__(settings)
        self.gateway = FpI4cSimulator(demo_stations())
        self._changeable: list[Point] = []
        self._rows: dict[str, tuple[str, str]] = {}
        """Each point's station (the map's device) and the gateway's type."""

    @property
    def device(self) -> str:
        return "FP-I4C example map (docs/fpi4c-example.csv), 2 stations"

    async def start(self) -> None:
        await self.gateway.start()

    async def stop(self) -> None:
        await self.gateway.stop()

    async def entry(self, hass: HomeAssistant) -> MockConfigEntry:
        text = EXAMPLE_CSV.read_text(encoding="utf-8")
        point_map = load_csv(text, check_point)
        rows = csv.DictReader(line for line in text.splitlines() if line[:1] != "#")
        types = {row["id"]: row["type"].upper() for row in rows}
        self._rows = {
            point.key: (point.device, types[point.id]) for point in point_map.points
        }
        return MockConfigEntry(
            domain=DOMAIN,
            title="FP-I4C",
            unique_id=address_identity(self.gateway.url, None, None),
            data={
                CONF_HOST: self.gateway.url,
                CONF_TRANSPORT: "fpi4c",
                CONF_POINT_MAP: await async_save_point_map(hass, point_map),
            },
            options=QUIET_OPTIONS,
        )

    def prepare(self, coordinator: PlcCoordinator, rng: random.Random) -> None:
        self._changeable = [
            point
            for point in coordinator.data.points.values()
            if point.kind in (ValueKind.INTEGER, ValueKind.REAL, ValueKind.BOOL)
            and point.attributes is not None
            and point.attributes.access is not Access.READ_WRITE
        ]

    def _station(self, point: Point) -> int:
        """The station of a point: the one its map row names, else the gateway's."""
        station, _ = parse_station(self._rows[point.key][0])
        return self.gateway.station if station is None else station

    def _read(self, point: Point) -> Any:
        """What the point's station holds at its address."""
        type_ = self._rows[point.key][1]
        return self.gateway.get(self._station(point), point.address, type_)

    def change(self, rng: random.Random) -> None:
        count = _changed_share(len(self._changeable), self.settings)
        for point in rng.sample(self._changeable, count):
            value = (
                not self._read(point)
                if point.kind is ValueKind.BOOL
                else rng.randint(0, 1000)
            )
            type_ = self._rows[point.key][1]
            self.gateway.set(self._station(point), point.address, type_, value)

    async def inject(self, fault: str, rng: random.Random) -> EndFault | None:
        gateway = self.gateway
        if fault == "offline_station":
            station = rng.choice(sorted(gateway.stations))
            gateway.silent.add(station)

            async def end_offline() -> None:
                gateway.silent.discard(station)

            return end_offline
        if fault == "item_error":
            registers = [p for p in self._changeable if p.kind is not ValueKind.BOOL]
            point = rng.choice(registers)
            where = (self._station(point), point.address)
            gateway.item_errors[where] = (61, "Data error")

            async def end_item_error() -> None:
                gateway.item_errors.pop(where, None)

            return end_item_error
        if fault == "lenient_json":
            gateway.lenient = True

            async def end_lenient() -> None:
                gateway.lenient = False

            return end_lenient
        gateway.max_requests = 1

        async def end_limit() -> None:
            gateway.max_requests = MAX_REQUESTS

        return end_limit

    def held(self, point: Point) -> Any:
        if point.kind not in (ValueKind.INTEGER, ValueKind.REAL, ValueKind.BOOL):
            return UNCHECKED
        return scaled(point, self._read(point))

    def settle(self) -> tuple[int, int]:
        posts = self.gateway.posts
        writes = sum(
            1
            for body in posts
            for request in body.get("req", ())
            if isinstance(request, dict) and "value" in request
        )
        count = len(posts)
        posts.clear()
        return count, writes


# --- Tekon ----------------------------------------------------------------------------


class TekonAdapter(SoakAdapter):
    """The demo building on a simulated Tekon OPC-HTTP gateway."""

    source: ClassVar[str] = "tekon"
    faults: ClassVar[tuple[str, ...]] = (
        "conflict_409",
        "unavailable_503",
        "configuration_mode",
        "lost_answers",
        "bad_quality",
    )

    def __init__(self, settings: SoakSettings) -> None:
        super().__init__(settings)
        self.gateway = TekonGateway()
        self._changeable: list[str] = []

    @property
    def device(self) -> str:
        return f"Tekon small building ({len(self.gateway.building.items)} items)"

    async def start(self) -> None:
        await self.gateway.start()

    async def stop(self) -> None:
        await self.gateway.stop()

    async def entry(self, hass: HomeAssistant) -> MockConfigEntry:
        return MockConfigEntry(
            domain=DOMAIN,
            title="ASUD.SCADA OPC-HTTP",
            data={
                CONF_HOST: self.gateway.url,
                CONF_VERIFY_SSL: True,
                CONF_TRANSPORT: "tekon",
            },
            options=QUIET_OPTIONS,
        )

    def prepare(self, coordinator: PlcCoordinator, rng: random.Random) -> None:
        by_name = self.gateway.building.by_name
        self._changeable = [
            point.address
            for point in coordinator.data.points.values()
            if (item := by_name.get(point.address)) is not None
            and item.vartype in (VT_R4, VT_R8)
            and not item.writable
        ]

    def change(self, rng: random.Random) -> None:
        count = _changed_share(len(self._changeable), self.settings)
        for name in rng.sample(self._changeable, count):
            self.gateway.set_value(name, f"{rng.uniform(-20, 40):.1f}")

    async def inject(self, fault: str, rng: random.Random) -> EndFault | None:
        gateway = self.gateway
        if fault == "conflict_409":
            gateway.expire_sessions()
            return None
        if fault == "configuration_mode":
            gateway.configuration_mode()
            return None
        if fault == "unavailable_503":
            gateway.opc_available = False

            async def end_unavailable() -> None:
                gateway.opc_available = True

            return end_unavailable
        if fault == "lost_answers":
            gateway.lost_answers = rng.randint(1, 3)

            async def end_lost() -> None:
                gateway.lost_answers = 0

            return end_lost
        name = rng.choice(self._changeable)
        gateway.set_value(name, quality=BAD_QUALITY)

        async def end_bad_quality() -> None:
            gateway.set_value(name, quality=GOOD)

        return end_bad_quality

    async def after_fault(self, coordinator: PlcCoordinator) -> None:
        # A failing gateway is asked again after the source's backoff (seconds,
        # doubling up to a minute; polls meanwhile fail without a request).
        backoff = coordinator.source.diagnostics()["requests"]["backoff_seconds"]
        await asyncio.sleep(backoff)

    def held(self, point: Point) -> Any:
        item = self.gateway.building.by_name.get(point.address)
        if item is None or item.quality != GOOD or item.vartype not in NUMBERS:
            return UNCHECKED
        return scaled(point, float(item.value))

    def settle(self) -> tuple[int, int]:
        count, writes = len(self.gateway.requests), len(self.gateway.writes)
        self.gateway.clear_requests()
        self.gateway.writes.clear()
        return count, writes


ADAPTERS: Final[dict[str, type[SoakAdapter]]] = {
    adapter.source: adapter
    for adapter in (
        TecoApiAdapter,
        MervisAdapter,
        FpI4cAdapter,
        TekonAdapter,
        PlcComsAdapter,
    )
}
