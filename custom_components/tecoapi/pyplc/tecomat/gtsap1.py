"""GTSAP1 block families: Teco's smart-home gateway blocks, recognised in a program.

Public variables ``<base>_GTSAP1_<TYPE>_<property>`` (or
``<base>.GTSAP1_<TYPE>_<property>``, the members of a block instance), matched
ignoring case anywhere in the program, make one device per base and type
(``docs/typed-devices.md`` gives the families). Their values may be text with
a decimal comma and flags 0/1, so a family's devices read them with
:data:`LENIENT` readings. :data:`GTSAP1` is the recogniser a descriptor
registers; its devices' keys are ``gtsap1:<type>:<base>``.
"""

from collections.abc import Mapping
from dataclasses import dataclass, field
import re
from types import MappingProxyType
from typing import Any, Final, override

from ..core.composition import climate_support
from ..core.devices import (
    CLIMATE_ROLES,
    COUNT,
    FLAG,
    NUMBER,
    ROLE_KINDS,
    ClimateSupport,
    CoverClass,
    DeviceKind,
    LightMode,
    Measurement,
    Readings,
    Recognised,
    Recogniser,
    Role,
    SwitchClass,
    TypedDevice,
    is_gate_name,
    name_from_base,
)
from ..core.models import Point, ValueKind
from ..core.scalars import format_real

NAME: Final = "gtsap1"
"""The recogniser's name: the first part of its devices' keys (never changes)."""

# Display symbol codes (BLOCKS.md); other codes are generic values.
DISPLAY_SYMBOLS: Final[Mapping[int, Measurement]] = MappingProxyType(
    {
        100: Measurement.TEMPERATURE,
        101: Measurement.HUMIDITY,
        104: Measurement.CO2,
        105: Measurement.CO,
        107: Measurement.ILLUMINANCE,
    }
)

# A thermostat block's type code: what it does.
CLIMATE_TYPES: Final[Mapping[int, ClimateSupport]] = MappingProxyType(
    {1: ClimateSupport.COOLING, 2: ClimateSupport.HEATING, 3: ClimateSupport.BOTH}
)

_DIRECTION_ROLES: Final = CLIMATE_ROLES[ClimateSupport.BOTH]

# --------------------------------------------------------------------------
# Values: numbers as text with a decimal comma, flags as 0/1 or words.

_TRUE_TEXT: Final = frozenset({"1", "true", "on"})
_FALSE_TEXT: Final = frozenset({"0", "false", "off"})


class LenientReadings(Readings):
    """Readings of what GTSAP1 variables hold: text as well as numbers and flags.

    A number from text too (``"21,5"``, ``" 21.5 "``); a flag from text
    (``1``/``0``, ``true``/``false``, ``on``/``off``); a flag or a number
    written to text as ``"1"``/``"0"`` or spelled with a point.
    """

    __slots__ = ()

    @override
    def number(self, value: Any) -> float | None:
        """Read a finite number from an int, a float or text; else None."""
        if isinstance(value, str):
            try:
                value = float(value.strip().replace(",", "."))
            except ValueError:
                return None
        return super().number(value)

    @override
    def flag(self, value: Any) -> bool | None:
        """Read a flag from a bool, 0/1 or text; else None."""
        if isinstance(value, str):
            text = value.strip().lower()
            if text in _TRUE_TEXT:
                return True
            if text in _FALSE_TEXT:
                return False
            return None
        return super().flag(value)

    @override
    def written(self, point: Point, value: bool | float) -> bool | int | float | str:
        """Write a flag or a number to a text variable as text; else as the kind says."""
        if point.kind is not ValueKind.STRING:
            return super().written(point, value)
        if isinstance(value, bool):
            return "1" if value else "0"
        number = float(value)
        return str(int(number)) if number.is_integer() else format_real(number)


LENIENT: Final = LenientReadings()


def _clean_name(value: Any) -> str | None:
    """Return a name variable's text, or None when it is empty or only a number."""
    if not isinstance(value, str):
        return None
    text = " ".join(value.split())
    if not text or LENIENT.number(text) is not None:
        return None
    return text


# --------------------------------------------------------------------------
# The families.

_GTSAP1: Final = re.compile(
    r"(?P<base>.+?)[._]GTSAP1_(?P<type>[A-Z]+)_(?P<property>[A-Z0-9]+)",
    re.IGNORECASE,
)


@dataclass(frozen=True, slots=True, kw_only=True)
class _Family:
    """A GTSAP1 family type: its device kind, its properties, what it cannot lack.

    ``properties`` map a lower-case property to its role; ``config`` map the
    configuration properties read once at discovery (a light's ``dimtype``)
    to the kinds they hold; ``essential``: at least one of these must be
    present for the family to be a device.
    """

    kind: DeviceKind
    properties: Mapping[str, Role]
    essential: frozenset[str]
    config: Mapping[str, frozenset[ValueKind]] = field(default_factory=dict)

    def knows(self, prop: str) -> bool:
        """Whether ``prop`` is one of the family's properties."""
        return prop in self.properties or prop in self.config


_GTSAP1_ROLES: Final[Mapping[str, Role]] = MappingProxyType(
    {
        "onoff": Role.ONOFF,
        "dimlevel": Role.LEVEL,
        "tgtlevel": Role.TARGET_LEVEL,
        "rgb": Role.RGB,
        "colortemp": Role.COLOR_TEMP,
        "mintempk": Role.MIN_KELVIN,
        "maxtempk": Role.MAX_KELVIN,
        "current": Role.POSITION,
        "target": Role.TARGET,
        "moving": Role.MOVING,
        "meastemp": Role.TEMPERATURE,
        "setpoint": Role.SETPOINT,
        "mintemp": Role.MIN_TEMP,
        "maxtemp": Role.MAX_TEMP,
        "heatmode": Role.HEAT_MODE,
        "coolmode": Role.COOL_MODE,
        "heat": Role.HEATING,
        "cool": Role.COOLING,
        "clickcnt": Role.CLICK_COUNT,
        "presscnt": Role.PRESS_COUNT,
        "value": Role.VALUE,
        "unit": Role.UNIT,
        "precision": Role.PRECISION,
        "state": Role.STATE,
        "name": Role.NAME,
    }
)
"""The role each GTSAP1 property (lower case) plays, in whichever family has it."""


def _family(
    kind: DeviceKind,
    essential: str,
    optional: str = "",
    config: Mapping[str, frozenset[ValueKind]] | None = None,
) -> _Family:
    """Make a family from its space-separated property names; all have a ``name``.

    ``essential``: at least one of these must be usable; ``optional``: the
    other properties; ``config``: as in :class:`_Family`.
    """
    names = [*essential.split(), *optional.split(), "name"]
    return _Family(
        kind=kind,
        properties={prop: _GTSAP1_ROLES[prop] for prop in names},
        essential=frozenset(essential.split()),
        config=config or {},
    )


# Each family type: its kind, its essential properties, its optional ones and
# the configuration read at discovery.
_FAMILIES: Final[Mapping[str, _Family]] = MappingProxyType(
    {
        "LIGHT": _family(
            DeviceKind.LIGHT,
            "onoff",
            "dimlevel tgtlevel rgb colortemp mintempk maxtempk",
            {"type": FLAG, "dimtype": COUNT},
        ),
        "OPENER": _family(DeviceKind.COVER, "current", "target moving"),
        "THERMOSTAT": _family(
            DeviceKind.CLIMATE,
            "meastemp",
            "setpoint mintemp maxtemp heatmode coolmode heat cool",
            {"type": COUNT},
        ),
        "BUTTON": _family(DeviceKind.BUTTON, "clickcnt presscnt"),
        "DISPLAY": _family(
            DeviceKind.DISPLAY,
            "value",
            "unit precision",
            {"type": COUNT, "symbol": COUNT},
        ),
        "CONTACT": _family(DeviceKind.CONTACT, "state"),
        "SOCKET": _family(DeviceKind.SWITCH, "onoff"),
        "RELAY": _family(DeviceKind.SWITCH, "onoff"),
    }
)


def _fits_leniently(kinds: frozenset[ValueKind], point: Point, value: Any) -> bool:
    """Whether a GTSAP1 variable holds one of ``kinds``, or a value that reads as one.

    GTSAP1 values may be text (``"21,5"``) or integer flags (0/1), so beyond
    the kinds themselves a number or text that parses as one is accepted.
    """
    if point.kind in kinds:
        return True
    if point.kind not in (ValueKind.INTEGER, ValueKind.REAL, ValueKind.STRING):
        return False
    if kinds == FLAG:
        return LENIENT.flag(value) is not None
    if kinds == COUNT:
        return LENIENT.integer(value) is not None
    if kinds == NUMBER:
        return LENIENT.number(value) is not None
    return False


@dataclass(slots=True)
class _FoundFamily:
    """The variables of one GTSAP1 family as found: base path and properties."""

    type: str
    base: str
    properties: dict[str, str] = field(default_factory=dict)


def _families(points: Mapping[str, Point], taken: frozenset[str]) -> list[_FoundFamily]:
    """Group the points that name a known GTSAP1 family, in catalogue order."""
    families: dict[tuple[str, str], _FoundFamily] = {}
    for point in points.values():
        if point.key in taken:
            continue
        match = _GTSAP1.fullmatch(point.path)
        if match is None or match["base"].endswith("."):
            continue
        family_type = match["type"].upper()
        prop = match["property"].lower()
        if family_type not in _FAMILIES or not _FAMILIES[family_type].knows(prop):
            continue  # unknown families and properties stay raw points
        found = families.setdefault(
            (match["base"].lower(), family_type),
            _FoundFamily(type=family_type, base=match["base"]),
        )
        # Two spellings of one property (LIGHT_onoff and .GTSAP1_LIGHT_ONOFF):
        # the first in catalogue order wins, the other stays a raw point.
        found.properties.setdefault(prop, point.key)
    return list(families.values())


def _device(
    found: _FoundFamily, points: Mapping[str, Point], values: Mapping[str, Any]
) -> TypedDevice | str:
    """Return the device of one GTSAP1 family, or why it is none."""
    family = _FAMILIES[found.type]
    roles: dict[Role, str] = {}
    config: dict[str, Any] = {}
    used: set[str] = set()
    for prop, key in found.properties.items():
        role = family.properties.get(prop)
        kinds = ROLE_KINDS[role] if role is not None else family.config[prop]
        if not _fits_leniently(kinds, points[key], values.get(key)):
            continue  # a property of a kind it cannot hold stays a raw point
        used.add(key)
        if role is None:
            config[prop] = values.get(key)
        else:
            roles[role] = key
    present = {p for p, key in found.properties.items() if key in used}
    if not family.essential & present:
        wanted = " or ".join(sorted(family.essential))
        return f"GTSAP1 {found.type} {found.base} has no usable {wanted}"
    name = _clean_name(values.get(roles.get(Role.NAME, ""))) or name_from_base(
        found.base
    )
    features: dict[str, Any] = {}
    match family.kind:
        case DeviceKind.LIGHT:
            features["light_mode"] = _light(roles, config)
        case DeviceKind.COVER:
            gate = is_gate_name(name, found.base)
            features["cover_class"] = CoverClass.GATE if gate else CoverClass.SHUTTER
        case DeviceKind.CLIMATE:
            code = LENIENT.integer(config.get("type"))
            by_code = CLIMATE_TYPES.get(code) if code is not None else None
            support = by_code or climate_support(roles)
            # A block carries heatmode and coolmode whatever its type: a
            # heating-only one's cooling properties play no part (and the other
            # way round), so its modes never offer, nor write, them.
            for role in _DIRECTION_ROLES - CLIMATE_ROLES[support]:
                roles.pop(role, None)
            features["climate"] = support
        case DeviceKind.DISPLAY:
            symbol = LENIENT.integer(config.get("symbol"))
            if symbol is not None:
                features["measurement"] = DISPLAY_SYMBOLS.get(symbol)
        case DeviceKind.SWITCH if found.type == "SOCKET":
            features["switch_class"] = SwitchClass.OUTLET
        case _:
            pass
    return TypedDevice(
        key=_key(found),
        kind=family.kind,
        source=NAME,
        base=found.base,
        name=name,
        roles=roles,
        points=frozenset(used),
        readings=LENIENT,
        **features,
    )


def _light(roles: dict[Role, str], config: Mapping[str, Any]) -> LightMode:
    """Return a GTSAP1 light's mode from ``type``/``dimtype``; set its level roles.

    Dimmable when ``type`` says so (without ``type``: when it has a level).
    ``dimtype`` 1 is RGB, 2 colour temperature, anything else brightness; a
    colour mode without its variable falls back to brightness. Brightness is
    read from ``dimlevel`` and written to ``tgtlevel`` for dimtype 0, to
    ``dimlevel`` for the colour modes (as the peer client does); whichever of
    the two exists stands in for the other.
    """
    levels = {Role.LEVEL, Role.TARGET_LEVEL} & roles.keys()
    dimmable = LENIENT.flag(config.get("type")) if "type" in config else bool(levels)
    if not dimmable or not levels:
        return LightMode.ONOFF
    dim_type = LENIENT.integer(config.get("dimtype"))
    mode = LightMode.BRIGHTNESS
    if dim_type == 1 and Role.RGB in roles:
        mode = LightMode.RGB
    elif dim_type == 2 and Role.COLOR_TEMP in roles:
        mode = LightMode.COLOR_TEMP
    level = roles[Role.LEVEL] = roles.get(Role.LEVEL) or roles[Role.TARGET_LEVEL]
    if mode is not LightMode.BRIGHTNESS or Role.TARGET_LEVEL not in roles:
        roles[Role.TARGET_LEVEL] = level
    return mode


# --------------------------------------------------------------------------
# Our struct convention for T_ApiObject programs.


def _key(found: _FoundFamily) -> str:
    return f"{NAME}:{found.type.lower()}:{found.base.lower()}"


def _find(
    points: Mapping[str, Point], values: Mapping[str, Any], taken: frozenset[str]
) -> Recognised:
    """Find the GTSAP1 families among the points not taken, and make their devices."""
    devices: list[TypedDevice] = []
    skipped: dict[str, str] = {}
    for found in _families(points, taken):
        device = _device(found, points, values)
        if isinstance(device, TypedDevice):
            devices.append(device)
        else:
            skipped[_key(found)] = device
    return Recognised(devices=tuple(devices), skipped=skipped)


GTSAP1: Final = Recogniser(name=NAME, find=_find)
"""The recogniser of GTSAP1 block families."""
