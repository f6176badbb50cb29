"""The form of one point of a map, and a list to choose points from.

A point form's fields are a map's columns (``pyplc.core.pointmap.CSV_COLUMNS``):
what is typed is checked as a map's row is.
"""

from collections.abc import Iterable, Mapping
from typing import Any, Final

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
from ..pyplc.core.descriptor import CONF_POINT_MAP, Field, FieldKind
from ..pyplc.core.pointmap import CSV_COLUMNS, MapPoint, PointMap, cells_of

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


def point_field(column: str) -> str:
    """Return the form field of a map's column (the whole form for none)."""
    return column if column in CSV_COLUMNS else "base"


def point_choice(
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
