"""Our struct convention: a struct's member names say what device it is.

A struct whose member names say what it is: ``temperature`` + ``setpoint`` is
a thermostat, ``position`` a blind, ``brightness`` a light (member names
matched ignoring case; ``docs/typed-devices.md``). It is this project's own
convention, not a vendor's, so it lives in the core: a T_ApiObject program's
structs, a Mervis function block's members, a map's or a gateway's dotted
names may follow it, and every built-in system's descriptor registers
:data:`STRUCTS` (Tecomat's after Teco's GTSAP1 families). The members keep
their attributes, and are checked as strictly as a composition; the devices'
keys are ``struct:<kind>:<struct path>``.
"""

from collections.abc import Mapping
from types import MappingProxyType
from typing import Any, Final

from .composition import CompositionError, build
from .devices import DeviceKind, Recognised, Recogniser, Role, TypedDevice
from .models import Point

NAME: Final = "struct"
"""The recogniser's name: the first part of its devices' keys (never changes)."""

STRUCT_MEMBERS: Final[Mapping[DeviceKind, Mapping[str, Role]]] = MappingProxyType(
    {
        DeviceKind.CLIMATE: {
            "temperature": Role.TEMPERATURE,
            "setpoint": Role.SETPOINT,
            "heatmode": Role.HEAT_MODE,
            "coolmode": Role.COOL_MODE,
            "heating": Role.HEATING,
            "cooling": Role.COOLING,
        },
        DeviceKind.COVER: {
            "position": Role.POSITION,
            "target": Role.TARGET,
            "moving": Role.MOVING,
        },
        DeviceKind.LIGHT: {
            "brightness": Role.LEVEL,
            "onoff": Role.ONOFF,
            "colortemp": Role.COLOR_TEMP,
        },
    }
)
"""Struct member names (lower case) per kind and the role each plays."""

STRUCT_SIGNATURES: Final[Mapping[DeviceKind, frozenset[str]]] = MappingProxyType(
    {
        DeviceKind.CLIMATE: frozenset({"temperature", "setpoint"}),
        DeviceKind.COVER: frozenset({"position"}),
        DeviceKind.LIGHT: frozenset({"brightness"}),
    }
)
"""The members that make a struct a device of the kind (all of them)."""


def _struct_groups(
    points: Mapping[str, Point], taken: frozenset[str]
) -> dict[str, tuple[str, dict[str, str]]]:
    """Points grouped by their struct: lower-case parent → (parent path, member → key)."""
    groups: dict[str, tuple[str, dict[str, str]]] = {}
    for point in points.values():
        parent, dot, member = point.path.rpartition(".")
        if not dot or "[" in member or point.key in taken:
            continue
        _, members = groups.setdefault(parent.lower(), (parent, {}))
        members.setdefault(member.lower(), point.key)
    return groups


def _find(
    points: Mapping[str, Point], values: Mapping[str, Any], taken: frozenset[str]
) -> Recognised:
    """Find the devices of our struct convention among the points not yet taken."""
    devices: list[TypedDevice] = []
    skipped: dict[str, str] = {}
    for parent_key, (parent, members) in _struct_groups(points, taken).items():
        for kind, signature in STRUCT_SIGNATURES.items():
            if not signature <= members.keys():
                continue
            key = f"{NAME}:{kind}:{parent_key}"
            chosen = {
                role: members[member]
                for member, role in STRUCT_MEMBERS[kind].items()
                if member in members
            }
            try:
                devices.append(
                    build(
                        kind,
                        chosen,
                        points,
                        source=NAME,
                        key=key,
                        base=parent,
                    )
                )
            except CompositionError as err:
                skipped[key] = str(err)
    return Recognised(devices=tuple(devices), skipped=skipped)


STRUCTS: Final = Recogniser(name=NAME, find=_find)
"""The recogniser of structs in our convention."""
