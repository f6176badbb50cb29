"""Lights: GTSAP1 ``LIGHT`` families, dimmers in our struct convention, composed lights.

A light is on when its ``onoff`` point says so, or (without one) when its level is
above zero. Brightness is the level (0-100 %) shown as Home Assistant's 0-255;
setting it writes the target level. Switched on without a brightness, a dimmable
light that is dark (its level 0) gets its last level above zero back, or full
when none is known, whether it has ``onoff`` or not: ``onoff`` alone would show
it on at 0 %. A light whose level is written to a target of its own (GTSAP1
``tgtlevel``) has its level read every second until it gets there (see
``motion``). RGB is written as R + G·256 + B·65536, the colour temperature in
kelvin.
"""

from functools import partial
from typing import Any, Final, override

from homeassistant.components.light import LightEntity
from homeassistant.const import Platform

from .compat import ATTR_BRIGHTNESS, ATTR_COLOR_TEMP_KELVIN, ATTR_RGB_COLOR, ColorMode
from .coordinator import PlcCoordinator
from .data import PlcData
from .entity import PlcDeviceEntity
from .follower import entity_platform
from .pyplc.core.devices import (
    LightMode,
    Role,
    TypedDevice,
    kelvin_range,
)

PARALLEL_UPDATES = 1

COLOR_MODES: Final[dict[LightMode, ColorMode]] = {
    LightMode.ONOFF: ColorMode.ONOFF,
    LightMode.BRIGHTNESS: ColorMode.BRIGHTNESS,
    LightMode.RGB: ColorMode.RGB,
    LightMode.COLOR_TEMP: ColorMode.COLOR_TEMP,
}
FULL: Final = 100.0


def _to_percent(brightness: int) -> float:
    """Home Assistant's 0-255 brightness as the PLC's 0-100 % level (1 stays on)."""
    return max(1.0, round(brightness * 100 / 255))


def arrived(device: TypedDevice, data: PlcData) -> bool:
    """Whether a light's level reached its target (or it is off: nothing to follow).

    Unknown values count as there.
    """
    roles = device.roles
    number = device.readings.number
    level = number(data.values.get(roles[Role.LEVEL]))
    target = number(data.values.get(roles[Role.TARGET_LEVEL]))
    if level is None or target is None:
        return True
    if data.flag(roles.get(Role.ONOFF), device.readings) is False:
        return True
    return round(level) == round(target)


class PlcLight(PlcDeviceEntity, LightEntity):
    """A light: on/off, dimmable, RGB or tunable white, by its light mode."""

    def __init__(self, coordinator: PlcCoordinator, device: TypedDevice) -> None:
        """Fix the colour mode, and the kelvin range of a tunable light."""
        super().__init__(coordinator, device)
        mode = COLOR_MODES[device.light_mode or LightMode.ONOFF]
        self._attr_color_mode = mode
        self._attr_supported_color_modes = {mode}
        if mode is ColorMode.COLOR_TEMP:
            data = coordinator.data
            low, high = kelvin_range(device, data.catalogue.points, data.values)
            self._attr_min_color_temp_kelvin = low
            self._attr_max_color_temp_kelvin = high
        self._target = (
            Role.TARGET_LEVEL if Role.TARGET_LEVEL in device.roles else (Role.LEVEL)
        )
        self._dimmable = mode is not ColorMode.ONOFF and self._target in device.roles
        roles = device.roles
        self._follows_target = (
            self._dimmable
            and Role.LEVEL in roles
            and roles.get(Role.TARGET_LEVEL, roles[Role.LEVEL]) != roles[Role.LEVEL]
        )
        self._last_level = FULL
        self._update_from_data(coordinator.data)

    @override
    def _update_from_data(self, data: PlcData) -> None:
        """Remember the last level above zero, to switch on to.

        The level written (the target, where it has its own point) rather than the
        one shown: a light the PLC dims down to 0 passes through levels nobody chose.
        """
        super()._update_from_data(data)
        level = self.role_number(self._target)
        if level is not None and level > 0:
            self._last_level = min(level, FULL)

    @property
    @override
    def is_on(self) -> bool | None:
        """The ``onoff`` point; without one, whether the level is above zero."""
        if Role.ONOFF in self.device.roles:
            return self.role_flag(Role.ONOFF)
        level = self.role_number(Role.LEVEL)
        return None if level is None else level > 0

    @property
    @override
    def brightness(self) -> int | None:
        """The level as 0-255."""
        level = self.role_number(Role.LEVEL)
        if level is None or self._attr_color_mode is ColorMode.ONOFF:
            return None
        return round(min(max(level, 0.0), FULL) * 255 / FULL)

    @property
    @override
    def rgb_color(self) -> tuple[int, int, int] | None:
        """The ``rgb`` point split into red, green and blue."""
        value = self.device.readings.integer(self.role_value(Role.RGB))
        if value is None:
            return None
        return value & 0xFF, (value >> 8) & 0xFF, (value >> 16) & 0xFF

    @property
    @override
    def color_temp_kelvin(self) -> int | None:
        """The ``colortemp`` point in kelvin."""
        value = self.role_number(Role.COLOR_TEMP)
        return None if value is None else round(value)

    @override
    async def async_turn_on(self, **kwargs: Any) -> None:
        """Switch on; write the brightness, colour or colour temperature asked for.

        Without a brightness, a dark dimmable light gets its last level above zero
        back (or full); a light without ``onoff`` is switched on by that alone.
        """
        if (
            rgb := kwargs.get(ATTR_RGB_COLOR)
        ) is not None and Role.RGB in self.device.roles:
            red, green, blue = rgb
            await self.async_write_role(Role.RGB, red + green * 256 + blue * 65536)
        if (
            kelvin := kwargs.get(ATTR_COLOR_TEMP_KELVIN)
        ) is not None and Role.COLOR_TEMP in self.device.roles:
            await self.async_write_role(Role.COLOR_TEMP, kelvin)
        level: float | None = None
        if self._dimmable:
            if (brightness := kwargs.get(ATTR_BRIGHTNESS)) is not None:
                level = _to_percent(brightness)
            elif not (self.role_number(Role.LEVEL) or 0.0) > 0:
                level = self._last_level
        if level is not None:
            await self.async_write_role(self._target, level)
        if Role.ONOFF in self.device.roles:
            await self.async_write_role(Role.ONOFF, True)
        if level is not None and self._follows_target:
            # The PLC brings the level to its target: shown as it gets there.
            roles = self.device.roles
            self.coordinator.motion.async_follow(
                self.device.key,
                {
                    roles[role]
                    for role in (Role.LEVEL, Role.TARGET_LEVEL, Role.ONOFF)
                    if role in roles
                },
                partial(arrived, self.device),
            )

    @override
    async def async_turn_off(self, **kwargs: Any) -> None:
        """Switch off: ``onoff`` false, or the level 0."""
        if Role.ONOFF in self.device.roles:
            await self.async_write_role(Role.ONOFF, False)
        else:
            await self.async_write_role(self._target, 0)


async_setup_entry = entity_platform(Platform.LIGHT, devices=PlcLight)
