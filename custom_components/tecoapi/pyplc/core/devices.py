"""Typed devices in a PLC's points: lights, covers, thermostats, buttons and more.

Three sources give points a type beyond "a value":

- **GTSAP1 block families**: public variables ``<base>_GTSAP1_<TYPE>_<property>``
  (or ``<base>.GTSAP1_<TYPE>_<property>``, the members of a block instance),
  matched ignoring case anywhere in the program. Their values may be text with
  a decimal comma, so they are read with :func:`parse_number` and friends.
- **Our struct convention** for T_ApiObject programs: a struct whose member names
  say what it is (``temperature`` + ``setpoint`` is a thermostat, ``position`` a
  blind, ``brightness`` a light). The members keep their T_ApiObject attributes.
- **Compositions** the user makes in the UI, validated by :func:`compose`.

:func:`find_devices` finds the first two in a catalogue; every point a device is
built from is ``consumed`` (not offered again as a raw entity). Keys are made of
names only, never of values, so a device keeps its key across program downloads
while its variables exist. This module knows nothing of Home Assistant.
"""

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from enum import StrEnum
import math
import re
from types import MappingProxyType
from typing import Any, Final
import unicodedata

from .models import Point, ValueKind
from .scalars import format_real


class DeviceKind(StrEnum):
    """What a typed device is; each is one kind of entity on the other side."""

    LIGHT = "light"
    COVER = "cover"
    CLIMATE = "climate"
    BUTTON = "button"
    CONTACT = "contact"
    SWITCH = "switch"
    DISPLAY = "display"


class DeviceSource(StrEnum):
    """Where a typed device comes from; the first part of its key.

    A GTSAP1 function block found by its variables' names, a struct of our own
    convention (the README's "Our struct convention"), or points the user composed
    in Home Assistant.
    """

    GTSAP1 = "gtsap1"
    STRUCT = "struct"
    COMPOSED = "composed"


class Role(StrEnum):
    """What a point does in a device: the name under which it is read or written."""

    ONOFF = "onoff"
    LEVEL = "level"
    TARGET_LEVEL = "target_level"
    RGB = "rgb"
    COLOR_TEMP = "color_temp"
    MIN_KELVIN = "min_kelvin"
    MAX_KELVIN = "max_kelvin"
    POSITION = "position"
    TARGET = "target"
    MOVING = "moving"
    TEMPERATURE = "temperature"
    SETPOINT = "setpoint"
    MIN_TEMP = "min_temp"
    MAX_TEMP = "max_temp"
    HEAT_MODE = "heat_mode"
    COOL_MODE = "cool_mode"
    HEATING = "heating"
    COOLING = "cooling"
    CLICK_COUNT = "click_count"
    PRESS_COUNT = "press_count"
    STATE = "state"
    VALUE = "value"
    UNIT = "unit"
    PRECISION = "precision"
    NAME = "name"


class LightMode(StrEnum):
    """How a light is controlled: exactly one per light, fixed at discovery."""

    ONOFF = "onoff"
    BRIGHTNESS = "brightness"
    RGB = "rgb"  # brightness as well: RGB lights are dimmable
    COLOR_TEMP = "color_temp"  # brightness as well


class CoverClass(StrEnum):
    """A shutter (blind, roller shutter) or a gate (gate, garage door)."""

    SHUTTER = "shutter"
    GATE = "gate"


class ClimateSupport(StrEnum):
    """What a thermostat can do: heat, cool, or both."""

    HEATING = "heating"
    COOLING = "cooling"
    BOTH = "both"


CLIMATE_ROLES: Final[Mapping[ClimateSupport, frozenset[Role]]] = MappingProxyType(
    {
        ClimateSupport.HEATING: frozenset({Role.HEAT_MODE, Role.HEATING}),
        ClimateSupport.COOLING: frozenset({Role.COOL_MODE, Role.COOLING}),
        ClimateSupport.BOTH: frozenset(
            {Role.HEAT_MODE, Role.HEATING, Role.COOL_MODE, Role.COOLING}
        ),
    }
)
"""The mode and action roles a thermostat may have, by what it does."""
_DIRECTION_ROLES: Final = CLIMATE_ROLES[ClimateSupport.BOTH]


class Measurement(StrEnum):
    """What a GTSAP1 display shows, from its symbol code."""

    TEMPERATURE = "temperature"
    HUMIDITY = "humidity"
    CO2 = "co2"
    CO = "co"
    ILLUMINANCE = "illuminance"


DEFAULT_MIN_KELVIN: Final = 2000
DEFAULT_MAX_KELVIN: Final = 6500

# GTSAP1 display symbol codes (BLOCKS.md); other codes are generic values.
DISPLAY_SYMBOLS: Final[Mapping[int, Measurement]] = MappingProxyType(
    {
        100: Measurement.TEMPERATURE,
        101: Measurement.HUMIDITY,
        104: Measurement.CO2,
        105: Measurement.CO,
        107: Measurement.ILLUMINANCE,
    }
)

# A name containing one of these (accents and case ignored) is a gate:
# English, Czech "brána" and "vrata" (garage door).
GATE_WORDS: Final = ("gate", "brana", "vrata")

# --------------------------------------------------------------------------
# Values: robust readings of what GTSAP1 variables hold (numbers as text with a
# decimal comma, flags as 0/1), reusable by anything that reads device roles.

_TRUE_TEXT: Final = frozenset({"1", "true", "on"})
_FALSE_TEXT: Final = frozenset({"0", "false", "off"})


def parse_number(value: Any) -> float | None:
    """Read a finite number from an int, a float or text (``"21,5"``, ``" 21.5 "``).

    None for booleans, empty or non-numeric text, NaN and infinities.
    """
    if isinstance(value, bool):
        return None
    if isinstance(value, int | float):
        number = float(value)
    elif isinstance(value, str):
        try:
            number = float(value.strip().replace(",", "."))
        except ValueError:
            return None
    else:
        return None
    return number if math.isfinite(number) else None


def parse_int(value: Any) -> int | None:
    """Read an integer from an int, an integral float or integral text; else None."""
    if isinstance(value, int) and not isinstance(value, bool):
        return value
    number = parse_number(value)
    if number is None or not number.is_integer():
        return None
    return int(number)


def parse_bool(value: Any) -> bool | None:
    """Read a flag from a bool, 0/1, or text (``1``/``0``, ``true``/``false``, ``on``/``off``)."""
    if isinstance(value, bool):
        return value
    if isinstance(value, str):
        text = value.strip().lower()
        if text in _TRUE_TEXT:
            return True
        if text in _FALSE_TEXT:
            return False
        return None
    number = parse_number(value)
    if number in (0.0, 1.0):
        return number == 1.0
    return None


def value_for_point(point: Point, value: bool | float) -> bool | int | float | str:
    """Return what to write to a role's point for a flag or a number, in its kind.

    GTSAP1 variables may be integers or text where a device thinks in flags and
    numbers: a flag becomes 1/0 for an integer and ``"1"``/``"0"`` for text, a
    number is rounded for an integer and spelled with a point for text. An
    inverted flag is written as its opposite.
    """
    match point.kind:
        case ValueKind.BOOL:
            return point.flag(bool(value))
        case ValueKind.INTEGER:
            return round(value)
        case ValueKind.REAL:
            return float(value)
        case ValueKind.STRING if isinstance(value, bool):
            return "1" if value else "0"
        case ValueKind.STRING:
            number = float(value)
            return str(int(number)) if number.is_integer() else format_real(number)
    raise ValueError(f"{point.path} holds a {point.kind}, not a flag or a number")


def _words(text: str) -> str:
    """Spell an identifier in lower-case words: ``LIVING_CEILING2`` → ``living ceiling 2``."""
    text = re.sub(r"[._\[\]]+", " ", text)
    text = re.sub(r"(?<=[a-z0-9])(?=[A-Z])|(?<=[A-Za-z])(?=[0-9])", " ", text)
    return " ".join(text.split()).lower()


def name_from_base(base: str) -> str:
    """Return a readable device name from its base path, without the root's name.

    ``LIVING_CEILING`` → ``Living ceiling``, ``Rooms.kidsRoom.blind`` →
    ``Kids room blind``, ``Main.blinds[2]`` → ``Blinds 2``. The root (a program
    instance or a top-level struct) is dropped when something follows it: it
    names the group the device sits in, which already names it in the UI.
    """
    root, dot, rest = base.partition(".")
    words = _words(rest if dot else root)
    return words[:1].upper() + words[1:]


def _clean_name(value: Any) -> str | None:
    """Return a name variable's text, or None when it is empty or only a number."""
    if not isinstance(value, str):
        return None
    text = " ".join(value.split())
    if not text or parse_number(text) is not None:
        return None
    return text


def _folded(text: str) -> str:
    """Text without accents and case: ``Brána`` → ``brana``."""
    decomposed = unicodedata.normalize("NFKD", text)
    return "".join(c for c in decomposed if not unicodedata.combining(c)).casefold()


def is_gate_name(*texts: str) -> bool:
    """Whether any text says "gate" (gate / brána / vrata, accents and case ignored)."""
    return any(word in _folded(text) for text in texts for word in GATE_WORDS)


# --------------------------------------------------------------------------
# The device model.


@dataclass(frozen=True, slots=True, kw_only=True)
class TypedDevice:
    """One typed device: what it is, where it comes from, which points play which role.

    ``key`` is unique within a PLC and made of names only:
    ``gtsap1:<type>:<base>`` (``gtsap1:light:main.living_ceiling``),
    ``struct:<kind>:<base>`` (``struct:cover:rooms.living.blind``) or
    ``composed:<ident>``. ``roles`` maps each role to a point key; ``points``
    are all the point keys the device is built from (the roles and the
    configuration read at discovery, such as a light's ``dimtype``). The
    feature of the device's kind (``light_mode``, ``cover_class``,
    ``climate``; a display's optional ``measurement``) is fixed at discovery.
    """

    key: str
    kind: DeviceKind
    source: DeviceSource
    base: str
    name: str
    roles: Mapping[Role, str]
    points: frozenset[str] = frozenset()
    light_mode: LightMode | None = None
    cover_class: CoverClass | None = None
    climate: ClimateSupport | None = None
    measurement: Measurement | None = None

    def __post_init__(self) -> None:
        """Freeze the roles and check that the features fit the kind."""
        roles = MappingProxyType({Role(role): key for role, key in self.roles.items()})
        object.__setattr__(self, "roles", roles)
        object.__setattr__(self, "points", self.points | frozenset(roles.values()))
        expected = {
            "light_mode": self.kind is DeviceKind.LIGHT,
            "cover_class": self.kind is DeviceKind.COVER,
            "climate": self.kind is DeviceKind.CLIMATE,
        }
        for feature, needed in expected.items():
            if (getattr(self, feature) is not None) != needed:
                raise ValueError(
                    f"{self.key}: a {self.kind} "
                    f"{'needs' if needed else 'has no'} {feature}"
                )
        if self.measurement is not None and self.kind is not DeviceKind.DISPLAY:
            raise ValueError(f"{self.key}: a {self.kind} has no measurement")

    def point(self, role: Role) -> str | None:
        """Return the key of the point playing ``role``, or None."""
        return self.roles.get(role)


@dataclass(frozen=True, slots=True)
class DeviceCatalogue:
    """The typed devices found in a catalogue.

    ``devices`` by key, in the order of the catalogue's points; ``consumed``
    every point key a device is built from; ``skipped`` the keys of would-be
    devices that were not made, with the reason (a family without its
    essential property, a struct whose setpoint is read-only, ...).
    """

    devices: Mapping[str, TypedDevice]
    consumed: frozenset[str]
    skipped: Mapping[str, str] = field(default_factory=dict)

    def of_kind(self, kind: DeviceKind) -> tuple[TypedDevice, ...]:
        """Return the devices of one kind, in catalogue order."""
        return tuple(d for d in self.devices.values() if d.kind is kind)


# --------------------------------------------------------------------------
# What each role holds, and the composition rules per kind.

_FLAG: Final = frozenset({ValueKind.BOOL})
_NUMBER: Final = frozenset({ValueKind.INTEGER, ValueKind.REAL})
_COUNT: Final = frozenset({ValueKind.INTEGER})
_TEXT: Final = frozenset({ValueKind.STRING})

ROLE_KINDS: Final[Mapping[Role, frozenset[ValueKind]]] = MappingProxyType(
    {
        Role.ONOFF: _FLAG,
        Role.LEVEL: _NUMBER,
        Role.TARGET_LEVEL: _NUMBER,
        Role.RGB: _COUNT,
        Role.COLOR_TEMP: _NUMBER,
        Role.MIN_KELVIN: _NUMBER,
        Role.MAX_KELVIN: _NUMBER,
        Role.POSITION: _NUMBER,
        Role.TARGET: _NUMBER,
        Role.MOVING: _FLAG,
        Role.TEMPERATURE: _NUMBER,
        Role.SETPOINT: _NUMBER,
        Role.MIN_TEMP: _NUMBER,
        Role.MAX_TEMP: _NUMBER,
        Role.HEAT_MODE: _FLAG,
        Role.COOL_MODE: _FLAG,
        Role.HEATING: _FLAG,
        Role.COOLING: _FLAG,
        Role.CLICK_COUNT: _COUNT,
        Role.PRESS_COUNT: _COUNT,
        Role.STATE: _FLAG,
        Role.VALUE: _NUMBER,
        Role.UNIT: _TEXT,
        Role.PRECISION: _NUMBER,
        Role.NAME: _TEXT,
    }
)
"""The value kinds a role takes from a typed point (T_ApiObject or plain)."""


@dataclass(frozen=True, slots=True, kw_only=True)
class RoleSpec:
    """One role of a composable kind.

    ``written``: the device writes it, so a read-only T_ApiObject cannot play
    it. ``defaults_to``: when not chosen, the point of that role plays it too
    (a blind without a separate target is moved by writing its position).
    ``needs``: the role only makes sense with that one (colour temperature
    needs a level).
    """

    role: Role
    kinds: frozenset[ValueKind]
    required: bool = False
    written: bool = False
    defaults_to: Role | None = None
    needs: Role | None = None

    def accepts(self, point: Point) -> bool:
        """Whether ``point`` may play this role (its kind; writable if written)."""
        return point.kind in self.kinds and (not self.written or is_writable(point))


@dataclass(frozen=True, slots=True, kw_only=True)
class KindSpec:
    """The roles of a composable kind; ``needs_any_of``: at least one of these."""

    kind: DeviceKind
    roles: tuple[RoleSpec, ...]
    needs_any_of: frozenset[Role] = frozenset()

    def role(self, role: Role) -> RoleSpec | None:
        """Return the spec of one role, or None if the kind has no such role."""
        return next((spec for spec in self.roles if spec.role is role), None)


def _role(role: Role, **options: Any) -> RoleSpec:
    return RoleSpec(role=role, kinds=ROLE_KINDS[role], **options)


COMPOSITIONS: Final[Mapping[DeviceKind, KindSpec]] = MappingProxyType(
    {
        DeviceKind.LIGHT: KindSpec(
            kind=DeviceKind.LIGHT,
            roles=(
                _role(Role.ONOFF, written=True),
                _role(Role.LEVEL, defaults_to=Role.TARGET_LEVEL),
                _role(Role.TARGET_LEVEL, written=True, defaults_to=Role.LEVEL),
                _role(Role.COLOR_TEMP, written=True, needs=Role.LEVEL),
            ),
            needs_any_of=frozenset({Role.ONOFF, Role.LEVEL}),
        ),
        DeviceKind.COVER: KindSpec(
            kind=DeviceKind.COVER,
            roles=(
                _role(Role.POSITION, required=True),
                _role(Role.TARGET, written=True, defaults_to=Role.POSITION),
                _role(Role.MOVING),
            ),
        ),
        DeviceKind.CLIMATE: KindSpec(
            kind=DeviceKind.CLIMATE,
            roles=(
                _role(Role.TEMPERATURE, required=True),
                _role(Role.SETPOINT, required=True, written=True),
                _role(Role.HEAT_MODE, written=True),
                _role(Role.COOL_MODE, written=True),
                _role(Role.HEATING),
                _role(Role.COOLING),
            ),
        ),
        DeviceKind.BUTTON: KindSpec(
            kind=DeviceKind.BUTTON,
            roles=(_role(Role.CLICK_COUNT), _role(Role.PRESS_COUNT)),
            needs_any_of=frozenset({Role.CLICK_COUNT, Role.PRESS_COUNT}),
        ),
        DeviceKind.SWITCH: KindSpec(
            kind=DeviceKind.SWITCH,
            roles=(_role(Role.ONOFF, required=True, written=True),),
        ),
    }
)
"""What the UI may compose (contacts and displays are raw entities already)."""


def is_writable(point: Point) -> bool:
    """Whether a device may write the point: all but those said to be read-only.

    A plain variable does not say whether it is writable (GTSAP1 variables are
    plain and written), so only attributes that say so forbid a write.
    """
    return point.attributes is None or point.attributes.writable


def fitting_points(
    kind: DeviceKind, role: Role, points: Mapping[str, Point]
) -> list[Point]:
    """Return the points that may play ``role`` in a composed ``kind``, in order.

    Beyond the kind of value (and writability) a role needs, a point must not say
    it is something else: a temperature role takes numbers in °C or °F (or,
    without a unit, whose title or path says temperature), a position or a
    level takes shares in % that are no humidity (or numbers without a unit
    that say no temperature). A plain variable says nothing but its path.
    """
    spec = COMPOSITIONS[kind].role(role)
    if spec is None:
        raise ValueError(f"a {kind} has no role {role}")
    says = _ROLE_MEASURES.get(role)
    return [
        point
        for point in points.values()
        if spec.accepts(point) and (says is None or says(point))
    ]


_TEMPERATURE_UNITS: Final = frozenset({"°c", "degc", "°f", "degf"})
_TEMPERATURE_WORDS: Final = re.compile(r"temp|tepl|setpoint|zadan|pozadovan")
# A light's colour temperature (in kelvin) is no temperature of a room.
_COLOUR_WORDS: Final = re.compile(r"colou?r ?temp|temp k\b|barv")
_HUMIDITY_WORDS: Final = re.compile(r"humid|vlhk")


def _units_and_words(point: Point) -> tuple[str, str]:
    """Return a point's unit and its title and path in folded words."""
    if point.attributes is None:
        return "", _folded(_words(point.path))
    title = point.attributes.name
    unit = point.attributes.unit.strip().casefold()
    return unit, _folded(f"{title} {_words(point.path)}")


def _says_temperature(point: Point) -> bool:
    """Whether a number may be a temperature (not a share, a power, a count ...)."""
    units, words = _units_and_words(point)
    if units:
        return units in _TEMPERATURE_UNITS
    return (
        _TEMPERATURE_WORDS.search(words) is not None
        and _COLOUR_WORDS.search(words) is None
    )


def _says_share(point: Point) -> bool:
    """Whether a number may be a position or a level in % (not a humidity)."""
    units, words = _units_and_words(point)
    if units:
        return units == "%" and _HUMIDITY_WORDS.search(words) is None
    return _TEMPERATURE_WORDS.search(words) is None


_ROLE_MEASURES: Final[Mapping[Role, Callable[[Point], bool]]] = MappingProxyType(
    {
        Role.TEMPERATURE: _says_temperature,
        Role.SETPOINT: _says_temperature,
        Role.MIN_TEMP: _says_temperature,
        Role.MAX_TEMP: _says_temperature,
        Role.POSITION: _says_share,
        Role.TARGET: _says_share,
        Role.LEVEL: _says_share,
        Role.TARGET_LEVEL: _says_share,
    }
)
"""What the points a role lists must not contradict (see :func:`fitting_points`)."""


class CompositionProblem(StrEnum):
    """Why a choice of points does not make a device (a translation key)."""

    NOT_COMPOSABLE = "not_composable"
    UNKNOWN_ROLE = "unknown_role"
    MISSING_ROLE = "missing_role"
    MISSING_POINT = "missing_point"
    WRONG_KIND = "wrong_kind"
    NOT_WRITABLE = "not_writable"


class CompositionError(ValueError):
    """A choice of points that does not make a device of the kind.

    ``problem`` says why, ``role`` which role (None for the kind itself),
    ``point`` the chosen point key when one is involved.
    """

    def __init__(
        self,
        problem: CompositionProblem,
        message: str,
        *,
        kind: str,
        role: str | None = None,
        point: str | None = None,
    ) -> None:
        """Keep the problem, the kind, the role and the point for the UI."""
        super().__init__(message)
        self.problem = problem
        self.kind = kind
        self.role = role
        self.point = point


def compose(
    kind: DeviceKind | str,
    roles: Mapping[str, str],
    points: Mapping[str, Point],
    *,
    ident: str,
    name: str = "",
) -> TypedDevice:
    """Validate a user's choice of points for a kind and make the device.

    ``roles`` maps role names to point keys (or paths, any case); ``ident`` is
    the caller's stable identifier (a config subentry ID) and makes the key
    ``composed:<ident>``. Raises :class:`CompositionError` naming the role and
    the problem: a kind that cannot be composed, an unknown role, a point not
    in ``points`` (it vanished with a program download), a point of the wrong
    value kind, a read-only point where the device writes, a required role
    left out. Call it again after each program download to revalidate.
    """
    try:
        device_kind = DeviceKind(kind)
    except ValueError:
        device_kind = None
    if device_kind is None or device_kind not in COMPOSITIONS:
        raise CompositionError(
            CompositionProblem.NOT_COMPOSABLE,
            f"a {kind} cannot be composed",
            kind=str(kind),
        )
    if not ident:
        raise ValueError("a composed device needs an ident")
    chosen: dict[Role, str] = {}
    for role_name, key in roles.items():
        try:
            chosen[Role(role_name)] = key
        except ValueError:
            raise CompositionError(
                CompositionProblem.UNKNOWN_ROLE,
                f"a {device_kind} has no role {role_name!r}",
                kind=device_kind,
                role=role_name,
            ) from None
    return _build(
        device_kind,
        chosen,
        points,
        source=DeviceSource.COMPOSED,
        key=f"{DeviceSource.COMPOSED}:{ident}",
        name=" ".join(name.split()),
    )


def _build(
    kind: DeviceKind,
    chosen: Mapping[Role, str],
    points: Mapping[str, Point],
    *,
    source: DeviceSource,
    key: str,
    name: str = "",
    base: str = "",
) -> TypedDevice:
    """Make a device from roles chosen by a user or by member names, checked strictly."""
    spec = COMPOSITIONS[kind]
    roles: dict[Role, str] = {}
    for role, point_key in chosen.items():
        role_spec = spec.role(role)
        if role_spec is None:
            raise CompositionError(
                CompositionProblem.UNKNOWN_ROLE,
                f"a {kind} has no role {role}",
                kind=kind,
                role=role,
            )
        point = points.get(point_key.lower())
        if point is None:
            raise CompositionError(
                CompositionProblem.MISSING_POINT,
                f"{role}: the variable {point_key!r} no longer exists",
                kind=kind,
                role=role,
                point=point_key,
            )
        if point.kind not in role_spec.kinds:
            raise CompositionError(
                CompositionProblem.WRONG_KIND,
                f"{role}: {point.path} holds a {point.kind} value, "
                f"expected {' or '.join(sorted(role_spec.kinds))}",
                kind=kind,
                role=role,
                point=point.key,
            )
        roles[role] = point.key
    for role_spec in spec.roles:
        default = role_spec.defaults_to
        if role_spec.role not in chosen and default is not None and default in chosen:
            roles[role_spec.role] = roles[default]
    for role_spec in spec.roles:
        if role_spec.required and role_spec.role not in roles:
            raise _missing(kind, role_spec.role, f"a {kind} needs {role_spec.role}")
        needs = role_spec.needs
        if role_spec.role in roles and needs is not None and needs not in roles:
            raise _missing(kind, needs, f"{role_spec.role} needs {needs}")
    if spec.needs_any_of and not spec.needs_any_of & roles.keys():
        first, *_ = sorted(spec.needs_any_of)
        wanted = " or ".join(sorted(spec.needs_any_of))
        raise _missing(kind, first, f"a {kind} needs {wanted}")
    for role_spec in spec.roles:
        role = role_spec.role
        if role_spec.written and role in roles and not is_writable(points[roles[role]]):
            # Name the role the user chose: a defaulted role is played by another.
            shown = role if role in chosen else role_spec.defaults_to or role
            raise CompositionError(
                CompositionProblem.NOT_WRITABLE,
                f"{shown}: {points[roles[role]].path} is read-only "
                f"and the {kind} writes its {role}",
                kind=kind,
                role=shown,
                point=roles[role],
            )
    primary = next(r.role for r in spec.roles if r.role in roles)
    base = base or points[roles[primary]].path
    name = name or name_from_base(base)
    features = _features(kind, base, name, roles, points)
    return TypedDevice(
        key=key, kind=kind, source=source, base=base, name=name, roles=roles, **features
    )


def _missing(kind: DeviceKind, role: Role, message: str) -> CompositionError:
    return CompositionError(
        CompositionProblem.MISSING_ROLE, message, kind=kind, role=role
    )


def _features(
    kind: DeviceKind,
    base: str,
    name: str,
    roles: Mapping[Role, str],
    points: Mapping[str, Point],
) -> dict[str, Any]:
    """Return the feature of a composed or struct device, from the roles it has."""
    match kind:
        case DeviceKind.LIGHT:
            mode = LightMode.ONOFF
            if Role.COLOR_TEMP in roles:
                mode = LightMode.COLOR_TEMP
            elif Role.LEVEL in roles:
                mode = LightMode.BRIGHTNESS
            return {"light_mode": mode}
        case DeviceKind.COVER:
            position = points[roles[Role.POSITION]]
            title = position.attributes.name if position.attributes is not None else ""
            gate = is_gate_name(name, base, title)
            return {"cover_class": CoverClass.GATE if gate else CoverClass.SHUTTER}
        case DeviceKind.CLIMATE:
            return {"climate": _climate_support(roles)}
        case _:
            return {}


def _climate_support(
    roles: Mapping[Role, str], type_code: int | None = None
) -> ClimateSupport:
    """Heating, cooling or both: from a GTSAP1 type code, else from the roles present."""
    by_code = {
        1: ClimateSupport.COOLING,
        2: ClimateSupport.HEATING,
        3: ClimateSupport.BOTH,
    }
    if type_code in by_code:
        return by_code[type_code]
    heats = bool({Role.HEAT_MODE, Role.HEATING} & roles.keys())
    cools = bool({Role.COOL_MODE, Role.COOLING} & roles.keys())
    if heats and cools:
        return ClimateSupport.BOTH
    return ClimateSupport.COOLING if cools else ClimateSupport.HEATING


# --------------------------------------------------------------------------
# GTSAP1 block families.

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
            {"type": _FLAG, "dimtype": _COUNT},
        ),
        "OPENER": _family(DeviceKind.COVER, "current", "target moving"),
        "THERMOSTAT": _family(
            DeviceKind.CLIMATE,
            "meastemp",
            "setpoint mintemp maxtemp heatmode coolmode heat cool",
            {"type": _COUNT},
        ),
        "BUTTON": _family(DeviceKind.BUTTON, "clickcnt presscnt"),
        "DISPLAY": _family(
            DeviceKind.DISPLAY,
            "value",
            "unit precision",
            {"type": _COUNT, "symbol": _COUNT},
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
    if kinds == _FLAG:
        return parse_bool(value) is not None
    if kinds == _COUNT:
        return parse_int(value) is not None
    if kinds == _NUMBER:
        return parse_number(value) is not None
    return False


@dataclass(slots=True)
class _FoundFamily:
    """The variables of one GTSAP1 family as found: base path and properties."""

    type: str
    base: str
    properties: dict[str, str] = field(default_factory=dict)


def _gtsap1_families(points: Mapping[str, Point]) -> list[_FoundFamily]:
    """Group the points that name a known GTSAP1 family, in catalogue order."""
    families: dict[tuple[str, str], _FoundFamily] = {}
    for point in points.values():
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


def _gtsap1_device(
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
            features["light_mode"] = _gtsap1_light(roles, config)
        case DeviceKind.COVER:
            gate = is_gate_name(name, found.base)
            features["cover_class"] = CoverClass.GATE if gate else CoverClass.SHUTTER
        case DeviceKind.CLIMATE:
            support = _climate_support(roles, parse_int(config.get("type")))
            # A block carries heatmode and coolmode whatever its type: a
            # heating-only one's cooling properties play no part (and the other
            # way round), so its modes never offer, nor write, them.
            for role in _DIRECTION_ROLES - CLIMATE_ROLES[support]:
                roles.pop(role, None)
            features["climate"] = support
        case DeviceKind.DISPLAY:
            symbol = parse_int(config.get("symbol"))
            if symbol is not None:
                features["measurement"] = DISPLAY_SYMBOLS.get(symbol)
        case _:
            pass
    return TypedDevice(
        key=f"{DeviceSource.GTSAP1}:{found.type.lower()}:{found.base.lower()}",
        kind=family.kind,
        source=DeviceSource.GTSAP1,
        base=found.base,
        name=name,
        roles=roles,
        points=frozenset(used),
        **features,
    )


def _gtsap1_light(roles: dict[Role, str], config: Mapping[str, Any]) -> LightMode:
    """Return a GTSAP1 light's mode from ``type``/``dimtype``; set its level roles.

    Dimmable when ``type`` says so (without ``type``: when it has a level).
    ``dimtype`` 1 is RGB, 2 colour temperature, anything else brightness; a
    colour mode without its variable falls back to brightness. Brightness is
    read from ``dimlevel`` and written to ``tgtlevel`` for dimtype 0, to
    ``dimlevel`` for the colour modes (as the peer client does); whichever of
    the two exists stands in for the other.
    """
    levels = {Role.LEVEL, Role.TARGET_LEVEL} & roles.keys()
    dimmable = parse_bool(config.get("type")) if "type" in config else bool(levels)
    if not dimmable or not levels:
        return LightMode.ONOFF
    dim_type = parse_int(config.get("dimtype"))
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


def _struct_devices(
    points: Mapping[str, Point], taken: frozenset[str]
) -> tuple[list[TypedDevice], dict[str, str]]:
    """Find the devices of our struct convention among the points not yet taken."""
    devices: list[TypedDevice] = []
    skipped: dict[str, str] = {}
    for parent_key, (parent, members) in _struct_groups(points, taken).items():
        for kind, signature in STRUCT_SIGNATURES.items():
            if not signature <= members.keys():
                continue
            key = f"{DeviceSource.STRUCT}:{kind}:{parent_key}"
            chosen = {
                role: members[member]
                for member, role in STRUCT_MEMBERS[kind].items()
                if member in members
            }
            try:
                devices.append(
                    _build(
                        kind,
                        chosen,
                        points,
                        source=DeviceSource.STRUCT,
                        key=key,
                        base=parent,
                    )
                )
            except CompositionError as err:
                skipped[key] = str(err)
    return devices, skipped


# --------------------------------------------------------------------------
# Discovery.


def find_devices(
    points: Mapping[str, Point], values: Mapping[str, Any]
) -> DeviceCatalogue:
    """Find the typed devices among a catalogue's points (keys: lower-case paths).

    GTSAP1 families first, then our struct convention among the points no
    family took. ``values`` are the catalogue's values: they fix the features
    (a light's dimtype, a thermostat's type, a display's symbol) and names.
    """
    devices: list[TypedDevice] = []
    skipped: dict[str, str] = {}
    for found in _gtsap1_families(points):
        device = _gtsap1_device(found, points, values)
        if isinstance(device, TypedDevice):
            devices.append(device)
        else:
            key = f"{DeviceSource.GTSAP1}:{found.type.lower()}:{found.base.lower()}"
            skipped[key] = device
    taken = frozenset(key for device in devices for key in device.points)
    struct_devices, struct_skipped = _struct_devices(points, taken)
    devices.extend(struct_devices)
    skipped.update(struct_skipped)
    order = {key: index for index, key in enumerate(points)}
    devices.sort(key=lambda device: min(order[key] for key in device.points))
    return DeviceCatalogue(
        devices={device.key: device for device in devices},
        consumed=frozenset(key for device in devices for key in device.points),
        skipped=skipped,
    )


# --------------------------------------------------------------------------
# Ranges a device's roles imply.


def setpoint_range(
    device: TypedDevice, points: Mapping[str, Point], values: Mapping[str, Any]
) -> tuple[float, float] | None:
    """Return a climate's target temperature range, or None when nothing says it.

    GTSAP1 ``mintemp``/``maxtemp`` values first, else the setpoint
    T_ApiObject's ``minValue``/``maxValue``; an empty or reversed range is none.
    """
    low = parse_number(values.get(device.roles.get(Role.MIN_TEMP, "")))
    high = parse_number(values.get(device.roles.get(Role.MAX_TEMP, "")))
    if low is not None and high is not None and low < high:
        return low, high
    setpoint = points.get(device.roles.get(Role.SETPOINT, ""))
    attributes = setpoint.attributes if setpoint is not None else None
    if attributes is not None:
        low, high = attributes.minimum, attributes.maximum
        if low is not None and high is not None and low < high:
            return low, high
    return None


def kelvin_range(
    device: TypedDevice, points: Mapping[str, Point], values: Mapping[str, Any]
) -> tuple[int, int]:
    """Return a light's colour temperature range in kelvin.

    GTSAP1 ``minTempK``/``maxTempK`` values first, else the colour temperature
    T_ApiObject's ``minValue``/``maxValue``, else 2000 to 6500 K.
    """
    low = parse_number(values.get(device.roles.get(Role.MIN_KELVIN, "")))
    high = parse_number(values.get(device.roles.get(Role.MAX_KELVIN, "")))
    if low is not None and high is not None and 0 < low < high:
        return round(low), round(high)
    color_temp = points.get(device.roles.get(Role.COLOR_TEMP, ""))
    if color_temp is not None and color_temp.attributes is not None:
        low, high = color_temp.attributes.minimum, color_temp.attributes.maximum
        if low is not None and high is not None and 0 < low < high:
            return round(low), round(high)
    return DEFAULT_MIN_KELVIN, DEFAULT_MAX_KELVIN


# --------------------------------------------------------------------------
# Button counters.

MAX_COUNTER_STEP: Final = 32
"""More increments than this between two readings are not clicks (see below)."""


def counter_bits(*readings: int) -> int:
    """Return the width of a counter the program does not declare: 16 bits, or 32.

    TecoApi does not say a variable's type. A counter is taken as 16 bits
    (UINT, or INT when negative) until a reading leaves that range; then it
    is 32 bits (UDINT/DINT). An 8-bit counter is taken as 16 bits: its wrap
    from 255 to 0 reads as a reset and loses one event in 256.
    """
    return 16 if all(-(2**15) <= r < 2**16 for r in readings) else 32


def counter_events(
    previous: int | None,
    current: int | None,
    *,
    bits: int | None = None,
    max_step: int = MAX_COUNTER_STEP,
) -> int:
    """How many button events a counter's change between two readings means.

    One event per increment, increments missed between readings included. No
    reading before (start-up, a point that reappeared) or now: none. The
    change is counted modulo the counter's width (``bits``, else
    :func:`counter_bits`), so a wrap from 65535 to 0 is one increment. A step
    of more than ``max_step`` is not clicks but a reset or a counter set by
    the program (a drop to a small value, a new program, retained values
    restored): no events. Keep ``current`` as the next ``previous`` either way.
    """
    if previous is None or current is None:
        return 0
    width = bits or counter_bits(previous, current)
    step = (current - previous) % (1 << width)
    return step if step <= max_step else 0
