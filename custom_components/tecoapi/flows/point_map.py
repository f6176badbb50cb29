"""The options flow's editor of a map: a newer file, or one point at a time.

A source whose points the user supplies (``Capability.POINT_MAP``) keeps its map
beside its entry; each change is checked as a map's row is and on the device
(a newer file: it answers it, and it is the entry's; a point added or moved to
another address: it reads it, once), stored, and applied at once, in place:
points kept keep their entities and their history. A point's form is in its
system's words (its step IDs are the descriptor's ``Words``: a Mervis
variable's address is ``CommUid[offset,length]``, an FP-I4C's ``DT100``); its
fields are a map's columns (``pyplc.core.pointmap.CSV_COLUMNS``) but its
classes, asked next (:mod:`.point_class`, the step a discovered point's
*Change a point* ends with too): its device class among Home Assistant's of
the platform it is shown on, and its state class. Points are removed once the
user confirmed what goes.
"""

from collections.abc import Callable, Collection, Iterable, Mapping
from dataclasses import replace
from typing import Any, Final

from homeassistant.config_entries import ConfigEntryState, ConfigFlowResult
from homeassistant.const import Platform
from homeassistant.data_entry_flow import AbortFlow
from homeassistant.helpers import entity_registry as er
from homeassistant.helpers.selector import (
    BooleanSelector,
    NumberSelector,
    NumberSelectorConfig,
    NumberSelectorMode,
    SelectSelector,
    SelectSelectorConfig,
    SelectSelectorMode,
    TextSelector,
)

from ..compat import vol
from ..connection import descriptor_of, source_context
from ..forms import form_schema
from ..mapping import PLATFORM_BY_KIND
from ..messages import async_load_texts, map_error_text, quality_text
from ..point_maps import async_save_point_map
from ..pyplc import PlcError, Point
from ..pyplc.core.descriptor import (
    CONF_POINT_MAP,
    Field,
    FieldKind,
    SourceDescriptor,
    SourceOptions,
)
from ..pyplc.core.pointmap import (
    CSV_COLUMNS,
    MapPoint,
    PointMap,
    PointMapError,
    cells_of,
    map_catalogue,
    point_of,
)
from .base import (
    async_setup_file_upload,
    async_stored_map,
    form_errors,
    point_picker,
)
from .point_class import (
    CONF_DEVICE_CLASS,
    CONF_STATE_CLASS,
    ClassesRefusedError,
    PointClassOptionsFlow,
)

CONF_POINT: Final = "point"
REMOVE_CONFIRM_STEP: Final = "remove_point_confirm"
"""The step that says what a removal takes, and asks once."""
LISTED: Final = 20
"""The most points (and entities) a removal's confirmation names one by one."""

type Change = Callable[[PointMap, MapPoint], PointMap]
"""How a point form changes a map: a new point, or one in place of another."""


class PointMapOptionsFlow(PointClassOptionsFlow):
    """The steps of the options menu that change a map's points."""

    def __init__(self) -> None:
        """Start with no point chosen yet, and no map uploaded (kept once read)."""
        super().__init__()
        self._editing: str | None = None
        self._removing: tuple[str, ...] = ()  # the points chosen for removal

    async def async_step_upload(
        self, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """Take a newer map file: points kept keep their entities and history."""
        descriptor = descriptor_of(self.config_entry.data)
        await async_setup_file_upload(self.hass)
        errors: dict[str, str] = {}
        placeholders = {"error": ""}
        if user_input is not None:
            point_map, errors = await self._async_read_upload(
                descriptor,
                user_input.get(CONF_POINT_MAP),
                placeholders,
                user_input,
                # (A map lost is none: the file uploaded stands for it.)
                await async_stored_map(self.hass, self.config_entry),
            )
            if point_map is not None:
                errors = await self._async_check_map(
                    descriptor, point_map, placeholders
                )
                if not errors:
                    return await self._async_take_map(point_map)
        return self.async_show_form(
            step_id=descriptor.words.upload_step_id,
            # The file is never suggested (see forms.py); what the form says of
            # it is (a Mervis project, after an error).
            data_schema=self.add_suggested_values_to_schema(
                form_schema(
                    (MAP_FIELD, *descriptor.map_fields),
                    accept=descriptor.point_map_formats,
                    uploaded=self._upload.map is not None,
                ),
                {
                    key: value
                    for key, value in (user_input or {}).items()
                    if key != CONF_POINT_MAP
                },
            ),
            description_placeholders=placeholders,
            errors=errors,
        )

    async def async_step_add_point(
        self, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """Add one point to the map (its form in the system's words)."""
        descriptor = descriptor_of(self.config_entry.data)
        await self._async_map()  # a map lost ends the options at once
        placeholders = {"error": ""}
        result, errors = await self._async_point_form(
            user_input, _add, None, placeholders
        )
        return result or self.async_show_form(
            step_id=descriptor.words.add_point_step_id,
            data_schema=self.add_suggested_values_to_schema(
                point_schema(descriptor.point_types, with_id=True),
                user_input or {"scale": 1.0},
            ),
            description_placeholders=placeholders,
            errors=errors,
        )

    async def async_step_edit_point(
        self, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """Choose the point to change in a list that searches as one types.

        The frontend searches only a list that takes several choices (one of a
        single choice searches only with a custom value, which offers to add
        what was typed as an item): this one takes one point, and offers no
        custom value.
        """
        point_map = await self._async_map()
        errors: dict[str, str] = {}
        if user_input is not None:
            chosen = list(user_input.get(CONF_POINT) or ())
            if len(chosen) == 1:
                self._editing = chosen[0]
                return await self.async_step_point()
            errors[CONF_POINT] = "point_one"
        return self.async_show_form(
            step_id="edit_point",
            data_schema=_choice_schema(point_map),
            description_placeholders={"count": str(len(point_map.points))},
            errors=errors,
        )

    async def async_step_point(
        self, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """Change the chosen point (its ID stays: its entity keeps its identity)."""
        descriptor = descriptor_of(self.config_entry.data)
        point_map = await self._async_map()
        assert self._editing is not None
        current = point_map.by_key()[self._editing]
        placeholders = {"error": "", "point": current.id}
        result, errors = await self._async_point_form(
            None if user_input is None else {**user_input, "id": current.id},
            _replacing(current.id),
            current,
            placeholders,
        )
        return result or self.async_show_form(
            step_id=descriptor.words.point_step_id,
            data_schema=self.add_suggested_values_to_schema(
                point_schema(descriptor.point_types, with_id=False),
                user_input or form_values(current),
            ),
            description_placeholders=placeholders,
            errors=errors,
        )

    async def async_step_remove_point(
        self, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """Choose points to remove (none is chosen before the user does)."""
        point_map = await self._async_map()
        errors: dict[str, str] = {}
        if user_input is not None:
            if chosen := tuple(user_input.get(CONF_POINT) or ()):
                self._removing = chosen
                return await self.async_step_remove_point_confirm()
            errors[CONF_POINT] = "point_none"
        return self.async_show_form(
            step_id="remove_point",
            data_schema=_choice_schema(point_map),
            description_placeholders={"count": str(len(point_map.points))},
            errors=errors,
        )

    async def async_step_remove_point_confirm(
        self, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """Say which points and entities a removal takes; remove them when confirmed."""
        point_map = await self._async_map()
        points = point_map.by_key()
        keys = [key for key in self._removing if key in points]
        if user_input is not None:
            changed = point_map
            for key in keys:
                changed = changed.without(key)
            return await self._async_take_map(changed)
        return self.async_show_form(
            step_id=REMOVE_CONFIRM_STEP,
            data_schema=vol.Schema({}),
            description_placeholders={
                "count": str(len(keys)),
                "points": _listed(_point_label(points[key]) for key in keys),
                "entities": _listed(f"`{ident}`" for ident in self._entities_of(keys)),
            },
        )

    def _entities_of(self, keys: Collection[str]) -> list[str]:
        """Return the entity IDs a removal of points takes or makes again.

        Each point's own entity, and the entity of each device a convention
        built on one of them (a light, a blind, a thermostat: made again
        without it, or gone). A device the user composed stays (unavailable).
        """
        entry = self.config_entry
        built: set[str] = set()
        # An entry not set up (or being set up) has no devices found yet.
        if (coordinator := getattr(entry, "runtime_data", None)) is not None:
            built = {
                key
                for key, device in coordinator.data.devices.items()
                if not device.composed and not device.points.isdisjoint(keys)
            }
        prefix = f"{entry.unique_id}_"
        wanted = set(keys) | built
        return sorted(
            item.entity_id
            for item in er.async_entries_for_config_entry(
                er.async_get(self.hass), entry.entry_id
            )
            if item.unique_id.startswith(prefix)
            and item.unique_id.removeprefix(prefix) in wanted
        )

    async def _async_point_form(
        self,
        user_input: Mapping[str, Any] | None,
        change: Change,
        current: MapPoint | None,
        placeholders: dict[str, str],
    ) -> tuple[ConfigFlowResult | None, dict[str, str]]:
        """Take a point form: its next step or the map changed, else its errors.

        The point is checked as a map's row is, then shown as what it may be
        (:func:`_shown_as_problem`), then read once on the device when it is
        new or reads elsewhere now (its address, type or device changed). A
        refusal names its field and says why in ``{error}``.
        """
        if user_input is None:
            return None, {}
        descriptor = descriptor_of(self.config_entry.data)
        try:
            point = point_of(
                cells_from_form(user_input),
                descriptor.check_address,
                descriptor.point_types,
            )
            change(await self._async_map(), point)
        except PointMapError as err:
            await async_load_texts(self.hass)
            placeholders["error"] = map_error_text(self.hass, err)
            return None, {_point_field(err.column): "point_invalid"}
        if (problem := _shown_as_problem(point)) is not None:
            return None, {"platform": problem}
        if current is None or _reads_elsewhere(point, current):
            errors = await self._async_check_point(descriptor, point, placeholders)
            if errors:
                return None, errors
        if current is not None:  # its classes so far, offered again
            point = replace(
                point,
                device_class=current.device_class,
                state_class=current.state_class,
            )

        async def take(device_class: str, state_class: str) -> ConfigFlowResult:
            chosen = replace(point, device_class=device_class, state_class=state_class)
            try:
                changed = change(await self._async_map(), chosen)
            except PointMapError as err:  # another flow took the ID meanwhile
                await async_load_texts(self.hass)
                raise ClassesRefusedError(
                    {"base": "point_invalid"},
                    {"error": map_error_text(self.hass, err)},
                ) from err
            return await self._async_take_map(changed)

        try:
            return await self._async_ask_classes(shown(point), take), {}
        except ClassesRefusedError as err:
            placeholders.update(err.placeholders)
            return None, err.errors

    async def _async_check_point(
        self,
        descriptor: SourceDescriptor,
        point: MapPoint,
        placeholders: dict[str, str],
    ) -> dict[str, str]:
        """Read a point once on the device, as a newer map is checked there.

        A source of a map holding this point alone (the entry's connection,
        its identity, its map's properties) reads it; a point it refuses is
        the form's address error, in the system's words, with the device's
        reason in ``{error}``. A failure of the device as a whole is the form's
        error, as the descriptor maps it.
        """
        entry = self.config_entry
        stored = await self._async_map()
        source = descriptor.create(
            source_context(self.hass),
            entry.data,
            SourceOptions(
                point_map=PointMap((point,), stored.format, (), stored.properties),
                identity=entry.unique_id,
            ),
        )
        try:
            refused = await source.check_points({point.key})
        except PlcError as err:
            return form_errors(descriptor, err, placeholders)
        finally:
            await source.close()
        if (quality := refused.get(point.key)) is not None:
            await async_load_texts(self.hass)
            placeholders["error"] = quality_text(self.hass, quality)
            return {"address": descriptor.words.point_refused}
        return {}

    async def _async_map(self) -> PointMap:
        """Return the entry's map as stored now."""
        found = await async_stored_map(self.hass, self.config_entry)
        if found is None:
            raise AbortFlow("point_map_lost")
        return found

    async def _async_check_map(
        self,
        descriptor: SourceDescriptor,
        point_map: PointMap,
        placeholders: dict[str, str],
    ) -> dict[str, str]:
        """Check a newer map on the device: it answers it, and it is the entry's.

        The form's errors, as the descriptor maps failures (none: it is); the
        details a failure's message shows go to ``placeholders``. The source is
        made as the entry's is, with the entry's identity: a device that cannot
        tell its own (a gateway moved to another address) keeps the entry's.
        """
        entry = self.config_entry
        source = descriptor.create(
            source_context(self.hass),
            entry.data,
            SourceOptions(point_map=point_map, identity=entry.unique_id),
        )
        try:
            info = await source.identify()
        except PlcError as err:
            return form_errors(descriptor, err, placeholders, field="base")
        finally:
            await source.close()
        if info.identity != entry.unique_id:
            return {"base": "point_map_other_device"}
        return {}

    async def _async_take_map(self, point_map: PointMap) -> ConfigFlowResult:
        """Store a changed map beside the entry and apply it in place."""
        entry = self.config_entry
        await async_save_point_map(self.hass, point_map, entry.data[CONF_POINT_MAP])
        if entry.state is ConfigEntryState.LOADED:
            await entry.runtime_data.applier.async_replace_point_map(point_map)
        return self.async_create_entry(data=dict(entry.options))


MAP_FIELD: Final = Field(key=CONF_POINT_MAP, kind=FieldKind.POINT_MAP)
# A point form's fields: a map's columns (pyplc.core.pointmap.CSV_COLUMNS).
_NUMBER: Final = NumberSelector(
    NumberSelectorConfig(mode=NumberSelectorMode.BOX, step="any")
)
_TEXT: Final = TextSelector()
SHOWN_ONLY: Final = (Platform.SENSOR, Platform.BINARY_SENSOR)
"""What a point may be shown as instead of its own platform (its "Show as")."""
_FORM_FIELDS: Final = tuple(
    column
    for column in CSV_COLUMNS
    if column not in ("id", CONF_DEVICE_CLASS, CONF_STATE_CLASS)
)
"""The columns a point's form shows, but its ID (its classes: a step of their own)."""


def _add(point_map: PointMap, point: MapPoint) -> PointMap:
    """Add a new point to a map (its ID must be a new one)."""
    return point_map.with_new_point(point)


def _replacing(ident: str) -> Change:
    """Return the change that puts a point in the place of the point ``ident``."""
    return lambda point_map, point: point_map.with_point(point, replacing=ident)


def point_schema(types: Iterable[str], *, with_id: bool) -> vol.Schema:
    """Return the form of one point of ``types`` (its ID only when it is a new one).

    Its classes are no fields: :mod:`.point_class` asks them next, among those
    of the platform the point is shown on.
    """
    fields: dict[Any, Any] = {}
    if with_id:
        fields[vol.Required("id")] = _TEXT
    fields.update(
        {
            vol.Required("name"): _TEXT,
            vol.Required("address"): _TEXT,
            vol.Required("type"): SelectSelector(
                SelectSelectorConfig(
                    options=[name.upper() for name in types],
                    mode=SelectSelectorMode.DROPDOWN,
                )
            ),
            vol.Optional("length"): _NUMBER,
            vol.Optional("unit"): _TEXT,
            vol.Optional("scale"): _NUMBER,
            vol.Optional("offset"): _NUMBER,
            vol.Required("writable", default=False): BooleanSelector(),
            vol.Optional("min"): _NUMBER,
            vol.Optional("max"): _NUMBER,
            vol.Optional("step"): _NUMBER,
            vol.Optional("device"): _TEXT,
            vol.Optional("platform"): SelectSelector(
                SelectSelectorConfig(
                    options=[platform.value for platform in SHOWN_ONLY],
                    mode=SelectSelectorMode.DROPDOWN,
                    translation_key="platform",
                )
            ),
            vol.Required("invert", default=False): BooleanSelector(),
            vol.Optional("description"): _TEXT,
        }
    )
    return vol.Schema(fields)


def _shown_as_problem(point: MapPoint) -> str | None:
    """Return the error of a "Show as" the point's type cannot be shown as (None: fine).

    Only a point's own read-only platform shows it only: a binary sensor for a
    BOOL, a sensor for any other type.
    """
    if not point.platform:
        return None
    own = PLATFORM_BY_KIND[point.type.kind, False]
    return None if point.platform == own.value else "point_platform"


def _reads_elsewhere(point: MapPoint, current: MapPoint) -> bool:
    """Whether a changed point reads other bytes than before (checked on the device)."""
    return (point.address, point.type, point.device) != (
        current.address,
        current.type,
        current.device,
    )


def cells_from_form(values: Mapping[str, Any]) -> dict[str, str]:
    """Return a point form's values as a map's cells (text, as a CSV row has)."""
    cells: dict[str, str] = {}
    for key, value in values.items():
        if isinstance(value, bool):
            cells[key] = "yes" if value else "no"
        elif isinstance(value, float) and value.is_integer() and key == "length":
            cells[key] = str(int(value))
        else:
            cells[key] = str(value)
    return cells


def shown(point: MapPoint) -> Point:
    """Return a map's point as it is shown (its catalogue's point)."""
    return map_catalogue(PointMap((point,))).points[point.key]


def form_values(point: MapPoint) -> dict[str, Any]:
    """Return a point as its form shows it (its ID and classes are not fields)."""
    values: dict[str, Any] = {}
    for key, cell in cells_of(point).items():
        if key not in _FORM_FIELDS or cell == "":
            continue
        if key in ("writable", "invert"):
            values[key] = cell == "yes"
        elif key in ("length", "scale", "offset", "min", "max", "step"):
            values[key] = float(cell)
        else:
            values[key] = cell.upper() if key == "type" else cell
    return values


def _point_field(column: str) -> str:
    """Return the form field of a map's column (the whole form for none)."""
    return column if column in CSV_COLUMNS else "base"


def _point_label(point: MapPoint) -> str:
    """Return how a list names a point: its name, and its ID where that differs."""
    return point.name if point.name == point.id else f"{point.name} ({point.id})"


def _listed(items: Iterable[str]) -> str:
    """Return items as a Markdown list of at most :data:`LISTED` lines ("—": none).

    Beyond that many, a last line says how many more (``… +5``).
    """
    lines = list(items)
    if not lines:
        return "—"
    shown = [f"- {line}" for line in lines[:LISTED]]
    if len(lines) > LISTED:
        shown.append(f"- … +{len(lines) - LISTED}")
    return "\n".join(shown)


def _choice_schema(point_map: PointMap) -> vol.Schema:
    """Return a choice of a map's points, none chosen before the user does.

    The field is optional, without a default: the frontend fills a required
    choice with its first option, which Submit would change or remove.
    """
    return vol.Schema({vol.Optional(CONF_POINT): _point_choice(point_map)})


def _point_choice(point_map: PointMap) -> SelectSelector:
    """Return a list of a map's points, by name and ID, that searches as one types."""
    return point_picker({point.key: _point_label(point) for point in point_map.points})
