"""Which entity a PLC point becomes: its platform, name, unit and classes.

Descriptions, not branches: tables from a point's value kind and writability to
a platform, and from the unit in ``attr.units`` to Home Assistant's unit,
device class and state class. :func:`describe` turns a point into the frozen
:class:`PointDescription` its entity is built from; what may change while the
program runs (title, range, enable) is read from the latest metadata instead.
"""

from contextlib import suppress
from dataclasses import dataclass, replace
from decimal import Decimal
from math import floor, log10
import re
from typing import Final

from homeassistant.components.number import NumberDeviceClass, NumberMode
from homeassistant.components.sensor import SensorDeviceClass, SensorStateClass
from homeassistant.const import (
    LIGHT_LUX,
    PERCENTAGE,
    Platform,
    UnitOfElectricCurrent,
    UnitOfElectricPotential,
    UnitOfEnergy,
    UnitOfFrequency,
    UnitOfLength,
    UnitOfMass,
    UnitOfPower,
    UnitOfPressure,
    UnitOfSpeed,
    UnitOfTemperature,
    UnitOfTime,
    UnitOfVolume,
    UnitOfVolumeFlowRate,
)

from .compat import BinarySensorDeviceClass
from .const import PlainVariables
from .names import folded, without_leading
from .pyplc import Access, Point, PointAttributes, ValueKind
from .pyplc.core.codec import shown_bounds
from .pyplc.core.devices import DeviceKind

NUMERIC_KINDS: Final = frozenset({ValueKind.INTEGER, ValueKind.REAL})

PLATFORM_BY_KIND: Final[dict[tuple[ValueKind, bool], Platform]] = {
    # (kind, writable): platform. Plain variables are never writable here.
    (ValueKind.BOOL, False): Platform.BINARY_SENSOR,
    (ValueKind.BOOL, True): Platform.SWITCH,
    (ValueKind.INTEGER, False): Platform.SENSOR,
    (ValueKind.INTEGER, True): Platform.NUMBER,
    (ValueKind.REAL, False): Platform.SENSOR,
    (ValueKind.REAL, True): Platform.NUMBER,
    (ValueKind.STRING, False): Platform.SENSOR,
    (ValueKind.STRING, True): Platform.TEXT,
    # A read-only TIME is a duration (a sensor in seconds); a writable one is a
    # time of day (TecoApi prints TIME and TIME_OF_DAY alike, ``hh:mm:ss.zzz``).
    (ValueKind.DATE, False): Platform.SENSOR,
    (ValueKind.DATE, True): Platform.DATE,
    (ValueKind.TIME, False): Platform.SENSOR,
    (ValueKind.TIME, True): Platform.TIME,
    (ValueKind.DATETIME, False): Platform.SENSOR,
    (ValueKind.DATETIME, True): Platform.DATETIME,
    # A pure duration (never a time of day): seconds, shown or set.
    (ValueKind.DURATION, False): Platform.SENSOR,
    (ValueKind.DURATION, True): Platform.NUMBER,
    # Text with parts (a lift's state): shown, never written.
    (ValueKind.RECORD, False): Platform.SENSOR,
    (ValueKind.RECORD, True): Platform.SENSOR,
}

PRESSED_KINDS: Final = frozenset({ValueKind.BOOL, ValueKind.INTEGER})
"""A write-only point of these kinds is a button: a press writes 1 (true)."""

DEVICE_PLATFORMS: Final[dict[DeviceKind, Platform]] = {
    DeviceKind.LIGHT: Platform.LIGHT,
    DeviceKind.COVER: Platform.COVER,
    DeviceKind.CLIMATE: Platform.CLIMATE,
    DeviceKind.BUTTON: Platform.EVENT,
    DeviceKind.CONTACT: Platform.BINARY_SENSOR,
    DeviceKind.SWITCH: Platform.SWITCH,
    DeviceKind.DISPLAY: Platform.SENSOR,
}
"""The platform of each kind of typed device."""

SENSOR_DEVICE_CLASS_BY_KIND: Final[dict[ValueKind, SensorDeviceClass]] = {
    ValueKind.DATE: SensorDeviceClass.DATE,
    ValueKind.DATETIME: SensorDeviceClass.TIMESTAMP,
}


@dataclass(frozen=True, slots=True)
class UnitMapping:
    """Home Assistant's view of a PLC unit.

    ``shown_unit`` and ``shown_precision``: the unit and decimals a sensor is
    shown in at first (the user may choose others), when not the PLC's.
    """

    unit: str
    device_class: SensorDeviceClass | None = None
    state_class: SensorStateClass = SensorStateClass.MEASUREMENT
    shown_unit: str | None = None
    shown_precision: int | None = None


_TEMPERATURE: Final = SensorDeviceClass.TEMPERATURE
_ENERGY: Final = SensorDeviceClass.ENERGY
_TOTAL_INCREASING: Final = SensorStateClass.TOTAL_INCREASING

# Keyed by the unit as a PLC program spells it (attr.units is STRING[16] and
# often ASCII-only, hence the "degC" and "m3" spellings).
UNITS: Final[dict[str, UnitMapping]] = {
    "°C": UnitMapping(UnitOfTemperature.CELSIUS, _TEMPERATURE),
    "degC": UnitMapping(UnitOfTemperature.CELSIUS, _TEMPERATURE),
    "°F": UnitMapping(UnitOfTemperature.FAHRENHEIT, _TEMPERATURE),
    "degF": UnitMapping(UnitOfTemperature.FAHRENHEIT, _TEMPERATURE),
    # In a building a kelvin is a temperature difference (a heating curve shift,
    # a hysteresis), never an absolute temperature.
    "K": UnitMapping(UnitOfTemperature.KELVIN, SensorDeviceClass.TEMPERATURE_DELTA),
    "%": UnitMapping(PERCENTAGE),
    "W": UnitMapping(UnitOfPower.WATT, SensorDeviceClass.POWER),
    "kW": UnitMapping(UnitOfPower.KILO_WATT, SensorDeviceClass.POWER),
    "MW": UnitMapping(UnitOfPower.MEGA_WATT, SensorDeviceClass.POWER),
    "Wh": UnitMapping(UnitOfEnergy.WATT_HOUR, _ENERGY, _TOTAL_INCREASING),
    "kWh": UnitMapping(UnitOfEnergy.KILO_WATT_HOUR, _ENERGY, _TOTAL_INCREASING),
    "MWh": UnitMapping(UnitOfEnergy.MEGA_WATT_HOUR, _ENERGY, _TOTAL_INCREASING),
    "mV": UnitMapping(UnitOfElectricPotential.MILLIVOLT, SensorDeviceClass.VOLTAGE),
    "V": UnitMapping(UnitOfElectricPotential.VOLT, SensorDeviceClass.VOLTAGE),
    "kV": UnitMapping(UnitOfElectricPotential.KILOVOLT, SensorDeviceClass.VOLTAGE),
    "mA": UnitMapping(UnitOfElectricCurrent.MILLIAMPERE, SensorDeviceClass.CURRENT),
    "A": UnitMapping(UnitOfElectricCurrent.AMPERE, SensorDeviceClass.CURRENT),
    "Hz": UnitMapping(UnitOfFrequency.HERTZ, SensorDeviceClass.FREQUENCY),
    "kHz": UnitMapping(UnitOfFrequency.KILOHERTZ, SensorDeviceClass.FREQUENCY),
    "lx": UnitMapping(LIGHT_LUX, SensorDeviceClass.ILLUMINANCE),
    "lux": UnitMapping(LIGHT_LUX, SensorDeviceClass.ILLUMINANCE),
    "ppm": UnitMapping("ppm", SensorDeviceClass.CO2),
    "Pa": UnitMapping(UnitOfPressure.PA, SensorDeviceClass.PRESSURE),
    "hPa": UnitMapping(UnitOfPressure.HPA, SensorDeviceClass.PRESSURE),
    "kPa": UnitMapping(UnitOfPressure.KPA, SensorDeviceClass.PRESSURE),
    "mbar": UnitMapping(UnitOfPressure.MBAR, SensorDeviceClass.PRESSURE),
    "bar": UnitMapping(UnitOfPressure.BAR, SensorDeviceClass.PRESSURE),
    "m³": UnitMapping(
        UnitOfVolume.CUBIC_METERS, SensorDeviceClass.VOLUME, _TOTAL_INCREASING
    ),
    "m3": UnitMapping(
        UnitOfVolume.CUBIC_METERS, SensorDeviceClass.VOLUME, _TOTAL_INCREASING
    ),
    "l": UnitMapping(UnitOfVolume.LITERS, SensorDeviceClass.VOLUME, _TOTAL_INCREASING),
    "L": UnitMapping(UnitOfVolume.LITERS, SensorDeviceClass.VOLUME, _TOTAL_INCREASING),
    "l/min": UnitMapping(
        UnitOfVolumeFlowRate.LITERS_PER_MINUTE, SensorDeviceClass.VOLUME_FLOW_RATE
    ),
    "L/min": UnitMapping(
        UnitOfVolumeFlowRate.LITERS_PER_MINUTE, SensorDeviceClass.VOLUME_FLOW_RATE
    ),
    "l/h": UnitMapping(
        UnitOfVolumeFlowRate.LITERS_PER_HOUR, SensorDeviceClass.VOLUME_FLOW_RATE
    ),
    "L/h": UnitMapping(
        UnitOfVolumeFlowRate.LITERS_PER_HOUR, SensorDeviceClass.VOLUME_FLOW_RATE
    ),
    "m³/h": UnitMapping(
        UnitOfVolumeFlowRate.CUBIC_METERS_PER_HOUR, SensorDeviceClass.VOLUME_FLOW_RATE
    ),
    "m3/h": UnitMapping(
        UnitOfVolumeFlowRate.CUBIC_METERS_PER_HOUR, SensorDeviceClass.VOLUME_FLOW_RATE
    ),
    "ms": UnitMapping(UnitOfTime.MILLISECONDS, SensorDeviceClass.DURATION),
    "s": UnitMapping(UnitOfTime.SECONDS, SensorDeviceClass.DURATION),
    "min": UnitMapping(UnitOfTime.MINUTES, SensorDeviceClass.DURATION),
    "h": UnitMapping(UnitOfTime.HOURS, SensorDeviceClass.DURATION),
    "m/s": UnitMapping(UnitOfSpeed.METERS_PER_SECOND, SensorDeviceClass.SPEED),
    "km/h": UnitMapping(UnitOfSpeed.KILOMETERS_PER_HOUR, SensorDeviceClass.SPEED),
    "mm": UnitMapping(UnitOfLength.MILLIMETERS, SensorDeviceClass.DISTANCE),
    "cm": UnitMapping(UnitOfLength.CENTIMETERS, SensorDeviceClass.DISTANCE),
    "m": UnitMapping(UnitOfLength.METERS, SensorDeviceClass.DISTANCE),
    "km": UnitMapping(UnitOfLength.KILOMETERS, SensorDeviceClass.DISTANCE),
    "g": UnitMapping(UnitOfMass.GRAMS, SensorDeviceClass.WEIGHT),
    "kg": UnitMapping(UnitOfMass.KILOGRAMS, SensorDeviceClass.WEIGHT),
}

HUMIDITY: Final = UnitMapping(PERCENTAGE, SensorDeviceClass.HUMIDITY)
DURATION: Final = UnitMapping(
    UnitOfTime.SECONDS,
    SensorDeviceClass.DURATION,
    shown_unit=UnitOfTime.HOURS,
    shown_precision=2,
)
"""A read-only TIME: its seconds, graphable, shown in hours and minutes.

The frontend spells a duration in hours as ``3 h 41 min``; two decimals of an
hour keep the minute (a duration in seconds shows as ``13,287 s``).
"""

# What a binary sensor's title says it watches, English, Czech and Russian (a
# Tekon gateway's channels; accents and case folded away, a short i too); the
# first that matches wins. A title about a blind or a shutter (its window, its
# movement) says nothing of a window or a motion.
NOT_A_CONTACT: Final = re.compile(r"blind|shutter|awning|zaluzi|rolet|marki|stineni")
# A title that says which state is on (closed, locked, off; zavřeno, zamčeno,
# vypnuto; закрыт) says the opposite of a class for which on means open or
# unlocked: it gets no class from its title (a map's class and ``invert`` can
# give it one), for a title never turns a value into its opposite.
SAYS_OFF_STATE: Final = re.compile(
    r"(?<!\w)(?:closed|shut|locked|off|zavren\w*|zamcen\w*|vypnut\w*|закрыт\w*"
    r"|заперт\w*)(?!\w)"
)
BINARY_CLASS_TITLES: Final[
    tuple[tuple[re.Pattern[str], BinarySensorDeviceClass], ...]
] = (
    (re.compile(r"smoke|fire|kour|pozar|пожар|дым"), BinarySensorDeviceClass.SMOKE),
    (
        re.compile(r"leak|flood|moisture|water detect|zaplav|unik vody|протеч|затоп"),
        BinarySensorDeviceClass.MOISTURE,
    ),
    (re.compile(r"window|okn[oa]|okenn|окн"), BinarySensorDeviceClass.WINDOW),
    (re.compile(r"door|gate|dver|vrat|bran|двер|ворот"), BinarySensorDeviceClass.DOOR),
    (
        re.compile(r"motion|presence|\bpir\b|pohyb|pritomn|движен|присутств"),
        BinarySensorDeviceClass.MOTION,
    ),
    (
        # Something wrong, or something to see to: a clogged filter (ucpaný,
        # zanesený, znečištěný), a fault (авария, неисправность, тревога).
        re.compile(
            r"fault|error|alarm|failure|problem|clogged|blocked|dirty"
            r"|porucha|chyba|poplach|ucpan|zanesen|znecist"
            r"|авари|неисправн|тревог"
        ),
        BinarySensorDeviceClass.PROBLEM,
    ),
)

# A read-only date and time whose name says it is a clock (the controller's own
# time, a Mervis project's ``clock``): it changes on every poll, so as a state it
# would be a logbook entry and a recorder row a poll. It is a diagnostic,
# disabled until the user wants it (the PLC's clock offset, where a source tells
# its time, is the steady view of it).
CLOCK_TITLE: Final = re.compile(
    r"(?<!\w)(?:clock|rtc|system ?time|current time|time now|hodiny|systemovy cas"
    r"|aktualni cas|datum a cas|часы)(?!\w)"
)
# "%" is a humidity only when the title says so (English or Czech "vlhkost").
HUMIDITY_TITLE: Final = re.compile(r"humid|vlhk", re.IGNORECASE)

# A writable number's range is its type's (an integer's bounds, scaled), within
# what its metadata or map says. A type without bounds gets the range of its
# kind: reals a range the PLC's JSON parser can take without scientific notation.
DEFAULT_NUMBER_RANGE: Final[dict[ValueKind, tuple[float, float]]] = {
    ValueKind.INTEGER: (-2147483648, 2147483647),
    ValueKind.REAL: (-1e9, 1e9),
    # A duration in seconds: up to a year.
    ValueKind.DURATION: (0, 366 * 24 * 3600),
}
REAL_STEP: Final = 0.1
MAX_SLIDER_STEPS: Final = 1000


@dataclass(frozen=True, slots=True, kw_only=True)
class PointDescription:
    """What the entity of a point is, fixed for the entity's lifetime.

    Two descriptions of a key that differ after a program download mean the
    entity is made again (under the same registry entry when the platform stays).
    """

    key: str
    platform: Platform
    kind: ValueKind
    described: bool
    units: UnitMapping | None
    enabled_default: bool
    binary_class: BinarySensorDeviceClass | None = None
    diagnostic: bool = False
    data_exchange: bool = False
    """A device's status: shown as whether it exchanges data (Point.exchange)."""
    precision: int | None = None
    """The decimals a sensor of it is shown with at first (:func:`display_precision`)."""


REAL_DECIMALS: Final = 2
"""The decimals a real is shown with at first: a value the PLC computes (an
LREAL of hours, 3.69083333333333) has digits no reading means."""
MAX_DECIMALS: Final = 6


def display_precision(point: Point) -> int | None:
    """Return the decimals a sensor of a point shows at first (None: as it comes).

    A real (REAL, LREAL): :data:`REAL_DECIMALS`, or its scale's and offset's
    decimals where they have more; an integer scaled to fractions (a register
    in tenths): its scale's and offset's decimals (0.1: 1, 0.25: 2); a whole
    number, text, a date: none. At most :data:`MAX_DECIMALS`; the user may
    choose others.
    """
    if point.kind is not ValueKind.REAL:
        return None
    decimals = max(_decimals(point.scale), _decimals(point.offset))
    if point.type.kind is ValueKind.REAL:
        decimals = max(decimals, REAL_DECIMALS)
    return min(decimals, MAX_DECIMALS)


def _decimals(number: float) -> int:
    """Return the decimals a number is written with (0.25: 2; 10: 0)."""
    exponent = Decimal(repr(float(number))).normalize().as_tuple().exponent
    return max(0, -exponent) if isinstance(exponent, int) else 0


def describe(
    point: Point, plain_variables: PlainVariables, *, consumed: bool = False
) -> PointDescription:
    """Describe the entity of a point.

    Plain variables are enabled as the options say; a point a typed device is
    built from (``consumed``) is created disabled: the typed entity shows it.
    """
    platform = platform_for(point)
    clock = platform is Platform.SENSOR and is_clock(point)
    return PointDescription(
        key=point.key,
        platform=platform,
        kind=point.kind,
        described=point.described,
        units=DURATION
        if (platform is Platform.SENSOR and point.kind is ValueKind.TIME)
        or point.kind is ValueKind.DURATION
        else unit_mapping(point),
        binary_class=binary_class(point)
        if platform is Platform.BINARY_SENSOR
        else None,
        diagnostic=point.diagnostic or clock,
        data_exchange=platform is Platform.SENSOR and point.data_exchange,
        precision=display_precision(point),
        enabled_default=not consumed
        and not clock
        and (
            point.attributes.visible
            if point.attributes is not None
            else plain_variables is PlainVariables.ENABLED
        ),
    )


def is_clock(point: Point) -> bool:
    """Whether a point is a date and time whose title or path says it is a clock."""
    if point.kind is not ValueKind.DATETIME:
        return False
    title = point.attributes.name if point.attributes is not None else ""
    return any(
        CLOCK_TITLE.search(folded(readable_path(text))) for text in (title, point.path)
    )


def platform_for(point: Point) -> Platform:
    """Return the platform whose entity shows the point.

    A writable point the user wants only shown (its map says ``sensor`` or
    ``binary_sensor``) gets the read-only platform of its kind. A flag or an
    integer that may be written but not read (an intercom's call) is a button;
    a flag whose rises are events (a call begins) is an event entity.
    """
    if point.event is not None and point.kind is ValueKind.BOOL:
        return Platform.EVENT
    if (
        point.attributes is not None
        and point.attributes.access is Access.WRITE
        and point.kind in PRESSED_KINDS
    ):
        return Platform.BUTTON
    read_only = PLATFORM_BY_KIND[point.kind, False]
    if point.platform == read_only.value:
        return read_only
    return PLATFORM_BY_KIND[point.kind, point.writable]


def binary_class(point: Point) -> BinarySensorDeviceClass | None:
    """Return a binary sensor's device class: the one asked for, else its title's."""
    with suppress(ValueError):
        return BinarySensorDeviceClass(point.device_class)
    return None if point.attributes is None else binary_class_of(point.attributes.name)


def binary_class_of(*texts: str) -> BinarySensorDeviceClass | None:
    """Return the device class the first of ``texts`` to say one says (see the table)."""
    for text in texts:
        words = folded(readable_path(text))
        if NOT_A_CONTACT.search(words) or SAYS_OFF_STATE.search(words):
            continue
        for pattern, device_class in BINARY_CLASS_TITLES:
            if pattern.search(words):
                return device_class
    return None


def unit_mapping(point: Point) -> UnitMapping | None:
    """Return unit, device class and state class of a numeric point (None: none).

    The unit is the user's where they gave one, else its attributes' (a plain
    point has none); the device class and the state class are those the user
    asked for (a map's, a point's override) where Home Assistant has them,
    else the unit's. A point without a unit has a state class only where the
    user asked for one (a count of starts kept as a total), and no unit.
    """
    if point.kind not in NUMERIC_KINDS:
        return None
    units = point.unit_of().strip()
    state_class = _state_class(point.state_class)
    if not units:
        return None if state_class is None else UnitMapping("", state_class=state_class)
    title = point.attributes.name if point.attributes is not None else ""
    if units == PERCENTAGE and HUMIDITY_TITLE.search(title):
        found = HUMIDITY
    else:
        found = UNITS.get(units, UnitMapping(units))
    with suppress(ValueError):
        found = replace(found, device_class=SensorDeviceClass(point.device_class))
    return found if state_class is None else replace(found, state_class=state_class)


def _state_class(name: str) -> SensorStateClass | None:
    """Return the state class a point asks for (None: none, or not Home Assistant's)."""
    try:
        return SensorStateClass(name) if name else None
    except ValueError:
        return None


def number_device_class(mapping: UnitMapping | None) -> NumberDeviceClass | None:
    """Return the number device class matching a sensor device class."""
    if mapping is None or mapping.device_class is None:
        return None
    try:
        return NumberDeviceClass(mapping.device_class.value)
    except ValueError:
        return None


def entity_name(
    point: Point,
    attributes: PointAttributes | None,
    *,
    in_group: bool = False,
    said: tuple[str | None, ...] = (),
) -> str:
    """Return the entity name: ``attr.title``, else the path (readable for objects).

    ``attributes`` are the point's latest. Plain variables keep their path as the
    user knows it from Mosaic; a T_ApiObject without a title gets its path spelled
    out in words. ``in_group``: the entity sits on its top-level name's device,
    which already says ``Main``, so ``Main.counter`` is named ``counter``.
    ``said``: the names its device and its area say already, which a title (or
    the path in words) does not say again (``Heating curve shift`` on *Heating* is ``Curve shift``); an
    empty name means the entity is its device's main feature.
    """
    path = point.path
    if in_group and (member := _member_path(path)):
        path = member
    if attributes is None:
        return path
    title = attributes.name.strip() or readable_path(path)
    return without_leading(title, *said)


def point_label(point: Point) -> str:
    """How a point is named in a list: its title and its path (``Boiler (boiler)``)."""
    title = point.attributes.name.strip() if point.attributes is not None else ""
    return f"{title} ({point.path})" if title else point.path


def _member_path(path: str) -> str:
    """Return the path below a top-level structure or program: ``Main.a.b`` → ``a.b``.

    An array's index stays on its name (``arr[2].x`` is not ``x``), and so does a
    top-level variable's name.
    """
    root, dot, member = path.partition(".")
    return member if dot and "[" not in root else ""


def readable_path(path: str) -> str:
    """Spell a path in words: ``Main.heatingPump_1[2]`` → ``Main heating pump 1 2``."""
    words = re.sub(r"[._\[\]]+", " ", path)
    words = re.sub(r"(?<=[a-z0-9])(?=[A-Z])|(?<=[A-Za-z])(?=[0-9])", " ", words)
    text = " ".join(words.split()).lower()
    return text[:1].upper() + text[1:]


def number_range(
    point: Point, attributes: PointAttributes | None
) -> tuple[float, float]:
    """Return the number's min and max: its type's, within its range if it has one.

    Its range is ``attributes``' (the latest), each end the user's where given.

    The type's range is an integer's bounds as shown (a UINT 0..65535, an INT in
    tenths -3276.8..3276.7), else its kind's. A range that says values the type
    cannot hold is cut to the type's; one wholly outside it is not taken.
    """
    low, high = shown_bounds(point) or DEFAULT_NUMBER_RANGE[point.kind]
    said_low, said_high = point.range_of(attributes)
    if (
        said_low is not None
        and said_high is not None
        and max(low, said_low) <= min(high, said_high)
    ):
        return max(low, said_low), min(high, said_high)
    return low, high


SETPOINT_STEP: Final = 0.5
"""A temperature setpoint's step: ten taps per degree is nine too many."""
SETPOINT_MIN_SPAN: Final = 2.0


def number_step(
    point: Point, minimum: float, maximum: float, *, temperature: bool = False
) -> float:
    """Return a number's step.

    The point's own step where its source gives one (a map's ``step``). 1 for
    integers. A writable temperature in °C (a setpoint) steps by 0.5, unless
    the PLC's range says otherwise: a range whose ends are not whole halves, or
    narrower than 2 °C, gets the general rule. Other reals step by 0.1, finer
    for ranges narrower than 10.
    """
    if point.step:
        return point.step
    if point.kind in (ValueKind.INTEGER, ValueKind.DURATION):
        return 1
    span = maximum - minimum
    if (
        temperature
        and (minimum * 2).is_integer()
        and (maximum * 2).is_integer()
        and span >= SETPOINT_MIN_SPAN
    ):
        return SETPOINT_STEP
    if span >= 10 or span <= 0:
        return REAL_STEP
    return float(10 ** floor(log10(span / 100)))


def number_mode(minimum: float, maximum: float, step: float) -> NumberMode:
    """Return a slider for up to a thousand steps, a box for wider ranges."""
    if (maximum - minimum) / step > MAX_SLIDER_STEPS:
        return NumberMode.BOX
    return NumberMode.SLIDER
