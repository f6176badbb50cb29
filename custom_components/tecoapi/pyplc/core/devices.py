"""Typed devices in a PLC's points: lights, covers, thermostats, buttons and more.

A typed device is a few points playing roles (a light's on/off and level, a
thermostat's temperature and setpoint). Devices come from two places:

- **Recognisers**: conventions for naming the points of a device
  (:class:`Recogniser`): the core's own struct convention (:mod:`.structs`)
  and a system's (Teco's GTSAP1 families, Tecomat's). Each system's
  descriptor registers those its devices follow, and :func:`find_devices`
  runs them, in order, on a catalogue. A device carries
  the :class:`Readings` its values are read and written with: a convention
  whose values may be text gives its devices readings that read text.
- **Compositions** the user makes in the UI, validated by
  :func:`~.composition.compose`.

Every point a recognised device is built from is ``consumed`` (not offered
again as a raw entity). Keys are made of names only, never of values, so a
device keeps its key across program downloads while its points exist. This
module knows nothing of Home Assistant, nor of any system.
"""

from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from enum import StrEnum
import math
import re
from types import MappingProxyType
from typing import Any, Final
import unicodedata

from .models import Point, ValueKind


class DeviceKind(StrEnum):
    """What a typed device is; each is one kind of entity on the other side."""

    LIGHT = "light"
    COVER = "cover"
    CLIMATE = "climate"
    BUTTON = "button"
    CONTACT = "contact"
    SWITCH = "switch"
    DISPLAY = "display"


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


class SwitchClass(StrEnum):
    """A switch, or a socket (an outlet)."""

    SWITCH = "switch"
    OUTLET = "outlet"


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


class Measurement(StrEnum):
    """What a display shows (a sensor's device class)."""

    TEMPERATURE = "temperature"
    HUMIDITY = "humidity"
    CO2 = "co2"
    CO = "co"
    ILLUMINANCE = "illuminance"


DEFAULT_MIN_KELVIN: Final = 2000
DEFAULT_MAX_KELVIN: Final = 6500

# A name containing one of these (accents and case ignored) is a gate:
# English, Czech "brána" and "vrata" (garage door).
GATE_WORDS: Final = ("gate", "brana", "vrata")

COMPOSED: Final = "composed"
"""The ``source`` of a device the user composed (its key: ``composed:<ident>``)."""

# --------------------------------------------------------------------------
# Values: how a device reads its points' values as numbers and flags.


class Readings:
    """How a device's values are read as numbers and flags, and written back.

    These read what a point's kind holds: a number from an int or a float (not
    a bool, NaN or an infinity), an integer from an integral number, a flag
    from a bool or 0/1; anything else, text among it, reads as None. A
    recogniser whose convention keeps numbers and flags in text gives its
    devices readings of its own that read text as well (a subclass).
    """

    __slots__ = ()

    def number(self, value: Any) -> float | None:
        """Read a finite number (None: none)."""
        if isinstance(value, bool) or not isinstance(value, int | float):
            return None
        number = float(value)
        return number if math.isfinite(number) else None

    def integer(self, value: Any) -> int | None:
        """Read an integer from an int or an integral number; else None."""
        if isinstance(value, int) and not isinstance(value, bool):
            return value
        number = self.number(value)
        if number is None or not number.is_integer():
            return None
        return int(number)

    def flag(self, value: Any) -> bool | None:
        """Read a flag from a bool or a number 0/1; else None."""
        if isinstance(value, bool):
            return value
        number = self.number(value)
        if number in (0.0, 1.0):
            return number == 1.0
        return None

    def written(self, point: Point, value: bool | float) -> bool | int | float | str:
        """Return what to write to a role's point for a flag or a number, in its kind.

        A number is rounded for an integer; an inverted flag is written as its
        opposite.
        """
        match point.kind:
            case ValueKind.BOOL:
                return point.flag(bool(value))
            case ValueKind.INTEGER:
                return round(value)
            case ValueKind.REAL:
                return float(value)
        raise ValueError(f"{point.path} holds a {point.kind}, not a flag or a number")


READINGS: Final = Readings()
"""The readings of a device whose points hold what their kinds say."""


def identifier_words(text: str) -> str:
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
    words = identifier_words(rest if dot else root)
    return words[:1].upper() + words[1:]


def folded(text: str) -> str:
    """Text without accents and case: ``Brána`` → ``brana``."""
    decomposed = unicodedata.normalize("NFKD", text)
    return "".join(c for c in decomposed if not unicodedata.combining(c)).casefold()


def is_gate_name(*texts: str) -> bool:
    """Whether any text says "gate" (gate / brána / vrata, accents and case ignored)."""
    return any(word in folded(text) for text in texts for word in GATE_WORDS)


# --------------------------------------------------------------------------
# The device model.


# The device model.


@dataclass(frozen=True, slots=True, kw_only=True)
class TypedDevice:
    """One typed device: what it is, where it comes from, which points play which role.

    ``key`` is unique within a PLC and made of names only: the name of the
    recogniser that found it (its ``source``) and what that recogniser makes
    of the names (``<source>:<kind>:<base>``, say), or ``composed:<ident>``.
    ``roles`` maps each role to a point key; ``points`` are all the point keys
    the device is built from (the roles and the configuration read at
    discovery, such as a light's dimming type). The feature of the device's
    kind (``light_mode``, ``cover_class``, ``climate``; a display's optional
    ``measurement``, a switch's optional ``switch_class``) is fixed at
    discovery. ``readings`` read its values (those of its recogniser).
    """

    key: str
    kind: DeviceKind
    source: str
    base: str
    name: str
    roles: Mapping[Role, str]
    points: frozenset[str] = frozenset()
    light_mode: LightMode | None = None
    cover_class: CoverClass | None = None
    climate: ClimateSupport | None = None
    measurement: Measurement | None = None
    switch_class: SwitchClass | None = None
    readings: Readings = field(default=READINGS, compare=False, repr=False)

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
        if self.switch_class is not None and self.kind is not DeviceKind.SWITCH:
            raise ValueError(f"{self.key}: a {self.kind} has no switch_class")

    @property
    def composed(self) -> bool:
        """Whether the user composed it (in the UI) rather than a recogniser found it."""
        return self.source == COMPOSED

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


# --------------------------------------------------------------------------
# What each role holds.

# What each role holds, and the composition rules per kind.

FLAG: Final = frozenset({ValueKind.BOOL})
NUMBER: Final = frozenset({ValueKind.INTEGER, ValueKind.REAL})
COUNT: Final = frozenset({ValueKind.INTEGER})
TEXT: Final = frozenset({ValueKind.STRING})

ROLE_KINDS: Final[Mapping[Role, frozenset[ValueKind]]] = MappingProxyType(
    {
        Role.ONOFF: FLAG,
        Role.LEVEL: NUMBER,
        Role.TARGET_LEVEL: NUMBER,
        Role.RGB: COUNT,
        Role.COLOR_TEMP: NUMBER,
        Role.MIN_KELVIN: NUMBER,
        Role.MAX_KELVIN: NUMBER,
        Role.POSITION: NUMBER,
        Role.TARGET: NUMBER,
        Role.MOVING: FLAG,
        Role.TEMPERATURE: NUMBER,
        Role.SETPOINT: NUMBER,
        Role.MIN_TEMP: NUMBER,
        Role.MAX_TEMP: NUMBER,
        Role.HEAT_MODE: FLAG,
        Role.COOL_MODE: FLAG,
        Role.HEATING: FLAG,
        Role.COOLING: FLAG,
        Role.CLICK_COUNT: COUNT,
        Role.PRESS_COUNT: COUNT,
        Role.STATE: FLAG,
        Role.VALUE: NUMBER,
        Role.UNIT: TEXT,
        Role.PRECISION: NUMBER,
        Role.NAME: TEXT,
    }
)
"""The value kinds a role takes from a point that says its kind."""


# --------------------------------------------------------------------------
# Recognisers: the plug-in point of systems' conventions.

type Recognise = Callable[
    [Mapping[str, Point], Mapping[str, Any], frozenset[str]], "Recognised"
]


@dataclass(frozen=True, slots=True)
class Recognised:
    """What a recogniser found: its devices, and the would-be devices it did not make.

    ``skipped`` maps the key a would-be device would have had to why it is
    none (a block without its essential property, a read-only setpoint ...).
    """

    devices: tuple[TypedDevice, ...] = ()
    skipped: Mapping[str, str] = field(default_factory=dict)


@dataclass(frozen=True, slots=True, kw_only=True)
class Recogniser:
    """A convention that makes typed devices of a catalogue's points: a plug-in.

    A system's descriptor registers those its devices follow
    (``SourceDescriptor.recognisers``: the core's :data:`~.structs.STRUCTS`, a
    system's own). ``name`` is the ``source`` of the devices it makes and the
    first part of their keys: it never changes (unique IDs are made of it).
    ``find`` is given a catalogue's points (keys: lower-case paths), its values,
    and the keys of the points recognisers before it took, which it leaves
    alone; it returns what it found, each device with the :class:`Readings` its
    values need.
    """

    name: str
    find: Recognise


def find_devices(
    points: Mapping[str, Point],
    values: Mapping[str, Any],
    recognisers: Iterable[Recogniser] = (),
) -> DeviceCatalogue:
    """Find the typed devices among a catalogue's points (keys: lower-case paths).

    Each recogniser in turn, among the points no recogniser before it took.
    ``values`` are the catalogue's values: they may fix devices' features
    (a light's dimming type) and names. The devices come in the order of the
    first of their points in the catalogue.
    """
    devices: list[TypedDevice] = []
    skipped: dict[str, str] = {}
    taken: frozenset[str] = frozenset()
    for recogniser in recognisers:
        found = recogniser.find(points, values, taken)
        devices.extend(found.devices)
        skipped.update(found.skipped)
        taken = taken.union(*(device.points for device in found.devices))
    order = {key: index for index, key in enumerate(points)}
    devices.sort(key=lambda device: min(order[key] for key in device.points))
    return DeviceCatalogue(
        devices={device.key: device for device in devices},
        consumed=taken,
        skipped=skipped,
    )


# --------------------------------------------------------------------------
# Ranges a device's roles imply.


def setpoint_range(
    device: TypedDevice, points: Mapping[str, Point], values: Mapping[str, Any]
) -> tuple[float, float] | None:
    """Return a climate's target temperature range, or None when nothing says it.

    The ``min_temp``/``max_temp`` roles' values first, else the setpoint
    point's own minimum and maximum (the user's where given); an empty or
    reversed range is none.
    """
    low = device.readings.number(values.get(device.roles.get(Role.MIN_TEMP, "")))
    high = device.readings.number(values.get(device.roles.get(Role.MAX_TEMP, "")))
    if low is not None and high is not None and low < high:
        return low, high
    setpoint = points.get(device.roles.get(Role.SETPOINT, ""))
    if setpoint is not None:
        low, high = setpoint.range_of()
        if low is not None and high is not None and low < high:
            return low, high
    return None


def kelvin_range(
    device: TypedDevice, points: Mapping[str, Point], values: Mapping[str, Any]
) -> tuple[int, int]:
    """Return a light's colour temperature range in kelvin.

    The ``min_kelvin``/``max_kelvin`` roles' values first, else the colour
    temperature point's own minimum and maximum, else 2000 to 6500 K.
    """
    low = device.readings.number(values.get(device.roles.get(Role.MIN_KELVIN, "")))
    high = device.readings.number(values.get(device.roles.get(Role.MAX_KELVIN, "")))
    if low is not None and high is not None and 0 < low < high:
        return round(low), round(high)
    color_temp = points.get(device.roles.get(Role.COLOR_TEMP, ""))
    if color_temp is not None:
        low, high = color_temp.range_of()
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
