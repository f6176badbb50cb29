"""An in-memory source: a device that is a dictionary, its points a user's map.

It is a source like any other: it implements the library's ``PlcSource`` on
``BaseSource``, takes its points from a point map (CSV), checks writes with the
core's codec (types, ranges, scale and offset) and is offered to Home Assistant
through a descriptor of its own. It is written here, in the tests, without
touching any Home Assistant module: registering :data:`MEMORY` is all it takes
for the config flow to offer it and for its entries to have entities.

The device (:class:`MemoryDevice`) holds raw values by address, the quality of
each, the devices that are offline and the failure its next request meets; a
test changes them as a real device would change, and counts its requests.
"""

from collections.abc import Collection, Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field, replace
from datetime import UTC, date, datetime, timedelta
from typing import Any, Final

from custom_components.tecoapi.pyplc.core import registry
from custom_components.tecoapi.pyplc.core.codec import to_shown
from custom_components.tecoapi.pyplc.core.descriptor import (
    CONF_HOST,
    CONF_POINT_MAP,
    Capability,
    ErrorRule,
    Field,
    FieldKind,
    Form,
    SourceContext,
    SourceDescriptor,
    SourceOptions,
    Words,
)
from custom_components.tecoapi.pyplc.core.exceptions import (
    NoPublicVariablesError,
    PlcConnectionError,
    PlcError,
    PlcResponseError,
    VariableNotFoundError,
)
from custom_components.tecoapi.pyplc.core.models import (
    Catalogue,
    DeviceNode,
    PointQuality,
    Quality,
    SourceInfo,
    WireCounts,
)
from custom_components.tecoapi.pyplc.core.pointmap import (
    CSV,
    PointMap,
    load_csv,
    map_catalogue,
)
from custom_components.tecoapi.pyplc.core.pointmap.model import NOT_AN_ADDRESS
from custom_components.tecoapi.pyplc.core.source import BaseSource, Snapshot, Write
from custom_components.tecoapi.pyplc.core.texts import Text
from custom_components.tecoapi.pyplc.tecomat.conventions import RECOGNISERS

NAME: Final = "memory"
MANUFACTURER: Final = "Memory & Co."


@dataclass
class MemoryDevice:
    """What a memory source reads and writes (see the module's docstring)."""

    identity: str = "MEM-0001"
    values: dict[str, Any] = field(default_factory=dict)
    """Raw values by address."""
    quality: dict[str, PointQuality] = field(default_factory=dict)
    """Addresses whose value is not good."""
    offline: dict[str, str] = field(default_factory=dict)
    """Devices (by key) that exchange no data, and why."""
    fail: PlcError | None = None
    """What the next requests meet (None: they succeed)."""
    parents: dict[str, str] = field(default_factory=dict)
    """Devices (by key) that sit under another, by the other's key."""
    wire: WireCounts = field(default_factory=WireCounts)
    """The requests it took."""
    writes: list[tuple[str, Any]] = field(default_factory=list)

    @property
    def requests(self) -> int:
        """The requests it took so far."""
        return self.wire.requests

    def request(self) -> None:
        """Count a request; raise the failure set for it."""
        self.wire.requests += 1
        if self.fail is not None:
            raise self.fail


DEVICES: dict[str, MemoryDevice] = {}
"""The devices a memory entry's host names."""


class MemorySource(BaseSource):
    """A source whose device is a :class:`MemoryDevice`, its points a map's."""

    def __init__(
        self, device: MemoryDevice, point_map: PointMap, **settings: Any
    ) -> None:
        """Read nothing yet."""
        super().__init__(wire=device.wire, **settings)
        self.device = device
        self.point_map = point_map
        self.closed = False

    @property
    def configuration_url(self) -> str | None:
        """A memory device has no web page."""
        return None

    async def identify(self) -> SourceInfo:
        """Tell the device's identity; a map of nothing the device has is refused."""
        self.device.request()
        known = {point.address for point in self.point_map.points}
        if known.isdisjoint(self.device.values):
            raise NoPublicVariablesError("The device has none of the map's points")
        return SourceInfo(
            identity=self.device.identity,
            name="Memory device",
            manufacturer=MANUFACTURER,
            model="M1",
        )

    async def _discover_catalogue(self, polled: frozenset[str]) -> Snapshot:
        self._info = await self.identify()
        listed = map_catalogue(self.point_map)
        devices = dict(listed.devices)
        for key, parent in self.device.parents.items():
            devices.setdefault(parent, DeviceNode(key=parent, name=parent.title()))
            devices[key] = replace(devices[key], parent=parent, model="Station")
        listed = replace(listed, devices=devices)
        values = self._read(listed, listed.points)
        # The catalogue holds what discovery read (typed devices read their
        # configuration from it).
        catalogue = replace(listed, values=values)
        self._catalogue = catalogue
        return self._discovered_map(self._info, catalogue, values)

    async def _poll(self, catalogue: Catalogue, polled: frozenset[str]) -> Snapshot:
        self.device.request()
        values = self._read(catalogue, polled)
        return self._snapshot(catalogue, values, {}, None)

    async def read_points(self, keys: Collection[str]) -> Snapshot | None:
        """Read some points now."""
        if self._catalogue is None:
            return None
        self.device.request()
        return self._snapshot(
            self._catalogue, self._read(self._catalogue, keys), {}, None
        )

    def _read(self, catalogue: Catalogue, keys: Collection[str]) -> dict[str, Any]:
        """Return the shown values of some points; note their quality and devices."""
        values: dict[str, Any] = {}
        missing: set[str] = set()
        for key in keys:
            point = catalogue.points.get(key)
            if point is None:
                continue
            if point.address not in self.device.values:
                missing.add(key)
                continue
            values[key] = to_shown(point, self.device.values[point.address])
            if (quality := self.device.quality.get(point.address)) is not None:
                self._quality[key] = quality
            else:
                self._quality.pop(key, None)
        self._missing = (self._missing - set(keys)) | missing
        self._offline = dict(self.device.offline)
        return values

    async def _send_writes(self, writes: Sequence[Write[Any]]) -> None:
        """Write a batch's raw values (the base checked them): a request each.

        The one hook of writing a source must give: the base checks, counts,
        pushes and reads back (here without a request, :meth:`_read_back`).
        """
        for write in writes:
            address = write.point.address
            self.device.request()
            if address not in self.device.values:
                raise VariableNotFoundError(f"{address} is gone", path=write.key)
            self.device.values[address] = write.wire
            self.device.writes.append((address, write.wire))

    async def _read_back(
        self, batch: Sequence[Write[Any]], carried: Mapping[str, Any]
    ) -> Snapshot | None:
        """Read the written points back (a memory's read costs no request)."""
        assert self._catalogue is not None
        keys = [write.key for write in batch]
        return self._snapshot(
            self._catalogue, self._read(self._catalogue, keys), {}, None
        )

    async def write_variable(self, path: str, value: Any) -> Snapshot | None:
        """A memory device has no paths beyond its points."""
        raise VariableNotFoundError(f"{path!r} is not a point", path=path)

    async def read_variable(self, path: str) -> Any:
        """A memory device has no paths beyond its points."""
        raise VariableNotFoundError(f"{path!r} is not a point", path=path)

    def push_value(self, address: str, raw: Any) -> None:
        """The device changed a value and tells at once (a push)."""
        self.device.values[address] = raw
        assert self._catalogue is not None
        keys = [
            key
            for key, point in self._catalogue.points.items()
            if point.address == address
        ]
        self._push(self._read(self._catalogue, keys))

    def diagnostics(self) -> dict[str, Any]:
        """What a maintainer would want: the points and the requests."""
        return {"points": len(self.point_map.points), "requests": self.device.requests}

    async def close(self) -> None:
        """Nothing to release."""
        self.closed = True


def _create(
    context: SourceContext, data: Mapping[str, Any], options: SourceOptions
) -> MemorySource:
    device = DEVICES.get(data[CONF_HOST])
    if device is None:
        raise PlcConnectionError(f"No memory device {data[CONF_HOST]!r}")
    assert options.point_map is not None
    return MemorySource(
        device,
        options.point_map,
        metadata_interval=options.metadata_interval,
        clock=context.clock,
    )


def _check_address(point: Any) -> Text | None:
    """A memory address is a word of letters, digits and underscores."""
    return None if point.address.replace("_", "").isalnum() else NOT_AN_ADDRESS()


MEMORY: Final = SourceDescriptor(
    name=NAME,
    title="Memory",
    manufacturer=MANUFACTURER,
    connect=Form(
        step_id=NAME,
        fields=(
            Field(key=CONF_HOST, kind=FieldKind.TEXT),
            Field(key=CONF_POINT_MAP, kind=FieldKind.POINT_MAP),
        ),
    ),
    reconfigure=Form(
        step_id=f"reconfigure_{NAME}",
        fields=(Field(key=CONF_HOST, kind=FieldKind.TEXT),),
    ),
    create=_create,
    capabilities=frozenset({Capability.POINT_MAP, Capability.PUSH}),
    errors=(
        ErrorRule(error=PlcConnectionError, key="cannot_connect"),
        ErrorRule(error=NoPublicVariablesError, key="no_public_variables"),
        ErrorRule(error=PlcResponseError, key="unknown", logged=True),
    ),
    point_map_loaders=CSV,
    check_address=_check_address,
    # A source with a map has its settings behind its menu, on a step of its own.
    words=Words(settings_step_id="settings"),
    # Its house's names follow Tecomat's conventions (GTSAP1 families).
    recognisers=RECOGNISERS,
)


@contextmanager
def memory_registered() -> Iterator[None]:
    """Offer the memory source while the block runs; forget its devices after."""
    unregister = registry.register(MEMORY)
    try:
        yield
    finally:
        unregister()
        DEVICES.clear()


HOUSE_CSV: Final = """\
id,name,address,type,length,unit,scale,offset,writable,min,max,step,device,platform,device_class,description,state_class
hall_motion,Hall motion,m1,BOOL,,,,,no,,,,Hall,,motion,PIR in the hall
garden_pump,Garden pump,m2,BOOL,,,,,yes,,,,Garden,,,
boiler_temp,Boiler temperature,m3,INT,,°C,0.1,,no,,,,Boiler,,,tenths of a degree
boiler_setpoint,Boiler setpoint,m4,INT,,°C,0.1,,yes,30,80,0.5,Boiler,,,
starts,Burner starts,m5,UDINT,,,,,no,,,,Boiler,,,,total_increasing
display_text,Display text,m6,STRING,16,,,,yes,,,,,,,
holiday_from,Holiday from,m7,DATE,,,,,yes,,,,,,,
wake_up,Wake up,m8,TOD,,,,,yes,,,,,,,
last_service,Last service,m9,DT,,,,,yes,,,,,,,
runtime,Burner runtime,m10,TIME,,,,,no,,,,Boiler,,,
fan_level,Fan level,m11,REAL,,%,,,yes,0,100,5,,,,
KITCHEN_GTSAP1_LIGHT_onoff,Kitchen light,k1,BOOL,,,,,yes,,,,Kitchen,,,
KITCHEN_GTSAP1_LIGHT_type,Kitchen light dimmable,k2,BOOL,,,,,no,,,,Kitchen,,,
KITCHEN_GTSAP1_LIGHT_dimlevel,Kitchen light level,k3,INT,,%,,,no,,,,Kitchen,,,
KITCHEN_GTSAP1_LIGHT_tgtlevel,Kitchen light target,k4,INT,,%,,,yes,0,100,,Kitchen,,,
BLIND_GTSAP1_OPENER_current,Blind position,b1,INT,,%,,,no,,,,,,,
BLIND_GTSAP1_OPENER_target,Blind target,b2,INT,,%,,,yes,0,100,,,,,
BLIND_GTSAP1_OPENER_moving,Blind moving,b3,BOOL,,,,,no,,,,,,,
ROOM_GTSAP1_THERMOSTAT_type,Room thermostat type,t1,INT,,,,,no,,,,,,,
ROOM_GTSAP1_THERMOSTAT_meastemp,Room temperature,t2,REAL,,°C,,,no,,,,,,,
ROOM_GTSAP1_THERMOSTAT_setpoint,Room setpoint,t3,REAL,,°C,,,yes,15,28,,,,,
ROOM_GTSAP1_THERMOSTAT_heatmode,Room heating on,t4,BOOL,,,,,yes,,,,,,,
DOOR_GTSAP1_BUTTON_CLICKCNT,Door button clicks,d1,UINT,,,,,no,,,,,,,
alarm_armed,Alarm,m12,BOOL,,,,,yes,,,,,binary_sensor,safety,shown only
tank_level,Tank,m13,REAL,,%,,,no,,,,,,moisture,
boost,Boost time,m15,TIME,,,,,yes,0,3600,,,,,
"""
"""A small house as a CSV map: every platform, on devices of its own."""

HOUSE_VALUES: Final[Mapping[str, Any]] = {
    "m1": False,
    "m2": True,
    "m3": 652,
    "m4": 600,
    "m5": 1234,
    "m6": "Hello",
    "m7": date(2026, 12, 20),
    "m8": timedelta(hours=6, minutes=30),
    "m9": datetime(2026, 3, 1, 8, 0, tzinfo=UTC),
    "m10": timedelta(hours=13, minutes=17),
    "m11": 40.0,
    "k1": False,
    "k2": True,
    "k3": 0,
    "k4": 0,
    "b1": 40,
    "b2": 40,
    "b3": False,
    "t1": 2,
    "t2": 21.5,
    "t3": 22.0,
    "t4": True,
    "d1": 3,
    "m12": True,
    "m13": 55.0,
    "m15": timedelta(minutes=10),
}
"""The house's raw values."""


def house_map() -> PointMap:
    """The house's map, as its CSV reads."""
    return load_csv(HOUSE_CSV, _check_address)


def house_device(identity: str = "MEM-0001") -> MemoryDevice:
    """A memory device holding the house's values, reachable as its identity."""
    device = MemoryDevice(identity=identity, values=dict(HOUSE_VALUES))
    DEVICES[identity] = device
    return device


BAD: Final = PointQuality(quality=Quality.BAD, reason="sensor_failure")
UNCERTAIN: Final = PointQuality(quality=Quality.UNCERTAIN, reason="last_usable")
