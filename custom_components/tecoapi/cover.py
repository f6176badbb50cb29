"""Covers: GTSAP1 ``OPENER`` families (blinds, gates), blinds in our struct convention.

The position is 0 % closed to 100 % open. A cover moves by writing its target
(or its position, when it has no separate target); it stops when its current
position is written as the target. It is opening or closing while ``moving``
says so, towards the target.
"""

from typing import Any, override

from homeassistant.components.cover import ATTR_POSITION, CoverEntity
from homeassistant.const import Platform

from .compat import CoverDeviceClass, CoverEntityFeature
from .coordinator import TecoApiCoordinator
from .entity import TecoApiDeviceEntity, entity_platform
from .pyplc.core.devices import CoverClass, Role, TypedDevice

PARALLEL_UPDATES = 1


class TecoApiCover(TecoApiDeviceEntity, CoverEntity):
    """A blind, shutter or gate with a position."""

    def __init__(self, coordinator: TecoApiCoordinator, device: TypedDevice) -> None:
        """Fix the class (gate or shutter); stop only with a target apart from the position."""
        super().__init__(coordinator, device)
        self._attr_device_class = (
            CoverDeviceClass.GATE
            if device.cover_class is CoverClass.GATE
            else CoverDeviceClass.SHUTTER
        )
        roles = device.roles
        self._target = Role.TARGET if Role.TARGET in roles else Role.POSITION
        features = (
            CoverEntityFeature.OPEN
            | CoverEntityFeature.CLOSE
            | CoverEntityFeature.SET_POSITION
        )
        if roles.get(Role.TARGET, roles[Role.POSITION]) != roles[Role.POSITION]:
            features |= CoverEntityFeature.STOP
        self._attr_supported_features = features

    @property
    @override
    def current_cover_position(self) -> int | None:
        """The position, 0 closed to 100 open."""
        value = self.role_number(Role.POSITION)
        return None if value is None else round(min(max(value, 0.0), 100.0))

    @property
    @override
    def is_closed(self) -> bool | None:
        """Closed at position 0."""
        position = self.current_cover_position
        return None if position is None else position == 0

    def _moving_towards(self) -> float | None:
        """Return the target while ``moving`` says it moves; None when it is still."""
        if not self.role_flag(Role.MOVING):
            return None
        return self.role_number(Role.TARGET)

    @property
    @override
    def is_opening(self) -> bool:
        """Moving, towards a target above the position."""
        target, position = self._moving_towards(), self.current_cover_position
        return target is not None and position is not None and target > position

    @property
    @override
    def is_closing(self) -> bool:
        """Moving, towards a target below the position."""
        target, position = self._moving_towards(), self.current_cover_position
        return target is not None and position is not None and target < position

    @override
    async def async_open_cover(self, **kwargs: Any) -> None:
        """Move to 100 %."""
        await self.async_write_role(self._target, 100)

    @override
    async def async_close_cover(self, **kwargs: Any) -> None:
        """Move to 0 %."""
        await self.async_write_role(self._target, 0)

    @override
    async def async_set_cover_position(self, **kwargs: Any) -> None:
        """Move to a position."""
        await self.async_write_role(self._target, kwargs[ATTR_POSITION])

    @override
    async def async_stop_cover(self, **kwargs: Any) -> None:
        """Stop where it is: its current position becomes the target."""
        if (position := self.current_cover_position) is not None:
            await self.async_write_role(Role.TARGET, position)


async_setup_entry = entity_platform(Platform.COVER, devices=TecoApiCover)
