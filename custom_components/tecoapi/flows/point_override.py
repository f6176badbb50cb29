"""The options flow's changes of discovered points: each point the user's.

A source that discovers its points (a PLC's program, a gateway's address space)
describes them as its device does. Behind its options menu the user picks a
point (searchable, as a map's *Change a point* is) and changes what it is:
writable (where its device takes a write), its unit, range, step, inverted, or
shown only; then its device class and state class, on the step a map's point
form ends with too (:mod:`.point_class`). What differs from what the device
says is kept beside the entry (``overrides``: a store of its own), given to
the source, which applies it to every catalogue it discovers (a new program, a
restart), and applied at once, in place: a point shown on another platform
keeps its unique ID there. The device's points are known only while the entry
is loaded: the steps need it.
"""

from collections.abc import Mapping
from typing import Any, Final

from homeassistant.config_entries import ConfigEntryState, ConfigFlowResult
from homeassistant.const import Platform
from homeassistant.data_entry_flow import AbortFlow
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
from ..coordinator import PlcCoordinator
from ..mapping import PLATFORM_BY_KIND, platform_for, point_label
from ..overrides import async_save_overrides
from ..pyplc import Point, PointAttributes, ValueKind
from ..pyplc.core.models import PointOverride
from ..pyplc.core.overrides import (
    HALF_RANGE,
    NOT_TAKEN,
    NOT_WRITABLE,
    RANGE,
    STEP,
    OverrideError,
    apply_override,
    check_override,
    fields_of,
)
from .base import point_picker
from .point_class import CONF_DEVICE_CLASS, CONF_STATE_CLASS, PointClassOptionsFlow

CONF_POINT: Final = "point"
# The form's fields by the override's (a map's point form says min and max).
FORM_FIELDS: Final[Mapping[str, str]] = {
    "writable": "writable",
    "unit": "unit",
    "device_class": "device_class",
    "state_class": "state_class",
    "minimum": "min",
    "maximum": "max",
    "step": "step",
    "invert": "invert",
    "platform": "platform",
}
# The form error of each reason a point does not take a change (pyplc.core.overrides).
ERRORS: Final[Mapping[str, str]] = {
    NOT_WRITABLE: "override_not_writable",
    NOT_TAKEN: "override_not_taken",
    RANGE: "override_range",
    HALF_RANGE: "override_range_half",
    STEP: "override_step",
}
_NUMBER: Final = NumberSelector(
    NumberSelectorConfig(mode=NumberSelectorMode.BOX, step="any")
)


class PointOverrideOptionsFlow(PointClassOptionsFlow):
    """The steps of the options menu that change what discovered points are."""

    def __init__(self) -> None:
        """Start with no point chosen yet."""
        super().__init__()
        self._overriding = ""

    async def async_step_override_point(
        self, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """Choose the point to change in a list that searches as one types.

        The map editor's picker (:func:`.base.point_picker`): nothing chosen
        beforehand, no custom value, one point taken. Points with nothing to
        change (a button, a record) are not offered.
        """
        points = {
            key: point
            for key, point in self._coordinator().data.points.items()
            if fields_of(point)
        }
        errors: dict[str, str] = {}
        if user_input is not None:
            chosen = list(user_input.get(CONF_POINT) or ())
            if len(chosen) != 1:
                errors[CONF_POINT] = "point_one"
            elif (key := chosen[0]) in points:
                self._overriding = key
                return await self.async_step_point_override()
            else:
                errors[CONF_POINT] = "override_point_unknown"
        return self.async_show_form(
            step_id="override_point",
            data_schema=self.add_suggested_values_to_schema(
                vol.Schema(
                    {
                        vol.Optional(CONF_POINT): point_picker(
                            {key: point_label(point) for key, point in points.items()}
                        )
                    }
                ),
                user_input or {},
            ),
            errors=errors,
        )

    async def async_step_point_override(
        self, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """Change the chosen point: what differs from what its device says is kept.

        Its classes are asked next, where the platform it is now shown on
        takes any (:mod:`.point_class`); until then they stay as they are.
        """
        coordinator = self._coordinator()
        key = self._overriding
        shown = coordinator.data.catalogue.points.get(key)
        described = coordinator.source.discovered_point(key)
        if shown is None or described is None:
            raise AbortFlow("override_unavailable")
        errors: dict[str, str] = {}
        if user_input is not None:
            values = {
                **user_input,
                CONF_DEVICE_CLASS: shown.device_class,
                CONF_STATE_CLASS: shown.state_class,
            }
            override = override_of(described, values)
            errors = _problems(described, override)
            if not errors:

                async def take(device_class: str, state_class: str) -> ConfigFlowResult:
                    chosen = override_of(
                        described,
                        {
                            **values,
                            CONF_DEVICE_CLASS: device_class,
                            CONF_STATE_CLASS: state_class,
                        },
                    )
                    overrides = {
                        **{
                            k: v
                            for k, v in coordinator.applier.overrides.items()
                            if k != key
                        },
                        **({} if chosen.empty else {key: chosen}),
                    }
                    return await self._async_take(coordinator, overrides)

                return await self._async_ask_classes(
                    apply_override(described, override), take
                )
        return self.async_show_form(
            step_id="point_override",
            data_schema=self.add_suggested_values_to_schema(
                point_schema(described),
                user_input
                or form_values(shown, coordinator.data.point_attributes(key)),
            ),
            description_placeholders={"point": point_label(shown)},
            errors=errors,
        )

    async def async_step_remove_overrides(
        self, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """Return points to what their device says (none is chosen beforehand)."""
        coordinator = self._coordinator()
        stored = coordinator.applier.overrides
        if not stored:
            raise AbortFlow("no_overrides")
        if user_input is not None:
            removed = set(user_input[CONF_POINT])
            return await self._async_take(
                coordinator,
                {key: item for key, item in stored.items() if key not in removed},
            )
        points = coordinator.data.catalogue.points
        return self.async_show_form(
            step_id="remove_overrides",
            data_schema=vol.Schema(
                {
                    vol.Required(CONF_POINT): point_picker(
                        {
                            key: point_label(points[key]) if key in points else key
                            for key in stored
                        },
                        ticked=True,
                    )
                }
            ),
        )

    def _coordinator(self) -> PlcCoordinator:
        """Return the entry's coordinator; abort while the entry is not loaded.

        The points are the device's: known only from it, once the entry is set up.
        """
        entry = self.config_entry
        coordinator = getattr(entry, "runtime_data", None)
        if entry.state is not ConfigEntryState.LOADED or not isinstance(
            coordinator, PlcCoordinator
        ):
            raise AbortFlow("override_unavailable")
        return coordinator

    async def _async_take(
        self, coordinator: PlcCoordinator, overrides: dict[str, PointOverride]
    ) -> ConfigFlowResult:
        """Store the overrides beside the entry and apply them in place (if changed)."""
        if overrides != coordinator.applier.overrides:
            await async_save_overrides(self.hass, self.config_entry.entry_id, overrides)
            await coordinator.applier.async_replace_overrides(overrides)
        return self.async_create_entry(data=dict(self.config_entry.options))


def point_schema(point: Point) -> vol.Schema:
    """Return the form of a point: the fields of what it may have changed.

    Its classes are no fields: :mod:`.point_class` asks them next.
    """
    taken = fields_of(point)
    # Every point offered may be made writable (or read only) and shown only.
    fields: dict[Any, Any] = {
        vol.Required("writable", default=False): BooleanSelector()
    }
    if "unit" in taken:
        fields[vol.Optional("unit")] = TextSelector()
    if "minimum" in taken:
        fields[vol.Optional("min")] = _NUMBER
        fields[vol.Optional("max")] = _NUMBER
        fields[vol.Optional("step")] = _NUMBER
    if "invert" in taken:
        fields[vol.Required("invert", default=False)] = BooleanSelector()
    fields[vol.Optional("platform")] = SelectSelector(
        SelectSelectorConfig(
            options=[str(platform) for platform in platforms_of(point.kind)],
            mode=SelectSelectorMode.DROPDOWN,
            translation_key="platform",
        )
    )
    return vol.Schema(fields)


def platforms_of(kind: ValueKind) -> tuple[Platform, Platform]:
    """Return the platforms a point of a kind is shown on: writable, shown only."""
    return PLATFORM_BY_KIND[kind, True], PLATFORM_BY_KIND[kind, False]


def form_values(point: Point, attributes: PointAttributes | None) -> dict[str, Any]:
    """Return a point as its form shows it: what it is now (changed or not).

    ``attributes`` are its latest; an empty class, unit or bound is left empty.
    """
    low, high = point.range_of(attributes)
    values: dict[str, Any] = {
        "writable": point.writable,
        "unit": point.unit_of(attributes),
        "min": low,
        "max": high,
        "step": point.step,
        "invert": point.invert,
        # Shown only or not: a choice of a writable point only.
        "platform": str(platform_for(point)) if point.writable else None,
    }
    return {key: value for key, value in values.items() if value not in (None, "")}


def override_of(described: Point, values: Mapping[str, Any]) -> PointOverride:
    """Return what a submitted form changes of a point as its device describes it.

    A field equal to what the device says changes nothing (it follows the
    device); an empty unit or bound is the device's, an empty class none (a
    number's is then its unit's). A class not given is the device's.
    """
    low, high = described.range_of()
    writable = values.get("writable", described.writable)
    shown_only = str(platforms_of(described.kind)[1])
    # Shown only: a point that may be written (a read-only one is anyway).
    platform = shown_only if writable and values.get("platform") == shown_only else ""
    given = {
        "writable": writable,
        "unit": str(values.get("unit", "")).strip() or described.unit_of(),
        "device_class": values.get(CONF_DEVICE_CLASS, described.device_class),
        "state_class": values.get(CONF_STATE_CLASS, described.state_class),
        "minimum": _number(values.get("min"), low),
        "maximum": _number(values.get("max"), high),
        "step": _number(values.get("step"), described.step),
        "invert": values.get("invert", described.invert),
        "platform": platform,
    }
    device = {
        "writable": described.writable,
        "unit": described.unit_of(),
        "device_class": described.device_class,
        "state_class": described.state_class,
        "minimum": low,
        "maximum": high,
        "step": described.step,
        "invert": described.invert,
        "platform": described.platform,
    }
    return PointOverride(
        **{
            name: value if value != device[name] else None
            for name, value in given.items()
        }
    )


def _number(value: Any, device: float | None) -> float | None:
    """Return a number field's value: the device's where it is empty."""
    return device if value is None else float(value)


def _problems(described: Point, override: PointOverride) -> dict[str, str]:
    """Return the form's errors: what the point does not take."""
    try:
        check_override(described, override)
    except OverrideError as err:
        return {FORM_FIELDS[err.field]: ERRORS[err.reason]}
    return {}
