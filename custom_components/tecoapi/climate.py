"""Climate: GTSAP1 ``THERMOSTAT`` families, thermostats in our struct convention, composed.

The HVAC modes follow what the thermostat can do (heating, cooling or both, from
its ``type`` or, without one, its members) and the mode flags that belong to it
(a heating-only GTSAP1 block's ``coolmode`` is no role of its device): with
``heatmode``/``coolmode`` the modes are heat, cool (heat and cool when it does
both) and off; without them the thermostat is always in its one mode. The action is heating or cooling
while the ``heat``/``cool`` flags say so, else idle. The target temperature's
range is the block's ``mintemp``/``maxtemp`` or the setpoint T_ApiObject's
``minValue``/``maxValue``; it steps by 0.5 °C unless that range's ends are finer.

The temperatures go by both their names: Home Assistant 2026.11 reads the
``native_*`` ones and warns about a class that gives only the old ones (they stop
working in 2027.11); 2026.10 and older know only the old ones, which return the
native values.
"""

from typing import Any, Final, override

from homeassistant.components.climate import ClimateEntity
from homeassistant.const import ATTR_TEMPERATURE, Platform, UnitOfTemperature

from .compat import ClimateEntityFeature, HVACAction, HVACMode
from .coordinator import PlcCoordinator
from .entity import PlcDeviceEntity
from .follower import entity_platform
from .pyplc.core.devices import (
    ClimateSupport,
    Role,
    TypedDevice,
    setpoint_range,
)

PARALLEL_UPDATES = 1

DEFAULT_RANGE: Final = (7.0, 35.0)
STEP: Final = 0.5
FINE_STEP: Final = 0.1

# The mode flags each mode switches on (the others off).
MODE_FLAGS: Final[dict[HVACMode, frozenset[Role]]] = {
    HVACMode.HEAT: frozenset({Role.HEAT_MODE}),
    HVACMode.COOL: frozenset({Role.COOL_MODE}),
    HVACMode.HEAT_COOL: frozenset({Role.HEAT_MODE, Role.COOL_MODE}),
    HVACMode.OFF: frozenset(),
}


def hvac_modes(support: ClimateSupport, flags: frozenset[Role]) -> list[HVACMode]:
    """Return the modes of a thermostat from what it supports and its mode flags."""
    if not flags:
        return [
            {
                ClimateSupport.HEATING: HVACMode.HEAT,
                ClimateSupport.COOLING: HVACMode.COOL,
                ClimateSupport.BOTH: HVACMode.HEAT_COOL,
            }[support]
        ]
    modes = [mode for mode, needs in MODE_FLAGS.items() if needs and needs <= flags]
    return [*modes, HVACMode.OFF]


class PlcClimate(PlcDeviceEntity, ClimateEntity):
    """A thermostat: the measured and the target temperature, modes, action."""

    _attr_native_temperature_unit = UnitOfTemperature.CELSIUS
    _attr_temperature_unit = UnitOfTemperature.CELSIUS  # before 2026.11

    def __init__(self, coordinator: PlcCoordinator, device: TypedDevice) -> None:
        """Fix the modes, the range and the step from the device."""
        super().__init__(coordinator, device)
        self._flags = frozenset({Role.HEAT_MODE, Role.COOL_MODE} & device.roles.keys())
        self._attr_hvac_modes = hvac_modes(
            device.climate or ClimateSupport.HEATING, self._flags
        )
        features = ClimateEntityFeature.TARGET_TEMPERATURE
        if HVACMode.OFF in self._attr_hvac_modes:
            features |= ClimateEntityFeature.TURN_ON | ClimateEntityFeature.TURN_OFF
        self._attr_supported_features = features
        data = coordinator.data
        low, high = (
            setpoint_range(device, data.catalogue.points, data.values) or DEFAULT_RANGE
        )
        self._attr_min_temp, self._attr_max_temp = low, high
        halves = (low * 2).is_integer() and (high * 2).is_integer()
        self._attr_target_temperature_step = STEP if halves else FINE_STEP

    @property
    def native_current_temperature(self) -> float | None:
        """The measured temperature."""
        return self.role_number(Role.TEMPERATURE)

    @property
    def native_target_temperature(self) -> float | None:
        """The setpoint."""
        return self.role_number(Role.SETPOINT)

    @property
    @override
    def current_temperature(self) -> float | None:
        """The measured temperature, for releases before 2026.11."""
        return self.native_current_temperature

    @property
    @override
    def target_temperature(self) -> float | None:
        """The setpoint, for releases before 2026.11."""
        return self.native_target_temperature

    @property
    @override
    def hvac_mode(self) -> HVACMode | None:
        """The mode the flags say (the one mode when there are none)."""
        if not self._flags:
            return self._attr_hvac_modes[0]
        on = frozenset(role for role in self._flags if self.role_flag(role))
        return next(
            (mode for mode, flags in MODE_FLAGS.items() if flags == on),
            HVACMode.OFF,
        )

    @property
    @override
    def hvac_action(self) -> HVACAction | None:
        """Heating or cooling while its flag says so; else idle (off when off)."""
        roles = self.device.roles
        if Role.HEATING not in roles and Role.COOLING not in roles:
            return None
        if self.role_flag(Role.HEATING):
            return HVACAction.HEATING
        if self.role_flag(Role.COOLING):
            return HVACAction.COOLING
        return HVACAction.OFF if self.hvac_mode is HVACMode.OFF else HVACAction.IDLE

    @override
    async def async_set_temperature(self, **kwargs: Any) -> None:
        """Write the setpoint."""
        if (temperature := kwargs.get(ATTR_TEMPERATURE)) is not None:
            await self.async_write_role(Role.SETPOINT, temperature)

    @override
    async def async_set_hvac_mode(self, hvac_mode: HVACMode) -> None:
        """Switch the mode flags: the mode's on, the others off."""
        wanted = MODE_FLAGS[hvac_mode]
        for role in sorted(self._flags):
            await self.async_write_role(role, role in wanted)

    @override
    async def async_turn_on(self) -> None:
        """Switch on in the first mode it has."""
        await self.async_set_hvac_mode(self._attr_hvac_modes[0])

    @override
    async def async_turn_off(self) -> None:
        """Switch every mode flag off."""
        await self.async_set_hvac_mode(HVACMode.OFF)


async_setup_entry = entity_platform(Platform.CLIMATE, devices=PlcClimate)
