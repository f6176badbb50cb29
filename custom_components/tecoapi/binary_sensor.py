"""Binary sensors: read-only boolean points, and whether the PLC is running."""

from typing import override

from homeassistant.components.binary_sensor import (
    BinarySensorEntity,
    BinarySensorEntityDescription,
)
from homeassistant.const import EntityCategory, Platform
from homeassistant.core import HomeAssistant
from homeassistant.helpers.entity_platform import AddConfigEntryEntitiesCallback

from .compat import BinarySensorDeviceClass
from .const import STATUS_RUNNING_PROBLEM
from .coordinator import TecoApiConfigEntry, TecoApiCoordinator
from .entity import TecoApiEntity, TecoApiPointEntity, async_add_point_entities
from .pytecoapi import PlcMode

PARALLEL_UPDATES = 0

RUNNING_PROBLEM = BinarySensorEntityDescription(
    key=STATUS_RUNNING_PROBLEM,
    translation_key="running_problem",
    device_class=BinarySensorDeviceClass.PROBLEM,
    entity_category=EntityCategory.DIAGNOSTIC,
)


async def async_setup_entry(
    hass: HomeAssistant,
    entry: TecoApiConfigEntry,
    async_add_entities: AddConfigEntryEntitiesCallback,
) -> None:
    """Create the running-problem sensor and one per read-only boolean point."""
    async_add_entities([TecoApiRunningProblem(entry.runtime_data)])
    async_add_point_entities(
        entry, Platform.BINARY_SENSOR, TecoApiPointBinarySensor, async_add_entities
    )


class TecoApiRunningProblem(TecoApiEntity, BinarySensorEntity):
    """On when the PLC's user program is not running (mode HALT or ERR)."""

    entity_description = RUNNING_PROBLEM

    def __init__(self, coordinator: TecoApiCoordinator) -> None:
        """Create the sensor for the PLC's mode."""
        super().__init__(coordinator, RUNNING_PROBLEM.key)

    @property
    @override
    def is_on(self) -> bool:
        """Whether the PLC is in HALT or ERR."""
        return self.coordinator.data.info.mode is not PlcMode.RUN


class TecoApiPointBinarySensor(TecoApiPointEntity, BinarySensorEntity):
    """A read-only boolean point."""

    @property
    @override
    def is_on(self) -> bool | None:
        """The point's value."""
        return self.point_is_on
