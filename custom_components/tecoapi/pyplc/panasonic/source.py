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
  (:data:`~.reading.SEARCH_POSTS`: a read costs at most its plan's bound and one POST a
  station), and the next reads go on halving what still fails until the
  points that fail are alone; the others get their values as soon as a half
  of theirs reads. After the search only those points are read apart, each in
  a request of its own, the others as the planner plans them; a lone point
  that reads :data:`~.reading.REJOIN_READS` times in a row joins its neighbours again,
  and a cut where no point failed (a failing address between two points, or
  an error that went away) is tried again after :data:`~.reading.CUT_POLLS` polls. The
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
with what the PLC holds; a batch (``write_many``) puts a station's writes and
their read-backs in one POST. A poll whose POSTs went out while a write was
acknowledged does not show its older value of the written point: a user's
write is never undone by the poll it overtook.
"""

from collections.abc import Collection, Iterable, Mapping, Sequence
from dataclasses import asdict, dataclass, replace
import logging
from typing import Any, Final, Unpack

from ..core.codec import OUTSIDE_REAL, to_shown
from ..core.exceptions import (
    InvalidValueError,
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
from ..core.pointmap import MapPoint, PointMap, PointMapError, map_catalogue
from ..core.source import NOT_FOUND, Snapshot, SourceSettings, Write, counted
from ..core.texts import Template
from .address import (
    MAX_STRING,
    AddressError,
    WireType,
    parse_address,
    type_problem,
    wire_type,
)
from .client import (
    FpI4cClient,
    ItemAnswer,
    ItemError,
    PlcNotAnsweringError,
    StationNotAnsweringError,
    real_fits,
)
from .mapping import (
    address_identity,
    device_key,
    device_name,
    parse_station,
)
from .planner import MAX_REQUESTS, ReadPlan, ReadRequest, Target
from .reading import UNREADABLE, GatewayReader, reason, reason_text

_LOGGER = logging.getLogger(__name__)

MANUFACTURER: Final = "Panasonic"
MODEL: Final = "FP-I4C"
STRING_ENCODING: Final = "ascii"
INVALID_ADDRESS: Final = Template(
    "fpi4c_invalid_address", "the FP-I4C cannot read this address as this type"
)
"""What a string written takes: an FP string is bytes (8-bit text is not documented)."""
PROBE: Final[Mapping[str, Any]] = {"area": "DT", "type": "INT", "start": 0, "count": 1}
"""The harmless read that checks a station: DT0, which every FP PLC has."""


class FpI4cSource(GatewayReader):
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
        super().__init__(client, **settings)
        self.point_map = point_map
        self._added = identity is None
        self.identity = identity or address_identity(
            client.base_url, interface, station
        )
        self.interface = interface
        self.station = station

    @property
    def configuration_url(self) -> str:
        """The gateway's HTTP server: its address with the REST API's port.

        The REST API and the HTTP server that serves the pages uploaded to the
        gateway share the port set on its *REST API / HTTP server* page (a page
        it serves calls ``plcpost`` by that name alone); where its own settings
        pages are served is not documented.
        """
        return self.client.base_url

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
            _raise_unless_answered(station, answer)
        if self._added:
            self.identity = await resolved_identity(self.identity)
        return self._source_info()

    async def check_points(self, keys: Collection[str]) -> dict[str, PointQuality]:
        """Read some points of the map once, each station's with its DT0: those refused.

        DT0 goes first in each station's POST (the check ``identify()`` makes):
        a station that does not answer raises as there, so that a point's
        failure is its address's; each point whose item fails is refused with
        the gateway's code and message, as a poll keeps them (``err_code 61:
        ...``). A point whose address or type this gateway cannot read is
        refused as a poll has it (``invalid_address``).
        """
        self._catalogue = self._catalogue_of_map()
        refused = {
            key: self._quality.get(key, NOT_FOUND)
            for key in keys
            if key not in self._targets
        }
        by_station: dict[int | None, list[ReadRequest]] = {}
        for post in self.plan(keys).posts:
            by_station.setdefault(post.station, []).extend(post.requests)
        room = MAX_REQUESTS - 1  # DT0 takes one request of each POST
        for station, requests in by_station.items():
            for start in range(0, len(requests), room):
                chunk = requests[start : start + room]
                probe, *answers = await self.client.post(
                    [PROBE, *(request.body() for request in chunk)], station
                )
                _raise_unless_answered(station, probe)
                for request, answer in zip(chunk, answers, strict=True):
                    for key, index in request.points:
                        if (error := answer.error) is not None:
                            refused[key] = PointQuality(
                                quality=Quality.BAD,
                                reason=reason(error),
                                text=reason_text(error),
                                code=error.code,
                            )
                        elif (
                            index >= len(answer.values) or answer.values[index] is None
                        ):
                            refused[key] = PointQuality(
                                quality=Quality.BAD,
                                reason="unreadable",
                                text=UNREADABLE(),
                            )
        return refused

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
            device = device_key(station)
            if device not in devices:
                devices[device] = DeviceNode(
                    key=device,
                    name=device_name(station),
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
            key: PointQuality(
                quality=Quality.BAD, reason="invalid_address", text=INVALID_ADDRESS()
            )
            for key in points
            if key not in self._targets
        }
        return Catalogue(
            points=points, values={}, groups=(), skipped_groups=(), devices=devices
        )

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

    # --- writing -------------------------------------------------------------------
    # The base's template: a POST carries a station's writes in the order given,
    # then their read-backs and PROBE (at most WRITES_PER_POST writes); a value
    # the PLC refused stops the batch after its POST: what that POST wrote is
    # pushed, the refusal raised, nothing more sent.

    def _encode(self, point: Point, value: Any) -> Write["_Wire"]:
        """Check a value: a point that cannot be read, the codec, a REAL's range."""
        target = self._targets.get(point.key)
        if target is None:
            raise VariableNotFoundError(
                f"{point.address} cannot be read", path=point.key
            )
        write = super()._encode(point, value)
        raw = write.wire
        if target.type is WireType.REAL and not real_fits(raw):
            raise InvalidValueError(point.path, value, OUTSIDE_REAL())
        read_back = ReadRequest(
            target.address.area,
            target.type,
            target.address.index,
            None if target.type is WireType.STRING else 1,
            ((point.key, 0),),
        )
        return Write(
            point=point,
            value=value,
            wire=_Wire(raw, target.station, read_back),
            shown=write.shown,
        )

    def _sends(
        self, batch: Sequence[Write["_Wire"]]
    ) -> Iterable[Sequence[Write["_Wire"]]]:
        """One POST a run of one station's writes, at most WRITES_PER_POST each."""
        posts: list[list[Write[_Wire]]] = []
        for write in batch:
            last = posts[-1] if posts else None
            if (
                last is not None
                and last[0].wire.station == write.wire.station
                and len(last) < WRITES_PER_POST
            ):
                last.append(write)
            else:
                posts.append([write])
        return posts

    async def _send_writes(self, writes: Sequence[Write["_Wire"]]) -> dict[str, Any]:
        """Send one POST of a station's writes and read-backs; what it read back.

        Each item is answered on its own: when one is refused, the values the
        POST wrote are pushed before the first refusal is raised.
        """
        count = len(writes)
        reads = [write.wire.read_back.body() for write in writes]
        items = [
            {**read, "value": write.wire.raw}
            for write, read in zip(writes, reads, strict=True)
        ]
        answers = await self.client.post(
            [*items, *reads, PROBE], writes[0].wire.station
        )
        written = self._acknowledged(writes, answers)
        failed = next(
            (
                (write, error)
                for write, answer in zip(writes, answers, strict=False)
                if (error := answer.error) is not None
            ),
            None,
        )
        if failed is not None:
            write, error = failed
            if written:
                self._push({done.key: done.shown for done in written})
            raise _write_error(
                error, answers[2 * count].error, write.point.path, write.value
            )
        held: dict[str, Any] = {}
        for write, confirmed in zip(writes, answers[count : 2 * count], strict=True):
            if (
                confirmed.error is None
                and confirmed.values
                and (value := confirmed.values[0]) is not None
            ):
                held[write.key] = to_shown(write.point, value)
        return held

    def _acknowledged(
        self, writes: Sequence[Write["_Wire"]], answers: list[ItemAnswer]
    ) -> list[Write["_Wire"]]:
        """Note the writes of a POST the gateway took (a poll it overtook keeps them)."""
        written = [
            write
            for write, answer in zip(writes, answers, strict=False)
            if answer.error is None
        ]
        for write in written:
            self._writes_done += 1
            self._written[write.key] = self._writes_done
        return written

    async def _read_back(
        self, batch: Sequence[Write["_Wire"]], carried: Mapping[str, Any]
    ) -> Snapshot | None:
        """Return what the POSTs read back with the writes (no request of its own)."""
        for key in carried:
            self._quality.pop(key, None)
        catalogue = self._catalogue
        if not carried or catalogue is None:
            return None
        return self._snapshot(catalogue, carried, {}, None)

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
                device_key(station): {
                    "points": count,
                    "offline": self._offline.get(device_key(station)),
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


WRITES_PER_POST: Final = (MAX_REQUESTS - 1) // 2
"""A POST's writes: each with its read-back, and :data:`PROBE`."""


@dataclass(frozen=True, slots=True)
class _Wire:
    """A checked write on the wire: the raw value, its station and its read-back."""

    raw: Any
    station: int | None
    read_back: ReadRequest


def _write_error(
    error: ItemError, probe: ItemError | None, path: str, value: Any
) -> PlcResponseError:
    """Return the error of a refused write: the value refused, or no answer.

    The write's POST also reads DT0 (:data:`PROBE`): when that failed too,
    the PLC did not answer; otherwise it answered and refused the value.
    """
    if probe is not None:
        return PlcNotAnsweringError(error.detail, code=error.code, said=error.detail)
    return ValueRejectedError(
        error.detail,
        path=path,
        value=value,
        code=error.code,
        said=error.detail,
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


def _raise_unless_answered(station: int | None, answer: ItemAnswer) -> None:
    """Raise when a station's DT0 failed: its PLC does not answer (with the code)."""
    if (error := answer.error) is None:
        return
    if station is None:
        raise PlcNotAnsweringError(error.message, code=error.code, said=error.detail)
    raise StationNotAnsweringError(error.message, code=error.code, station=station)
