"""Checking a device and storing its entry: what the config flow's steps share.

A submitted connection form is prepared as the source's descriptor says (a map
uploaded with it is read), the device is asked who it is (the source closed
again after), and the entry is added, or an entry's connection is changed to
reach the same device (reauthentication, reconfiguration). A device configured
already keeps its entry; one told apart by where it is (a gateway) gets a
numbered unique ID where another entry holds its identity.
"""

from abc import abstractmethod
from collections.abc import Mapping
from itertools import chain, count
from typing import TYPE_CHECKING, Any

from homeassistant.config_entries import (
    SOURCE_RECONFIGURE,
    ConfigEntry,
    ConfigEntryState,
    ConfigFlow,
    ConfigFlowResult,
)

from ..compat import vol
from ..connection import descriptor_of, source_context
from ..const import CONF_EXCLUDE, CONF_TRANSPORT, DOMAIN, LOGGER
from ..forms import without_secrets
from ..options import PlcOptions
from ..point_maps import async_save_point_map
from ..pyplc import PlcAuthenticationError, PlcError, SourceInfo
from ..pyplc.core.descriptor import CONF_POINT_MAP, SourceDescriptor, SourceOptions
from ..pyplc.core.pointmap import PointMap
from ..reconcile import entry_title
from .base import PlcFlow, async_stored_map, form_errors

if TYPE_CHECKING:
    from ..pyplc.core.source import PlcSource


class DeviceConfigFlow(PlcFlow, ConfigFlow):
    """The config flow's checks of a device, and how it stores what they found."""

    def __init__(self) -> None:
        """Start a flow: a typed secret is shown again after an error, unless refused."""
        super().__init__()
        self._secret_refused = False

    async def _async_prepare(
        self,
        descriptor: SourceDescriptor,
        user_input: Mapping[str, Any],
        placeholders: dict[str, str],
    ) -> tuple[dict[str, Any] | None, PointMap | None, dict[str, str]]:
        """Return a submitted form as the connection to store, and its point map.

        Or the form's errors: an uploaded map that cannot be read (the row and
        the column in its message), a host that is none.
        """
        self._secret_refused = False
        form = {
            key: value for key, value in user_input.items() if key != CONF_POINT_MAP
        }
        point_map = None
        # Without a file, the map read before (the form shown again asks none).
        file_id = user_input.get(CONF_POINT_MAP)
        if file_id is not None or self._upload.map is not None:
            point_map, errors = await self._async_read_upload(
                descriptor, file_id, placeholders
            )
            if point_map is None:
                return None, None, errors
        try:
            connection = named(descriptor, descriptor.prepare(form))
        except PlcError as err:
            return None, None, form_errors(descriptor, err, placeholders)
        return connection, point_map, {}

    async def _async_update_same_device(
        self,
        entry: ConfigEntry,
        descriptor: SourceDescriptor,
        connection: dict[str, Any] | None,
        placeholders: dict[str, str],
    ) -> tuple[ConfigFlowResult | None, dict[str, str]]:
        """Check a new connection of an entry's device and store it (reauth, reconfigure).

        Returns the flow's end, or the form's errors (none while nothing was
        submitted). It must reach the same device (identity; a device that
        tells none of its own keeps the entry's). A loaded entry is reloaded
        by its update listener; one that is not loaded (setup failed) is
        reloaded here.
        """
        if connection is None:
            return None, {}
        info, errors = await self._async_try_connect(
            descriptor,
            connection,
            await async_stored_map(self.hass, entry),
            placeholders,
            identity=entry.unique_id,
        )
        if info is None:
            return None, errors
        words = descriptor.words
        await self.async_set_unique_id(info.identity)
        self._abort_if_unique_id_mismatch(reason=words.wrong_device)
        if (other := self._entry_at(descriptor, connection, entry)) is not None:
            return self.async_abort(
                reason="device_of_another_entry",
                description_placeholders={"title": other.title},
            ), {}
        # Stored new credentials say so in every system's words.
        reason = (
            words.reconfigured
            if self.source == SOURCE_RECONFIGURE
            else "reauth_successful"
        )
        if entry.state is ConfigEntryState.LOADED:
            return self.async_update_and_abort(
                entry, data=connection, reason=reason
            ), {}
        return self.async_update_reload_and_abort(
            entry, data=connection, reason=reason
        ), {}

    async def _async_add_connection(
        self,
        descriptor: SourceDescriptor,
        connection: dict[str, Any],
        point_map: PointMap | None,
        placeholders: dict[str, str],
    ) -> tuple[ConfigFlowResult | None, dict[str, str]]:
        """Check a new device's connection and add its entry (new and DHCP steps).

        Returns the flow's end, or the form's errors. A device configured already
        keeps its entry, with the connection's address stored in it. A point map
        is stored beside the entry (a store of its own), named in its data.
        """
        info, errors = await self._async_try_connect(
            descriptor, connection, point_map, placeholders
        )
        if info is None:
            return None, errors
        if self._entry_at(descriptor, connection) is not None:
            return self.async_abort(reason=descriptor.words.already_configured), {}
        await self._async_abort_if_configured(
            descriptor,
            self._unique_id(
                descriptor, await self._known_identity(descriptor, info.identity)
            ),
            {key: connection[key] for key in descriptor.address if key in connection},
            raise_on_progress=False,
        )
        # What the source leaves out until the user says otherwise.
        options = (
            {CONF_EXCLUDE: list(descriptor.default_exclude)}
            if descriptor.default_exclude
            else None
        )
        if point_map is None:
            return self.async_create_entry(
                title=entry_title(info), data=connection, options=options
            ), {}
        connection[CONF_POINT_MAP] = await async_save_point_map(self.hass, point_map)
        return self.async_create_entry(
            title=entry_title(info),
            data=connection,
            options=options,
            description="point_map",
            description_placeholders=map_counts(
                point_map, PlcOptions.from_form(options or {})
            ),
        ), {}

    async def _known_identity(self, descriptor: SourceDescriptor, identity: str) -> str:
        """Return the identity of the entry of the same device, spelled otherwise.

        A device known by its address (a gateway added as ``localhost:2000``
        before, now as ``127.0.0.1:2000``) is one device: its entry's identity.
        Else the identity found.
        """
        if (canonical := descriptor.canonical_identity) is None:
            return identity
        for entry in self._async_current_entries(include_ignore=False):
            if (
                entry.unique_id not in (None, identity)
                and descriptor_of(entry.data) is descriptor
                and await canonical(str(entry.unique_id)) == identity
            ):
                return str(entry.unique_id)
        return identity

    @abstractmethod
    async def _async_abort_if_configured(
        self,
        descriptor: SourceDescriptor,
        unique_id: str | None,
        address: dict[str, Any] | None,
        *,
        raise_on_progress: bool = True,
    ) -> None:
        """Take the device's unique ID; abort if an entry has it already.

        Home Assistant reads this check where it reads the flow
        (``config_flow.PlcConfigFlow`` defines it); the entry that has it keeps
        the new ``address``, if any.
        """

    def _entry_at(
        self,
        descriptor: SourceDescriptor,
        connection: Mapping[str, Any],
        moved: ConfigEntry | None = None,
    ) -> ConfigEntry | None:
        """Return the entry of the source's device at a connection's location, if any.

        Only for a source whose devices are told apart by where they are
        (``location``). ``moved`` is an entry being reconfigured: it may stay
        where it is.
        """
        if not descriptor.location:
            return None

        def where(data: Mapping[str, Any]) -> list[Any]:
            return [data.get(key) for key in descriptor.location]

        if moved is not None and where(moved.data) == where(connection):
            return None
        return next(
            (
                entry
                for entry in self._async_current_entries(include_ignore=False)
                if descriptor_of(entry.data) is descriptor
                and where(entry.data) == where(connection)
            ),
            None,
        )

    def _unique_id(self, descriptor: SourceDescriptor, identity: str) -> str:
        """Return a new entry's unique ID: its device's identity, numbered if taken.

        Only for a source whose devices are told apart by where they are, once
        no entry is at the new one's location: an entry holding the identity
        was added there and moved since, and the device there now is another.
        """
        if not descriptor.location:
            return identity
        taken = {
            entry.unique_id for entry in self.hass.config_entries.async_entries(DOMAIN)
        }
        numbered = (f"{identity} ({number})" for number in count(2))
        return next(
            unique_id
            for unique_id in chain([identity], numbered)
            if unique_id not in taken
        )

    def _suggested(
        self,
        schema: vol.Schema,
        values: Mapping[str, Any] | None,
        descriptor: SourceDescriptor,
        *,
        typed: bool = False,
    ) -> vol.Schema:
        """Return the form's schema showing what was typed or stored.

        A stored secret is never shown; one ``typed`` in the form is shown again
        after an error, unless the device refused it (the error is about it).
        An uploaded file is never suggested (see :mod:`..forms`).
        """
        shown = {
            key: value for key, value in (values or {}).items() if key != CONF_POINT_MAP
        }
        if not typed or self._secret_refused:
            shown = without_secrets(shown, descriptor)
        return self.add_suggested_values_to_schema(schema, shown)

    async def _async_try_connect(
        self,
        descriptor: SourceDescriptor,
        connection: Mapping[str, Any],
        point_map: PointMap | None,
        placeholders: dict[str, str],
        identity: str | None = None,
    ) -> tuple[SourceInfo | None, dict[str, str]]:
        """Return the device's info, or the form errors explaining why there is none.

        ``identity`` is the entry's, for a device it has. The failure's
        details its message shows go to ``placeholders``. The source is
        closed again: a check leaves no connection open.
        """
        source: PlcSource | None = None
        try:
            source = descriptor.create(
                source_context(self.hass),
                connection,
                SourceOptions(point_map=point_map, identity=identity),
            )
            return await source.identify(), {}
        except PlcError as err:
            self._secret_refused = isinstance(err, PlcAuthenticationError)
            return None, form_errors(descriptor, err, placeholders)
        except Exception:  # noqa: BLE001
            LOGGER.exception("Unexpected error while checking the device")
            return None, {"base": "unknown"}
        finally:
            if source is not None:
                await source.close()


def named(descriptor: SourceDescriptor, connection: dict[str, Any]) -> dict[str, Any]:
    """Return a connection as stored: with its source's name, where it stores one."""
    return (
        {**connection, CONF_TRANSPORT: descriptor.name}
        if descriptor.stores_name
        else connection
    )


def map_counts(point_map: PointMap, options: PlcOptions) -> dict[str, str]:
    """Return what a new entry's map holds: its points, those shown, rows left out."""
    shown = sum(1 for point in point_map.points if options.matches(point.key))
    return {
        "points": str(len(point_map.points)),
        "entities": str(shown),
        "skipped": str(len(point_map.skipped)),
    }
