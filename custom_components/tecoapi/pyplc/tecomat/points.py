"""Tecomat's variables as neutral points: plain variables and T_ApiObjects.

TecoApi and PLCComS read the same public variables of a Tecomat program, so both
make the same points of them:

- the key is the path in lower case (PLC names are case-insensitive), the path
  and the address the path as the PLC spells it;
- the data type is what the PLC's JSON tells: a flag, an integer (the JSON does
  not say which IEC type, so the widest bounds apply, DINT..UDINT), a real, ASCII
  text of at most 255 characters, a date or a date and time (from 1970 on), a
  time (at most ``T#24d20h31m23s647ms``); PLCComS' ``LIST:`` names the type,
  so there an integer has its IEC type's bounds (an ``INT`` -32768..32767);
- a T_ApiObject (manual chapter 5.3) carries its ``attr``: its title is the
  point's display name, ``units`` its unit, ``readOnly`` its access, ``minValue``
  and ``maxValue`` its range (both 0: none), ``enable`` and ``visibility`` whether
  it can be used and is shown; its value is the ``.value`` member;
- a plain variable has no attributes;
- every point is ``settable``: SetObject and PutObject (manual 3.5, 3.6) and
  PLCComS' ``SET:`` write any public variable, a plain one or a T_ApiObject
  whose ``readOnly`` is true alike (the PLC stores what it is sent; read-only
  is what the program tells its clients), so the user may make any writable.
"""

from collections.abc import Mapping
from types import MappingProxyType
from typing import Final

from ..core.models import Access, DataType, Point, PointAttributes, ValueKind
from .tecoapi.values import (
    EARLIEST,
    INTEGER_MAX,
    INTEGER_MIN,
    STRING_MAX_LENGTH,
    TIME_LONGEST,
)

MANUFACTURER: Final = "Teco a.s."

TECOMAT_TYPES: Final[Mapping[ValueKind, DataType]] = MappingProxyType(
    {
        ValueKind.BOOL: DataType(kind=ValueKind.BOOL),
        ValueKind.INTEGER: DataType(
            kind=ValueKind.INTEGER, minimum=INTEGER_MIN, maximum=INTEGER_MAX
        ),
        ValueKind.REAL: DataType(kind=ValueKind.REAL),
        ValueKind.STRING: DataType(
            kind=ValueKind.STRING, encoding="ascii", length=STRING_MAX_LENGTH
        ),
        ValueKind.DATE: DataType(kind=ValueKind.DATE, earliest=EARLIEST),
        ValueKind.TIME: DataType(kind=ValueKind.TIME, longest=TIME_LONGEST),
        ValueKind.DATETIME: DataType(kind=ValueKind.DATETIME, earliest=EARLIEST),
    }
)
"""The data type of each kind a Tecomat variable's JSON can have."""


def tecomat_point(
    path: str,
    kind: ValueKind,
    attributes: PointAttributes | None = None,
    data_type: DataType | None = None,
) -> Point:
    """Return the point of a Tecomat variable (a T_ApiObject with its attributes).

    ``data_type`` is its type where the way in tells it (PLCComS' ``LIST:``
    names an integer's IEC type: its bounds); else the kind's.
    """
    return Point(
        key=path.lower(),
        path=path,
        address=path,
        type=data_type or TECOMAT_TYPES[kind],
        attributes=attributes,
        settable=True,
    )


def api_object_attributes(
    *,
    title: str,
    units: str,
    read_only: bool,
    min_value: float,
    max_value: float,
    enable: bool,
    visibility: bool,
) -> PointAttributes:
    """Return a T_ApiObject's ``attr`` as attributes (min = max = 0: no range)."""
    ranged = not (min_value == 0 and max_value == 0)
    return PointAttributes(
        name=title,
        unit=units,
        access=Access.READ if read_only else Access.READ_WRITE,
        minimum=min_value if ranged else None,
        maximum=max_value if ranged else None,
        enabled=enable,
        visible=visibility,
    )


def value_path(point: Point) -> str:
    """Return the path that holds a point's value: ``path.value`` for a T_ApiObject."""
    return f"{point.address}.value" if point.described else point.address


def point_key(points: Mapping[str, Point], path: str) -> str | None:
    """Return the key of the point at a variable path, if it is one.

    Paths are case-insensitive; a T_ApiObject is its own path or its ``.value``
    member.
    """
    key = path.lower()
    if key in points:
        return key
    key = key.removesuffix(".value")
    point = points.get(key)
    return key if point is not None and point.described else None
