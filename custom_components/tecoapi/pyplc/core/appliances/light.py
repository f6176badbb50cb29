"""Lights: on/off, dimmable, RGB or tunable white, by their light mode."""

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, Final

from ..devices import LightMode, Role, TypedDevice, kelvin_range
from ..models import Point
from .base import FULL, Appliance, Batch

BRIGHTNESS_SCALE: Final = 255
"""The top of the 0-255 brightness scale home automation shows a level in."""


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
        """Its colour temperature range in kelvin (see :func:`~..devices.kelvin_range`)."""
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
