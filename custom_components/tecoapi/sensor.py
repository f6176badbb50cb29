"""Sensors: read-only points (numbers, texts, dates, durations), GTSAP1 displays, status."""

from collections.abc import Callable
from dataclasses import dataclass
from datetime import date, datetime, timedelta
from typing import Any, Final, override

from homeassistant.components.sensor import (
    SensorDeviceClass,
    SensorEntity,
    SensorEntityDescription,
    SensorStateClass,
)
from homeassistant.components.sensor.const import UNITS_PRECISION
from homeassistant.const import (
    LIGHT_LUX,
    PERCENTAGE,
    EntityCategory,
    Platform,
    UnitOfTemperature,
    UnitOfTime,
)

from .compat import PARTS_PER_MILLION
from .const import (
    STATUS_CLOCK_OFFSET,
    STATUS_MODE,
    STATUS_PROGRAM_COMPILED,
    STATUS_PROGRAM_NAME,
)
from .coordinator import PlcCoordinator
from .data import PlcData
from .entity import PlcApplianceEntity, PlcEntity, PlcPointEntity
from .follower import entity_platform
from .mapping import SENSOR_DEVICE_CLASS_BY_KIND, PointDescription
from .pyplc import PlcMode, Record, ValueKind
from .pyplc.core.appliances import Display
from .pyplc.core.descriptor import Capability
from .pyplc.core.devices import Measurement, TypedDevice
from .pyplc.core.models import DataExchange

PARALLEL_UPDATES = 0


@dataclass(frozen=True, kw_only=True)
class PlcStatusSensorDescription(SensorEntityDescription):
    """A device status sensor (diagnostic): what of the device's info it shows."""

    value_fn: Callable[[PlcData], str | int | datetime | None]
    capability: Capability
    """What the source must tell for the sensor to exist."""
    entity_category: EntityCategory | None = EntityCategory.DIAGNOSTIC


STATUS_SENSORS: Final = (
    PlcStatusSensorDescription(
        key=STATUS_MODE,
        capability=Capability.MODE,
        translation_key="mode",
        device_class=SensorDeviceClass.ENUM,
        options=[mode.value.lower() for mode in PlcMode],
        value_fn=lambda data: (
            None if data.info.mode is None else data.info.mode.value.lower()
        ),
    ),
    PlcStatusSensorDescription(
        key=STATUS_PROGRAM_NAME,
        capability=Capability.PROGRAM,
        translation_key="program_name",
        value_fn=lambda data: data.info.program_name,
    ),
    PlcStatusSensorDescription(
        key=STATUS_PROGRAM_COMPILED,
        capability=Capability.PROGRAM,
        translation_key="program_compiled",
        device_class=SensorDeviceClass.TIMESTAMP,
        value_fn=lambda data: data.info.program_compiled,
    ),
    # The PLC's clock as an offset from Home Assistant's: a steady value that
    # changes when the clock is set or drifts, where a timestamp of the PLC's time
    # would change (and be recorded) on every GetInfo. A unit keeps it out of the
    # logbook; the state class gives long-term statistics of the drift.
    PlcStatusSensorDescription(
        key=STATUS_CLOCK_OFFSET,
        capability=Capability.CLOCK,
        translation_key="clock_offset",
        device_class=SensorDeviceClass.DURATION,
        state_class=SensorStateClass.MEASUREMENT,
        native_unit_of_measurement=UnitOfTime.SECONDS,
        suggested_display_precision=0,
        value_fn=lambda data: data.clock_offset,
    ),
)


class PlcStatusSensor(PlcEntity, SensorEntity):
    """A device status value from its info (diagnostic)."""

    entity_description: PlcStatusSensorDescription

    def __init__(
        self,
        coordinator: PlcCoordinator,
        description: PlcStatusSensorDescription,
    ) -> None:
        """Create the sensor for one status value."""
        super().__init__(coordinator, description.key)
        self.entity_description = description

    @property
    @override
    def native_value(self) -> str | int | datetime | None:
        """The status value from the info read last."""
        return self.entity_description.value_fn(self.coordinator.data)


class PlcPointSensor(PlcPointEntity, SensorEntity):
    """A read-only point: a number with its unit, a text, a date or a duration."""

    def __init__(
        self, coordinator: PlcCoordinator, description: PointDescription
    ) -> None:
        """Take unit, device class and state class from the description."""
        super().__init__(coordinator, description)
        if description.data_exchange:
            # A device's status: whether it exchanges data, its score an attribute.
            self._attr_device_class = SensorDeviceClass.ENUM
            self._attr_options = [state.value for state in DataExchange]
            self._attr_translation_key = "data_exchange"
        elif (units := description.units) is not None:
            self._attr_native_unit_of_measurement = units.unit or None
            self._attr_device_class = units.device_class
            self._attr_state_class = units.state_class
            self._attr_suggested_unit_of_measurement = units.shown_unit
            precision = units.shown_precision
            if precision is None and units.device_class not in UNITS_PRECISION:
                # Home Assistant shows a class it knows at its own precision
                # (a temperature with one decimal); the others at the point's.
                precision = description.precision
            self._attr_suggested_display_precision = precision
        else:
            self._attr_device_class = SENSOR_DEVICE_CLASS_BY_KIND.get(description.kind)
            self._attr_suggested_display_precision = description.precision
        self._duration = description.kind in (ValueKind.TIME, ValueKind.DURATION)

    @property
    @override
    def native_value(self) -> str | int | float | date | datetime | None:
        """The point's value as the PLC holds it (a duration in seconds).

        A record (a lift's state) shows its text; its parts are attributes. A
        device's status shows whether it exchanges data.
        """
        value = self.point_value
        if self.description.data_exchange:
            exchange = self.point.exchange(value)
            return None if exchange is None else exchange.value
        if isinstance(value, timedelta):
            return value.total_seconds()
        if isinstance(value, Record):
            return value.text
        return None if self._duration else value

    @property
    @override
    def extra_state_attributes(self) -> dict[str, Any] | None:
        """A record's parts (a lift's floor, doors, direction), with the point's own.

        A device's status has its score (the value the device gives) beside.
        """
        shown = super().extra_state_attributes
        value = self.point_value
        if self.description.data_exchange and isinstance(value, int):
            return {**(shown or {}), "score": value}
        if not isinstance(value, Record):
            return shown
        return {**dict(value.parts), **(shown or {})}


# What a display's measurement says it shows.
DISPLAY_CLASSES: Final[dict[Measurement, tuple[SensorDeviceClass, str]]] = {
    Measurement.TEMPERATURE: (SensorDeviceClass.TEMPERATURE, UnitOfTemperature.CELSIUS),
    Measurement.HUMIDITY: (SensorDeviceClass.HUMIDITY, PERCENTAGE),
    Measurement.CO2: (SensorDeviceClass.CO2, PARTS_PER_MILLION),
    Measurement.CO: (SensorDeviceClass.CO, PARTS_PER_MILLION),
    Measurement.ILLUMINANCE: (SensorDeviceClass.ILLUMINANCE, LIGHT_LUX),
}


class PlcDisplay(PlcApplianceEntity[Display], SensorEntity):
    """A GTSAP1 ``DISPLAY``: a measured value with the device class of its symbol."""

    _attr_state_class = SensorStateClass.MEASUREMENT

    def __init__(self, coordinator: PlcCoordinator, device: TypedDevice) -> None:
        """Device class and unit from the symbol; else the ``unit`` variable's text."""
        display = Display(device, coordinator.data.catalogue.points)
        super().__init__(coordinator, device, display)
        values = coordinator.data.values
        if display.measurement is not None:
            device_class, unit = DISPLAY_CLASSES[display.measurement]
            self._attr_device_class = device_class
            self._attr_native_unit_of_measurement = unit
        elif (unit_text := display.unit(values)) is not None:
            self._attr_native_unit_of_measurement = unit_text
        if (precision := display.precision(values)) is not None:
            self._attr_suggested_display_precision = precision

    @property
    @override
    def native_value(self) -> float | None:
        """The ``value`` point as a number.

        A display's value may be text (``"21,5"``): a decimal comma is read, and
        text that is not a number shows as unknown.
        """
        return self.per_update(self.appliance.state)


async_setup_entry = entity_platform(
    Platform.SENSOR,
    fixed=lambda coordinator: (
        PlcStatusSensor(coordinator, description)
        for description in STATUS_SENSORS
        if description.capability in coordinator.descriptor.status_entities
    ),
    points=PlcPointSensor,
    devices=PlcDisplay,
)
