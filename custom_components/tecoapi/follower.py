"""The platform follower: each platform's entities, now and as points and devices come and go.

A platform's ``async_setup_entry`` (``entity_platform``) creates the entities of
the selection's point descriptions and typed devices on it, then follows the
coordinator: after a new program or new options a point or typed device may be
new on the platform (its entity is created) or its description may have changed
(its entity is made again under the same registry entry).
"""

from collections.abc import Callable, Coroutine, Iterable, Mapping
from typing import Any

from homeassistant.const import Platform
from homeassistant.core import HomeAssistant, callback
from homeassistant.helpers import entity_registry as er
from homeassistant.helpers.entity import Entity
from homeassistant.helpers.entity_platform import (
    AddConfigEntryEntitiesCallback,
    async_get_current_platform,
)

from .const import DOMAIN
from .coordinator import PlcConfigEntry, PlcCoordinator
from .data import PlcData
from .mapping import DEVICE_PLATFORMS, PointDescription
from .pyplc.core.devices import TypedDevice

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
