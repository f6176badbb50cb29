"""An OPC address space as the neutral model: devices from dotted names, points by properties.

**Devices.** Every controller and device has a ``.Status`` channel
(``Controller1.Status``, ``Controller1.Device1.Status``): each such prefix is a
:class:`DeviceNode` under the nearest prefix above it that is one (a device
under its controller), identified by its status channel's properties (install
address 6001, IP address 6000, registration number 9002). A channel belongs to
the nearest device above it; one under no device at all belongs to its top-level
name, a device without a status of its own (``DBMonitoring``).

**Points.** An item's *name* is its key (lower case: the options' patterns match
it), its path and its address: ``ItemID``s move when the address space changes.
What it is comes from its properties:

==========================  ====================================================
5001 channel type           the point
==========================  ====================================================
3000 discrete               a flag (the value's low bit), read only
3001 intercom               written 1 to call: a write-only flag (a button);
                            read only where it may not be written; and its
                            calls, a flag keyed ``<name>#ring`` whose every
                            rise is an event (:attr:`PointEvent.RING`), and
                            beside a button its call state (the low bit: a
                            call is on), a read-only flag keyed
                            ``<name>#call``, not shown unless the user wants
3002 control                a flag (the low bit), written to switch
3005 status                 an integer, read only, diagnostic; its range 6003
                            (0 when absent) .. 6004; above its minimum the
                            device exchanges data (``data_exchange``)
3060 number                 an integer or a real by its value type (1)
3061 string                 text
3070 lift state             a :class:`Record` of the state's XML, read only
none, or another            by its value type (1): a VARTYPE
==========================  ====================================================

Access is property 5 (OPC DA's, and the seed's example) or, without it, 3 (the
seed's table; in OPC DA 3 is an item's quality, so it is taken only as 1, 2 or
3): 1 read, 2 write, 3 both. An item whose rights grant a write is
``settable`` even where its channel shows it read only (a discrete input): its
user may make it writable, never one whose rights are read only. The name shown is the fault description (7001),
else the comment (5003), else the last part of the item's name. OPC DA's own
properties are taken where a server gives them: 100 the unit, 102 and 103 the
range.

**Values** are text: numbers may have a decimal comma (``"0,05"``), flags are
read from the low bit, a lift's state is XML (see :func:`parse_record`).
**Quality** is OPC DA's: 192 (and 216, a local override) good; 0x00 unknown
(the seed's ``DA_QUALITY_UNCKNOWN``: no value, the entity available); the
others uncertain (0x40..0x7F) or bad, by their name (``comm_failure``).
"""

from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field, replace
from enum import IntEnum
import re
from types import MappingProxyType
from typing import Any, Final
from xml.etree import ElementTree as ET

from ..core.models import (
    NO_TEXTS,
    Access,
    Catalogue,
    DataExchange,
    DataType,
    DeviceNode,
    Point,
    PointAttributes,
    PointEvent,
    PointQuality,
    Quality,
    Record,
    ValueKind,
)
from .client import AddressItem

VALUE_TYPE: Final = 1
ACCESS_TABLE: Final = 3
ACCESS: Final = 5
UNIT: Final = 100
HIGH_EU: Final = 102
LOW_EU: Final = 103
CHANNEL_TYPE: Final = 5001
COMMENT: Final = 5003
IP_ADDRESS: Final = 6000
INSTALL_ADDRESS: Final = 6001
STATUS_MIN: Final = 6003
STATUS_MAX: Final = 6004
FAULT_CATEGORY: Final = 7000
FAULT_DESCRIPTION: Final = 7001
REGISTRATION_NUMBER: Final = 9002
KEPT_PROPERTIES: Final = frozenset(
    {
        VALUE_TYPE,
        ACCESS_TABLE,
        ACCESS,
        UNIT,
        HIGH_EU,
        LOW_EU,
        CHANNEL_TYPE,
        COMMENT,
        IP_ADDRESS,
        INSTALL_ADDRESS,
        STATUS_MIN,
        STATUS_MAX,
        FAULT_CATEGORY,
        FAULT_DESCRIPTION,
        REGISTRATION_NUMBER,
    }
)
"""The properties a point or a device is made of (the others are not kept)."""

IDENTIFYING: Final[Mapping[int, str]] = {
    INSTALL_ADDRESS: "install_address",
    IP_ADDRESS: "ip_address",
    REGISTRATION_NUMBER: "registration_number",
}
"""A status channel's properties that identify its device, by the name shown."""
DETAILS: Final[Mapping[int, str]] = {
    **IDENTIFYING,
    FAULT_CATEGORY: "fault_category",
}
"""A channel's properties shown beside its value."""

STATUS_SUFFIX: Final = ".status"
MAX_RECORD_CHARS: Final = 64 * 1024
"""The longest lift state read as XML (longer is a malformed value)."""
MAX_RECORD_PARTS: Final = 64
MAX_SHOWN_CHARS: Final = 255
"""The most characters of a record's text (Home Assistant's longest state)."""
SHOWN_PARTS: Final = ("state", "status", "mode", "состояние")
"""The part of a record shown as its value, the first there is (any case)."""
NO_DATA_EXCHANGE: Final = DataExchange.NO_DATA_EXCHANGE.value
"""Why a device whose status is 0 is offline."""
MALFORMED: Final = PointQuality(quality=Quality.BAD, reason="malformed_value")


class ChannelType(IntEnum):
    """Tekon's channel data types (property 5001)."""

    DISCRETE = 3000
    INTERCOM = 3001
    CONTROL = 3002
    STATUS = 3005
    NUMBER = 3060
    STRING = 3061
    LIFT_STATE = 3070


# VARTYPE codes (property 1) of numbers: (bits, signed) for integers.
_INTEGERS: Final[Mapping[int, tuple[int, bool]]] = {
    2: (16, True),  # VT_I2
    3: (32, True),  # VT_I4
    16: (8, True),  # VT_I1
    17: (8, False),  # VT_UI1
    18: (16, False),  # VT_UI2
    19: (32, False),  # VT_UI4
    20: (64, True),  # VT_I8
    21: (64, False),  # VT_UI8
    22: (32, True),  # VT_INT
    23: (32, False),  # VT_UINT
}
_REALS: Final[Mapping[int, int]] = {4: 32, 5: 64, 6: 64}  # VT_R4, VT_R8, VT_CY
VT_BOOL: Final = 11
_FLAG: Final = DataType(kind=ValueKind.BOOL)
_TEXT: Final = DataType(kind=ValueKind.STRING)
_RECORD: Final = DataType(kind=ValueKind.RECORD)
_STATUS: Final = DataType(kind=ValueKind.INTEGER, bits=32, signed=False)
_NUMBER: Final = re.compile(
    r"[+-]?(?:[0-9]+(?:[.,][0-9]*)?|[.,][0-9]+)(?:[eE][+-]?[0-9]+)?"
)

QUALITY_NAMES: Final[Mapping[int, str]] = {
    0x00: "unknown",
    0x04: "config_error",
    0x08: "not_connected",
    0x0C: "device_failure",
    0x10: "sensor_failure",
    0x14: "last_known",
    0x18: "comm_failure",
    0x1C: "out_of_service",
    0x20: "waiting_for_initial_data",
    0x40: "uncertain",
    0x44: "last_usable",
    0x50: "sensor_cal",
    0x54: "egu_exceeded",
    0x58: "sub_normal",
    0xC0: "good",
    0xD8: "local_override",
}
"""OPC DA's qualities by their status bits (the two limit bits left out)."""
GOOD: Final = 0xC0
UNKNOWN: Final = 0x00
NOT_KNOWN: Final = PointQuality(quality=Quality.UNKNOWN, reason="unknown")
"""The quality of a value the gateway does not know (0x00)."""


def key_of(name: str) -> str:
    """Return the point key of an item name: the name in lower case."""
    return name.lower()


def quality_of(code: int) -> PointQuality | None:
    """Return the quality of an OPC DA quality code (None: good).

    0x00 is the seed's ``DA_QUALITY_UNCKNOWN``: no value is known (OPC DA's
    plain "bad", without a reason), shown as unknown rather than unavailable.
    """
    status = code & 0xFC
    if code & GOOD == GOOD:
        return None
    if status == UNKNOWN:
        return NOT_KNOWN
    name = QUALITY_NAMES.get(status, f"quality_{code}")
    if code & GOOD == 0x40:
        return PointQuality(quality=Quality.UNCERTAIN, reason=name)
    return PointQuality(quality=Quality.BAD, reason=name)


@dataclass(frozen=True, slots=True, kw_only=True)
class AddressSpace:
    """What an address space became: the catalogue and how to read its updates.

    ``status_of`` is each device's status point (by device key), ``ids`` each
    point's key by its ``ItemID`` now (for a gateway that answers by ID only),
    ``readers`` the keys of the other points an item's value is read into, by
    the item's key (an intercom's call state and its calls).
    """

    catalogue: Catalogue
    status_of: Mapping[str, str]
    ids: Mapping[int, str]
    devices_above: Mapping[str, tuple[str, ...]] = field(default_factory=dict)
    """Each device's key and those above it, nearest first."""
    readers: Mapping[str, tuple[str, ...]] = field(default_factory=dict)
    _item_ids: dict[str, int] = field(default_factory=dict, compare=False, repr=False)

    def item_id(self, name: str) -> int | None:
        """Return an item's ``ItemID`` in this address space by its name (any case).

        For a gateway spoken to by ID (API 2.0, or 2.1's reads and writes); the
        inverse of ``ids`` is made at the first call (most gateways never ask).
        """
        if not self._item_ids and self.ids:
            self._item_ids.update((key, item_id) for item_id, key in self.ids.items())
        return self._item_ids.get(key_of(name))


def build_address_space(items: Iterable[AddressItem]) -> AddressSpace:
    """Make the catalogue of an address space (see the module's docstring)."""
    listed = list(items)
    device_names = {
        item.name[: -len(STATUS_SUFFIX)]: item
        for item in listed
        if item.name.lower().endswith(STATUS_SUFFIX)
        and len(item.name) > len(STATUS_SUFFIX)
    }
    devices = _devices(device_names)
    points: dict[str, Point] = {}
    ids: dict[int, str] = {}
    status_of: dict[str, str] = {}
    readers: dict[str, tuple[str, ...]] = {}
    roots: dict[str, None] = {}
    for item in listed:
        key = key_of(item.name)
        if key in points:
            continue  # a name given twice (in another case): the first one counts
        prefix, dot, _ = item.name.rpartition(".")
        device = _device_of(prefix, devices) if dot else ""
        if not device and dot:
            root = item.name.split(".", 1)[0]
            device = key_of(root)
            devices.setdefault(device, DeviceNode(key=device, name=root))
        roots[item.name.split(".", 1)[0]] = None
        status = item.name.lower().endswith(STATUS_SUFFIX) and prefix in device_names
        if status:
            device = key_of(prefix)
            status_of[device] = key
        points[key] = point = _point(item, key, device, status=status)
        ids[item.item_id] = key
        if _int(item.properties.get(CHANNEL_TYPE)) == ChannelType.INTERCOM:
            intercom = _intercom(point)
            readers[key] = tuple(intercom)
            points.update(intercom)
    above = {key: _chain(key, devices) for key in devices}
    return AddressSpace(
        catalogue=Catalogue(
            points=points,
            values={},
            groups=tuple(roots),
            skipped_groups=(),
            devices=devices,
        ),
        status_of=status_of,
        ids=ids,
        devices_above=above,
        readers=readers,
    )


CALL: Final = "#call"
"""What an intercom's key is followed by in the key of its call state."""
RING: Final = "#ring"
"""What an intercom's key is followed by in the key of its calls (events)."""


def _intercom(point: Point) -> dict[str, Point]:
    """Return the points read beside an intercom's own: its call state, its calls.

    Its own point keeps its key and what it is (a button where it may be
    written, its call state where not); every intercom's calls are events,
    and a button's call state is read beside it, not shown by default (its
    calls tell a call; a building of a thousand intercoms is not a thousand
    entities more than it needs). Both read the item's low bit (the seed: a
    call is on).
    """
    assert point.attributes is not None
    shown = replace(point.attributes, access=Access.READ)
    derived: dict[str, Point] = {}
    if point.attributes.access is Access.WRITE:
        derived[point.key + CALL] = replace(
            point, key=point.key + CALL, attributes=replace(shown, visible=False)
        )
    derived[point.key + RING] = replace(
        point, key=point.key + RING, attributes=shown, event=PointEvent.RING
    )
    return derived


def _devices(statuses: Mapping[str, AddressItem]) -> dict[str, DeviceNode]:
    """Return the devices of the prefixes with a status, each under the nearest above."""
    keys = {key_of(prefix): prefix for prefix in statuses}
    names: dict[str, str] = {}
    parents: dict[str, str] = {}
    for key, prefix in keys.items():
        parents[key] = _device_of(prefix.rpartition(".")[0], keys)
        names[key] = prefix.rpartition(".")[2]
    taken: dict[str, int] = {}
    for name in names.values():
        taken[name] = taken.get(name, 0) + 1
    devices: dict[str, DeviceNode] = {}
    for key, prefix in keys.items():
        name = names[key]
        if taken[name] > 1 and (parent := parents[key]):
            # Two "Lift 1" under two entrances: each says its entrance too.
            name = f"{names[parent]} {name}"
        properties = statuses[prefix].properties
        shown = {
            label: properties[prop].strip()
            for prop, label in IDENTIFYING.items()
            if properties.get(prop, "").strip()
        }
        devices[key] = DeviceNode(
            key=key,
            name=name,
            parent=parents[key],
            serial_number=shown.get("registration_number"),
            properties=MappingProxyType(shown),
        )
    return devices


def _device_of(prefix: str, devices: Mapping[str, Any]) -> str:
    """Return the key of the nearest device at or above a dotted prefix ("": none)."""
    while prefix:
        if (key := key_of(prefix)) in devices:
            return key
        prefix = prefix.rpartition(".")[0]
    return ""


def _chain(key: str, devices: Mapping[str, DeviceNode]) -> tuple[str, ...]:
    """Return a device's key and the keys of those above it, nearest first."""
    chain: list[str] = []
    while key and key not in chain:
        chain.append(key)
        node = devices.get(key)
        key = node.parent if node is not None else ""
    return tuple(chain)


def _point(item: AddressItem, key: str, device: str, *, status: bool) -> Point:
    """Return the point of a channel (or of a device's status)."""
    props = item.properties
    channel = _int(props.get(CHANNEL_TYPE))
    access = granted = _access(props)
    data_type = _data_type(_int(props.get(VALUE_TYPE)))
    minimum, maximum = _float(props.get(LOW_EU)), _float(props.get(HIGH_EU))
    if status or channel == ChannelType.STATUS:
        status = True
        data_type, access = _STATUS, Access.READ
        minimum = _float(props.get(STATUS_MIN)) or 0.0
        maximum = _float(props.get(STATUS_MAX))
    elif channel == ChannelType.DISCRETE:
        data_type, access = _FLAG, Access.READ
    elif channel == ChannelType.INTERCOM:
        # Written 1 to call: a button where it may be written.
        data_type = _FLAG
        access = Access.WRITE if access.writable else Access.READ
    elif channel == ChannelType.CONTROL:
        data_type = _FLAG
    elif channel == ChannelType.NUMBER:
        if data_type.kind not in (ValueKind.INTEGER, ValueKind.REAL):
            data_type = DataType(kind=ValueKind.REAL)
    elif channel == ChannelType.STRING:
        data_type = _TEXT
    elif channel == ChannelType.LIFT_STATE:
        data_type, access = _RECORD, Access.READ
    described = (
        props.get(FAULT_DESCRIPTION, "").strip() or props.get(COMMENT, "").strip()
    )
    name = described or item.name.rpartition(".")[2]
    numeric = data_type.kind in (ValueKind.INTEGER, ValueKind.REAL)
    has_range = numeric and minimum is not None and maximum is not None
    details = {
        label: value.strip()
        for prop, label in DETAILS.items()
        if (value := props.get(prop, "")).strip()
    }
    return Point(
        key=key,
        path=item.name,
        address=item.name,
        type=data_type,
        attributes=PointAttributes(
            name=name,
            unit=props.get(UNIT, "").strip() if numeric else "",
            access=access,
            minimum=minimum if has_range else None,
            maximum=maximum if has_range else None,
        ),
        device=device,
        description=described,
        details=MappingProxyType(details) if details else NO_TEXTS,
        diagnostic=status,
        data_exchange=status,
        # What the item's access rights grant, whatever its channel shows: the
        # user may make it writable.
        settable=granted.writable,
    )


def _access(props: Mapping[int, str]) -> Access:
    """Access from property 5, or 3 where it says 1, 2 or 3; read only without."""
    code = _int(props.get(ACCESS))
    if code is None and _int(props.get(ACCESS_TABLE)) in (1, 2, 3):
        code = _int(props.get(ACCESS_TABLE))
    match code:
        case 2:
            return Access.WRITE
        case 3:
            return Access.READ_WRITE
        case _:
            return Access.READ


def _data_type(vartype: int | None) -> DataType:
    """Return the data type of a VARTYPE (text for what is not a number or a flag)."""
    if vartype is None:
        return _TEXT
    if (integer := _INTEGERS.get(vartype)) is not None:
        return DataType(kind=ValueKind.INTEGER, bits=integer[0], signed=integer[1])
    if (bits := _REALS.get(vartype)) is not None:
        return DataType(kind=ValueKind.REAL, bits=bits)
    if vartype == VT_BOOL:
        return _FLAG
    return _TEXT


def _int(text: str | None) -> int | None:
    if text is None:
        return None
    try:
        return int(text.strip())
    except ValueError:
        return None


def _float(text: str | None) -> float | None:
    number = parse_number(text or "")
    return None if number is None else float(number)


def parse_number(text: str) -> int | float | None:
    """Read a number as the gateway writes it: ``"0,05"``, ``"12"``, ``"1 234,5"``."""
    compact = text.strip().replace("\u00a0", "").replace(" ", "")
    if not _NUMBER.fullmatch(compact):
        return None
    compact = compact.replace(",", ".")
    if re.fullmatch(r"[+-]?[0-9]+", compact):
        return int(compact)
    return float(compact)


def parse_value(point: Point, text: str) -> tuple[Any, PointQuality | None]:
    """Return a point's value of its text, or None and why it is malformed."""
    match point.type.kind:
        case ValueKind.BOOL:
            lowered = text.strip().lower()
            if lowered in ("true", "false"):
                return lowered == "true", None
            number = parse_number(text)
            if isinstance(number, int):
                return bool(number & 1), None
        case ValueKind.INTEGER:
            number = parse_number(text)
            if isinstance(number, int):
                return number, None
            if isinstance(number, float) and number.is_integer():
                return int(number), None
        case ValueKind.REAL:
            number = parse_number(text)
            if number is not None:
                return float(number) + 0.0, None
        case ValueKind.RECORD:
            if (record := parse_record(text)) is not None:
                return record, None
        case _:
            return text, None
    return None, MALFORMED


def parse_record(text: str) -> Record | None:
    """Return a lift's state of its XML (None: not XML).

    The parts are the root element's attributes, then each element below it by
    its tag (its text, and its attributes as ``tag_attribute``; an element with
    elements below it gives theirs as ``tag_child``). The text shown is the part
    named ``state``, ``status`` or ``mode`` (any case) where there is one, else
    the root's own text, else the first parts as ``name: value``.
    """
    if len(text) > MAX_RECORD_CHARS:
        return None
    try:
        root = ET.fromstring(text)  # noqa: S314 (expat refuses entity expansion bombs)
    except ET.ParseError:
        return None
    parts: list[tuple[str, str]] = list(root.attrib.items())
    for element in root:
        _parts_of(element, element.tag, parts)
    parts = parts[:MAX_RECORD_PARTS]
    by_name = {name.lower(): value for name, value in reversed(parts)}
    shown = next((by_name[name] for name in SHOWN_PARTS if name in by_name), None)
    if shown is None:
        shown = (root.text or "").strip() or "; ".join(
            f"{name}: {value}" for name, value in parts[:4]
        )
    return Record(text=shown[:MAX_SHOWN_CHARS], parts=tuple(parts))


def _parts_of(element: ET.Element, name: str, parts: list[tuple[str, str]]) -> None:
    """Add an element's parts: its text, its attributes, its children's (one level)."""
    parts.extend((f"{name}_{attr}", value) for attr, value in element.attrib.items())
    children = list(element)
    if not children:
        parts.append((name, (element.text or "").strip()))
        return
    parts.extend(
        (f"{name}_{child.tag}", (child.text or "").strip()) for child in children
    )


def compact(items: Iterable[AddressItem]) -> list[list[Any]]:
    """Items as kept between runs: name, ID and the properties points are made of."""
    return [
        [
            item.name,
            item.item_id,
            {
                str(prop): value
                for prop, value in item.properties.items()
                if prop in KEPT_PROPERTIES
            },
        ]
        for item in items
    ]


def from_compact(kept: Any) -> list[AddressItem] | None:
    """Items kept by :func:`compact` (None: not what it keeps)."""
    if not isinstance(kept, list):
        return None
    items: list[AddressItem] = []
    for row in kept:
        if (
            not isinstance(row, list)
            or len(row) != 3
            or not isinstance(row[0], str)
            or not isinstance(row[1], int)
            or not isinstance(row[2], dict)
        ):
            return None
        items.append(
            AddressItem(
                name=row[0],
                item_id=row[1],
                properties={int(prop): str(value) for prop, value in row[2].items()},
            )
        )
    return items
