"""The forms of a source's descriptor as Home Assistant forms (selectors, schemas).

Each kind of field has one selector; a required field is required, with its
default where it has one. In a reconfigure form a secret is optional: left
empty, the stored one stays. In a form shown again after its map file was read
the file is optional: left empty, the map read before is used (the file is
never suggested again: Home Assistant's file selector names only a file it
uploaded itself, another is an "Unknown file").
"""

from collections.abc import Iterable, Mapping
from enum import StrEnum
from typing import Any, Final

from homeassistant.components.number import NumberDeviceClass
from homeassistant.const import Platform
from homeassistant.core import HomeAssistant
from homeassistant.helpers import selector as selectors
from homeassistant.helpers.selector import (
    BooleanSelector,
    FileSelector,
    FileSelectorConfig,
    NumberSelector,
    NumberSelectorConfig,
    NumberSelectorMode,
    SelectOptionDict,
    Selector,
    SelectSelector,
    SelectSelectorConfig,
    SelectSelectorMode,
    TextSelector,
    TextSelectorConfig,
    TextSelectorType,
)
from homeassistant.helpers.translation import async_get_translations

from .compat import BinarySensorDeviceClass, vol
from .pyplc.core.descriptor import Field, FieldKind, Form, SourceDescriptor

PORT_SELECTOR: Final = NumberSelector(
    NumberSelectorConfig(min=1, max=65535, step=1, mode=NumberSelectorMode.BOX)
)
HOST_SELECTOR: Final = TextSelector()
USERNAME_SELECTOR: Final = TextSelector(
    TextSelectorConfig(type=TextSelectorType.TEXT, autocomplete="username")
)
PASSWORD_SELECTOR: Final = TextSelector(
    TextSelectorConfig(type=TextSelectorType.PASSWORD, autocomplete="current-password")
)
DEVICE_CLASSES: Final[Mapping[Platform, type[StrEnum]]] = {
    Platform.BINARY_SENSOR: BinarySensorDeviceClass,
    Platform.NUMBER: NumberDeviceClass,
}
"""The device classes of the platforms whose classes a point may take."""
SELECTORS: Final[Mapping[FieldKind, Selector[Any]]] = {
    FieldKind.URL: HOST_SELECTOR,
    FieldKind.HOST: HOST_SELECTOR,
    FieldKind.PORT: PORT_SELECTOR,
    FieldKind.TEXT: TextSelector(),
    FieldKind.USERNAME: USERNAME_SELECTOR,
    FieldKind.PASSWORD: PASSWORD_SELECTOR,
    FieldKind.BOOLEAN: BooleanSelector(),
}


def field_selector(field: Field, accept: Iterable[str] = ()) -> Selector[Any]:
    """Return the selector of a field (a point map's upload takes ``accept``)."""
    if field.kind is FieldKind.POINT_MAP:
        return FileSelector(
            FileSelectorConfig(accept=",".join(f".{ending}" for ending in accept))
        )
    return SELECTORS[field.kind]


def form_schema(
    form: Form | tuple[Field, ...],
    *,
    reconfigure: bool = False,
    accept: Iterable[str] = (),
    uploaded: bool = False,
) -> vol.Schema:
    """Return the schema of a descriptor's form (or of some fields).

    ``uploaded``: the flow has read a map file of the form already (see the
    module's docstring).
    """
    fields = form.fields if isinstance(form, Form) else form
    schema: dict[Any, Selector[Any]] = {}
    for field in fields:
        optional = (
            not field.required
            or (reconfigure and field.secret)
            or (uploaded and field.kind is FieldKind.POINT_MAP)
        )
        marker: type[vol.Required | vol.Optional] = (
            vol.Optional if optional else vol.Required
        )
        key = (
            marker(field.key)
            if field.default is None
            else marker(field.key, default=field.default)
        )
        schema[key] = field_selector(field, accept)
    return vol.Schema(schema)


def without_secrets(
    values: Mapping[str, Any], descriptor: SourceDescriptor
) -> dict[str, Any]:
    """Return form values without the descriptor's secrets (never shown again)."""
    secrets = descriptor.secrets
    return {key: value for key, value in values.items() if key not in secrets}


async def async_device_class_selector(
    hass: HomeAssistant, platform: Platform
) -> Selector[Any]:
    """Return Home Assistant's selector of a platform's device classes.

    The frontend lists them by their names in the viewing user's language,
    and the selector takes only them. Home Assistant 2026.2 has none: there, a
    list of the platform's classes labelled with Home Assistant's names of
    them in its language.
    """
    factory: Any = getattr(selectors, "DeviceClassSelector", None)
    if factory is not None:
        found: Selector[Any] = factory({"domain": platform})
        return found
    # Home Assistant 2026.2 (its floor test covers it).
    classes = DEVICE_CLASSES[platform]  # pragma: no cover
    names = await async_get_translations(  # pragma: no cover
        hass, hass.config.language, "entity_component", [platform]
    )
    prefix = f"component.{platform}.entity_component"  # pragma: no cover
    return SelectSelector(  # pragma: no cover
        SelectSelectorConfig(
            options=[
                SelectOptionDict(
                    value=str(item), label=names.get(f"{prefix}.{item}.name", str(item))
                )
                for item in classes
            ],
            mode=SelectSelectorMode.DROPDOWN,
            sort=True,
        )
    )
