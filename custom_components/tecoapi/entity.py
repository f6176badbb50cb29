"""Base entities: devices, unique IDs, availability, and entities that follow the PLC.

Every entity hears of every update of the coordinator and writes its state only
when a key it shows changed or the coordinator's success did: a poll that
changes one value of a thousand costs one state write.

Devices: the PLC is one device; with grouping on (``selection``), each top-level
struct, program instance or array is a device under it. Two PLCs of the same type
get distinct names: the second one's name carries its serial number.
"""

from collections.abc import Callable, Coroutine, Iterable, Mapping
from datetime import date, datetime, timedelta
from typing import Any, Final, cast, override

from homeassistant.const import EntityCategory, Platform
from homeassistant.core import HomeAssistant, callback
from homeassistant.helpers import (
    area_registry as ar,
    device_registry as dr,
    entity_registry as er,
)
from homeassistant.helpers.device_registry import (
    CONNECTION_NETWORK_MAC,
    DeviceInfo,
    format_mac,
)
from homeassistant.helpers.entity import Entity
from homeassistant.helpers.entity_platform import (
    AddConfigEntryEntitiesCallback,
    async_get_current_platform,
)
from homeassistant.helpers.update_coordinator import CoordinatorEntity
from homeassistant.util import slugify

from .compat import AREA_IN_ENTITY_ID, entry_device, via_device
from .const import DOMAIN
from .coordinator import PlcConfigEntry, PlcCoordinator
from .data import PlcData
from .mapping import DEVICE_PLATFORMS, PointDescription, entity_name
from .names import folded
from .pyplc import Point, PointAttributes, Quality, Record
from .pyplc.core.devices import (
    CoverClass,
    DeviceKind,
    Role,
    TypedDevice,
)
from .selection import Group, Place

type PointValue = bool | int | float | str | date | datetime | timedelta | Record | None
"""A point's value as the library types it (None: unknown)."""

CONFIGURATION_ROLES: Final = frozenset({Role.NAME, Role.UNIT, Role.PRECISION})
"""Roles read once, at discovery: a typed entity neither polls nor watches them."""


def plc_device_name(coordinator: PlcCoordinator) -> str:
    """Return the PLC device's name: ``Tecomat CP-2080``, unique among the PLCs."""
    info = coordinator.data.info
    return unique_device_name(coordinator, info.identity, info.name)


def unique_device_name(coordinator: PlcCoordinator, ident: str, name: str) -> str:
    """Return the name of the PLC's device ``ident``: ``name``, unless another PLC has it.

    A device that exists keeps its name. A new one whose name a device of another
    PLC already has (a second CP-2080, both programs with a ``Heating`` struct) is
    named with its PLC's serial number too, so that neither the names nor the
    entity IDs made from them collide.
    """
    hass = coordinator.hass
    entry_id = coordinator.config_entry.entry_id
    if (device := entry_device(hass, entry_id, identifier=(DOMAIN, ident))) is not None:
        return device.name or name
    return _untaken(coordinator, name)


def _untaken(coordinator: PlcCoordinator, name: str) -> str:
    """Return ``name``, with the PLC's serial number if another PLC has a device of it."""
    hass = coordinator.hass
    registry = dr.async_get(hass)
    taken = any(
        other.name == name
        for entry in hass.config_entries.async_entries(DOMAIN)
        if entry.entry_id != coordinator.config_entry.entry_id
        for other in dr.async_entries_for_config_entry(registry, entry.entry_id)
    )
    return f"{name} {coordinator.data.info.identity}" if taken else name


def plc_device_info(coordinator: PlcCoordinator) -> DeviceInfo:
    """Return the device of the PLC itself."""
    info = coordinator.data.info
    device = DeviceInfo(
        identifiers={(DOMAIN, info.identity)},
        manufacturer=info.manufacturer,
        model=info.model,
        name=coordinator.device_name,
        serial_number=info.serial_number,
        sw_version=info.firmware,
        configuration_url=coordinator.source.configuration_url,
    )
    if info.mac:
        device["connections"] = {(CONNECTION_NETWORK_MAC, format_mac(info.mac))}
    return device


def device_info_of(coordinator: PlcCoordinator, path: str) -> DeviceInfo:
    """Return the device an entity of ``path`` sits on: its group's or the PLC's."""
    group = coordinator.data.selection.group_of(path)
    if group is None:
        return plc_device_info(coordinator)
    return group_device_info(coordinator, group)


def group_device_info(coordinator: PlcCoordinator, group: Group) -> DeviceInfo:
    """Return the device of a group, under its parent's or the source's own."""
    data = coordinator.data
    identity = data.info.identity
    ident = f"{identity}_{group.key}"
    if (name := coordinator.group_device_names.get(group.key)) is None:
        name = unique_device_name(coordinator, ident, group.name)
        coordinator.group_device_names[group.key] = name
    device = DeviceInfo(
        identifiers={(DOMAIN, ident)},
        manufacturer=group.manufacturer or data.info.manufacturer,
        model=group.model or data.info.program_name,
        name=name,
        suggested_area=area_named(coordinator.hass, group.area),
    )
    if group.serial_number is not None:
        device["serial_number"] = group.serial_number
    above = f"{identity}_{group.parent}" if group.parent else identity
    device.update(
        via_device(
            coordinator.hass,
            coordinator.config_entry.entry_id,
            (DOMAIN, above),
        )
    )
    return device


def area_named(hass: HomeAssistant, name: str | None) -> str | None:
    """Return the area to suggest for a room: the one there is, however spelled.

    An area made before names had their accents (*Detsky pokoj*) is the room's
    area still; Home Assistant matches names by case and spaces only.
    """
    if name is None:
        return None
    wanted = folded(name).replace(" ", "")
    return next(
        (
            area.name
            for area in ar.async_get(hass).async_list_areas()
            if folded(area.name).replace(" ", "") == wanted
        ),
        name,
    )


KIND_NAMES: Final[Mapping[DeviceKind, str]] = {
    DeviceKind.LIGHT: "light",
    DeviceKind.COVER: "blind",
    DeviceKind.CLIMATE: "thermostat",
    DeviceKind.BUTTON: "button",
    DeviceKind.CONTACT: "contact",
    DeviceKind.SWITCH: "switch",
    DeviceKind.DISPLAY: "sensor",
}
"""The translation key naming a typed device by its kind (a gate: ``gate``)."""

ENGLISH_KIND_NAMES: Final[Mapping[str, str]] = {
    "light": "Light",
    "blind": "Blind",
    "gate": "Gate",
    "thermostat": "Thermostat",
    "button": "Button",
    "contact": "Contact",
    "switch": "Switch",
    "sensor": "Sensor",
}
"""What each kind's translation key says in English: entity IDs' words."""


def typed_device_info(coordinator: PlcCoordinator, device: TypedDevice) -> DeviceInfo:
    """Return the device of a typed device that is a device of its own, under the PLC.

    Its name says what it is, and where when that is what tells it apart:
    *Strop* in the area *Obývák*, but the *Ložnice light* and the *Dětský
    pokoj thermostat*, not a *Light* and a *Thermostat* among others. A device
    not in an area (the user took it out, or it was made before areas were
    suggested) says its room in its name, as every device does where IDs have
    no area. Its entity's ID says the room once (``typed_entity_id``).
    """
    data = coordinator.data
    place = data.selection.places[device.key]
    identity = data.info.identity
    entry_id = coordinator.config_entry.entry_id
    ident = f"{identity}_{device.key}"
    existing = entry_device(coordinator.hass, entry_id, identifier=(DOMAIN, ident))
    area = area_named(coordinator.hass, place.area)
    info = DeviceInfo(
        identifiers={(DOMAIN, ident)},
        manufacturer=data.info.manufacturer,
        suggested_area=area,
    )
    if place.rest:
        name = place.rest if _named_by_rest(place, existing) else place.name
        # It follows the program's (or the user's) name; another PLC's is kept apart.
        suffixed = f"{name} {identity}"
        known = existing.name if existing is not None else None
        info["name"] = (
            known if known in (name, suffixed) else _untaken(coordinator, name)
        )
    else:
        # Named by its kind and its room: the Ložnice light.
        placeholders = {"room": area or place.name}
        key = f"{_kind_key(device)}_in"
        if _of_another_plc(coordinator, device.key):
            key, placeholders["serial_number"] = f"{key}_of_plc", identity
        info["translation_key"] = key
        info["translation_placeholders"] = placeholders
    info.update(via_device(coordinator.hass, entry_id, (DOMAIN, identity)))
    return info


def _kind_key(device: TypedDevice) -> str:
    """Return the translation key of a typed device's kind (a gate: ``gate``)."""
    return "gate" if device.cover_class is CoverClass.GATE else KIND_NAMES[device.kind]


def _named_by_rest(place: Place, existing: dr.DeviceEntry | None) -> bool:
    """Whether a typed device is named without its room: the area says it.

    Where entity IDs start with the area, a device in its room's area whose
    name without the room tells it apart (*Strop* in *Obývák*).
    """
    in_area = place.area is not None and (
        existing is None or existing.area_id is not None
    )
    return AREA_IN_ENTITY_ID and in_area and place.distinct


def typed_entity_id(
    coordinator: PlcCoordinator, device: TypedDevice, info: DeviceInfo
) -> str | None:
    """Return the entity ID a new typed device's entity is to have (None: Home Assistant's).

    Where Home Assistant starts a new entity's ID with its device's area, a
    device in its area whose name says the room too (*Ložnice light* in
    *Ložnice*) would say it twice (``light.loznice_loznice_light``): its entity
    is given the ID of the area and what the device is (``light.loznice_light``),
    the words of the family in English as entity names' are. None for an entity
    registered before (its ID stays), or a device the user renamed or moved to
    another area (Home Assistant's own ID says what it says). ``info``
    is the device's: another PLC's device says its serial number in the ID too.
    """
    data = coordinator.data
    place = data.selection.places.get(device.key)
    if not AREA_IN_ENTITY_ID or place is None or place.area is None or place.distinct:
        return None
    hass = coordinator.hass
    identity = data.info.identity
    platform = DEVICE_PLATFORMS[device.kind]
    if er.async_get(hass).async_get_entity_id(
        platform, DOMAIN, f"{identity}_{device.key}"
    ):
        return None
    ident = (DOMAIN, f"{identity}_{device.key}")
    existing = entry_device(hass, coordinator.config_entry.entry_id, identifier=ident)
    room = area_named(hass, place.area)
    if existing is not None:
        # Renamed, or in another area than its room's: Home Assistant's own ID.
        area = ar.async_get(hass).async_get_area(existing.area_id or "")
        if existing.name_by_user or area is None or area.name != room:
            return None
    what = place.rest or ENGLISH_KIND_NAMES[_kind_key(device)]
    # Another PLC's device (the same program) says its serial number, as its name.
    if str(info.get("translation_key", "")).endswith("_of_plc") or str(
        info.get("name", "")
    ).endswith(f" {identity}"):
        what = f"{what} {identity}"
    return f"{platform}.{slugify(f'{room} {what}')}"


def _of_another_plc(coordinator: PlcCoordinator, key: str) -> bool:
    """Whether another PLC has a device of this key (it runs the same program)."""
    hass = coordinator.hass
    registry = dr.async_get(hass)
    suffix = f"_{key}"
    return any(
        ident.endswith(suffix)
        for entry in hass.config_entries.async_entries(DOMAIN)
        if entry.entry_id != coordinator.config_entry.entry_id
        for device in dr.async_entries_for_config_entry(registry, entry.entry_id)
        for _, ident in device.identifiers
    )


def device_info_for(coordinator: PlcCoordinator, key: str) -> DeviceInfo:
    """Return the device the entity of a point or typed device sits on.

    A point's entity sits on its group's device (or the PLC's); a typed device
    on its own, or with everything on the PLC's device on the PLC's.
    """
    data = coordinator.data
    if (device := data.devices.get(key)) is None:
        return device_info_of(coordinator, data.points[key].path)
    if key in data.selection.places:
        return typed_device_info(coordinator, device)
    return device_info_of(coordinator, device.base)


@callback
def async_place_entities(coordinator: PlcCoordinator) -> None:
    """Move the entry's entities to the devices the selection puts them on.

    After new options (a device per group, or everything on the PLC's device)
    an entity keeps its registry entry, entity ID and state; only its device
    changes. Entities of composed devices stay on their own devices.
    """
    hass = coordinator.hass
    entry_id = coordinator.config_entry.entry_id
    entities, devices = er.async_get(hass), dr.async_get(hass)
    data = coordinator.data
    prefix = f"{data.info.identity}_"
    for registry_entry in er.async_entries_for_config_entry(entities, entry_id):
        key = registry_entry.unique_id.removeprefix(prefix)
        typed = data.devices.get(key)
        if key not in data.points and (typed is None or typed.composed):
            continue
        device = devices.async_get_or_create(
            config_entry_id=entry_id,
            config_subentry_id=registry_entry.config_subentry_id,
            **device_info_for(coordinator, key),
        )
        if registry_entry.device_id != device.id:
            entities.async_update_entity(registry_entry.entity_id, device_id=device.id)


class PlcEntity(CoordinatorEntity[PlcCoordinator]):
    """An entity of a Tecomat PLC that writes its state only when it has to."""

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

        The quality and its reason are there while the value is uncertain.
        """
        shown: dict[str, Any] = dict(self.point.details)
        quality = self.coordinator.data.quality.get(self.key)
        if quality is not None and quality.quality is Quality.UNCERTAIN:
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


class PlcDeviceEntity(PlcEntity):
    """The entity of a typed device (a light, a blind, a thermostat, ...)."""

    def __init__(self, coordinator: PlcCoordinator, device: TypedDevice) -> None:
        """Name the entity after the device; it shows the points of its roles."""
        shown = {
            key for role, key in device.roles.items() if role not in CONFIGURATION_ROLES
        }
        super().__init__(
            coordinator, device.key, watched=frozenset(shown), path=device.base
        )
        self.device = device
        self._attr_device_info = info = device_info_for(coordinator, device.key)
        if (entity_id := typed_entity_id(coordinator, device, info)) is not None:
            self.entity_id = entity_id
        self._attr_name = self._name_in(coordinator.data)

    def _name_in(self, data: PlcData) -> str | None:
        """Return the entity's name: none on a device of its own (its main feature).

        With everything on the PLC's device, the typed device's name.
        """
        return None if self.key in data.selection.places else self.device.name

    @override
    def _update_from_data(self, data: PlcData) -> None:
        """Follow a move to a device of its own or to the PLC's (new options)."""
        self._attr_name = self._name_in(data)

    def role_value(self, role: Role) -> Any:
        """Return the latest value of the point playing ``role`` (None: none, unknown)."""
        return self.value_of(self.device.roles.get(role))

    def role_number(self, role: Role) -> float | None:
        """Return the ``role`` point's value as a number (None: none, unknown)."""
        return self.device.readings.number(self.role_value(role))

    def role_flag(self, role: Role) -> bool | None:
        """Return the ``role`` point's value as a flag (None: none, unknown).

        An inverted point's flag is its opposite (as its own entity shows it).
        """
        return self.coordinator.data.flag(
            self.device.roles.get(role), self.device.readings
        )

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

    async def async_write_role(self, role: Role, value: bool | float) -> None:
        """Write a flag or a number to the point playing ``role``, in the point's kind.

        It goes through the coordinator's write path: validated, sent, shown.
        """
        key = self.device.roles[role]
        point = self.coordinator.point(key)
        await self.coordinator.async_write(
            key, self.device.readings.written(point, value)
        )


type PointEntityFactory = Callable[[PlcCoordinator, PointDescription], Entity]
type DeviceEntityFactory = Callable[[PlcCoordinator, TypedDevice], Entity]
type FixedEntities = Callable[[PlcCoordinator], Iterable[Entity]]
type PlatformSetup = Callable[
    [HomeAssistant, PlcConfigEntry, AddConfigEntryEntitiesCallback],
    Coroutine[Any, Any, None],
]


def entity_platform(
    platform: Platform,
    *,
    points: PointEntityFactory | None = None,
    devices: DeviceEntityFactory | None = None,
    fixed: FixedEntities | None = None,
) -> PlatformSetup:
    """Return the ``async_setup_entry`` of a platform.

    ``fixed`` makes the entities every entry has on the platform (the PLC's status);
    ``points`` and ``devices`` make the entities of the selection's point
    descriptions and typed devices on this platform. Those are created now and
    followed later: after a new program a point or typed device may be new on the
    platform (its entity is created), or its description may have changed (its
    entity is made again under the same registry entry). Entities that left the
    platform are removed through the entity registry by the coordinator.
    """

    async def async_setup_entry(
        hass: HomeAssistant,
        entry: PlcConfigEntry,
        async_add_entities: AddConfigEntryEntitiesCallback,
    ) -> None:
        """Create this platform's entities, now and after a new program."""
        if fixed is not None:
            async_add_entities(fixed(entry.runtime_data))
        follower = _Follower(entry, platform, async_add_entities, points, devices)
        follower.follow()
        entry.async_on_unload(entry.runtime_data.async_add_listener(follower.follow))

    return async_setup_entry


class _Follower:
    """Keeps one platform's entities in step with the coordinator's selection."""

    def __init__(
        self,
        entry: PlcConfigEntry,
        platform: Platform,
        async_add_entities: AddConfigEntryEntitiesCallback,
        points: PointEntityFactory | None,
        devices: DeviceEntityFactory | None,
    ) -> None:
        self._entry = entry
        self._coordinator = entry.runtime_data
        self._platform = platform
        self._entity_platform = async_get_current_platform()
        self._add_entities = async_add_entities
        self._points = points
        self._devices = devices
        self._selection: object = None
        self._shown: dict[str, object] = {}

    def _wanted(self, data: PlcData) -> dict[str, PointDescription | TypedDevice]:
        """Return what this platform shows of the data: descriptions and devices."""
        wanted: dict[str, PointDescription | TypedDevice] = {}
        if self._points is not None:
            wanted.update(
                (key, description)
                for key, description in data.descriptions.items()
                if description.platform is self._platform
            )
        if self._devices is not None:
            wanted.update(
                (key, device)
                for key, device in data.devices.items()
                if DEVICE_PLATFORMS[device.kind] is self._platform
            )
        return wanted

    @callback
    def follow(self) -> None:
        """Create or re-create entities when the selection changed."""
        data = self._coordinator.data
        if data.selection is self._selection:
            return
        self._selection = data.selection
        wanted = self._wanted(data)
        shown = self._shown
        changed = [item for key, item in wanted.items() if shown.get(key) != item]
        self._shown = dict(wanted)
        registry = er.async_get(self._coordinator.hass)
        identity = data.info.identity
        existing: dict[str, PointDescription | TypedDevice] = {}
        new: list[PointDescription | TypedDevice] = []
        for item in changed:
            entity_id = registry.async_get_entity_id(
                self._platform, DOMAIN, f"{identity}_{item.key}"
            )
            if entity_id is not None and entity_id in self._entity_platform.entities:
                existing[entity_id] = item
            else:
                new.append(item)
        self._add(new)
        if existing:
            self._entry.async_create_task(
                self._coordinator.hass,
                self._async_recreate(existing),
                f"{self._coordinator.name} re-created {self._platform} entities",
            )

    async def _async_recreate(
        self, items: Mapping[str, PointDescription | TypedDevice]
    ) -> None:
        """Remove the entities of changed items, then create them anew.

        The registry entry stays: the new entity takes it over (a changed
        description, or a composed device whose points came back).
        """
        for entity_id in items:
            await self._entity_platform.async_remove_entity(entity_id)
        self._add(list(items.values()))

    def _add(self, items: list[PointDescription | TypedDevice]) -> None:
        """Create the entities of descriptions and devices (composed: per subentry)."""
        coordinator = self._coordinator
        plain: list[Entity] = []
        composed: dict[str, list[Entity]] = {}
        for item in items:
            if isinstance(item, PointDescription):
                assert self._points is not None
                plain.append(self._points(coordinator, item))
            elif item.composed:
                assert self._devices is not None
                subentry_id = item.key.partition(":")[2]
                composed.setdefault(subentry_id, []).append(
                    self._devices(coordinator, item)
                )
            else:
                assert self._devices is not None
                plain.append(self._devices(coordinator, item))
        if plain:
            self._add_entities(plain)
        for subentry_id, entities in composed.items():
            self._add_entities(entities, config_subentry_id=subentry_id)


@callback
def async_create_declared_devices(coordinator: PlcCoordinator) -> None:
    """Create the devices the source declares, each after the one it sits under.

    A device with no entity of its own (a controller above its devices) exists
    too, so that the devices below it can name it as theirs.
    """
    selection = coordinator.data.selection
    declared = coordinator.data.catalogue.devices
    registry = dr.async_get(coordinator.hass)
    entry_id = coordinator.config_entry.entry_id
    done: set[str] = set()

    def create(group: Group) -> None:
        if group.key in done:
            return
        done.add(group.key)
        if group.parent is not None and (parent := selection.groups.get(group.parent)):
            create(parent)
        registry.async_get_or_create(
            config_entry_id=entry_id, **group_device_info(coordinator, group)
        )

    for key, group in selection.groups.items():
        if key in declared:
            create(group)
