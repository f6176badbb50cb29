"""Climate: GTSAP1 ``THERMOSTAT`` families, thermostats in our struct convention, composed.

The HVAC modes follow what the thermostat can do (heating, cooling or both, from
its ``type`` or, without one, its members) and the mode flags that belong to it
(a heating-only GTSAP1 block's ``coolmode`` is no role of its device): with
``heatmode``/``coolmode`` the modes are heat, cool (heat and cool when it does
both) and off; without them the thermostat is always in its one mode. The action is heating or cooling
while the ``heat``/``cool`` flags say so, else idle. The target temperature's
range is the block's ``mintemp``/``maxtemp`` or the setpoint T_ApiObject's
``minValue``/``maxValue``; it steps by 0.5 °C unless that range's ends are finer.
The library's ``Thermostat`` (``pyplc.core.appliances``) holds all this: the
entity shows its state and sends each command as one batch (a mode's flags
together).

The temperatures go by both their names: Home Assistant 2026.11 reads the
``native_*`` ones and warns about a class that gives only the old ones (they stop
working in 2027.11); 2026.10 and older know only the old ones, which return the
native values.
"""

from typing import Any, override

from homeassistant.components.climate import ClimateEntity
from homeassistant.const import ATTR_TEMPERATURE, Platform, UnitOfTemperature

from .compat import ClimateEntityFeature, HVACAction, HVACMode
from .coordinator import PlcCoordinator
from .entity import PlcApplianceEntity
from .follower import entity_platform
from .pyplc.core.appliances import Thermostat, ThermostatMode
from .pyplc.core.devices import TypedDevice

PARALLEL_UPDATES = 1


class PlcClimate(PlcApplianceEntity[Thermostat], ClimateEntity):
    """A thermostat: the measured and the target temperature, modes, action."""

    _attr_native_temperature_unit = UnitOfTemperature.CELSIUS
    _attr_temperature_unit = UnitOfTemperature.CELSIUS  # before 2026.11

    def __init__(self, coordinator: PlcCoordinator, device: TypedDevice) -> None:
        """Fix the modes, the range and the step from the device."""
        data = coordinator.data
        thermostat = Thermostat(device, data.catalogue.points)
        super().__init__(coordinator, device, thermostat)
        self._attr_hvac_modes = [HVACMode(mode) for mode in thermostat.modes]
        features = ClimateEntityFeature.TARGET_TEMPERATURE
        if HVACMode.OFF in self._attr_hvac_modes:
            features |= ClimateEntityFeature.TURN_ON | ClimateEntityFeature.TURN_OFF
        self._attr_supported_features = features
        low, high, step = thermostat.setpoint_range(data.catalogue.points, data.values)
        self._attr_min_temp, self._attr_max_temp = low, high
        self._attr_target_temperature_step = step

    @property
    def native_current_temperature(self) -> float | None:
        """The measured temperature."""
        return self.per_update(self.appliance.state).temperature

    @property
    def native_target_temperature(self) -> float | None:
        """The setpoint."""
        return self.per_update(self.appliance.state).setpoint

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
        return HVACMode(self.per_update(self.appliance.state).mode)

    @property
    @override
    def hvac_action(self) -> HVACAction | None:
        """Heating or cooling while its flag says so; else idle (off when off)."""
        action = self.per_update(self.appliance.state).action
        return None if action is None else HVACAction(action)

    @override
    async def async_set_temperature(self, **kwargs: Any) -> None:
        """Write the setpoint."""
        if (temperature := kwargs.get(ATTR_TEMPERATURE)) is not None:
            await self.async_send(lambda: self.appliance.set_setpoint(temperature))

    @override
    async def async_set_hvac_mode(self, hvac_mode: HVACMode) -> None:
        """Switch the mode flags, the mode's on and the others off: one batch."""
        mode = ThermostatMode(hvac_mode)
        await self.async_send(lambda: self.appliance.set_mode(mode))

    @override
    async def async_turn_on(self) -> None:
        """Switch on in the first mode it has."""
        await self.async_send(self.appliance.turn_on)

    @override
    async def async_turn_off(self) -> None:
        """Switch every mode flag off."""
        await self.async_send(self.appliance.turn_off)


async_setup_entry = entity_platform(Platform.CLIMATE, devices=PlcClimate)
