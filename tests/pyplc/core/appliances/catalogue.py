"""A typed device with a point per role, and its catalogue, for the appliances' tests."""

from collections.abc import Mapping
from typing import Any

from custom_components.tecoapi.pyplc import DataType, Point, PointAttributes, ValueKind
from custom_components.tecoapi.pyplc.core.devices import (
    READINGS,
    DeviceKind,
    Readings,
    Role,
    TypedDevice,
)
from custom_components.tecoapi.pyplc.tecomat.gtsap1 import LenientReadings

LENIENT = LenientReadings()


def make_point(
    key: str,
    kind: ValueKind,
    *,
    invert: bool = False,
    minimum: float | None = None,
    maximum: float | None = None,
) -> Point:
    """A point of ``kind``, maybe inverted or with a range."""
    attributes = (
        None
        if minimum is None and maximum is None
        else PointAttributes(minimum=minimum, maximum=maximum)
    )
    return Point(
        key=key,
        path=key.upper(),
        address=key,
        type=DataType(kind=kind),
        invert=invert,
        attributes=attributes,
    )


FLAG, INT, REAL, TEXT = (
    ValueKind.BOOL,
    ValueKind.INTEGER,
    ValueKind.REAL,
    ValueKind.STRING,
)


def make_device(
    kind: DeviceKind,
    roles: Mapping[Role, tuple[str, ValueKind]],
    *,
    readings: Readings = READINGS,
    invert: frozenset[str] = frozenset(),
    **features: Any,
) -> tuple[TypedDevice, dict[str, Point]]:
    """A device of ``kind`` with a point per role (key, kind), and its catalogue."""
    device = TypedDevice(
        key=f"test:{kind}:x",
        kind=kind,
        source="test",
        base="x",
        name="X",
        roles={role: key for role, (key, _) in roles.items()},
        readings=readings,
        **features,
    )
    points = {
        key: make_point(key, value_kind, invert=key in invert)
        for key, value_kind in roles.values()
    }
    return device, points
