"""Lights: GTSAP1 ``LIGHT`` families, dimmers in our struct convention, composed lights.

A light is on when its ``onoff`` point says so, or (without one) when its level is
above zero. Brightness is the level (0-100 %) shown as Home Assistant's 0-255;
setting it writes the target level. Switched on without a brightness, a dimmable
light that is dark (its level 0) gets its last level above zero back, or full
when none is known, whether it has ``onoff`` or not: ``onoff`` alone would show
it on at 0 %. A light whose level is written to a target of its own (GTSAP1
``tgtlevel``) has its level read every second until it gets there (see
``motion``). RGB is written as R + G·256 + B·65536, the colour temperature in
kelvin. The library's ``Light`` (``pyplc.core.appliances``) holds all this: the
entity shows its state and sends each command as one batch of writes (colour,
level and ``onoff`` together, checked whole before anything is sent).
"""

from typing import Any, Final, override

from homeassistant.components.light import LightEntity
from homeassistant.const import Platform

from .compat import ATTR_BRIGHTNESS, ATTR_COLOR_TEMP_KELVIN, ATTR_RGB_COLOR, ColorMode
from .coordinator import PlcCoordinator
from .data import PlcData
from .entity import PlcApplianceEntity
from .follower import entity_platform
from .pyplc.core.appliances import Light
from .pyplc.core.devices import LightMode, TypedDevice

PARALLEL_UPDATES = 1

COLOR_MODES: Final[dict[LightMode, ColorMode]] = {
    LightMode.ONOFF: ColorMode.ONOFF,
    LightMode.BRIGHTNESS: ColorMode.BRIGHTNESS,
    LightMode.RGB: ColorMode.RGB,
    LightMode.COLOR_TEMP: ColorMode.COLOR_TEMP,
}


class PlcLight(PlcApplianceEntity[Light], LightEntity):
    """A light: on/off, dimmable, RGB or tunable white, by its light mode."""

    def __init__(self, coordinator: PlcCoordinator, device: TypedDevice) -> None:
        """Fix the colour mode, and the kelvin range of a tunable light."""
        data = coordinator.data
        light = Light(device, data.catalogue.points)
        super().__init__(coordinator, device, light)
        mode = COLOR_MODES[light.mode]
        self._attr_color_mode = mode
        self._attr_supported_color_modes = {mode}
        if mode is ColorMode.COLOR_TEMP:
            low, high = light.kelvin_range(data.catalogue.points, data.values)
            self._attr_min_color_temp_kelvin = low
            self._attr_max_color_temp_kelvin = high
        self._update_from_data(data)

    @override
    def _update_from_data(self, data: PlcData) -> None:
        """Let the light remember its last level above zero, to switch on to."""
        super()._update_from_data(data)
        self.appliance.rebind(data.catalogue.points)
        self.appliance.update(data.values)

    @property
    @override
    def is_on(self) -> bool | None:
        """The ``onoff`` point; without one, whether the level is above zero."""
        return self.per_update(self.appliance.state).is_on

    @property
    @override
    def brightness(self) -> int | None:
        """The level as 0-255."""
        return self.per_update(self.appliance.state).brightness

    @property
    @override
    def rgb_color(self) -> tuple[int, int, int] | None:
        """The ``rgb`` point split into red, green and blue."""
        return self.per_update(self.appliance.state).rgb

    @property
    @override
    def color_temp_kelvin(self) -> int | None:
        """The ``colortemp`` point in kelvin."""
        return self.per_update(self.appliance.state).kelvin

    @override
    async def async_turn_on(self, **kwargs: Any) -> None:
        """Switch on, with the brightness, colour or colour temperature asked for: one batch."""
        await self.async_send(
            lambda: self.appliance.turn_on(
                self.values,
                brightness=kwargs.get(ATTR_BRIGHTNESS),
                rgb=kwargs.get(ATTR_RGB_COLOR),
                kelvin=kwargs.get(ATTR_COLOR_TEMP_KELVIN),
            )
        )

    @override
    async def async_turn_off(self, **kwargs: Any) -> None:
        """Switch off: ``onoff`` false, or the level 0."""
        await self.async_send(self.appliance.turn_off)


async_setup_entry = entity_platform(Platform.LIGHT, devices=PlcLight)
