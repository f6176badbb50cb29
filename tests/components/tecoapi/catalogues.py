"""Small catalogues of a made-up device, and its snapshots, for unit tests.

The Home Assistant layer's modules that turn a catalogue into what entities
show (``data``, ``selection``, ``issues``) are tested on these, without a
simulator: a point is named by its path, its key the path in lower case.
"""

from collections.abc import Mapping
from typing import Any, Final

from custom_components.tecoapi.pyplc import (
    Access,
    Catalogue,
    DataType,
    Point,
    PointAttributes,
    PointQuality,
    SourceInfo,
    ValueKind,
)
from custom_components.tecoapi.pyplc.core.models import DeviceNode, PlcMode
from custom_components.tecoapi.pyplc.core.source import Snapshot

REAL: Final = DataType(kind=ValueKind.REAL)
BOOL: Final = DataType(kind=ValueKind.BOOL)
INFO: Final = SourceInfo(
    identity="SN 1",
    name="Acme PLC",
    manufacturer="Acme",
    model="P-1",
    mode=PlcMode.RUNNING,
    program_name="HOUSE",
)


def point(
    path: str,
    *,
    kind: DataType = REAL,
    title: str = "",
    unit: str = "",
    writable: bool = False,
    described: bool = True,
    device: str = "",
) -> Point:
    """A point of the made-up device; a plain variable when not ``described``."""
    attributes = (
        PointAttributes(
            name=title,
            unit=unit,
            access=Access.READ_WRITE if writable else Access.READ,
        )
        if described
        else None
    )
    return Point(
        key=path.lower(),
        path=path,
        address=path,
        type=kind,
        attributes=attributes,
        device=device,
    )


def catalogue(
    *points: Point,
    values: Mapping[str, Any] | None = None,
    groups: tuple[str, ...] = (),
    devices: Mapping[str, DeviceNode] | None = None,
) -> Catalogue:
    """A catalogue of the points (their values 0 unless given, by key)."""
    return Catalogue(
        points={item.key: item for item in points},
        values={item.key: 0 for item in points} | dict(values or {}),
        groups=groups,
        skipped_groups=(),
        devices=dict(devices or {}),
    )


def snapshot(
    found: Catalogue,
    values: Mapping[str, Any] | None = None,
    *,
    info: SourceInfo = INFO,
    quality: Mapping[str, PointQuality] | None = None,
    offline: Mapping[str, str] | None = None,
) -> Snapshot:
    """What a poll of the catalogue read: ``values`` (all of them unless given)."""
    return Snapshot(
        info=info,
        catalogue=found,
        values=dict(found.values if values is None else values),
        attributes={},
        quality=dict(quality or {}),
        offline=dict(offline or {}),
    )
