"""Thermostats: the measured and the target temperature, modes and action."""

from collections.abc import Mapping
from dataclasses import dataclass
from enum import StrEnum
from types import MappingProxyType
from typing import Any, Final

from ..devices import ClimateSupport, Role, TypedDevice, setpoint_range
from ..models import Point
from .base import Appliance, Batch


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

        The range of :func:`~..devices.setpoint_range`, else 7 to 35 °C; it
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
