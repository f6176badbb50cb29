"""The base the config and options flows share, and the helpers both use.

Both flows answer steps whose IDs a source names (its connection form's, its
sign-in form's, its options' in its own words): :class:`PlcFlow` finds such a
step among the registered sources. Both take a point map as an uploaded file,
kept for the flow's life (Home Assistant's ``file_upload``), and show a
failure of the device as the source's descriptor maps it to a form error.
"""

from abc import ABC, abstractmethod
from collections.abc import Callable, Coroutine, Mapping
from typing import Any

from homeassistant.config_entries import (
    ConfigEntry,
    ConfigEntryBaseFlow,
    ConfigFlowResult,
)
from homeassistant.core import HomeAssistant
from homeassistant.helpers.selector import (
    SelectOptionDict,
    SelectSelector,
    SelectSelectorConfig,
    SelectSelectorMode,
)
from homeassistant.setup import async_setup_component

from ..const import LOGGER
from ..messages import async_load_texts, map_error_text
from ..point_maps import KeptUpload, PointMapUploadError, async_load_point_map
from ..pyplc import PlcError
from ..pyplc.core.descriptor import CONF_POINT_MAP, SourceDescriptor
from ..pyplc.core.pointmap import PointMap, PointMapError
from ..pyplc.core.registry import sources

type StepHandler = Callable[
    [dict[str, Any] | None], Coroutine[Any, Any, ConfigFlowResult]
]


class PlcFlow(ABC, ConfigEntryBaseFlow):
    """A flow of the integration's entries: its config flow or its options flow.

    Its steps include forms whose IDs are a source's own (:meth:`_source_step`
    says which step answers one), and it may read an uploaded map.
    """

    def __init__(self) -> None:
        """Start with no map uploaded (an upload is kept once read)."""
        self._upload = KeptUpload()

    def __getattr__(self, name: str) -> StepHandler:
        """Return the step of a form whose ID a source names: ``async_step_<ID>``."""
        step = name.removeprefix("async_step_")
        if step != name:
            for descriptor in sources():
                if (handler := self._source_step(descriptor, step)) is not None:
                    return handler
        raise AttributeError(name)

    @abstractmethod
    def _source_step(
        self, descriptor: SourceDescriptor, step: str
    ) -> StepHandler | None:
        """Return the step answering a form of a source with this ID (None: none)."""

    async def _async_read_upload(
        self,
        descriptor: SourceDescriptor,
        file_id: str | None,
        placeholders: dict[str, str],
        form: Mapping[str, Any],
        stored: PointMap | None = None,
    ) -> tuple[PointMap | None, dict[str, str]]:
        """Return an uploaded map as the entry takes it, or the form's errors.

        No file (``None``): the map this flow read before (a form shown again
        after an error has the file optional only then). The map is adopted as
        the source's descriptor says (``adopt_map``: what the form's fields say
        of it, what the entry's ``stored`` map does). The reason it cannot be
        (for a file that cannot be read: the row and the column) goes to
        ``placeholders``' ``error``, the error on the field at fault.
        """
        if file_id is None:
            point_map = self._upload.map
            assert point_map is not None, "the file is optional only once a map is read"
        else:
            try:
                point_map = await self._upload.async_read(
                    self.hass, descriptor, file_id
                )
            except PointMapUploadError as err:
                placeholders["error"] = err.message
                return None, {CONF_POINT_MAP: err.key}
        if descriptor.adopt_map is None:
            return point_map, {}
        try:
            return descriptor.adopt_map(point_map, form, stored), {}
        except PointMapError as err:
            await async_load_texts(self.hass)
            placeholders["error"] = map_error_text(self.hass, err)
            return None, {err.column or CONF_POINT_MAP: "point_map_invalid"}


def form_errors(
    descriptor: SourceDescriptor,
    err: PlcError,
    placeholders: dict[str, str],
    field: str | None = None,
) -> dict[str, str]:
    """Return the form error of a failure, as the source's descriptor maps it.

    On the rule's field, or on ``field`` where the form has only that one (an
    upload). What its message shows of the failure (the device's code) goes to
    the form's ``placeholders``; a failure no rule maps, or one it says to log,
    is logged.
    """
    rule = descriptor.error_for(err)
    if rule is None or rule.logged:
        LOGGER.exception("The device answered the check with an error")
    if rule is None:
        return {"base": "unknown"}
    placeholders.update(rule.shown(err))
    return {field or rule.field: rule.key}


async def async_setup_file_upload(hass: HomeAssistant) -> None:
    """Set up Home Assistant's file upload, which a map's upload field posts to."""
    await async_setup_component(hass, "file_upload", {})


async def async_stored_map(hass: HomeAssistant, entry: ConfigEntry) -> PointMap | None:
    """Return the point map an entry stores beside it (None: it has none)."""
    if (map_id := entry.data.get(CONF_POINT_MAP)) is None:
        return None
    return await async_load_point_map(hass, map_id)


def point_picker(labels: Mapping[str, str], *, ticked: bool = False) -> SelectSelector:
    """Return a list of points by key, each by its label, none chosen beforehand.

    The frontend searches a list of several choices (a picker filtering as one
    types, among thousands of points), without a custom value: a step that
    wants one point refuses more. It is an optional field without a default:
    the frontend fills a required choice with its first option, which Submit
    would then take. ``ticked``: a list of boxes to tick instead (a few points,
    all in sight), which preselects nothing even as a required field.
    """
    return SelectSelector(
        SelectSelectorConfig(
            options=[
                SelectOptionDict(value=key, label=label)
                for key, label in labels.items()
            ],
            mode=SelectSelectorMode.LIST if ticked else SelectSelectorMode.DROPDOWN,
            multiple=True,
        )
    )
