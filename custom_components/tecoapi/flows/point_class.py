"""A point's device class and state class: one step after its form, for every point.

Both forms of one point (a map's, :mod:`.point_map`; a discovered point's,
:mod:`.point_override`) ask its classes the same way, on a step of their own
once the form has passed, when the platform the point is shown on and its
unit are known:

- a binary sensor takes a binary sensor's device class;
- a sensor or a number with a unit takes one of Home Assistant's numeric
  device classes, which must fit the unit (``%`` is no temperature);
- a sensor takes a state class, which its device class (the one chosen, or
  its unit's: kWh is energy) must take (an energy counter is a total);
- a switch, text, a date or a time takes none: no step.

The device classes are Home Assistant's selector of the platform's, which the
frontend names in the viewing user's language (Home Assistant 2026.2 has
none: there, a list labelled with Home Assistant's names in its language); the
state classes are named by the integration's own translations, as Home
Assistant names them. A class left empty is none (a number's is then its
unit's, a binary sensor's its name's); one not asked stays as it was.
"""

from collections.abc import Awaitable, Callable, Mapping
from dataclasses import dataclass, replace
from typing import Any, Final

from homeassistant.components.sensor import SensorDeviceClass, SensorStateClass
from homeassistant.components.sensor.const import (
    DEVICE_CLASS_STATE_CLASSES,
    DEVICE_CLASS_UNITS,
)
from homeassistant.config_entries import ConfigFlowResult, OptionsFlow
from homeassistant.const import Platform
from homeassistant.helpers.selector import (
    SelectSelector,
    SelectSelectorConfig,
    SelectSelectorMode,
)

from ..compat import vol
from ..forms import async_device_class_selector
from ..mapping import NUMERIC_KINDS, platform_for, point_label, unit_mapping
from ..pyplc import Point
from .base import PlcFlow

CLASS_STEP: Final = "point_class"
"""The step that asks a point's classes, after its form."""
CONF_DEVICE_CLASS: Final = "device_class"
CONF_STATE_CLASS: Final = "state_class"
STATE_CLASS_SELECTOR: Final = SelectSelector(
    SelectSelectorConfig(
        options=[str(state) for state in SensorStateClass],
        mode=SelectSelectorMode.DROPDOWN,
        translation_key=CONF_STATE_CLASS,
    )
)

type TakeClasses = Callable[[str, str], Awaitable[ConfigFlowResult]]
"""Finishes a point's change with its device class and state class ("": none)."""


class ClassesRefusedError(Exception):
    """A change that cannot be taken after all (another flow took the point's ID).

    ``errors`` are the step's, ``placeholders`` what its texts then fill.
    """

    def __init__(self, errors: Mapping[str, str], placeholders: Mapping[str, str]):
        """Keep the step's errors and what they say."""
        super().__init__(dict(errors))
        self.errors = dict(errors)
        self.placeholders = dict(placeholders)


@dataclass(frozen=True, slots=True)
class ClassRequest:
    """A point whose form passed: as it will be shown (its classes so far), and its finish."""

    point: Point
    take: TakeClasses


def class_domain(point: Point) -> Platform | None:
    """Return the platform whose device classes a point takes (None: none).

    A binary sensor's are its own; a sensor's or a number's are the numeric
    ones (Home Assistant's number classes), given a unit.
    """
    platform = platform_for(point)
    if platform is Platform.BINARY_SENSOR:
        return platform
    if (
        platform in (Platform.SENSOR, Platform.NUMBER)
        and point.kind in NUMERIC_KINDS
        and point.unit_of().strip()
    ):
        return Platform.NUMBER
    return None


def takes_state_class(point: Point) -> bool:
    """Whether a point takes a state class: a number shown as a sensor."""
    return platform_for(point) is Platform.SENSOR and point.kind in NUMERIC_KINDS


def class_problems(point: Point) -> dict[str, str]:
    """Return the step's errors for a point with its classes chosen (none: it fits).

    Home Assistant's tables decide: a device class's units, and the state
    classes a device class takes (its statistics are kept only then).
    """
    if platform_for(point) is Platform.BINARY_SENSOR:
        return {}
    mapping = unit_mapping(point)
    if point.device_class and class_domain(point) is not None:
        # One of the selector's: Home Assistant's numeric classes, all a sensor's.
        units = DEVICE_CLASS_UNITS.get(SensorDeviceClass(point.device_class))
        if mapping is None or (units is not None and mapping.unit not in units):
            return {CONF_DEVICE_CLASS: "point_class_unit"}
    if takes_state_class(point) and mapping is not None and mapping.device_class:
        states = DEVICE_CLASS_STATE_CLASSES.get(mapping.device_class)
        if states is not None and mapping.state_class not in states:
            return {CONF_STATE_CLASS: "point_class_state"}
    return {}


async def async_class_schema(flow: PlcFlow, point: Point) -> vol.Schema:
    """Return the step's form: the classes the point's platform takes."""
    fields: dict[Any, Any] = {}
    if (domain := class_domain(point)) is not None:
        fields[vol.Optional(CONF_DEVICE_CLASS)] = await async_device_class_selector(
            flow.hass, domain
        )
    if takes_state_class(point):
        fields[vol.Optional(CONF_STATE_CLASS)] = STATE_CLASS_SELECTOR
    return vol.Schema(fields)


class PointClassOptionsFlow(PlcFlow, OptionsFlow):
    """The step of a point's classes, which both forms of one point end with."""

    def __init__(self) -> None:
        """Start with no point waiting for its classes."""
        super().__init__()
        self._classing: ClassRequest | None = None

    async def _async_ask_classes(
        self, point: Point, take: TakeClasses
    ) -> ConfigFlowResult:
        """Ask a point's classes where its platform takes any; else finish at once.

        ``point`` is the point as it will be shown, with its classes so far
        (suggested, and kept where none is asked).
        """
        if class_domain(point) is None and not takes_state_class(point):
            return await take(point.device_class, point.state_class)
        self._classing = ClassRequest(point, take)
        return await self.async_step_point_class()

    async def async_step_point_class(
        self, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """Ask the classes of the point whose form passed, then take them."""
        assert self._classing is not None
        point, take = self._classing.point, self._classing.take
        schema = await async_class_schema(self, point)
        placeholders = {"point": point_label(point), "unit": point.unit_of() or "—"}
        errors: dict[str, str] = {}
        if user_input is not None:
            chosen = replace(
                point,
                device_class=str(user_input.get(CONF_DEVICE_CLASS) or "")
                if CONF_DEVICE_CLASS in schema.schema
                else point.device_class,
                state_class=str(user_input.get(CONF_STATE_CLASS) or "")
                if CONF_STATE_CLASS in schema.schema
                else point.state_class,
            )
            errors = class_problems(chosen)
            if not errors:
                try:
                    return await take(chosen.device_class, chosen.state_class)
                except ClassesRefusedError as err:
                    errors = err.errors
                    placeholders |= err.placeholders
        suggested = {
            CONF_DEVICE_CLASS: point.device_class or None,
            CONF_STATE_CLASS: point.state_class or None,
        }
        return self.async_show_form(
            step_id=CLASS_STEP,
            data_schema=self.add_suggested_values_to_schema(
                schema, user_input or suggested
            ),
            description_placeholders=placeholders,
            errors=errors,
        )
