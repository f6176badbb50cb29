"""Events: GTSAP1 ``BUTTON`` families and composed buttons, from their counters.

The PLC counts short clicks (``CLICKCNT``) and long presses (``PRESSCNT``); each
increment is one event. Increments missed between two readings are fired
together; a counter's first reading (start-up, a new program) fires nothing,
and neither does a reset (see ``pyplc.core.devices.counter_events``).
"""

from typing import Final, override

from homeassistant.components.event import EventDeviceClass, EventEntity
from homeassistant.const import Platform

from .coordinator import PlcCoordinator
from .data import PlcData
from .entity import PlcDeviceEntity
from .follower import entity_platform
from .pyplc.core.devices import Role, TypedDevice, counter_events

PARALLEL_UPDATES = 0

EVENT_TYPES: Final[dict[Role, str]] = {
    Role.CLICK_COUNT: "click",
    Role.PRESS_COUNT: "long_press",
}


class PlcButtonEvent(PlcDeviceEntity, EventEntity):
    """A button: one event per click or long press the PLC counted."""

    _attr_device_class = EventDeviceClass.BUTTON
    _attr_translation_key = "button"

    def __init__(self, coordinator: PlcCoordinator, device: TypedDevice) -> None:
        """Start from the counters as they are: no event for what came before."""
        super().__init__(coordinator, device)
        self._counters = {
            role: device.readings.integer(self.role_value(role))
            for role in EVENT_TYPES
            if role in device.roles
        }
        self._attr_event_types = [EVENT_TYPES[role] for role in self._counters]

    @override
    def _update_from_data(self, data: PlcData) -> None:
        """Fire an event per increment of each counter since the last reading.

        Each event is a state of its own (the last one is written by the caller),
        so an automation hears every click.
        """
        super()._update_from_data(data)
        events: list[str] = []
        for role, previous in self._counters.items():
            current = self.device.readings.integer(
                data.values.get(self.device.roles[role])
            )
            events += [EVENT_TYPES[role]] * counter_events(previous, current)
            self._counters[role] = current
        for index, event_type in enumerate(events):
            if index:
                self.async_write_ha_state()
            self._trigger_event(event_type)


async_setup_entry = entity_platform(Platform.EVENT, devices=PlcButtonEvent)
