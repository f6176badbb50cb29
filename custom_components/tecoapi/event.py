"""Events: buttons' clicks from their counters, and flags whose rises are events.

The PLC counts short clicks (``CLICKCNT``) and long presses (``PRESSCNT``); each
increment is one event. Increments missed between two readings are fired
together; a counter's first reading (start-up, a new program) fires nothing,
and neither does a reset: the library's ``Button`` (``pyplc.core.appliances``)
keeps the counters' last readings and says what events a new one means.

A point with an ``event`` (an intercom's calls) fires one each time its flag
rises from off to on: every rise the source reports, those it pushes between
two polls too; its first reading (start-up) fires nothing.
"""

from typing import Final, override

from homeassistant.components.event import EventDeviceClass, EventEntity
from homeassistant.const import Platform

from .coordinator import PlcCoordinator
from .data import PlcData
from .entity import PlcApplianceEntity, PlcPointEntity
from .follower import entity_platform
from .mapping import PointDescription
from .pyplc.core.appliances import Button
from .pyplc.core.devices import TypedDevice
from .pyplc.core.models import PointEvent

PARALLEL_UPDATES = 0

EVENT_CLASSES: Final = {PointEvent.RING: EventDeviceClass.DOORBELL}
"""The device class of each kind of a point's events."""


class PlcButtonEvent(PlcApplianceEntity[Button], EventEntity):
    """A button: one event per click or long press the PLC counted."""

    _attr_device_class = EventDeviceClass.BUTTON
    _attr_translation_key = "button"

    def __init__(self, coordinator: PlcCoordinator, device: TypedDevice) -> None:
        """Start from the counters as they are: no event for what came before."""
        button = Button(device, coordinator.data.catalogue.points)
        super().__init__(coordinator, device, button)
        button.update(coordinator.data.values)
        self._attr_event_types = [event.value for event in button.events]

    @override
    def _update_from_data(self, data: PlcData) -> None:
        """Fire an event per increment of each counter since the last reading.

        Each event is a state of its own (the last one is written by the caller),
        so an automation hears every click.
        """
        super()._update_from_data(data)
        self.appliance.rebind(data.catalogue.points)
        for index, event in enumerate(self.appliance.update(data.values)):
            if index:
                self.async_write_ha_state()
            self._trigger_event(event.value)


class PlcPointEvent(PlcPointEntity, EventEntity):
    """A flag whose every rise is an event: an intercom's calls (a ring each)."""

    def __init__(
        self, coordinator: PlcCoordinator, description: PointDescription
    ) -> None:
        """Start from the flag as it is: no event for a call already on."""
        super().__init__(coordinator, description)
        event = self.point.event or PointEvent.RING
        self._event = event.value
        self._attr_event_types = [event.value]
        self._attr_device_class = EVENT_CLASSES.get(event)
        self._attr_translation_key = event.value
        self._flag = self.point_is_on

    @override
    def _update_from_data(self, data: PlcData) -> None:
        """Fire an event when the flag rose from off to on since the last data."""
        super()._update_from_data(data)
        flag = self.point_is_on
        if flag and self._flag is False:
            self._trigger_event(self._event)
        self._flag = flag


async_setup_entry = entity_platform(
    Platform.EVENT, points=PlcPointEvent, devices=PlcButtonEvent
)
