"""Sensors: read-only numeric, text, date and time points, and the PLC status."""

from collections.abc import Callable
from dataclasses import dataclass
from datetime import date, datetime
from typing import Final, override

from homeassistant.components.sensor import (
    SensorDeviceClass,
    SensorEntity,
    SensorEntityDescription,
    SensorStateClass,
)
from homeassistant.const import EntityCategory, Platform, UnitOfTime
from homeassistant.core import HomeAssistant
from homeassistant.helpers.entity_platform import AddConfigEntryEntitiesCallback

from .const import (
    STATUS_CLOCK_OFFSET,
    STATUS_MODE,
    STATUS_PROGRAM_COMPILED,
    STATUS_PROGRAM_NAME,
)
from .coordinator import TecoApiConfigEntry, TecoApiCoordinator
from .data import TecoApiData
from .entity import TecoApiEntity, TecoApiPointEntity, async_add_point_entities
from .mapping import SENSOR_DEVICE_CLASS_BY_KIND, PointDescription
from .pytecoapi import PlcMode

PARALLEL_UPDATES = 0


@dataclass(frozen=True, kw_only=True)
class TecoApiStatusSensorDescription(SensorEntityDescription):
    """A PLC status sensor (diagnostic): what of GetInfo it shows."""

    value_fn: Callable[[TecoApiData], str | int | datetime | None]
    entity_category: EntityCategory | None = EntityCategory.DIAGNOSTIC


STATUS_SENSORS: Final = (
    TecoApiStatusSensorDescription(
        key=STATUS_MODE,
        translation_key="mode",
        device_class=SensorDeviceClass.ENUM,
        options=[mode.value.lower() for mode in PlcMode],
        value_fn=lambda data: data.info.mode.value.lower(),
    ),
    TecoApiStatusSensorDescription(
        key=STATUS_PROGRAM_NAME,
        translation_key="program_name",
        value_fn=lambda data: data.info.program_name,
    ),
    TecoApiStatusSensorDescription(
        key=STATUS_PROGRAM_COMPILED,
        translation_key="program_compiled",
        device_class=SensorDeviceClass.TIMESTAMP,
        value_fn=lambda data: data.info.program_compiled,
    ),
    # The PLC's clock as an offset from Home Assistant's: a steady value that
    # changes when the clock is set or drifts, where a timestamp of the PLC's time
    # would change (and be recorded) on every GetInfo. A unit keeps it out of the
    # logbook; the state class gives long-term statistics of the drift.
    TecoApiStatusSensorDescription(
        key=STATUS_CLOCK_OFFSET,
        translation_key="clock_offset",
        device_class=SensorDeviceClass.DURATION,
        state_class=SensorStateClass.MEASUREMENT,
        native_unit_of_measurement=UnitOfTime.SECONDS,
        suggested_display_precision=0,
        value_fn=lambda data: data.clock_offset,
    ),
)


async def async_setup_entry(
    hass: HomeAssistant,
    entry: TecoApiConfigEntry,
    async_add_entities: AddConfigEntryEntitiesCallback,
) -> None:
    """Create the PLC status sensors and a sensor per read-only point."""
    coordinator = entry.runtime_data
    async_add_entities(
        TecoApiStatusSensor(coordinator, description) for description in STATUS_SENSORS
    )
    async_add_point_entities(
        entry, Platform.SENSOR, TecoApiPointSensor, async_add_entities
    )


class TecoApiStatusSensor(TecoApiEntity, SensorEntity):
    """A PLC status value from GetInfo (diagnostic)."""

    entity_description: TecoApiStatusSensorDescription

    def __init__(
        self,
        coordinator: TecoApiCoordinator,
        description: TecoApiStatusSensorDescription,
    ) -> None:
        """Create the sensor for one status value."""
        super().__init__(coordinator, description.key)
        self.entity_description = description

    @property
    @override
    def native_value(self) -> str | int | datetime | None:
        """The status value from the latest GetInfo."""
        return self.entity_description.value_fn(self.coordinator.data)


class TecoApiPointSensor(TecoApiPointEntity, SensorEntity):
    """A read-only point: a number with its unit, a text, a date or a time."""

    def __init__(
        self, coordinator: TecoApiCoordinator, description: PointDescription
    ) -> None:
        """Take unit, device class and state class from the description."""
        super().__init__(coordinator, description)
        if (units := description.units) is not None:
            self._attr_native_unit_of_measurement = units.unit
            self._attr_device_class = units.device_class
            self._attr_state_class = units.state_class
        else:
            self._attr_device_class = SENSOR_DEVICE_CLASS_BY_KIND.get(description.kind)

    @property
    @override
    def native_value(self) -> str | int | float | date | datetime | None:
        """The point's value as the PLC holds it."""
        return self.point_value
