"""Binary sensors: read-only boolean points, GTSAP1 contacts, whether the PLC runs."""

from typing import override

from homeassistant.components.binary_sensor import (
    BinarySensorEntity,
    BinarySensorEntityDescription,
)
from homeassistant.const import EntityCategory, Platform

from .compat import BinarySensorDeviceClass
from .const import STATUS_RUNNING_PROBLEM
from .coordinator import PlcCoordinator
from .entity import PlcApplianceEntity, PlcEntity, PlcPointEntity
from .follower import entity_platform
from .mapping import PointDescription, binary_class_of
from .pyplc import PlcMode
from .pyplc.core.appliances import Contact
from .pyplc.core.descriptor import Capability
from .pyplc.core.devices import TypedDevice

PARALLEL_UPDATES = 0

RUNNING_PROBLEM = BinarySensorEntityDescription(
    key=STATUS_RUNNING_PROBLEM,
    translation_key="running_problem",
    device_class=BinarySensorDeviceClass.PROBLEM,
    entity_category=EntityCategory.DIAGNOSTIC,
)


class PlcRunningProblem(PlcEntity, BinarySensorEntity):
    """On while the device's program is stopped or in fault (a Tecomat's HALT, ERR)."""

    entity_description = RUNNING_PROBLEM

    def __init__(self, coordinator: PlcCoordinator) -> None:
        """Create the sensor for the PLC's mode."""
        super().__init__(coordinator, RUNNING_PROBLEM.key)

    @property
    @override
    def is_on(self) -> bool:
        """Whether the program is stopped or in fault."""
        return self.coordinator.data.info.mode is not PlcMode.RUNNING


class PlcPointBinarySensor(PlcPointEntity, BinarySensorEntity):
    """A read-only boolean point; its title may say what it watches (door, smoke...)."""

    def __init__(
        self, coordinator: PlcCoordinator, description: PointDescription
    ) -> None:
        """Take the device class the title gave (see ``mapping.binary_class``)."""
        super().__init__(coordinator, description)
        self._attr_device_class = description.binary_class

    @property
    @override
    def is_on(self) -> bool | None:
        """The point's value."""
        return self.point_is_on


class PlcContact(PlcApplianceEntity[Contact], BinarySensorEntity):
    """A GTSAP1 ``CONTACT``: a door, window or motion contact."""

    def __init__(self, coordinator: PlcCoordinator, device: TypedDevice) -> None:
        """Its name may say what it watches, as a binary sensor's title does."""
        super().__init__(
            coordinator, device, Contact(device, coordinator.data.catalogue.points)
        )
        self._attr_device_class = binary_class_of(device.name, device.base)

    @property
    @override
    def is_on(self) -> bool | None:
        """The ``state`` point, read as a flag."""
        return self.per_update(self.appliance.state)


async_setup_entry = entity_platform(
    Platform.BINARY_SENSOR,
    fixed=lambda coordinator: (
        [PlcRunningProblem(coordinator)]
        if Capability.MODE in coordinator.descriptor.status_entities
        else []
    ),
    points=PlcPointBinarySensor,
    devices=PlcContact,
)
