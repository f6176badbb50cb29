"""The neutral model of a PLC source: its points, their values, its devices.

Every system a source speaks (TecoApi, PLCComS, a gateway's HTTP API, a register
map the user supplies) is described in these terms and no others:

- a :class:`Point` is one value the source can read or write: a stable ``key``,
  the ``path`` it is known by (a hierarchical name: ``Main.heating.setpoint``,
  ``Controller1.Device1.Channel4``), an ``address`` only its source reads, a
  :class:`DataType` (kind, width, signedness, text encoding and length), the
  device it belongs to, a scale and an offset (what is shown is ``raw * scale +
  offset``), a step, and :class:`PointAttributes` when the source describes it
  (a display name, a unit, access, a range, whether it is enabled and shown);
- a value has a :class:`Quality`: a point whose value is not good carries a
  :class:`PointQuality` with the reason, and only that point's entity suffers;
- what the user changed of a point a source discovered (writable, its unit, its
  range, how it is shown) is a :class:`PointOverride`, which the source applies
  to every catalogue it discovers (:mod:`.overrides`);
- the source's own device is described by :class:`SourceInfo` (its identity,
  manufacturer, model, firmware, and what it can tell of a program, a run mode
  and a clock); the devices below it (a program's structs, a gateway's
  controllers and stations) are :class:`DeviceNode` in the catalogue, each with
  its own health.

Nothing here does I/O, and nothing names a protocol.
"""

from collections.abc import Mapping
from dataclasses import dataclass, field
from datetime import datetime, timedelta
from enum import StrEnum
from types import MappingProxyType
from typing import Any, Final

from .texts import Text

NO_TEXTS: Final[Mapping[str, str]] = MappingProxyType({})
"""An empty read-only mapping of texts: one for every point or device without details."""


class ValueKind(StrEnum):
    """What a point's value is, whatever its width or encoding."""

    BOOL = "bool"
    INTEGER = "integer"
    REAL = "real"
    STRING = "string"
    DATE = "date"
    TIME = "time"
    """A duration that may also be written as a time of day (a ``timedelta``)."""
    DATETIME = "datetime"
    DURATION = "duration"
    """A duration only (a ``timedelta``)."""
    RECORD = "record"
    """Text with named parts (a :class:`Record`: a lift's state); read only."""


class DataExchange(StrEnum):
    """Whether a device exchanges data, as its status point tells (Point.exchange)."""

    EXCHANGING = "exchanging"
    NO_DATA_EXCHANGE = "no_data_exchange"


NUMERIC_KINDS: Final = frozenset({ValueKind.INTEGER, ValueKind.REAL})


class Access(StrEnum):
    """What may be done with a point's value."""

    READ = "read"
    WRITE = "write"
    READ_WRITE = "read_write"

    @property
    def readable(self) -> bool:
        """Whether the value can be read."""
        return self is not Access.WRITE

    @property
    def writable(self) -> bool:
        """Whether the value can be written."""
        return self is not Access.READ


class PointEvent(StrEnum):
    """What each rise of a flag is, where it is an event as well as a state."""

    RING = "ring"
    """A call begins (an intercom's, a doorbell's)."""


class PlcMode(StrEnum):
    """A device's run mode, for sources that have one.

    The members say what the mode means; their values are what the device and
    Home Assistant have always shown and stored (the mode sensor's states, the
    repair issue's text): they do not change with the members' names.
    """

    RUNNING = "RUN"
    """It runs its program: its values are live."""
    STOPPED = "HALT"
    """Its program was stopped on purpose: its values are not updated."""
    FAULT = "ERR"
    """Its program was stopped by an error: its values are not updated."""


class Quality(StrEnum):
    """How far a value can be trusted (OPC's three classes, and a value not known)."""

    GOOD = "good"
    UNCERTAIN = "uncertain"
    """Shown, with the reason: the last usable value, a sensor out of calibration."""
    BAD = "bad"
    """Not shown: the point's entity is unavailable, with the reason."""
    UNKNOWN = "unknown"
    """The device has no value it vouches for (an OPC DA server's quality 0, named
    unknown): the entity stays available and shows unknown (the source gives no
    value), with the reason."""


@dataclass(slots=True)
class WireCounts:
    """What a source's client sent and received on the wire, counted as it goes.

    ``requests`` counts every request (an HTTP request, a challenge's round trip
    included; a command line of a line protocol); ``bytes_sent`` and
    ``bytes_received`` the bodies' bytes where a client counts them.
    """

    requests: int = 0
    bytes_sent: int = 0
    bytes_received: int = 0


@dataclass(frozen=True, slots=True, kw_only=True)
class PointQuality:
    """The quality of a point's value when it is not good, and why.

    ``code`` is the device's own code for the failure where it gave one (an
    FP-I4C gateway's ``err_code`` for an address its PLC lacks); ``reason``
    then tells it with the device's message. A bad point with a code is one
    the device refuses: the user's map may name what the device does not have.
    ``text`` is the reason in a user's words where the source wrote it
    (:mod:`.texts`); None: the reason is the device's own words.
    """

    quality: Quality
    reason: str = ""
    code: str | None = None
    text: Text | None = field(default=None, compare=False)


@dataclass(frozen=True, slots=True)
class Record:
    """A value made of named parts, as a device reports it (a lift's state).

    ``text`` is what is shown as the value (short: a state, a summary);
    ``parts`` are every part by name, in the device's order, for the user to
    read beside it (a lift's floor, its doors, its direction).
    """

    text: str
    parts: tuple[tuple[str, str], ...] = ()


@dataclass(frozen=True, slots=True, kw_only=True)
class DataType:
    """What a point's value is on the device.

    ``bits`` is the width of a number (None: not known); integers are ``signed``
    or not. Where the width is not known, ``minimum``/``maximum`` bound an
    integer. Text is ``encoding`` (a Python codec name; None: any Unicode) and
    holds at most ``length`` characters (None: no limit known). A DATE or a DT
    holds no moment before ``earliest`` (UTC; a DATE its day and the days
    after), a TIME or a DURATION nothing longer than ``longest`` (None: no
    bound known; a duration is never negative).
    """

    kind: ValueKind
    bits: int | None = None
    signed: bool = True
    minimum: int | None = None
    maximum: int | None = None
    encoding: str | None = None
    length: int | None = None
    earliest: datetime | None = None
    longest: timedelta | None = None

    def integer_bounds(self) -> tuple[int, int] | None:
        """Return the range of an integer of this type (None: unbounded, or not one)."""
        if self.kind is not ValueKind.INTEGER:
            return None
        if self.bits is not None:
            if self.signed:
                half = 1 << (self.bits - 1)
                return -half, half - 1
            return 0, (1 << self.bits) - 1
        if self.minimum is None or self.maximum is None:
            return None
        return self.minimum, self.maximum


@dataclass(frozen=True, slots=True, kw_only=True)
class PointAttributes:
    """What a source tells about a point beyond its value; it may change at run time.

    ``name`` is the display name the device gives (empty: none), ``unit`` its
    unit, ``access`` what may be done with it, ``minimum``/``maximum`` its range
    in what is shown (None: no range), ``enabled`` whether it can be used now
    (a disabled point's entity is unavailable) and ``visible`` whether it is
    shown by default.
    """

    name: str = ""
    unit: str = ""
    access: Access = Access.READ
    minimum: float | None = None
    maximum: float | None = None
    enabled: bool = True
    visible: bool = True

    @property
    def has_range(self) -> bool:
        """Whether a minimum and a maximum bound the value."""
        return self.minimum is not None and self.maximum is not None

    @property
    def writable(self) -> bool:
        """Whether the value may be written."""
        return self.access.writable


@dataclass(frozen=True, slots=True, kw_only=True)
class PointOverride:
    """What the user changed of a point a source discovered (None: as the source says).

    ``writable`` makes the point writable (where its device takes a write:
    :attr:`Point.settable`) or read only; ``unit``, ``minimum`` and ``maximum``
    stand in place of its attributes' (a plain point, which has none, gets
    them); ``device_class``, ``state_class``, ``step``, ``invert`` and
    ``platform`` are how it is shown, as a map's point says them (the
    :class:`Point` fields of those names). Which of them a point may take, and
    their JSON, are :mod:`.overrides`'.
    """

    writable: bool | None = None
    unit: str | None = None
    device_class: str | None = None
    state_class: str | None = None
    minimum: float | None = None
    maximum: float | None = None
    step: float | None = None
    invert: bool | None = None
    platform: str | None = None

    @property
    def empty(self) -> bool:
        """Whether it changes nothing."""
        return self == NO_OVERRIDE


NO_OVERRIDE: Final = PointOverride()
"""An override that changes nothing."""


@dataclass(frozen=True, slots=True, kw_only=True)
class Point:
    """One value a source reads or writes (see the module's docstring).

    ``attributes`` is None for a point the source describes by its value only
    (a *plain* variable: a PLC variable without metadata); such a point is read
    only. ``device`` is the key of the :class:`DeviceNode` it belongs to, or ""
    for the source's own device. ``platform`` and ``device_class`` are what the
    user asked it to be shown as ("": the default for its kind); ``description``
    is descriptive text the source has (a comment, what the item is for),
    ``details`` whatever else it knows, for the user to read. A ``diagnostic``
    point tells how a device works (its data exchange, a fault count) rather
    than what it measures or controls. An ``invert`` flag means the opposite of
    what is shown (a contact that is true when a door is closed, shown as a
    door): it is shown, and written, as its opposite (:meth:`flag`). A
    ``data_exchange`` point is a device's status (a Tekon ``.Status``): an integer
    whose value above its minimum means the device exchanges data, and at its
    minimum (or below) that it does not (:meth:`exchange`). A flag with an
    ``event`` is an event of that kind each time it rises to on (a call
    begins): shown as events, one per rise the source reports, those between
    two polls too. ``state_class`` is how its history is kept, as the user
    asked ("": as its unit says).

    A ``settable`` point is one its device takes a write of although it is not
    writable as the source describes it (a Tecomat variable without metadata,
    which SetObject writes as any other): the user may make it writable.
    ``override`` is what the user changed of it (None: nothing), already
    applied to the fields above; its writability, unit and range are read
    through :attr:`writable`, :meth:`takes_writes`, :meth:`unit_of` and
    :meth:`range_of`, which put it in place of the (latest) attributes'.
    """

    key: str
    path: str
    address: str
    type: DataType
    attributes: PointAttributes | None = None
    device: str = ""
    scale: float = 1.0
    offset: float = 0.0
    step: float | None = None
    platform: str = ""
    device_class: str = ""
    description: str = ""
    details: Mapping[str, str] = field(default=NO_TEXTS)
    diagnostic: bool = False
    invert: bool = False
    data_exchange: bool = False
    event: PointEvent | None = None
    state_class: str = ""
    settable: bool = False
    override: PointOverride | None = None

    def exchange(self, value: object) -> DataExchange | None:
        """Return what a ``data_exchange`` point's value says (None: no integer)."""
        if not isinstance(value, int) or isinstance(value, bool):
            return None
        lowest = (self.attributes.minimum if self.attributes else None) or 0
        return (
            DataExchange.EXCHANGING if value > lowest else DataExchange.NO_DATA_EXCHANGE
        )

    def flag(self, value: bool) -> bool:
        """Return the flag shown for a value read, or the value to write for a flag.

        The same for both ways: an inverted point's opposite, else the flag itself.
        """
        return value is not self.invert

    @property
    def kind(self) -> ValueKind:
        """What the value shown is: a scaled integer shows a real, unless all is whole."""
        kind = self.type.kind
        if (
            kind is ValueKind.INTEGER
            and self.scaled
            and not (float(self.scale).is_integer() and float(self.offset).is_integer())
        ):
            return ValueKind.REAL
        return kind

    @property
    def described(self) -> bool:
        """Whether the source describes the point (it has attributes)."""
        return self.attributes is not None

    @property
    def writable(self) -> bool:
        """Whether the point is shown writable: as the user made it, else as described.

        A plain point is not (unless the user made it so).
        """
        if self.override is not None and self.override.writable is not None:
            return self.override.writable
        return self.attributes is not None and self.attributes.writable

    def takes_writes(self, attributes: PointAttributes | None = None) -> bool:
        """Whether a write of the point is taken (a write's check).

        Not where the user made it read only, or where its attributes (the
        latest: ``attributes``, else the catalogue's) say it is; a plain point
        says nothing against a write.
        """
        if self.override is not None and self.override.writable is not None:
            return self.override.writable
        attributes = attributes if attributes is not None else self.attributes
        return attributes is None or attributes.writable

    def unit_of(self, attributes: PointAttributes | None = None) -> str:
        """Return the point's unit: the user's, else its attributes' ("": none).

        ``attributes`` are the latest (default: the catalogue's).
        """
        if self.override is not None and self.override.unit is not None:
            return self.override.unit
        attributes = attributes if attributes is not None else self.attributes
        return attributes.unit if attributes is not None else ""

    def range_of(
        self, attributes: PointAttributes | None = None
    ) -> tuple[float | None, float | None]:
        """Return the point's lowest and highest value: each the user's, else its attributes'.

        ``attributes`` are the latest (default: the catalogue's); None: no bound.
        """
        attributes = attributes if attributes is not None else self.attributes
        low = attributes.minimum if attributes is not None else None
        high = attributes.maximum if attributes is not None else None
        if (override := self.override) is not None:
            low = override.minimum if override.minimum is not None else low
            high = override.maximum if override.maximum is not None else high
        return low, high

    @property
    def scaled(self) -> bool:
        """Whether the value shown differs from the raw one (a scale or an offset)."""
        return self.scale != 1.0 or self.offset != 0.0


@dataclass(frozen=True, slots=True, kw_only=True)
class DeviceNode:
    """A device below the source's own: a program's struct, a gateway's station.

    ``parent`` is the key of the device it sits under ("" for the source's own
    device). ``properties`` are what identifies it to a user (an install
    address, an IP address, a registration number).
    """

    key: str
    name: str
    parent: str = ""
    manufacturer: str | None = None
    model: str | None = None
    serial_number: str | None = None
    properties: Mapping[str, str] = field(default=NO_TEXTS)


@dataclass(frozen=True, slots=True, kw_only=True)
class SourceInfo:
    """The source's own device (a PLC, a gateway) and what it tells of itself.

    ``identity`` is what makes two entries the same device (a PLC's serial
    number); ``name`` the device's name before the user renames it;
    ``location`` where it is reached, for a device that names no program (a
    gateway's address and station), to tell two apart. ``way_in`` names the
    way the source reaches a device that may also be reached another way (a
    communication server in front of a PLC: ``PLCComS``), so that two entries
    of one device can be told apart by their titles and their devices' names
    (None: the device's own way, or its only one). ``mode`` is None for a
    source without a run mode; ``program_*`` are None where the source knows
    no program, ``time`` where it tells no clock.
    """

    identity: str
    name: str
    manufacturer: str
    model: str | None = None
    family: str | None = None
    serial_number: str | None = None
    firmware: str | None = None
    mac: str | None = None
    mode: PlcMode | None = None
    program_name: str | None = None
    program_compiled: datetime | None = None
    program_stamp: str | None = None
    time: datetime | None = None
    api_version: str | None = None
    location: str | None = None
    way_in: str | None = None

    @property
    def running(self) -> bool:
        """Whether the device serves live values (a PLC runs its program)."""
        return self.mode is None or self.mode is PlcMode.RUNNING


@dataclass(frozen=True, slots=True, kw_only=True)
class DiscoveryCost:
    """What discovery cost in requests, against the least it could have cost.

    For a source that reads its catalogue in requests whose answers are
    limited in size. ``requests`` are the requests sent (authentication
    challenges not counted); ``lower_bound`` is the fewest any client needs to
    read the same groups knowing their sizes beforehand. ``too_large`` counts
    the answers refused as too large; ``overflowing_groups`` the groups that
    turned out too big to share the request they were first sent in (each then
    read alone) and ``oversized_groups`` those too big for any answer:
    ``too_large <= overflowing_groups + oversized_groups`` always holds.
    ``item_limit`` is the most items one answer may hold, as discovery ended
    knowing it.
    """

    requests: int
    lower_bound: int
    too_large: int
    overflowing_groups: int
    oversized_groups: int
    item_limit: int


@dataclass(frozen=True, slots=True)
class Catalogue:
    """Everything discovery learned: the points, their values, the devices.

    ``groups`` are the top-level containers the points were read by (a
    program's variables and structs, a gateway's top-level items; none where
    the points come from a map), and ``skipped_groups`` those that could not be
    read this time (their points may come back). ``discovery`` is what reading
    them cost, where the source counts it. ``devices`` are the devices below the source's own, by key:
    a tree, each naming its ``parent``, whose health :meth:`device_serves`
    and :meth:`point_serves` walk.
    """

    points: Mapping[str, Point]
    values: Mapping[str, Any]
    groups: tuple[str, ...]
    skipped_groups: tuple[str, ...]
    discovery: DiscoveryCost | None = None
    devices: Mapping[str, DeviceNode] = field(default_factory=dict)

    def device_serves(
        self, device: str, *, running: bool, offline: Mapping[str, str]
    ) -> bool:
        """Whether a device serves live values: the source's own ("") or one below.

        The source's own device does while it runs (``running``: a PLC running its program, a
        source without modes); a device below it while it exchanges data (it is
        not ``offline``), and while every device above it does. A device the
        tree does not know sits under the source's own.
        """
        if not running:
            return False
        seen: set[str] = set()
        while device and device not in seen:
            if device in offline:
                return False
            seen.add(device)
            node = self.devices.get(device)
            device = node.parent if node is not None else ""
        return True

    def point_serves(
        self, key: str, *, running: bool, offline: Mapping[str, str]
    ) -> bool:
        """Whether the device a point's value comes through serves (False: no such point).

        A diagnostic point tells how its own device works (a station's data
        exchange): it is served while the device above that one serves.
        """
        point = self.points.get(key)
        if point is None:
            return False
        device = point.device
        if point.diagnostic and (node := self.devices.get(device)):
            device = node.parent
        return self.device_serves(device, running=running, offline=offline)
