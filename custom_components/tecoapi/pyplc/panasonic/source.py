"""An FP-I4C gateway and the FP PLCs behind it as a source, its points a register map.

The gateway lists nothing: the points are the user's map (``core.pointmap``),
each a register or a bit (:mod:`.address`) of a station. Each station is a
device under the gateway's (``station_<n>``; the gateway's own configured
station, when neither the form nor the map names one, is ``plc``), so that a
station that stops answering takes its own entities only:

- a poll reads the polled points in the POSTs the planner makes
  (:mod:`.planner`: the fewest there can be), one station per POST;
- a failed item makes its points' values bad, with the PLC protocol's code
  (``err_code 61: ...``); nothing else suffers. A request fails as a whole
  when one of its addresses is one the PLC lacks: while its station answers
  other items, the read halves the failed request in one more POST a station
  (:data:`SEARCH_POSTS`: a read costs at most its plan's bound and one POST a
  station), and the next reads go on halving what still fails until the
  points that fail are alone; the others get their values as soon as a half
  of theirs reads. After the search only those points are read apart, each in
  a request of its own, the others as the planner plans them; a lone point
  that reads :data:`REJOIN_READS` times in a row joins its neighbours again,
  and a cut where no point failed (a failing address between two points, or
  an error that went away) is tried again after :data:`CUT_POLLS` polls. The
  code and the
  gateway's message of each point that fails are in its quality (``code``,
  ``reason``), in the diagnostics, and in the log once when it starts failing;
- a station whose every item failed (or whose POST the gateway refused, or
  that did not answer in time while others did) is *offline*, with the
  reason; its points come back with the first poll that reads them;
- nothing answering at all is a :class:`~..core.exceptions.PlcConnectionError`
  and a broken answer a response error: the poll fails, and the next good one
  brings everything back.

A write is checked by the core's codec (the type's integer bounds, a REAL's
range, a string's 1000 characters, the map's range, scale and offset turned
back), sent in one POST with its read-back (and DT0, which tells a value the
PLC refused from a PLC that does not answer), pushed at once, and returned
with what the PLC holds. A poll whose POSTs went out while a write was
acknowledged does not show its older value of the written point: a user's
write is never undone by the poll it overtook.
"""

from collections import defaultdict
from collections.abc import Collection, Iterable, Mapping
from dataclasses import asdict, dataclass, field, replace
import logging
import re
from typing import Any, Final, Unpack

from yarl import URL

from ..core.codec import check_write, to_raw, to_shown
from ..core.exceptions import (
    InvalidValueError,
    PlcConnectionError,
    PlcResponseError,
    ValueRejectedError,
    VariableNotFoundError,
)
from ..core.host import resolved_identity
from ..core.models import (
    Catalogue,
    DataType,
    DeviceNode,
    Point,
    PointQuality,
    Quality,
    SourceInfo,
    ValueKind,
)
from ..core.pointmap import (
    TYPE_NAMES,
    MapPoint,
    PointMap,
    PointMapError,
    map_catalogue,
)
from ..core.source import BaseSource, Snapshot, SourceSettings, counted
from .address import (
    MAX_STRING,
    AddressError,
    WireType,
    end_problem,
    kind_problem,
    parse_address,
    type_problem,
    wire_type,
)
from .client import (
    FpI4cClient,
    GatewayError,
    ItemAnswer,
    ItemError,
    PlcNotAnsweringError,
    StationNotAnsweringError,
    real_fits,
)
from .planner import (
    MAX_REQUESTS,
    Post,
    ReadPlan,
    ReadRequest,
    Target,
    covering,
    plan_reads,
)

_LOGGER = logging.getLogger(__name__)

MANUFACTURER: Final = "Panasonic"
MODEL: Final = "FP-I4C"
MAX_STATION: Final = 99
DEFAULT_DEVICE: Final = "plc"
"""The device of the points of the station the gateway is set to use."""
STRING_ENCODING: Final = "ascii"
"""What a string written takes: an FP string is bytes (8-bit text is not documented)."""
PROBE: Final[Mapping[str, Any]] = {"area": "DT", "type": "INT", "start": 0, "count": 1}
"""The harmless read that checks a station: DT0, which every FP PLC has."""
_PLANS_KEPT: Final = 8
SEARCH_POSTS: Final = 1
"""POSTs a read spends at most per station on halving failed requests, beyond
its plan's (the planner's bound): a request of 100 values is down to its single
failing value after ``ceil(log2(100))`` = 7 reads."""
REJOIN_READS: Final = 3
"""Good reads in a row after which a point read alone joins its neighbours."""
CUT_POLLS: Final = 30
"""Polls after which a cut no point failed at is tried again (dropped)."""

_STATION: Final = re.compile(r"([0-9]{1,2})(?:\s+(.*))?", re.DOTALL)


def parse_station(text: str) -> tuple[int | None, str]:
    """Return the station a map's ``device`` names, and the device's name.

    The cell is empty (the connection's station), or the station's number
    (0 … 99), optionally followed by a name: ``2``, ``2 Garage door``.
    """
    cleaned = text.strip()
    if not cleaned:
        return None, ""
    found = _STATION.fullmatch(cleaned)
    if found is None or int(found[1]) > MAX_STATION:
        raise PointMapError(
            f"{cleaned!r} is not a station: its number (0 to {MAX_STATION}), "
            "optionally followed by a name (2 Garage door)",
            column="device",
        )
    return int(found[1]), (found[2] or "").strip()


FPI4C_TYPES: Final = tuple(
    name for name, known in TYPE_NAMES.items() if wire_type(known) is not None
)
"""The type names a map may give an FP-I4C point: those the gateway reads."""


def check_point(point: MapPoint) -> str | None:
    """Check a map's point for an FP-I4C: its address, its type, length and station.

    Returns what is wrong with the address, or raises :class:`PointMapError`
    naming the column at fault (``type``, ``length``, ``device``).
    """
    try:
        address = parse_address(point.address)
    except AddressError as err:
        return str(err)
    wire = wire_type(point.type)
    if (problem := kind_problem(address, wire)) is not None:
        raise PointMapError(problem, column="type")
    if wire is not None and (problem := end_problem(address, wire)) is not None:
        return problem
    length = point.type.length
    if wire is not WireType.STRING and length is not None:
        raise PointMapError(
            "only a STRING has a length (its most characters)", column="length"
        )
    if length is not None and length > MAX_STRING:
        raise PointMapError(
            f"the FP-I4C writes strings of at most {MAX_STRING} characters",
            column="length",
        )
    parse_station(point.device)
    return None


def address_identity(base_url: str, interface: int | None, station: int | None) -> str:
    """Return the identity of a gateway added at an address: ``192.168.1.5:2000``.

    The gateway tells no serial number; the address it was added at (its
    REST port, and the interface and station the form named, as its GET
    form's ``I`` and ``A`` parameters) stays its identity (see the README).
    """
    url = URL(base_url)
    host = str(url.host)
    identity = f"[{host}]:{url.port}" if ":" in host else f"{host}:{url.port}"
    if interface is not None:
        identity += f"/I{interface}"
    if station is not None:
        identity += f"/A{station}"
    return identity


@dataclass(slots=True)
class _Reading:
    """What one read of points (a poll, a read-back) gathered."""

    values: dict[str, Any] = field(default_factory=dict)
    bad: dict[str, PointQuality] = field(default_factory=dict)
    answered: set[int | None] = field(default_factory=set)
    """Stations of which at least one item was answered."""
    failures: dict[int | None, str] = field(default_factory=dict)
    """Each station's first failure, as its reason."""
    errors: dict[str, ItemError] = field(default_factory=dict)
    """Each point's failed item."""
    failed: list[tuple[int | None, ReadRequest]] = field(default_factory=list)
    """The requests that failed (not yet halved), by station."""


class FpI4cSource(BaseSource):
    """An FP-I4C gateway and the stations behind it (see the module's docstring).

    ``station`` is the station of the map's points that name none (None: the
    one set in the gateway); ``identity`` what the entry knows the gateway by
    (None: a gateway being added, known by its address, its name resolved when
    it is identified).
    """

    def __init__(
        self,
        client: FpI4cClient,
        point_map: PointMap,
        *,
        identity: str | None = None,
        interface: int | None = None,
        station: int | None = None,
        **settings: Unpack[SourceSettings],
    ) -> None:
        """Read nothing yet."""
        super().__init__(**settings)
        self.client = client
        self.point_map = point_map
        self._added = identity is None
        self.identity = identity or address_identity(
            client.base_url, interface, station
        )
        self.interface = interface
        self.station = station
        self._targets: dict[str, Target] = {}
        self._plans: dict[frozenset[str], ReadPlan] = {}
        # What the reads learned about failing addresses (see _search): the
        # points read alone (each with its good reads in a row), the points
        # that begin a request (each with the poll that cut there), the
        # halvings of each station's search under way; each failing point's
        # item now.
        self._alone: dict[str, int] = {}
        self._cuts: dict[str, int] = {}
        self._retried: set[str] = set()
        self._searching: dict[int | None, set[str]] = {}
        self._polls = 0
        self._errors: dict[str, ItemError] = {}
        self.read_plan: ReadPlan | None = None
        """The plan of the latest poll (for diagnostics and the benchmark)."""
        # Writes acknowledged so far, and the count when each point was last
        # written: a read sent before then shows an older value.
        self._writes_done = 0
        self._written: dict[str, int] = {}

    @property
    def configuration_url(self) -> str:
        """The gateway's web pages (its address without the REST API's port)."""
        return str(URL(self.client.base_url).with_port(None))

    # --- who it is -------------------------------------------------------------

    def _source_info(self) -> SourceInfo:
        return SourceInfo(
            identity=self.identity,
            name=MODEL,
            manufacturer=MANUFACTURER,
            model=MODEL,
            location=self.location,
        )

    @property
    def location(self) -> str:
        """Where the gateway is, as typed: ``192.168.1.5:2000, station 1``."""
        parts = [address_identity(self.client.base_url, None, None)]
        if self.interface is not None:
            parts.append(f"interface {self.interface}")
        if self.station is not None:
            parts.append(f"station {self.station}")
        return ", ".join(parts)

    @property
    def _gateway(self) -> str:
        """The gateway as its log lines name it: ``192.168.1.5:2000``, its interface."""
        gateway = address_identity(self.client.base_url, None, None)
        if self.interface is not None:
            gateway += f" (interface {self.interface})"
        return gateway

    async def identify(self) -> SourceInfo:
        """Read DT0 of each station the map uses: the gateway and its PLCs answer.

        Raises :class:`StationNotAnsweringError` (or
        :class:`PlcNotAnsweringError` for the gateway's own station) with the
        item's code when a PLC does not answer.
        """
        stations = sorted(
            {self._station_of(point)[0] for point in self.point_map.points}
            or {self.station},
            key=lambda item: -1 if item is None else item,
        )
        for station in stations:
            answer = (await self.client.post([PROBE], station))[0]
            if (error := answer.error) is not None:
                if station is None:
                    raise PlcNotAnsweringError(error.message, code=error.code)
                raise StationNotAnsweringError(
                    error.message, code=error.code, station=station
                )
        if self._added:
            self.identity = await resolved_identity(self.identity)
        return self._source_info()

    # --- the catalogue -----------------------------------------------------------

    def _station_of(self, point: MapPoint) -> tuple[int | None, str]:
        """Return a point's station (the connection's when it names none) and name."""
        try:
            station, name = parse_station(point.device)
        except PointMapError:
            return self.station, ""
        return (self.station, name) if station is None else (station, name)

    def _catalogue_of_map(self) -> Catalogue:
        """Return the map's points, each on its station's device, as the gateway reads."""
        listed = map_catalogue(self.point_map)
        points: dict[str, Point] = {}
        devices: dict[str, DeviceNode] = {}
        named: set[str] = set()
        self._targets = {}
        self._plans.clear()
        self._alone.clear()
        self._cuts.clear()
        self._retried.clear()
        self._searching.clear()
        self._errors.clear()
        for item in self.point_map.points:
            point = listed.points[item.key]
            station, name = self._station_of(item)
            device = _device_key(station)
            if device not in devices:
                devices[device] = DeviceNode(
                    key=device,
                    name=_device_name(station),
                    manufacturer=MANUFACTURER,
                    properties={} if station is None else {"station": str(station)},
                )
            if name and device not in named:
                # The first name the map gives a station is its device's.
                named.add(device)
                devices[device] = replace(devices[device], name=name)
            data_type = point.type
            if data_type.kind is ValueKind.STRING:
                data_type = DataType(
                    kind=ValueKind.STRING,
                    encoding=STRING_ENCODING,
                    length=min(data_type.length or MAX_STRING, MAX_STRING),
                )
            try:
                address = parse_address(point.address)
            except AddressError:
                address = None
            wire = wire_type(data_type)
            if (
                address is not None
                and wire is not None
                and type_problem(address, wire) is None
            ):
                self._targets[item.key] = Target(item.key, station, address, wire)
            points[item.key] = replace(
                point,
                address=str(address) if address is not None else point.address,
                type=data_type,
                device=device,
            )
        # A point a stored map has that this gateway cannot read (it passed
        # an older check) is bad, and costs nothing else.
        self._quality = {
            key: PointQuality(quality=Quality.BAD, reason="invalid_address")
            for key in points
            if key not in self._targets
        }
        return Catalogue(
            points=points, values={}, roots=(), skipped_roots=(), devices=devices
        )

    def _requests_sent(self) -> int:
        return self.client.statistics.posts

    async def _discover_catalogue(self, polled: frozenset[str]) -> Snapshot:
        """Make the catalogue of the map and read every point once."""
        self._info = self._source_info()
        catalogue = self._catalogue_of_map()
        self._catalogue = catalogue
        values = await self._read_keys(catalogue.points.keys(), poll=True)
        catalogue = replace(catalogue, values=values)
        self._catalogue = catalogue
        return self._discovered_map(self._info, catalogue, values)

    async def _poll(self, catalogue: Catalogue, polled: frozenset[str]) -> Snapshot:
        """Read the polled points."""
        return self._snapshot(
            catalogue, await self._read_keys(polled, poll=True), {}, None
        )

    async def read_points(self, keys: Collection[str]) -> Snapshot | None:
        """Read some points now, between polls (the planner's POSTs for them alone)."""
        catalogue = self._catalogue
        if catalogue is None or self._info is None:
            return None
        wanted = [key for key in keys if key in catalogue.points]
        if not wanted:
            return None
        return self._snapshot(catalogue, await self._read_keys(wanted), {}, None)

    # --- reading -------------------------------------------------------------------

    def plan(self, keys: Iterable[str]) -> ReadPlan:
        """Return the plan of some points' reads (kept while they stay the same)."""
        wanted = frozenset(key for key in keys if key in self._targets)
        plan = self._plans.get(wanted)
        if plan is None:
            if len(self._plans) >= _PLANS_KEPT:
                self._plans.clear()
            plan = self._plans[wanted] = plan_reads(
                (self._targets[key] for key in wanted),
                breaks=self._breaks(),
                alone=self._alone.keys(),
            )
        return plan

    def _breaks(self) -> set[str]:
        """Return the points that begin a request: the cuts and the searches' halvings."""
        return set(self._cuts).union(*self._searching.values())

    async def _read_keys(
        self, keys: Collection[str], *, poll: bool = False
    ) -> dict[str, Any]:
        """Read some points; note their quality and their stations' health.

        A POST nothing answered costs its station only while another POST of
        the read was answered; when none was, the read fails. A poll's plan is
        kept as :attr:`read_plan`.
        """
        if poll:
            self._polls += 1
            self._expire_cuts()
        plan = self.plan(keys)
        if poll:
            self.read_plan = plan
        begun = self._writes_done
        reading = _Reading()
        unreachable: PlcConnectionError | None = None
        for post in plan.posts:
            try:
                answers = await self.client.post(
                    [request.body() for request in post.requests], post.station
                )
            except PlcConnectionError as err:
                unreachable = unreachable or err
                reading.failures.setdefault(post.station, f"no answer: {err}")
                continue
            except GatewayError as err:
                reading.failures.setdefault(post.station, f"refused: {err}")
                continue
            self._take(post, answers, reading)
        if unreachable is not None and not reading.answered:
            raise unreachable
        await self._search(plan, reading)
        self._account(plan, reading)
        # A point written since this read began shows what the write left.
        return {
            key: value
            for key, value in reading.values.items()
            if self._written.get(key, 0) <= begun
        }

    def _take(self, post: Post, answers: list[ItemAnswer], reading: _Reading) -> None:
        """Take one POST's answers: values by point, bad points, station health."""
        catalogue = self._catalogue
        assert catalogue is not None
        for request, answer in zip(post.requests, answers, strict=True):
            if (error := answer.error) is not None:
                reading.failures.setdefault(post.station, _reason(error))
                # Only a request of one address tells that the code is its
                # points'; the points of a longer one wait for the search.
                own = len(request.indices) == 1
                bad = PointQuality(
                    quality=Quality.BAD,
                    reason=_reason(error),
                    code=error.code if own else None,
                )
                reading.bad.update((key, bad) for key, _ in request.points)
                if own:
                    reading.errors.update((key, error) for key, _ in request.points)
                reading.failed.append((post.station, request))
                _LOGGER.debug("%s failed: %s", request.name, error)
                continue
            reading.answered.add(post.station)
            for key, index in request.points:
                reading.errors.pop(key, None)
                raw = answer.values[index] if index < len(answer.values) else None
                if raw is None:
                    reading.bad[key] = PointQuality(
                        quality=Quality.BAD, reason="unreadable"
                    )
                    continue
                reading.bad.pop(key, None)
                reading.values[key] = to_shown(catalogue.points[key], raw)

    async def _search(self, plan: ReadPlan, reading: _Reading) -> None:
        """Halve the requests that failed, in one more POST a station.

        Only a station that answered other items is searched (one whose every
        item failed is offline: nothing tells a bad address from a PLC that
        does not answer). Its POST halves at most ten failed requests; the
        halves' values count as read. While halves still fail, the halving
        points stay the station's search (:attr:`_searching`: later plans
        begin requests there, and the next read halves what fails again);
        once none does, they go, and what is left apart is what isolates the
        failures: the single failing addresses (:attr:`_alone`) and, where
        both halves of a failed request read, a cut between them
        (:attr:`_cuts`).
        """
        halves: dict[
            int | None, list[tuple[frozenset[str], ReadRequest, ReadRequest]]
        ] = defaultdict(list)
        unfinished: set[int | None] = set()
        for station, request in self._suspects(reading):
            if 2 * len(halves[station]) + 2 <= MAX_REQUESTS:
                halves[station].append(self._halve(station, request))
            else:
                unfinished.add(station)
        self._retried.clear()
        for station, pairs in halves.items():
            requests = [half for _, *two in pairs for half in two]
            try:
                answers = await self.client.post(
                    [request.body() for request in requests], station
                )
            except (PlcConnectionError, GatewayError):
                # The plan's failures stand; the next read halves them again.
                unfinished.add(station)
                continue
            self._take(Post(station, tuple(requests)), answers, reading)
            for (middle, _, _), low, high in zip(
                pairs, answers[::2], answers[1::2], strict=True
            ):
                if low.error is None and high.error is None:
                    self._cut(middle)
        unfinished.update(station for station, _ in self._suspects(reading))
        for station in reading.answered & {post.station for post in plan.posts}:
            if station not in unfinished and station in self._searching:
                del self._searching[station]
                self._plans.clear()

    def _suspects(self, reading: _Reading) -> list[tuple[int | None, ReadRequest]]:
        """Take the failed requests of stations that answered: those to halve.

        A failed request of one address is that address's: its points are
        read alone from now on.
        """
        suspects: list[tuple[int | None, ReadRequest]] = []
        for station, request in reading.failed:
            if station not in reading.answered:
                continue
            if len(request.indices) > 1:
                suspects.append((station, request))
                continue
            for key, _ in request.points:
                if key not in self._alone:
                    self._plans.clear()
                self._alone[key] = 0
        reading.failed = []
        return suspects

    def _halve(
        self, station: int | None, request: ReadRequest
    ) -> tuple[frozenset[str], ReadRequest, ReadRequest]:
        """Split a request's points in two at their middle address.

        A cut this poll dropped (:meth:`_expire_cuts`) splits first: when its
        failing address is still there, both halves read in this one POST.
        Returns the middle's points (noted in the station's search) and the
        two halves.
        """
        indices = sorted(request.indices)
        middle = min(
            (
                index
                for key, index in request.points
                if key in self._retried and index > indices[0]
            ),
            default=indices[len(indices) // 2],
        )
        keys = frozenset(key for key, index in request.points if index == middle)
        self._searching.setdefault(station, set()).update(keys)
        self._plans.clear()
        return (
            keys,
            covering(
                self._targets[key] for key, index in request.points if index < middle
            ),
            covering(
                self._targets[key] for key, index in request.points if index >= middle
            ),
        )

    def _cut(self, keys: Iterable[str]) -> None:
        """Begin requests at some points from now on (for :data:`CUT_POLLS` polls)."""
        self._cuts.update(dict.fromkeys(keys, self._polls))
        self._plans.clear()

    def _expire_cuts(self) -> None:
        """Drop the cuts made :data:`CUT_POLLS` polls ago: their neighbours read together.

        This poll's search splits a failed request at such a cut first.
        """
        self._retried = {
            key for key, since in self._cuts.items() if self._polls - since >= CUT_POLLS
        }
        for key in self._retried:
            del self._cuts[key]
        if self._retried:
            self._plans.clear()

    def _rejoin(self, key: str, bad: bool) -> None:
        """Count a lone point's good reads; after :data:`REJOIN_READS` it rejoins."""
        if key not in self._alone:
            return
        if bad:
            self._alone[key] = 0
            return
        self._alone[key] += 1
        if self._alone[key] >= REJOIN_READS:
            del self._alone[key]
            self._plans.clear()

    def _account(self, plan: ReadPlan, reading: _Reading) -> None:
        """Keep what a read learned: the points' quality, the stations' health."""
        read = plan.point_keys
        stations = {post.station for post in plan.posts}
        offline = {station for station in stations if station not in reading.answered}
        for key in read:
            if self._targets[key].station in offline:
                # Its station's reason stands for it.
                self._quality.pop(key, None)
                self._errors.pop(key, None)
            elif key in reading.bad:
                self._quality[key] = reading.bad[key]
                if key in reading.errors:
                    self._follow_error(key, reading.errors[key])
                self._rejoin(key, bad=True)
            else:
                self._quality.pop(key, None)
                self._follow_error(key, None)
                self._rejoin(key, bad=False)
        for station in stations:
            device = _device_key(station)
            if station in offline:
                reason = reading.failures.get(station, "no answer")
                if device not in self._offline:
                    self._note(
                        "poll",
                        PlcNotAnsweringError(f"{_device_name(station)}: {reason}"),
                    )
                    _LOGGER.info(
                        "%s behind the FP-I4C gateway %s does not answer, its "
                        "entities are unavailable: %s",
                        _station_named(station),
                        self._gateway,
                        reason,
                    )
                self._offline[device] = reason
            elif self._offline.pop(device, None) is not None:
                _LOGGER.info(
                    "%s behind the FP-I4C gateway %s answers again",
                    _station_named(station),
                    self._gateway,
                )

    def _follow_error(self, key: str, error: ItemError | None) -> None:
        """Keep a point's failed item; log when it starts failing, changes, reads again."""
        known = self._errors.pop(key, None)
        if error is None:
            if known is not None:
                _LOGGER.info("%s reads again", key)
            return
        self._errors[key] = error
        if known is None or known.code != error.code:
            _LOGGER.warning(
                "%s cannot be read, its entity is unavailable: %s", key, error
            )

    # --- writing -------------------------------------------------------------------

    async def write(self, key: str, value: Any) -> Snapshot | None:
        """Check a value, write it with its read-back in one POST, push it, return it."""
        point = self._point(key)
        target = self._targets.get(key)
        if target is None:
            raise VariableNotFoundError(f"{point.address} cannot be read", path=key)
        raw = to_raw(point, check_write(point, value))
        if target.type is WireType.REAL and not real_fits(raw):
            raise InvalidValueError(point.path, value, "outside a REAL's range")
        read_back = ReadRequest(
            target.address.area,
            target.type,
            target.address.index,
            None if target.type is WireType.STRING else 1,
            ((key, 0),),
        )
        written = {**read_back.body(), "value": raw}
        answers: list[ItemAnswer] = []

        async def send() -> None:
            answers.extend(
                await self.client.post(
                    [written, read_back.body(), PROBE], target.station
                )
            )
            if (error := answers[0].error) is not None:
                raise _write_error(error, answers[2].error, point.path, value)

        await self._send(send())
        self._writes_done += 1
        self._written[key] = self._writes_done
        self._push({key: to_shown(point, raw)})
        catalogue = self._catalogue
        assert catalogue is not None
        confirmed = answers[1]
        if confirmed.error is not None or not confirmed.values:
            return None
        if (held := confirmed.values[0]) is None:
            return None
        self._quality.pop(key, None)
        return self._snapshot(catalogue, {key: to_shown(point, held)}, {}, None)

    async def write_variable(self, path: str, value: Any) -> Snapshot | None:
        """Write a point by its ID (a gateway has no paths beyond the map's points)."""
        return await self.write(self._map_key(path), value)

    async def read_variable(self, path: str) -> Any:
        """Read a point by its ID (None when it cannot be read now)."""
        key = self._map_key(path)
        snapshot = await self._read(self.read_points([key]))
        return None if snapshot is None else snapshot.values.get(key)

    # --- the rest --------------------------------------------------------------------

    def diagnostics(self) -> dict[str, Any]:
        """Describe the map, the stations, the read plan, the wire's figures.

        Each station's points and whether it answers; the plan against its
        bound. The keys are those the diagnostics download reads of every source
        (``points``, ``read_plans``, ``requests``), and the gateway's own.
        """
        point_map = self.point_map
        stations: dict[int | None, int] = {}
        for point in point_map.points:
            station = self._station_of(point)[0]
            stations[station] = stations.get(station, 0) + 1
        return {
            "points": len(point_map.points),
            "connection": {"interface": self.interface, "station": self.station},
            "map": {
                "format": point_map.format,
                "readable_points": len(self._targets),
                "skipped_rows": len(point_map.skipped),
            },
            # Each station's points and why it does not answer (None: it does),
            # by its device (``plc``: the station set in the gateway).
            "stations": {
                _device_key(station): {
                    "points": count,
                    "offline": self._offline.get(_device_key(station)),
                }
                for station, count in sorted(
                    stations.items(),
                    key=lambda item: -1 if item[0] is None else item[0],
                )
            },
            "failed_points": [
                {
                    "key": key,
                    "request": error.request,
                    "err_code": error.code,
                    "meaning": error.message,
                }
                for key, error in sorted(self._errors.items())
            ],
            "read_apart": {
                "breaks": len(self._breaks()),
                "alone": sorted(self._alone),
            },
            "read_plans": {"values": _plan(self.read_plan)},
            "requests": {
                **asdict(self.client.statistics),
                **counted(self._statistics, None),
            },
        }

    async def close(self) -> None:
        """Nothing to release: the HTTP session belongs to whoever made it."""


def _device_key(station: int | None) -> str:
    """Return the key of a station's device (the gateway's own PLC without one)."""
    return DEFAULT_DEVICE if station is None else f"station_{station}"


def _device_name(station: int | None) -> str:
    return "PLC" if station is None else f"Station {station}"


def _station_named(station: int | None) -> str:
    """Return a station as a log line begins with it: ``Station 2``, ``The PLC``."""
    return "The PLC" if station is None else f"Station {station}"


def _reason(error: ItemError) -> str:
    """Return a failed item as a reason (a point's, a station's): code and message."""
    return f"err_code {error.code}: {error.message}"


def _write_error(
    error: ItemError, probe: ItemError | None, path: str, value: Any
) -> PlcResponseError:
    """Return the error of a refused write: the value refused, or no answer.

    The write's POST also reads DT0 (:data:`PROBE`): when that failed too,
    the PLC did not answer; otherwise it answered and refused the value.
    """
    if probe is not None:
        return PlcNotAnsweringError(error.detail, code=error.code)
    return ValueRejectedError(
        error.detail,
        path=path,
        value=value,
        code=error.code,
    )


def _plan(plan: ReadPlan | None) -> dict[str, Any] | None:
    """Describe a read plan: its POSTs against the bound, its requests."""
    if plan is None:
        return None
    return {
        "posts": len(plan.posts),
        "lower_bound": plan.lower_bound,
        "requests": plan.requests,
        "minimal_requests": plan.minimal_requests,
        "unused_values": plan.unused_values,
        "points": len(plan.point_keys),
        "by_post": [
            {
                "station": post.station,
                "requests": [
                    f"{request.type} {request.name}"
                    + ("" if request.count is None else f" x{request.count}")
                    for request in post.requests
                ],
            }
            for post in plan.posts
        ],
    }
