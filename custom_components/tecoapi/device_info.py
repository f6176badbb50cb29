"""The devices entities sit on: their names, their DeviceInfo, and moving entities to them.

The source's device (a PLC, a controller, a gateway) is one device; with
grouping on (``selection``), each group of its points (a program's top-level
struct, a function block, a station, a building's controller) is a device
under it, and a typed device found or composed may be a device of its own. Two
devices of the same type get distinct names: the second one's name carries its
identity (a serial number), or the way in where it is one device's second
entry (``Heating PLCComS``: a Tecomat through PLCComS alone beside TecoApi),
never an address. A group device's name is chosen once and kept on
the coordinator (``group_device_names``): its entities' names leave out what
it says.
"""

from collections.abc import Mapping
from typing import Final

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
from homeassistant.util import slugify

from .compat import AREA_IN_ENTITY_ID, entry_device, via_device
from .const import DOMAIN
from .coordinator import PlcCoordinator
from .mapping import DEVICE_PLATFORMS
from .names import folded
from .pyplc import SourceInfo
from .pyplc.core.devices import CoverClass, DeviceKind, TypedDevice
from .selection import Group, Place


def plc_device_name(coordinator: PlcCoordinator) -> str:
    """Return the PLC device's name: ``Tecomat CP-2080``, unique among the PLCs."""
    info = coordinator.data.info
    return unique_device_name(coordinator, info.identity, info.name)


def unique_device_name(coordinator: PlcCoordinator, ident: str, name: str) -> str:
    """Return the name of the PLC's device ``ident``: ``name``, unless another PLC has it.

    A device that exists keeps its name (one named with its PLC's address
    before names said the way in says the way in now). A new one whose name a
    device of another entry already has (a second CP-2080, both programs with a
    ``Heating`` struct; the same PLC through PLCComS alone) is named with
    :func:`name_suffix` too, so that neither the names nor the entity IDs made
    from them collide.
    """
    hass = coordinator.hass
    entry_id = coordinator.config_entry.entry_id
    if (device := entry_device(hass, entry_id, identifier=(DOMAIN, ident))) is not None:
        return _without_address(coordinator.data.info, device.name, name) or name
    return _untaken(coordinator, name)


def name_suffix(info: SourceInfo) -> str:
    """Return what a name adds to be told from another entry's: ``PLCComS``, ``SD 2081``.

    The way in, where the source names one (the same PLC may have an entry of
    another way), else the device's identity (a serial number).
    """
    return info.way_in or info.identity


def _without_address(info: SourceInfo, known: str | None, name: str) -> str | None:
    """Return a device's known name, the way in for the address it was named with.

    Before names said the way in, the second entry of a PLC through PLCComS
    named its devices with the PLC's address (its identity,
    ``Heating EPSNET 192.168.1.5:61682``): such a name says the way in now.
    """
    if info.way_in and known == f"{name} {info.identity}":
        return f"{name} {info.way_in}"
    return known


def _untaken(coordinator: PlcCoordinator, name: str) -> str:
    """Return ``name``, with :func:`name_suffix` if another entry has a device of it."""
    hass = coordinator.hass
    registry = dr.async_get(hass)
    taken = any(
        other.name == name
        for entry in hass.config_entries.async_entries(DOMAIN)
        if entry.entry_id != coordinator.config_entry.entry_id
        for other in dr.async_entries_for_config_entry(registry, entry.entry_id)
    )
    return f"{name} {name_suffix(coordinator.data.info)}" if taken else name


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
        suffixed = f"{name} {name_suffix(data.info)}"
        known = _without_address(
            data.info, existing.name if existing is not None else None, name
        )
        info["name"] = (
            known if known in (name, suffixed) else _untaken(coordinator, name)
        )
    else:
        # Named by its kind and its room: the Ložnice light.
        placeholders = {"room": area or place.name}
        key = f"{_kind_key(device)}_in"
        if _of_another_plc(coordinator, device.key):
            key, placeholders["serial_number"] = f"{key}_of_plc", name_suffix(data.info)
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
    # Another entry's device (the same program) says what its name says.
    suffix = name_suffix(data.info)
    if str(info.get("translation_key", "")).endswith("_of_plc") or str(
        info.get("name", "")
    ).endswith(f" {suffix}"):
        what = f"{what} {suffix}"
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
