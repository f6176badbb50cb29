"""Events: GTSAP1 ``BUTTON`` families and composed buttons, from their counters.

The PLC counts short clicks (``CLICKCNT``) and long presses (``PRESSCNT``); each
increment is one event. Increments missed between two readings are fired
together; a counter's first reading (start-up, a new program) fires nothing,
and neither does a reset: the library's ``Button`` (``pyplc.core.appliances``)
keeps the counters' last readings and says what events a new one means.
"""

from typing import override

from homeassistant.components.event import EventDeviceClass, EventEntity
from homeassistant.const import Platform

from .coordinator import PlcCoordinator
from .data import PlcData
from .entity import PlcApplianceEntity
from .follower import entity_platform
from .pyplc.core.appliances import Button
from .pyplc.core.devices import TypedDevice

PARALLEL_UPDATES = 0


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


async_setup_entry = entity_platform(Platform.EVENT, devices=PlcButtonEvent)
