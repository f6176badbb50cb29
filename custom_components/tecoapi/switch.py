"""Switches: writable boolean points, and typed switches (sockets among them)."""

from typing import Any, override

from homeassistant.components.switch import SwitchEntity
from homeassistant.const import Platform

from .compat import SwitchDeviceClass
from .coordinator import PlcCoordinator
from .entity import PlcApplianceEntity, PlcPointEntity
from .follower import entity_platform
from .pyplc.core.appliances import Switch
from .pyplc.core.devices import TypedDevice

PARALLEL_UPDATES = 1


class PlcSwitch(PlcPointEntity, SwitchEntity):
    """A writable boolean point."""

    @property
    @override
    def is_on(self) -> bool | None:
        """The point's value."""
        return self.point_is_on

    @override
    async def async_turn_on(self, **kwargs: Any) -> None:
        """Write true to the PLC (false to an inverted point)."""
        await self.coordinator.async_write(self.key, self.point.flag(True))

    @override
    async def async_turn_off(self, **kwargs: Any) -> None:
        """Write false to the PLC (true to an inverted point)."""
        await self.coordinator.async_write(self.key, self.point.flag(False))


class PlcDeviceSwitch(PlcApplianceEntity[Switch], SwitchEntity):
    """A typed switch: a socket or a relay a recogniser found, or a composed one."""

    def __init__(self, coordinator: PlcCoordinator, device: TypedDevice) -> None:
        """Show a socket as an outlet."""
        switch = Switch(device, coordinator.data.catalogue.points)
        super().__init__(coordinator, device, switch)
        if switch.outlet:
            self._attr_device_class = SwitchDeviceClass.OUTLET

    @property
    @override
    def is_on(self) -> bool | None:
        """The ``onoff`` point, read as a flag."""
        return self.per_update(self.appliance.state)

    @override
    async def async_turn_on(self, **kwargs: Any) -> None:
        """Switch it on."""
        await self.async_send(self.appliance.turn_on)

    @override
    async def async_turn_off(self, **kwargs: Any) -> None:
        """Switch it off."""
        await self.async_send(self.appliance.turn_off)


async_setup_entry = entity_platform(
    Platform.SWITCH, points=PlcSwitch, devices=PlcDeviceSwitch
)
