"""The options flow's editor of a map: a newer file, or one point at a time.

A source whose points the user supplies (``Capability.POINT_MAP``) keeps its map
beside its entry; each change is checked as a map's row is (a newer file on the
device: it answers it, and it is the entry's), stored, and applied at once, in
place: points kept keep their entities and their history. A point form's fields
are a map's columns (``pyplc.core.pointmap.CSV_COLUMNS``); its form lives here,
beside the steps that show it.
"""

from collections.abc import Callable, Iterable, Mapping
from typing import Any, Final

from homeassistant.config_entries import ConfigEntryState, ConfigFlowResult, OptionsFlow
from homeassistant.data_entry_flow import AbortFlow
from homeassistant.helpers.selector import (
    BooleanSelector,
    NumberSelector,
    NumberSelectorConfig,
    NumberSelectorMode,
    SelectOptionDict,
    SelectSelector,
    SelectSelectorConfig,
    SelectSelectorMode,
    TextSelector,
)

from ..compat import vol
from ..connection import descriptor_of, source_context
from ..forms import form_schema
from ..point_maps import async_save_point_map
from ..pyplc import PlcError
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
    point_key,
    point_of,
)
from .base import PlcFlow, async_setup_file_upload, async_stored_map, form_errors


class PointMapOptionsFlow(PlcFlow, OptionsFlow):
    """The steps of the options menu that change a map's points."""

    def __init__(self) -> None:
        """Start with no point chosen yet, and no map uploaded (kept once read)."""
        super().__init__()
        self._editing: str | None = None

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
                descriptor, user_input.get(CONF_POINT_MAP), placeholders
            )
            if point_map is not None:
                errors = await self._async_check_map(
                    descriptor, point_map, placeholders
                )
                if not errors:
                    return await self._async_take_map(point_map)
        return self.async_show_form(
            step_id=descriptor.words.upload_step_id,
            # The file is never suggested: see forms.py.
            data_schema=form_schema(
                (MAP_FIELD,),
                accept=descriptor.point_map_formats,
                uploaded=self._upload.map is not None,
            ),
            description_placeholders=placeholders,
            errors=errors,
        )

    async def async_step_add_point(
        self, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """Add one point to the map."""
        point_map = await self._async_map()
        placeholders = {"error": ""}
        result, errors = await self._async_change(
            user_input,
            point_map.with_new_point,
            placeholders,
        )
        return result or self.async_show_form(
            step_id="add_point",
            data_schema=self.add_suggested_values_to_schema(
                point_schema(self._point_types, with_id=True),
                user_input or {"scale": 1.0},
            ),
            description_placeholders=placeholders,
            errors=errors,
        )

    @property
    def _point_types(self) -> tuple[str, ...]:
        """The type names a point of this entry's source may take."""
        return descriptor_of(self.config_entry.data).point_types

    async def async_step_edit_point(
        self, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """Choose the point to change: picked from the list, or its ID typed.

        The list is searchable (a custom value makes the frontend show a picker
        that filters as one types, among thousands of points); what is typed
        must be a point's ID, in any case.
        """
        point_map = await self._async_map()
        errors: dict[str, str] = {}
        if user_input is not None:
            key = point_key(str(user_input[CONF_POINT]))
            if key in point_map.by_key():
                self._editing = key
                return await self.async_step_point()
            errors[CONF_POINT] = "point_unknown"
        return self.async_show_form(
            step_id="edit_point",
            data_schema=self.add_suggested_values_to_schema(
                vol.Schema(
                    {
                        vol.Required(CONF_POINT): _point_choice(
                            point_map, searchable=True
                        )
                    }
                ),
                user_input or {},
            ),
            description_placeholders={"count": str(len(point_map.points))},
            errors=errors,
        )

    async def async_step_point(
        self, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """Change the chosen point (its ID stays: its entity keeps its identity)."""
        point_map = await self._async_map()
        assert self._editing is not None
        current = point_map.by_key()[self._editing]
        placeholders = {"error": "", "point": current.id}
        result, errors = await self._async_change(
            None if user_input is None else {**user_input, "id": current.id},
            lambda point: point_map.with_point(point, replacing=current.id),
            placeholders,
        )
        return result or self.async_show_form(
            step_id="point",
            data_schema=self.add_suggested_values_to_schema(
                point_schema(self._point_types, with_id=False),
                user_input or form_values(current),
            ),
            description_placeholders=placeholders,
            errors=errors,
        )

    async def async_step_remove_point(
        self, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """Remove points from the map (their entities go with them)."""
        point_map = await self._async_map()
        if user_input is not None:
            changed = point_map
            for key in user_input[CONF_POINT]:
                changed = changed.without(key)
            return await self._async_take_map(changed)
        return self.async_show_form(
            step_id="remove_point",
            data_schema=vol.Schema(
                {vol.Required(CONF_POINT): _point_choice(point_map, multiple=True)}
            ),
        )

    async def _async_change(
        self,
        user_input: Mapping[str, Any] | None,
        change: Callable[[MapPoint], PointMap],
        placeholders: dict[str, str],
    ) -> tuple[ConfigFlowResult | None, dict[str, str]]:
        """Apply a point form to the map, or return the form's errors.

        The point is checked as a map's row is; a refusal names its field and
        says why in ``{error}``.
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
            changed = change(point)
        except PointMapError as err:
            placeholders["error"] = err.message
            return None, {_point_field(err.column): "point_invalid"}
        return await self._async_take_map(changed), {}

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
            await entry.runtime_data.async_replace_point_map(point_map)
        return self.async_create_entry(data=dict(entry.options))


CONF_POINT: Final = "point"
MAP_FIELD: Final = Field(key=CONF_POINT_MAP, kind=FieldKind.POINT_MAP)
# A point form's fields: a map's columns (pyplc.core.pointmap.CSV_COLUMNS).
_NUMBER: Final = NumberSelector(
    NumberSelectorConfig(mode=NumberSelectorMode.BOX, step="any")
)
_TEXT: Final = TextSelector()


def point_schema(types: Iterable[str], *, with_id: bool) -> vol.Schema:
    """Return the form of one point of ``types`` (its ID only when it is a new one)."""
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
                    options=["sensor", "binary_sensor"],
                    mode=SelectSelectorMode.DROPDOWN,
                    translation_key="platform",
                )
            ),
            vol.Optional("device_class"): _TEXT,
            vol.Required("invert", default=False): BooleanSelector(),
            vol.Optional("description"): _TEXT,
        }
    )
    return vol.Schema(fields)


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


def form_values(point: MapPoint) -> dict[str, Any]:
    """Return a point as its form shows it."""
    values: dict[str, Any] = {}
    for key, cell in cells_of(point).items():
        if key == "id" or cell == "":
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


def _point_choice(
    point_map: PointMap, *, multiple: bool = False, searchable: bool = False
) -> SelectSelector:
    """Return a list of a map's points, by name and ID.

    ``searchable`` lets the user type (an ID, or part of a name to filter by):
    the frontend shows a single choice with a custom value as a picker that
    searches, where a plain dropdown has no search.
    """
    return SelectSelector(
        SelectSelectorConfig(
            options=[
                SelectOptionDict(
                    value=point.key,
                    label=point.name
                    if point.name == point.id
                    else f"{point.name} ({point.id})",
                )
                for point in point_map.points
            ],
            mode=SelectSelectorMode.DROPDOWN,
            multiple=multiple,
            custom_value=searchable,
        )
    )
