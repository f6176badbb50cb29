"""What an entry asks for, and its changes applied to the running entry in place.

The options (polling, which points become entities, devices, push), the
composed devices, the user's point map and what the user changed of the points
discovered (overrides) decide what the coordinator polls and how it selects
from a catalogue. :class:`OptionsApplier` holds them and applies a change
without a reload: a new selection from the catalogue known, or a new source
that reads the device anew; the entities not concerned keep their values.
"""

from collections.abc import Mapping
from dataclasses import replace
from typing import TYPE_CHECKING

from homeassistant.config_entries import ConfigEntry
from homeassistant.core import HomeAssistant, callback

from .connection import create_source
from .const import LOGGER
from .issues import async_follow_compositions
from .options import PlcOptions
from .pyplc.core.descriptor import SourceOptions
from .pyplc.core.models import PointOverride
from .pyplc.core.pointmap import PointMap
from .pyplc.core.source import PlcSource
from .reconcile import async_follow_catalogue, async_remove_stale_entries
from .selection import Composition, compositions_of, selector

if TYPE_CHECKING:
    from .coordinator import PlcCoordinator
    from .data import PlcData


def create_entry_source(
    hass: HomeAssistant,
    entry: ConfigEntry,
    options: PlcOptions,
    point_map: PointMap | None,
    overrides: Mapping[str, PointOverride] | None = None,
) -> PlcSource:
    """Return the source an entry reaches its device through, as its options say.

    Made at setup, and again when the options swap it (push switched on, off
    or to another server; the user's points edited, or what the user changed
    of the points discovered: ``overrides``).
    """
    return create_source(
        hass,
        entry.data,
        SourceOptions(
            metadata_interval=options.attribute_interval,
            companion=options.push_server,
            point_map=point_map,
            identity=entry.unique_id,
            overrides=overrides or {},
        ),
        entry.entry_id,
    )


class OptionsApplier:
    """An entry's options, composed devices, point map and overrides; applied in place.

    ``select`` makes the coordinator's selection of a catalogue, as the options
    and the composed devices say.
    """

    def __init__(
        self,
        coordinator: "PlcCoordinator",
        entry: ConfigEntry,
        *,
        point_map: PointMap | None = None,
        overrides: Mapping[str, PointOverride] | None = None,
    ) -> None:
        """Hold what ``entry`` asks for now, for ``coordinator`` to poll by."""
        self._coordinator = coordinator
        self._entry = entry
        self.options = PlcOptions.from_entry(entry)
        self.compositions = compositions_of(entry.subentries)
        self.point_map = point_map
        """The user's points, for a source that takes a map."""
        self.overrides: Mapping[str, PointOverride] = dict(overrides or {})
        """What the user changed of the points discovered, by key."""
        self._recognisers = coordinator.descriptor.recognisers
        self.select = selector(self.options, self.compositions, self._recognisers)

    async def async_apply_options(
        self, options: PlcOptions, compositions: list[Composition]
    ) -> bool:
        """Apply new options and composed devices in place, without a reload.

        Only what changes changes: new polling intervals apply at once; push
        switched on, off or to another server swaps the source (the old one is
        closed); another choice of entities (filters, plain variables, devices)
        or composed devices selects anew from the catalogue known, and the
        platforms add and remove just the entities concerned. The other
        entities keep showing their values. Returns whether it selected anew
        (the caller then moves entities whose device changed).
        """
        coordinator = self._coordinator
        previous, self.options = self.options, options
        reselect = (
            not options.same_entities(previous) or compositions != self.compositions
        )
        if reselect:
            self.compositions = compositions
            self.select = selector(options, compositions, self._recognisers)
        if options.push_server != previous.push_server:
            await self._async_swap_source()
        else:
            coordinator.source.metadata_interval = options.attribute_interval
        if reselect:
            self._async_reselect()
            # The values of points new to the selection, at once.
            await coordinator.async_refresh()
        if options.scan_interval != previous.scan_interval:
            coordinator.update_interval = options.scan_interval
            # Poll now: the next poll is then scheduled at the new interval.
            await coordinator.async_request_refresh()
        return reselect

    async def async_replace_point_map(self, point_map: PointMap) -> None:
        """Take the user's new or edited points in place, without a reload.

        A new source reads the new map; the catalogue it discovers is selected
        from as a new program's is: points kept keep their entities (their keys
        are the map's IDs), new ones get entities, and those gone leave the
        registry; the title follows the map's project (a Mervis
        installation's). The other entities keep showing their values meanwhile.
        """
        self.point_map = point_map
        if await self._async_swap_points():
            LOGGER.info(
                "The points of %s changed: %d points now",
                self._entry.title,
                len(point_map.points),
            )

    async def async_replace_overrides(
        self, overrides: Mapping[str, PointOverride]
    ) -> None:
        """Take what the user changed of the points discovered, in place.

        A new source discovers the points again with the changes applied, and
        the catalogue is selected from as a new program's is: a point shown on
        another platform now (made writable, or shown only) has its entity
        there, under the same unique ID, and its old registry entry goes; one
        whose description changed (a unit) is made again under its registry
        entry. The other entities keep showing their values meanwhile.
        """
        self.overrides = dict(overrides)
        if await self._async_swap_points():
            LOGGER.info(
                "The points of %s changed: %d of them as the user asked",
                self._entry.title,
                len(overrides),
            )

    async def _async_swap_source(self) -> None:
        """Reach the device through a new source made as the entry says now.

        Its first poll discovers the catalogue again; the entities keep showing
        the values they have until it answers.
        """
        coordinator = self._coordinator
        await coordinator.async_use_source(
            create_entry_source(
                coordinator.hass,
                self._entry,
                self.options,
                self.point_map,
                self.overrides,
            )
        )

    async def _async_swap_points(self) -> bool:
        """Swap the source for the user's points; follow the catalogue it finds.

        What a new catalogue no longer backs leaves (see
        ``reconcile.async_follow_catalogue``). Returns whether there is one.
        """
        coordinator = self._coordinator
        previous = coordinator.data
        await self._async_swap_source()
        data: PlcData = coordinator.data
        if data is previous:
            return False
        async_follow_catalogue(coordinator.hass, self._entry, previous, data)
        return True

    @callback
    def _async_reselect(self) -> None:
        """Select from the known catalogue again, as the new options say.

        Registry entries the selection no longer backs go first (their entities
        with them); the platforms then create the new entities.
        """
        coordinator = self._coordinator
        data: PlcData = coordinator.data
        selection = self.select(data.catalogue)
        points = data.catalogue.points
        coordinator.data = replace(
            data,
            selection=selection,
            values={key: data.values.get(key) for key in selection.watched},
            attributes={
                key: attributes
                for key in selection.watched
                if (attributes := data.attributes.get(key)) is not None
                or (
                    key in points and (attributes := points[key].attributes) is not None
                )
            },
            changed=frozenset(),
        )
        async_follow_compositions(coordinator.hass, self._entry, selection)
        async_remove_stale_entries(coordinator.hass, self._entry, coordinator.data)
        coordinator.async_update_listeners()
