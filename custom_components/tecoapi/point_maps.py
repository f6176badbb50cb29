"""Point maps beside their entries: a versioned store each, and the uploads they come from.

A source whose points the user supplies (``Capability.POINT_MAP``) keeps its map
in a Home Assistant ``Store`` of its own (``tecoapi.point_map.<id>``), not in the
entry's data, which only names it (``point_map``: the ID). A map arrives as a
file uploaded through Home Assistant's ``file_upload`` and is read by the
library's loaders (``pyplc.core.pointmap``) off the event loop.
"""

from pathlib import Path
from typing import Any, Final

from homeassistant.components.file_upload import process_uploaded_file
from homeassistant.core import HomeAssistant
from homeassistant.helpers.storage import Store
from homeassistant.util.ulid import ulid_hex

from .const import DOMAIN
from .messages import async_load_texts, map_error_text
from .pyplc.core.descriptor import SourceDescriptor
from .pyplc.core.pointmap import PointMap, PointMapError, load

STORAGE_VERSION: Final = 1
"""The version of a stored map (the library's JSON, ``PointMap.as_json``)."""


class PointMapUploadError(Exception):
    """An uploaded map that cannot be used: ``key`` is the form error's.

    ``message`` says why (for a file that cannot be read: the row and the
    column), for the form's ``{error}``, in Home Assistant's language.
    """

    def __init__(self, key: str, message: str) -> None:
        """Keep the form error and the reason."""
        super().__init__(message)
        self.key = key
        self.message = message


def _store(hass: HomeAssistant, map_id: str) -> Store[dict[str, Any]]:
    return Store(hass, STORAGE_VERSION, f"{DOMAIN}.point_map.{map_id}")


async def async_save_point_map(
    hass: HomeAssistant, point_map: PointMap, map_id: str | None = None
) -> str:
    """Store a map (under a new ID unless one is given); return its ID."""
    map_id = map_id or ulid_hex()
    await _store(hass, map_id).async_save(point_map.as_json())
    return map_id


async def async_load_point_map(hass: HomeAssistant, map_id: str) -> PointMap | None:
    """Return a stored map (None: there is none)."""
    data = await _store(hass, map_id).async_load()
    return None if data is None else PointMap.from_json(data)


async def async_remove_point_map(hass: HomeAssistant, map_id: str) -> None:
    """Remove a stored map."""
    await _store(hass, map_id).async_remove()


async def async_read_upload(
    hass: HomeAssistant, descriptor: SourceDescriptor, file_id: str
) -> PointMap:
    """Read an uploaded file as a map of one of the source's formats.

    The file is removed once read. Raises :class:`PointMapUploadError`.
    """

    def read() -> tuple[bytes, str]:
        with process_uploaded_file(hass, file_id) as path:
            return Path(path).read_bytes(), Path(path).name

    try:
        data, name = await hass.async_add_executor_job(read)
    except ValueError as err:
        # The form error says it all: the file is gone.
        raise PointMapUploadError("point_map_missing", "") from err
    await async_load_texts(hass)
    try:
        return await hass.async_add_executor_job(
            load,
            data,
            name,
            descriptor.point_map_loaders,
            descriptor.check_address,
            descriptor.point_types,
        )
    except PointMapError as err:
        raise PointMapUploadError(
            "point_map_invalid", map_error_text(hass, err)
        ) from err


class KeptUpload:
    """The map of the file a flow's form was given last: read once, kept for the flow.

    Home Assistant removes an uploaded file once it is read. A form shown again
    after an error (a wrong password, a port) does not name the file (the
    frontend would show a file it did not upload itself as "Unknown file"):
    submitted without one, it gives the map read before. The same file ID
    submitted again gives the same map (or the same reason it could not be
    read). Only the last file's is kept.
    """

    def __init__(self) -> None:
        """Keep nothing yet."""
        self._kept: tuple[str, PointMap | PointMapUploadError] | None = None

    @property
    def map(self) -> PointMap | None:
        """The map read last (None: nothing read yet, or a file that could not be)."""
        if self._kept is None or isinstance(self._kept[1], PointMapUploadError):
            return None
        return self._kept[1]

    async def async_read(
        self, hass: HomeAssistant, descriptor: SourceDescriptor, file_id: str
    ) -> PointMap:
        """Return the map of an uploaded file (see :func:`async_read_upload`)."""
        if self._kept is None or self._kept[0] != file_id:
            try:
                read: PointMap | PointMapUploadError = await async_read_upload(
                    hass, descriptor, file_id
                )
            except PointMapUploadError as err:
                read = err
            self._kept = (file_id, read)
        if isinstance(found := self._kept[1], PointMapUploadError):
            raise PointMapUploadError(found.key, found.message)
        return found
