"""Numbers: writable integer, real and duration points."""

from datetime import timedelta
from typing import override

from homeassistant.components.number import NumberDeviceClass, NumberEntity, NumberMode
from homeassistant.const import Platform

from .coordinator import PlcCoordinator
from .entity import PlcPointEntity
from .follower import entity_platform
from .mapping import (
    PointDescription,
    number_device_class,
    number_mode,
    number_range,
    number_step,
)
from .pyplc import ValueKind

PARALLEL_UPDATES = 1


class PlcNumber(PlcPointEntity, NumberEntity):
    """A writable number; its range follows ``attr.minValue``/``maxValue``."""

    def __init__(
        self, coordinator: PlcCoordinator, description: PointDescription
    ) -> None:
        """Take unit and device class from the description."""
        super().__init__(coordinator, description)
        units = description.units
        self._attr_native_unit_of_measurement = (units.unit or None) if units else None
        self._attr_device_class = number_device_class(units)
        self._temperature = self._attr_device_class is NumberDeviceClass.TEMPERATURE

    @property
    @override
    def native_value(self) -> float | None:
        """The point's value (a duration in seconds)."""
        value = self.point_value
        if isinstance(value, timedelta):
            return value.total_seconds()
        return value if isinstance(value, int | float) else None

    @property
    @override
    def native_min_value(self) -> float:
        """``attr.minValue``, or the kind's minimum when there is no range."""
        return number_range(self.point, self.point_attributes)[0]

    @property
    @override
    def native_max_value(self) -> float:
        """``attr.maxValue``, or the kind's maximum when there is no range."""
        return number_range(self.point, self.point_attributes)[1]

    @property
    @override
    def native_step(self) -> float:
        """1 for integers, 0.5 for setpoints, 0.1 or finer for other reals."""
        return number_step(
            self.point,
            *number_range(self.point, self.point_attributes),
            temperature=self._temperature,
        )

    @property
    @override
    def mode(self) -> NumberMode:
        """A slider for narrow ranges, a box for wide ones."""
        minimum, maximum = number_range(self.point, self.point_attributes)
        return number_mode(minimum, maximum, self.native_step)

    @override
    async def async_set_native_value(self, value: float) -> None:
        """Write the value to the PLC (integers as integers, durations as such)."""
        if self.point.kind is ValueKind.DURATION:
            await self.coordinator.async_write(self.key, timedelta(seconds=value))
        elif self.point.kind is ValueKind.INTEGER and float(value).is_integer():
            await self.coordinator.async_write(self.key, int(value))
        else:
            await self.coordinator.async_write(self.key, value)


async_setup_entry = entity_platform(Platform.NUMBER, points=PlcNumber)
