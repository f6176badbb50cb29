"""Covers: GTSAP1 ``OPENER`` families (blinds, gates), blinds in our struct convention.

The position is 0 % closed to 100 % open. A cover moves by writing its target
(or its position, when it has no separate target); it stops when its current
position is written as the target. It is opening or closing while its target
differs from its position: at once after a move is asked for, before the PLC
has set it moving. While it moves there, its points are read every second until
it arrives (see ``motion``).
"""

from functools import partial
from typing import Any, override

from homeassistant.components.cover import ATTR_POSITION, CoverEntity
from homeassistant.const import Platform

from .compat import CoverDeviceClass, CoverEntityFeature
from .coordinator import PlcCoordinator
from .data import PlcData
from .entity import PlcDeviceEntity
from .follower import entity_platform
from .pyplc.core.devices import (
    CoverClass,
    Role,
    TypedDevice,
)

PARALLEL_UPDATES = 1


def _percent(value: float) -> int:
    """Return a position or target as the whole percent shown (0-100)."""
    return round(min(max(value, 0.0), 100.0))


def arrived(device: TypedDevice, data: PlcData) -> bool:
    """Whether a cover is where its target says, and ``moving`` (if any) says still.

    Unknown values count as there: nothing is left to follow.
    """
    roles = device.roles
    number = device.readings.number
    position = number(data.values.get(roles[Role.POSITION]))
    target = number(data.values.get(roles[Role.TARGET]))
    if position is None or target is None:
        return True
    moving = data.flag(roles.get(Role.MOVING), device.readings)
    return _percent(position) == _percent(target) and moving is not True


class PlcCover(PlcDeviceEntity, CoverEntity):
    """A blind, shutter or gate with a position."""

    def __init__(self, coordinator: PlcCoordinator, device: TypedDevice) -> None:
        """Fix the class (gate or shutter); stop only with a target apart from the position."""
        super().__init__(coordinator, device)
        self._attr_device_class = (
            CoverDeviceClass.GATE
            if device.cover_class is CoverClass.GATE
            else CoverDeviceClass.SHUTTER
        )
        roles = device.roles
        self._target = Role.TARGET if Role.TARGET in roles else Role.POSITION
        # Moved by a target of its own: it can stop, and it is on its way while
        # the target differs from the position.
        self._has_target = (
            roles.get(Role.TARGET, roles[Role.POSITION]) != (roles[Role.POSITION])
        )
        features = (
            CoverEntityFeature.OPEN
            | CoverEntityFeature.CLOSE
            | CoverEntityFeature.SET_POSITION
        )
        if self._has_target:
            features |= CoverEntityFeature.STOP
        self._attr_supported_features = features

    @property
    @override
    def current_cover_position(self) -> int | None:
        """The position, 0 closed to 100 open."""
        value = self.role_number(Role.POSITION)
        return None if value is None else _percent(value)

    @property
    @override
    def is_closed(self) -> bool | None:
        """Closed at position 0."""
        position = self.current_cover_position
        return None if position is None else position == 0

    def _heading(self) -> int | None:
        """Return the target it is on its way to (None: it is where its target says)."""
        if not self._has_target:
            return None
        target, position = self.role_number(Role.TARGET), self.current_cover_position
        if target is None or position is None or _percent(target) == position:
            return None
        return _percent(target)

    @property
    @override
    def is_opening(self) -> bool:
        """On its way to a target above the position."""
        target = self._heading()
        return target is not None and target > (self.current_cover_position or 0)

    @property
    @override
    def is_closing(self) -> bool:
        """On its way to a target below the position."""
        target = self._heading()
        return target is not None and target < (self.current_cover_position or 0)

    @override
    async def async_open_cover(self, **kwargs: Any) -> None:
        """Move to 100 %."""
        await self._async_move(100)

    @override
    async def async_close_cover(self, **kwargs: Any) -> None:
        """Move to 0 %."""
        await self._async_move(0)

    @override
    async def async_set_cover_position(self, **kwargs: Any) -> None:
        """Move to a position."""
        await self._async_move(kwargs[ATTR_POSITION])

    @override
    async def async_stop_cover(self, **kwargs: Any) -> None:
        """Stop where it is: its current position becomes the target."""
        if (position := self.current_cover_position) is not None:
            await self._async_move(position)

    async def _async_move(self, position: float) -> None:
        """Write where to go; follow it there when it moves by a target."""
        await self.async_write_role(self._target, position)
        if self._has_target:
            roles = self.device.roles
            self.coordinator.motion.async_follow(
                self.device.key,
                {
                    roles[role]
                    for role in (Role.POSITION, Role.TARGET, Role.MOVING)
                    if role in roles
                },
                partial(arrived, self.device),
            )


async_setup_entry = entity_platform(Platform.COVER, devices=PlcCover)
