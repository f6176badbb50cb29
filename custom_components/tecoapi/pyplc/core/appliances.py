"""Appliances: typed devices that read their state and turn a command into one write batch.

A :class:`~.devices.TypedDevice` says which points play which role. An
appliance made of it and the catalogue's points holds a :class:`RoleValue`
per role -- the point's key and how its value is read and written (its
transcoder) -- and gives:

- typed **state** read from a values mapping (:class:`LightState`,
  :class:`CoverState`, :class:`ThermostatState`);
- **commands** (switch a light on at a brightness and colour, move a cover,
  set a thermostat's mode) that each return ONE ordered write batch: point key
  to the value to write, in the point's kind, to be sent together;
- for a device the PLC moves to a target (a blind, a light dimming to a target
  level) the points to read while it moves and whether it ``arrived``.

Values are read and written with the device's :class:`~.devices.Readings`
(its recogniser's: they may read text), and an inverted flag is read and
written as its opposite. An appliance knows nothing of Home Assistant.
"""

from collections.abc import Mapping
from dataclasses import dataclass
from enum import StrEnum
from types import MappingProxyType
from typing import Any, Final

from .devices import (
    ClimateSupport,
    CoverClass,
    LightMode,
    Readings,
    Role,
    TypedDevice,
    kelvin_range,
    setpoint_range,
)
from .models import Point

type Batch = dict[str, Any]
"""One command's writes: point key → value in the point's kind, in order."""

FULL: Final = 100.0
"""A light's full level, and a cover's open position (%)."""

BRIGHTNESS_SCALE: Final = 255
"""The top of the 0-255 brightness scale home automation shows a level in."""


class MissingPointError(LookupError):
    """A role's point is not in the catalogue: nothing can be written to it."""

    def __init__(self, key: str) -> None:
        """Name the point (its key)."""
        super().__init__(f"No point {key!r} in the catalogue")
        self.key = key


class RoleValue:
    """A role's point and its transcoder: how its value is read and written.

    ``point`` is the catalogue's (None: not in the catalogue, nothing to write
    to); a flag read or written is its opposite when the point is inverted.
    """

    __slots__ = ("key", "point", "readings")

    def __init__(self, key: str, point: Point | None, readings: Readings) -> None:
        """Bind a point key to its point and the device's readings."""
        self.key = key
        self.point = point
        self.readings = readings

    def number(self, values: Mapping[str, Any]) -> float | None:
        """Read the value as a finite number (None: unknown or not one)."""
        return self.readings.number(values.get(self.key))

    def integer(self, values: Mapping[str, Any]) -> int | None:
        """Read the value as an integer (None: unknown or not one)."""
        return self.readings.integer(values.get(self.key))

    def flag(self, values: Mapping[str, Any]) -> bool | None:
        """Read the value as a flag, an inverted point's opposite (None: unknown)."""
        flag = self.readings.flag(values.get(self.key))
        if flag is None or self.point is None:
            return flag
        return self.point.flag(flag)

    def encode(self, value: bool | float) -> bool | int | float | str:
        """Return what to write for a flag or a number, in the point's kind.

        Raises :class:`MissingPointError` when the point is not in the catalogue.
        """
        if self.point is None:
            raise MissingPointError(self.key)
        return self.readings.written(self.point, value)


class Appliance:
    """A typed device with a transcoder per role, read against a catalogue's points.

    :meth:`rebind` follows a new catalogue (a point may be inverted now); it
    costs nothing when the points are the same object.
    """

    __slots__ = ("_points", "_values", "device")

    def __init__(self, device: TypedDevice, points: Mapping[str, Point]) -> None:
        """Make a transcoder of each role's point."""
        self.device = device
        self._points: Mapping[str, Point] | None = None
        self._values: Mapping[Role, RoleValue] = MappingProxyType({})
        self.rebind(points)

    def rebind(self, points: Mapping[str, Point]) -> None:
        """Read and write the roles' points as ``points`` (a catalogue's) say."""
        if points is self._points:
            return
        self._points = points
        readings = self.device.readings
        self._values = MappingProxyType(
            {
                role: RoleValue(key, points.get(key), readings)
                for role, key in self.device.roles.items()
            }
        )

    def has(self, role: Role) -> bool:
        """Whether a point plays ``role``."""
        return role in self._values

    def value(self, role: Role) -> RoleValue:
        """Return the transcoder of a role (KeyError: no point plays it)."""
        return self._values[role]

    def number(self, role: Role, values: Mapping[str, Any]) -> float | None:
        """Read a role's value as a number (None: no such role, unknown)."""
        value = self._values.get(role)
        return None if value is None else value.number(values)

    def flag(self, role: Role, values: Mapping[str, Any]) -> bool | None:
        """Read a role's value as a flag (None: no such role, unknown)."""
        value = self._values.get(role)
        return None if value is None else value.flag(values)

    def write(self, batch: Batch, role: Role, value: bool | float) -> Batch:
        """Add a flag or a number for a role's point to a batch; return the batch."""
        transcoder = self._values[role]
        batch[transcoder.key] = transcoder.encode(value)
        return batch

    @property
    def motion(self) -> frozenset[str]:
        """The points to read while the PLC moves it to a target (none: it never moves)."""
        return frozenset()

    def moves(self, batch: Mapping[str, Any]) -> bool:
        """Whether a batch sends it on a way the PLC takes (read :attr:`motion` then)."""
        return False

    def arrived(self, values: Mapping[str, Any]) -> bool:
        """Whether it is where its target says: nothing is left to follow."""
        return True

    def _keys(self, *roles: Role) -> frozenset[str]:
        """Return the keys of the points playing those of ``roles`` it has."""
        return frozenset(
            value.key for role in roles if (value := self._values.get(role))
        )


# --------------------------------------------------------------------------
# Lights.


def brightness_level(brightness: int) -> float:
    """Return a 0-255 brightness as a 0-100 % level; 1 stays on (1 %)."""
    return max(1.0, round(brightness * FULL / BRIGHTNESS_SCALE))


def level_brightness(level: float) -> int:
    """Return a level (%, clamped to 0-100) as a 0-255 brightness."""
    return round(min(max(level, 0.0), FULL) * BRIGHTNESS_SCALE / FULL)


def rgb_split(value: int) -> tuple[int, int, int]:
    """Split R + G·256 + B·65536 into red, green and blue."""
    return value & 0xFF, (value >> 8) & 0xFF, (value >> 16) & 0xFF


def rgb_packed(red: int, green: int, blue: int) -> int:
    """Pack red, green and blue as R + G·256 + B·65536."""
    return red + green * 256 + blue * 65536


@dataclass(frozen=True, slots=True)
class LightState:
    """What a light shows: on, its level (%), brightness (0-255), colour, white."""

    is_on: bool | None
    level: float | None
    brightness: int | None
    rgb: tuple[int, int, int] | None
    kelvin: int | None


class Light(Appliance):
    """A light: on/off, dimmable, RGB or tunable white, by its light mode.

    It is on when its ``onoff`` point says so, or (without one) when its level
    is above zero. Brightness writes the target level (the level, without a
    target of its own). Switched on without a brightness, a dimmable light that
    is dark gets its last level above zero back (:meth:`update` keeps it), or
    full when none is known: ``onoff`` alone would show it on at 0 %.
    """

    __slots__ = ("_last_level", "dimmable", "follows_target", "mode", "target")

    def __init__(self, device: TypedDevice, points: Mapping[str, Point]) -> None:
        """Fix its mode, the role its level is written to, and whether it dims."""
        super().__init__(device, points)
        roles = device.roles
        self.mode = device.light_mode or LightMode.ONOFF
        self.target = Role.TARGET_LEVEL if Role.TARGET_LEVEL in roles else Role.LEVEL
        self.dimmable = self.mode is not LightMode.ONOFF and self.target in roles
        self.follows_target = (
            self.dimmable
            and Role.LEVEL in roles
            and roles.get(Role.TARGET_LEVEL, roles[Role.LEVEL]) != roles[Role.LEVEL]
        )
        self._last_level = FULL

    @property
    def last_level(self) -> float:
        """The last level above zero written (or seen), to switch on to."""
        return self._last_level

    def update(self, values: Mapping[str, Any]) -> None:
        """Remember the last level above zero, from what the PLC holds now.

        The level written (the target, where it has a point of its own) rather
        than the one shown: a light the PLC dims down to 0 passes through
        levels nobody chose.
        """
        level = self.number(self.target, values)
        if level is not None and level > 0:
            self._last_level = min(level, FULL)

    def kelvin_range(
        self, points: Mapping[str, Point], values: Mapping[str, Any]
    ) -> tuple[int, int]:
        """Its colour temperature range in kelvin (see :func:`~.devices.kelvin_range`)."""
        return kelvin_range(self.device, points, values)

    def state(self, values: Mapping[str, Any]) -> LightState:
        """Read what it shows from the values."""
        level = self.number(Role.LEVEL, values)
        if self.has(Role.ONOFF):
            is_on = self.flag(Role.ONOFF, values)
        else:
            is_on = None if level is None else level > 0
        rgb = self.value(Role.RGB).integer(values) if self.has(Role.RGB) else None
        kelvin = self.number(Role.COLOR_TEMP, values)
        return LightState(
            is_on=is_on,
            level=level,
            brightness=(
                None
                if level is None or self.mode is LightMode.ONOFF
                else level_brightness(level)
            ),
            rgb=None if rgb is None else rgb_split(rgb),
            kelvin=None if kelvin is None else round(kelvin),
        )

    def turn_on(
        self,
        values: Mapping[str, Any],
        *,
        brightness: int | None = None,
        rgb: tuple[int, int, int] | None = None,
        kelvin: float | None = None,
    ) -> Batch:
        """Switch on at the brightness (0-255), colour or colour temperature asked for.

        The colour first, then the colour temperature, the level and ``onoff``:
        without a brightness, a dark dimmable light gets its last level above
        zero back; a light without ``onoff`` is switched on by that alone.
        """
        batch: Batch = {}
        if rgb is not None and self.has(Role.RGB):
            self.write(batch, Role.RGB, rgb_packed(*rgb))
        if kelvin is not None and self.has(Role.COLOR_TEMP):
            self.write(batch, Role.COLOR_TEMP, kelvin)
        if self.dimmable:
            if brightness is not None:
                self.write(batch, self.target, brightness_level(brightness))
            elif not (self.number(Role.LEVEL, values) or 0.0) > 0:
                self.write(batch, self.target, self._last_level)
        if self.has(Role.ONOFF):
            self.write(batch, Role.ONOFF, True)
        return batch

    def turn_off(self) -> Batch:
        """Switch off: ``onoff`` false, or the level 0."""
        if self.has(Role.ONOFF):
            return self.write({}, Role.ONOFF, False)
        return self.write({}, self.target, 0)

    @property
    def motion(self) -> frozenset[str]:
        """Its level, target level and ``onoff``, while it dims to a target."""
        if not self.follows_target:
            return frozenset()
        return self._keys(Role.LEVEL, Role.TARGET_LEVEL, Role.ONOFF)

    def moves(self, batch: Mapping[str, Any]) -> bool:
        """Whether the batch sets the target level of a light that dims to one."""
        return self.follows_target and self.value(self.target).key in batch

    def arrived(self, values: Mapping[str, Any]) -> bool:
        """Whether its level reached its target, or it is off; unknown: there."""
        if not self.follows_target:
            return True
        level = self.number(Role.LEVEL, values)
        target = self.number(Role.TARGET_LEVEL, values)
        if level is None or target is None:
            return True
        if self.flag(Role.ONOFF, values) is False:
            return True
        return round(level) == round(target)


# --------------------------------------------------------------------------
# Covers.


def percent(value: float) -> int:
    """Return a position or target as the whole percent shown (0-100)."""
    return round(min(max(value, 0.0), FULL))


@dataclass(frozen=True, slots=True)
class CoverState:
    """Where a cover is (0 closed to 100 open) and where it is on its way to.

    ``target`` is the target it is heading for (None: it is where its target
    says, or it has none); ``moving`` the ``moving`` flag (None: none, unknown).
    """

    position: int | None
    target: int | None
    moving: bool | None
    opening: bool
    closing: bool

    @property
    def is_closed(self) -> bool | None:
        """Closed at position 0 (None: unknown)."""
        return None if self.position is None else self.position == 0


class Cover(Appliance):
    """A blind, shutter or gate with a position, 0 % closed to 100 % open.

    It moves by writing its target (its position, when it has no target of its
    own) and stops when its current position is written as the target. It is
    opening or closing while its target differs from its position: at once
    after a move is asked for, before the PLC has set it moving.
    """

    __slots__ = ("can_stop", "gate", "target")

    def __init__(self, device: TypedDevice, points: Mapping[str, Point]) -> None:
        """Fix the role moved, and whether it has a target apart from its position."""
        super().__init__(device, points)
        roles = device.roles
        self.gate = device.cover_class is CoverClass.GATE
        self.target = Role.TARGET if Role.TARGET in roles else Role.POSITION
        self.can_stop = (
            roles.get(Role.TARGET, roles[Role.POSITION]) != (roles[Role.POSITION])
        )

    def state(self, values: Mapping[str, Any]) -> CoverState:
        """Read where it is and where it is heading from the values."""
        number = self.number(Role.POSITION, values)
        position = None if number is None else percent(number)
        target = self.number(Role.TARGET, values) if self.can_stop else None
        heading = (
            None
            if target is None or position is None or percent(target) == position
            else percent(target)
        )
        return CoverState(
            position=position,
            target=heading,
            moving=self.flag(Role.MOVING, values),
            opening=heading is not None and heading > (position or 0),
            closing=heading is not None and heading < (position or 0),
        )

    def move_to(self, position: float) -> Batch:
        """Go to a position (%)."""
        return self.write({}, self.target, position)

    def open(self) -> Batch:
        """Go to 100 %."""
        return self.move_to(FULL)

    def close(self) -> Batch:
        """Go to 0 %."""
        return self.move_to(0)

    def stop(self, values: Mapping[str, Any]) -> Batch:
        """Stop where it is: its current position becomes the target (unknown: nothing)."""
        position = self.state(values).position
        return {} if position is None else self.move_to(position)

    @property
    def motion(self) -> frozenset[str]:
        """Its position, target and ``moving``, for a cover moved by a target."""
        if not self.can_stop:
            return frozenset()
        return self._keys(Role.POSITION, Role.TARGET, Role.MOVING)

    def moves(self, batch: Mapping[str, Any]) -> bool:
        """Whether the batch sets the target of a cover moved by one."""
        return self.can_stop and self.value(self.target).key in batch

    def arrived(self, values: Mapping[str, Any]) -> bool:
        """Whether it is where its target says and ``moving`` (if any) says still.

        Unknown values count as there: nothing is left to follow.
        """
        position = self.number(Role.POSITION, values)
        target = self.number(Role.TARGET, values)
        if not self.can_stop or position is None or target is None:
            return True
        moving = self.flag(Role.MOVING, values)
        return percent(position) == percent(target) and moving is not True


# --------------------------------------------------------------------------
# Thermostats.


class ThermostatMode(StrEnum):
    """What a thermostat is set to do."""

    HEAT = "heat"
    COOL = "cool"
    HEAT_COOL = "heat_cool"
    OFF = "off"


class ThermostatAction(StrEnum):
    """What a thermostat is doing."""

    HEATING = "heating"
    COOLING = "cooling"
    IDLE = "idle"
    OFF = "off"


MODE_FLAGS: Final[Mapping[ThermostatMode, frozenset[Role]]] = MappingProxyType(
    {
        ThermostatMode.HEAT: frozenset({Role.HEAT_MODE}),
        ThermostatMode.COOL: frozenset({Role.COOL_MODE}),
        ThermostatMode.HEAT_COOL: frozenset({Role.HEAT_MODE, Role.COOL_MODE}),
        ThermostatMode.OFF: frozenset(),
    }
)
"""The mode flags each mode switches on (the others off)."""

ONE_MODE: Final[Mapping[ClimateSupport, ThermostatMode]] = MappingProxyType(
    {
        ClimateSupport.HEATING: ThermostatMode.HEAT,
        ClimateSupport.COOLING: ThermostatMode.COOL,
        ClimateSupport.BOTH: ThermostatMode.HEAT_COOL,
    }
)
"""The one mode of a thermostat without mode flags, by what it does."""

DEFAULT_RANGE: Final = (7.0, 35.0)
STEP: Final = 0.5
FINE_STEP: Final = 0.1


def thermostat_modes(
    support: ClimateSupport, flags: frozenset[Role]
) -> tuple[ThermostatMode, ...]:
    """Return a thermostat's modes from what it does and its mode flags."""
    if not flags:
        return (ONE_MODE[support],)
    modes = [mode for mode, needs in MODE_FLAGS.items() if needs and needs <= flags]
    return (*modes, ThermostatMode.OFF)


@dataclass(frozen=True, slots=True)
class ThermostatState:
    """The measured temperature, the setpoint, the mode and the action."""

    temperature: float | None
    setpoint: float | None
    mode: ThermostatMode
    action: ThermostatAction | None


class Thermostat(Appliance):
    """A thermostat: the measured and the target temperature, modes, action.

    With ``heatmode``/``coolmode`` flags its modes are heat, cool (heat and
    cool when it does both) and off; without them it is always in its one mode.
    The action is heating or cooling while the ``heat``/``cool`` flags say so,
    else idle (off when off); none without those flags.
    """

    __slots__ = ("flags", "modes")

    def __init__(self, device: TypedDevice, points: Mapping[str, Point]) -> None:
        """Fix its modes from what it does and its mode flags."""
        super().__init__(device, points)
        self.flags = frozenset({Role.HEAT_MODE, Role.COOL_MODE} & device.roles.keys())
        self.modes = thermostat_modes(
            device.climate or ClimateSupport.HEATING, self.flags
        )

    def setpoint_range(
        self, points: Mapping[str, Point], values: Mapping[str, Any]
    ) -> tuple[float, float, float]:
        """Its target temperature's range and step: lowest, highest, step.

        The range of :func:`~.devices.setpoint_range`, else 7 to 35 °C; it
        steps by 0.5 °C unless the range's ends are finer (0.1 °C).
        """
        low, high = setpoint_range(self.device, points, values) or DEFAULT_RANGE
        halves = (low * 2).is_integer() and (high * 2).is_integer()
        return low, high, STEP if halves else FINE_STEP

    def mode(self, values: Mapping[str, Any]) -> ThermostatMode:
        """Return the mode its flags say (the one mode when it has none)."""
        if not self.flags:
            return self.modes[0]
        on = frozenset(role for role in self.flags if self.flag(role, values))
        return next(
            (mode for mode, flags in MODE_FLAGS.items() if flags == on),
            ThermostatMode.OFF,
        )

    def state(self, values: Mapping[str, Any]) -> ThermostatState:
        """Read its temperatures, mode and action from the values."""
        mode = self.mode(values)
        action: ThermostatAction | None = None
        if self.has(Role.HEATING) or self.has(Role.COOLING):
            if self.flag(Role.HEATING, values):
                action = ThermostatAction.HEATING
            elif self.flag(Role.COOLING, values):
                action = ThermostatAction.COOLING
            elif mode is ThermostatMode.OFF:
                action = ThermostatAction.OFF
            else:
                action = ThermostatAction.IDLE
        return ThermostatState(
            temperature=self.number(Role.TEMPERATURE, values),
            setpoint=self.number(Role.SETPOINT, values),
            mode=mode,
            action=action,
        )

    def set_setpoint(self, temperature: float) -> Batch:
        """Write the setpoint."""
        return self.write({}, Role.SETPOINT, temperature)

    def set_mode(self, mode: ThermostatMode) -> Batch:
        """Switch the mode flags: the mode's on, the others off (none: nothing)."""
        wanted = MODE_FLAGS[mode]
        batch: Batch = {}
        for role in sorted(self.flags):
            self.write(batch, role, role in wanted)
        return batch

    def turn_on(self) -> Batch:
        """Switch on in its first mode."""
        return self.set_mode(self.modes[0])

    def turn_off(self) -> Batch:
        """Switch every mode flag off."""
        return self.set_mode(ThermostatMode.OFF)
