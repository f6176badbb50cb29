"""Covers: GTSAP1 ``OPENER`` families (blinds, gates), blinds in our struct convention.

The position is 0 % closed to 100 % open. A cover moves by writing its target
(or its position, when it has no separate target); it stops when its current
position is written as the target. It is opening or closing while its target
differs from its position: at once after a move is asked for, before the PLC
has set it moving. While it moves there, its points are read every second until
it arrives (see ``motion``). The library's ``Cover`` (``pyplc.core.appliances``)
holds all this: the entity shows its state and sends each move as one batch.
"""

from typing import Any, override

from homeassistant.components.cover import ATTR_POSITION, CoverEntity
from homeassistant.const import Platform

from .compat import CoverDeviceClass, CoverEntityFeature
from .coordinator import PlcCoordinator
from .entity import PlcApplianceEntity
from .follower import entity_platform
from .pyplc.core.appliances import Cover
from .pyplc.core.devices import TypedDevice

PARALLEL_UPDATES = 1


class PlcCover(PlcApplianceEntity[Cover], CoverEntity):
    """A blind, shutter or gate with a position."""

    def __init__(self, coordinator: PlcCoordinator, device: TypedDevice) -> None:
        """Fix the class (gate or shutter); stop only with a target apart from the position."""
        cover = Cover(device, coordinator.data.catalogue.points)
        super().__init__(coordinator, device, cover)
        self._attr_device_class = (
            CoverDeviceClass.GATE if cover.gate else CoverDeviceClass.SHUTTER
        )
        features = (
            CoverEntityFeature.OPEN
            | CoverEntityFeature.CLOSE
            | CoverEntityFeature.SET_POSITION
        )
        if cover.can_stop:
            features |= CoverEntityFeature.STOP
        self._attr_supported_features = features

    @property
    @override
    def current_cover_position(self) -> int | None:
        """The position, 0 closed to 100 open."""
        return self.per_update(self.appliance.state).position

    @property
    @override
    def is_closed(self) -> bool | None:
        """Closed at position 0."""
        return self.per_update(self.appliance.state).is_closed

    @property
    @override
    def is_opening(self) -> bool:
        """On its way to a target above the position."""
        return self.per_update(self.appliance.state).opening

    @property
    @override
    def is_closing(self) -> bool:
        """On its way to a target below the position."""
        return self.per_update(self.appliance.state).closing

    @override
    async def async_open_cover(self, **kwargs: Any) -> None:
        """Move to 100 %."""
        await self.async_send(self.appliance.open)

    @override
    async def async_close_cover(self, **kwargs: Any) -> None:
        """Move to 0 %."""
        await self.async_send(self.appliance.close)

    @override
    async def async_set_cover_position(self, **kwargs: Any) -> None:
        """Move to a position."""
        position: float = kwargs[ATTR_POSITION]
        await self.async_send(lambda: self.appliance.move_to(position))

    @override
    async def async_stop_cover(self, **kwargs: Any) -> None:
        """Stop where it is: its current position becomes the target."""
        await self.async_send(lambda: self.appliance.stop(self.values))


async_setup_entry = entity_platform(Platform.COVER, devices=PlcCover)
