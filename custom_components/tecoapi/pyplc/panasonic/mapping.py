"""An FP-I4C register map's points: checked, and placed on their stations' devices.

A map's ``device`` cell names a point's station (``2``, ``2 Garage door``);
each station is a device under the gateway's. Nothing here does I/O.
"""

import re
from typing import Final

from yarl import URL

from ..core.pointmap import TYPE_NAMES, MapPoint, PointMapError
from ..core.texts import Template, Text
from .address import (
    MAX_STRING,
    AddressError,
    WireType,
    end_problem,
    kind_problem,
    parse_address,
    wire_type,
)

MAX_STATION: Final = 99
DEFAULT_DEVICE: Final = "plc"
"""The device of the points of the station the gateway is set to use."""

NOT_A_STATION: Final = Template(
    "fpi4c_station",
    "{value} is not a station: its number (0 to {most}), optionally followed by "
    "a name (2 Garage door)",
)
LENGTH_OF_TEXT: Final = Template(
    "fpi4c_length", "only a STRING has a length (its most characters)"
)
LONGEST_TEXT: Final = Template(
    "fpi4c_longest", "the FP-I4C writes strings of at most {most} characters"
)
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
            NOT_A_STATION(value=repr(cleaned), most=MAX_STATION), column="device"
        )
    return int(found[1]), (found[2] or "").strip()


FPI4C_TYPES: Final = tuple(
    name for name, known in TYPE_NAMES.items() if wire_type(known) is not None
)
"""The type names a map may give an FP-I4C point: those the gateway reads."""


def check_point(point: MapPoint) -> Text | None:
    """Check a map's point for an FP-I4C: its address, its type, length and station.

    Returns what is wrong with the address, or raises :class:`PointMapError`
    naming the column at fault (``type``, ``length``, ``device``).
    """
    try:
        address = parse_address(point.address)
    except AddressError as err:
        return err.text
    wire = wire_type(point.type)
    if (problem := kind_problem(address, wire)) is not None:
        raise PointMapError(problem, column="type")
    if wire is not None and (problem := end_problem(address, wire)) is not None:
        return problem
    length = point.type.length
    if wire is not WireType.STRING and length is not None:
        raise PointMapError(LENGTH_OF_TEXT(), column="length")
    if length is not None and length > MAX_STRING:
        raise PointMapError(LONGEST_TEXT(most=MAX_STRING), column="length")
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


def device_key(station: int | None) -> str:
    """Return the key of a station's device (the gateway's own PLC without one)."""
    return DEFAULT_DEVICE if station is None else f"station_{station}"


def device_name(station: int | None) -> str:
    """Return the name of a station's device: ``Station 2``, ``PLC``."""
    return "PLC" if station is None else f"Station {station}"


def station_named(station: int | None) -> str:
    """Return a station as a log line begins with it: ``Station 2``, ``The PLC``."""
    return "The PLC" if station is None else f"Station {station}"
