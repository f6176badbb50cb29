"""Base entities: unique IDs, availability, and state written only when it changed.

Every entity hears of every update of the coordinator and writes its state only
when a key it shows changed or the coordinator's success did: a poll that
changes one value of a thousand costs one state write. The devices entities sit
on are ``device_info``'s; the platform follower, which creates and re-creates
each platform's entities, is ``follower``'s.
"""

from collections.abc import Callable, Mapping
from datetime import date, datetime, timedelta
from typing import Any, Final, cast, override

from homeassistant.const import EntityCategory
from homeassistant.core import callback
from homeassistant.helpers.update_coordinator import CoordinatorEntity

from .coordinator import PlcCoordinator
from .data import PlcData
from .device_info import device_info_for, device_info_of, typed_entity_id
from .mapping import PointDescription, entity_name
from .pyplc import Point, PointAttributes, Quality, Record
from .pyplc.core.appliances import Appliance, Batch
from .pyplc.core.devices import Role, TypedDevice

type PointValue = bool | int | float | str | date | datetime | timedelta | Record | None
"""A point's value as the library types it (None: unknown)."""

SHOWN_QUALITIES: Final = frozenset({Quality.UNCERTAIN, Quality.UNKNOWN})
"""Qualities an available entity tells in its attributes."""
CONFIGURATION_ROLES: Final = frozenset({Role.NAME, Role.UNIT, Role.PRECISION})
"""Roles read once, at discovery: a typed entity neither polls nor watches them."""


class PlcEntity(CoordinatorEntity[PlcCoordinator]):
    """An entity of an entry's device that writes its state only when it has to."""

    _attr_has_entity_name = True

    def __init__(
        self,
        coordinator: PlcCoordinator,
        key: str,
        *,
        watched: frozenset[str] | None = None,
        path: str = "",
    ) -> None:
        """Attach the entity to its device; ``key`` names it, ``watched`` what it shows.

        ``path`` places it on a group's device (none: the PLC's device).
        """
        self._watched = frozenset({key}) if watched is None else watched
        super().__init__(coordinator, context=key if watched is None else self._watched)
        self.key = key
        self._attr_unique_id = f"{coordinator.data.info.identity}_{key}"
        self._attr_device_info = device_info_of(coordinator, path)
        self._shown_data: PlcData | None = None
        self._shown_selection: object = None
        self._shown_success = True

    @override
    async def async_added_to_hass(self) -> None:
        """Remember what the first state write shows."""
        await super().async_added_to_hass()
        self._shown_data = data = self.coordinator.data
        self._shown_selection = data.selection
        self._shown_success = self.coordinator.last_update_success

    @callback
    def async_entity_id_changed(self, old_entity_id: str) -> None:
        """Keep the entity added when the user renames its entity ID.

        Nothing it keeps depends on the entity ID, so Home Assistant 2026.11 and
        later change it in place; an entity that extends ``async_added_to_hass``
        without this method is removed and added again instead (a way Home
        Assistant drops in 2027.11). Older releases never call it.
        """
        if (changed := getattr(super(), "async_entity_id_changed", None)) is not None:
            changed(old_entity_id)

    @callback
    @override
    def _handle_coordinator_update(self) -> None:
        """Write the state only if what this entity shows or its availability changed.

        It runs for every entity on every update, so it is kept cheap: whatever
        changes what a point entity shows or its availability -- a value, its
        attributes, a missing point, the PLC's mode -- puts its key in
        ``data.changed``; a failed or recovered poll flips ``last_update_success``;
        a new program brings a new selection (a typed device may have gone).
        """
        coordinator = self.coordinator
        data = coordinator.data
        success = coordinator.last_update_success
        if (
            success is self._shown_success
            and data.selection is self._shown_selection
            and (data is self._shown_data or self._watched.isdisjoint(data.changed))
        ):
            return
        self._shown_data, self._shown_success = data, success
        self._shown_selection = data.selection
        self._update_from_data(data)
        self.async_write_ha_state()

    def _update_from_data(self, data: PlcData) -> None:
        """Take what changed in the data before the state is written."""

    def value_of(self, key: str | None) -> Any:
        """Return the latest value of a point (None: unknown, or no such point)."""
        return None if key is None else self.coordinator.data.values.get(key)


class PlcPointEntity(PlcEntity):
    """An entity showing one point (variable) of the PLC, built from its description."""

    def __init__(
        self, coordinator: PlcCoordinator, description: PointDescription
    ) -> None:
        """Name the entity from ``attr.title`` (or the path)."""
        point = coordinator.data.points[description.key]
        super().__init__(coordinator, description.key, path=point.path)
        self.description = description
        self.point: Point = point
        self._named_by = self.point_attributes
        self._group = coordinator.data.selection.group_of(point.path)
        self._attr_name = self._name()
        self._attr_entity_registry_enabled_default = description.enabled_default
        if description.diagnostic:
            self._attr_entity_category = EntityCategory.DIAGNOSTIC

    def _name(self) -> str | None:
        """Return the name below the device's (none: the device's main feature).

        A title does not say again what its device's name or its area say.
        """
        group = self._group
        if group is None:
            said: tuple[str | None, ...] = (self.coordinator.device_name,)
        else:
            device = self.coordinator.group_device_names.get(group.key, group.name)
            said = (device, group.alias, group.area)
        name = entity_name(
            self.point, self._named_by, in_group=group is not None, said=said
        )
        return name or None

    @property
    def point_attributes(self) -> PointAttributes | None:
        """The point's latest attributes (None for a plain variable)."""
        return self.coordinator.data.point_attributes(self.key)

    @property
    def point_value(self) -> PointValue:
        """The point's latest value."""
        return cast("PointValue", self.coordinator.data.values.get(self.key))

    @property
    def point_is_on(self) -> bool | None:
        """The point's value as on/off (None: unknown); an inverted point's opposite."""
        value = self.point_value
        return None if value is None else self.point.flag(bool(value))

    @property
    @override
    def available(self) -> bool:
        """Whether the point can be shown.

        Not when polling fails, its device serves no live values (a PLC not
        running, a station offline), or the point is not selected, reads badly
        (missing, gone from the program) or is disabled (``enable=false``).
        """
        data = self.coordinator.data
        attributes = self.point_attributes
        return (
            super().available
            and self.key in data.points
            and data.point_available(self.key)
            and (attributes is None or attributes.enabled)
        )

    @property
    @override
    def extra_state_attributes(self) -> dict[str, Any] | None:
        """What the source tells of the point for the user to read, and its quality.

        The quality and its reason are there while the value is uncertain or
        not known (a bad one makes the entity unavailable).
        """
        shown: dict[str, Any] = dict(self.point.details)
        quality = self.coordinator.data.quality.get(self.key)
        if quality is not None and quality.quality in SHOWN_QUALITIES:
            shown |= {
                "quality": quality.quality.value,
                "quality_reason": quality.reason,
            }
        return shown or None

    @override
    def _update_from_data(self, data: PlcData) -> None:
        """Follow a changed path spelling or title, or another device (new options)."""
        point = data.points.get(self.key, self.point)
        attributes = data.point_attributes(self.key)
        group = data.selection.group_of(point.path)
        if (
            point is not self.point
            or attributes is not self._named_by
            or group != self._group
        ):
            self.point, self._named_by, self._group = point, attributes, group
            self._attr_name = self._name()


class PlcValueEntity[T](PlcPointEntity):
    """A writable point Home Assistant shows and sets as one ``T`` (date, text, …).

    ``_value_type`` is the type the point's value has when it can be shown; a
    subclass whose point holds another type (a time of day as text) reads it in its
    own ``native_value`` instead.
    """

    _value_type: type[T]

    @property
    def native_value(self) -> T | None:
        """The point's value, when it has the type shown (else unknown)."""
        value = self.point_value
        return value if isinstance(value, self._value_type) else None

    async def async_set_value(self, value: T) -> None:
        """Write the value to the PLC."""
        await self.coordinator.async_write(self.key, value)


class PlcApplianceEntity[A: Appliance](PlcEntity):
    """The entity of a typed device: a light, a blind, a switch, a button, ...

    It is named after the device and shows the points of its roles; the
    library's appliance made of the device reads its state from the data's
    values and turns each command into one batch of writes; a device the PLC
    then moves is followed until it arrives (see ``motion``).
    """

    def __init__(
        self, coordinator: PlcCoordinator, device: TypedDevice, appliance: A
    ) -> None:
        """Name the entity after the device; hold the appliance made of it."""
        shown = {
            key for role, key in device.roles.items() if role not in CONFIGURATION_ROLES
        }
        super().__init__(
            coordinator, device.key, watched=frozenset(shown), path=device.base
        )
        self.device = device
        self.appliance = appliance
        self._attr_device_info = info = device_info_for(coordinator, device.key)
        if (entity_id := typed_entity_id(coordinator, device, info)) is not None:
            self.entity_id = entity_id
        self._attr_name = self._name_in(coordinator.data)
        self._read_from: PlcData | None = None
        self._read: dict[Callable[[Mapping[str, Any]], Any], Any] = {}

    def _name_in(self, data: PlcData) -> str | None:
        """Return the entity's name: none on a device of its own (its main feature).

        With everything on the PLC's device, the typed device's name.
        """
        return None if self.key in data.selection.places else self.device.name

    @override
    def _update_from_data(self, data: PlcData) -> None:
        """Follow a move to a device of its own or to the PLC's (new options)."""
        self._attr_name = self._name_in(data)

    @property
    @override
    def available(self) -> bool:
        """Whether the device can be shown: it is in the program and its points read."""
        data = self.coordinator.data
        return (
            super().available
            and self.key in data.devices
            and all(data.point_available(key) for key in self._watched)
        )

    @property
    def values(self) -> Mapping[str, Any]:
        """The latest values, the appliance bound to the catalogue's points."""
        data = self.coordinator.data
        self.appliance.rebind(data.catalogue.points)
        return data.values

    def per_update[S](self, read: Callable[[Mapping[str, Any]], S]) -> S:
        """Return what ``read`` (the appliance's state) makes of the latest values.

        Computed once per update of the coordinator, however many of the
        entity's properties ask for it while its state is written.
        """
        data = self.coordinator.data
        if data is not self._read_from:
            self.appliance.rebind(data.catalogue.points)
            self._read_from, self._read = data, {}
        if read not in self._read:
            self._read[read] = read(data.values)
        return cast("S", self._read[read])

    async def async_send(self, command: Callable[[], Batch]) -> None:
        """Send what a command of the appliance writes as one batch.

        Every value is checked before anything is sent (a translated error names
        the point refused); a device sent on its way is then followed there.
        """
        self.appliance.rebind(self.coordinator.data.catalogue.points)
        batch = await self.coordinator.writer.async_send(command)
        if self.appliance.moves(batch):
            self.coordinator.motion.async_follow(
                self.device.key, self.appliance.motion, self._arrived
            )

    def _arrived(self, data: PlcData) -> bool:
        """Whether the appliance is where its target says, in the data shown."""
        self.appliance.rebind(data.catalogue.points)
        return self.appliance.arrived(data.values)
