"""Config flow: every source's forms, built from its descriptor.

The first step offers each source the library knows (``pyplc.core.registry``);
its connection, reconfiguration and sign-in forms are made of the fields its
descriptor declares, its errors are the ones its descriptor maps failures to,
and what its options offer follows its capabilities. No step is written for one
source: adding a source adds its forms here by itself (compare ``zha``'s radio
types). A source that takes a point map asks for it as an uploaded file
(Home Assistant's ``file_upload``, as ``knx`` imports an ETS project).
"""

from collections.abc import Callable, Coroutine, Iterable, Mapping
from functools import partial
from itertools import chain, count
from typing import TYPE_CHECKING, Any, Final, override

from homeassistant.config_entries import (
    SOURCE_RECONFIGURE,
    ConfigEntry,
    ConfigEntryState,
    ConfigFlow,
    ConfigFlowResult,
    ConfigSubentryFlow,
    OptionsFlow,
    SubentryFlowResult,
)
from homeassistant.const import CONF_HOST
from homeassistant.core import HomeAssistant, callback
from homeassistant.data_entry_flow import AbortFlow
from homeassistant.helpers import device_registry as dr
from homeassistant.helpers.aiohttp_client import async_get_clientsession
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
from homeassistant.helpers.service_info.dhcp import DhcpServiceInfo
from homeassistant.setup import async_setup_component

from .compat import entry_device, vol
from .connection import descriptor_of, source_context
from .const import (
    CONF_EXCLUDE,
    CONF_PUSH,
    CONF_TRANSPORT,
    DOMAIN,
    ENTRY_MINOR_VERSION,
    ENTRY_VERSION,
    LOGGER,
)
from .discovery import moved_host
from .forms import field_selector, form_schema, without_secrets
from .mapping import point_label
from .options import PlcOptions, settings_schema
from .point_maps import (
    KeptUpload,
    PointMapUploadError,
    async_load_point_map,
    async_save_point_map,
)
from .pyplc import (
    PlcAuthenticationError,
    PlcError,
    SourceInfo,
)
from .pyplc.core.composition import (
    COMPOSITIONS,
    CompositionError,
    compose,
    fitting_points,
)
from .pyplc.core.descriptor import (
    CONF_POINT_MAP,
    Capability,
    Field,
    FieldKind,
    SourceDescriptor,
    SourceOptions,
)
from .pyplc.core.devices import DeviceKind
from .pyplc.core.pointmap import (
    CSV_COLUMNS,
    MapPoint,
    PointMap,
    PointMapError,
    cells_of,
    point_key,
    point_of,
)
from .pyplc.core.registry import sources
from .reconcile import entry_title

if TYPE_CHECKING:
    from .pyplc.core.source import PlcSource

__all__ = ["entry_title"]

type StepHandler = Callable[
    [dict[str, Any] | None], Coroutine[Any, Any, ConfigFlowResult]
]


class PlcConfigFlow(ConfigFlow, domain=DOMAIN):
    """Add a device through one of the sources the library knows."""

    VERSION = ENTRY_VERSION
    MINOR_VERSION = ENTRY_MINOR_VERSION

    def __init__(self) -> None:
        """Start a flow; a discovered device's source and address wait for its confirm.

        An uploaded map is kept for the flow's life (its file is gone once read);
        a typed secret is shown again after an error, unless the device refused it.
        """
        self._discovered: tuple[SourceDescriptor, str] | None = None
        self._upload = KeptUpload()
        self._secret_refused = False

    @classmethod
    @callback
    @override
    def async_get_supported_subentry_types(
        cls, config_entry: ConfigEntry
    ) -> dict[str, type[ConfigSubentryFlow]]:
        """Typed devices composed from the device's points: one subentry each."""
        return dict.fromkeys(COMPOSED_KINDS, CompositionFlow)

    @staticmethod
    @callback
    @override
    def async_get_options_flow(config_entry: ConfigEntry) -> OptionsFlow:
        """Options: polling cadence, which points become entities, push."""
        return PlcOptionsFlow()

    @override
    async def async_step_user(
        self, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """Ask which way into the device: one choice per source."""
        return self.async_show_menu(
            step_id="user",
            menu_options=[descriptor.connect.step_id for descriptor in sources()],
        )

    def __getattr__(self, name: str) -> StepHandler:
        """Return the step of a source's form: ``async_step_<its step ID>``.

        A source's connection form is its own step; its reconfigure form's ID is
        answered by :meth:`async_step_reconfigure`, its sign-in form's (its
        words' ``reauth_step_id``) by :meth:`async_step_reauth_confirm`.
        """
        step = name.removeprefix("async_step_")
        if step != name:
            for descriptor in sources():
                if step == descriptor.connect.step_id:
                    return partial(self._async_step_connect, descriptor)
                if step == descriptor.reconfigure.step_id:
                    return self.async_step_reconfigure
                if step == descriptor.words.reauth_step_id:
                    return self.async_step_reauth_confirm
        raise AttributeError(name)

    async def _async_step_connect(
        self, descriptor: SourceDescriptor, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """Ask for a source's connection, then check it on the device."""
        form = descriptor.connect
        if _takes_upload(descriptor):
            await _async_setup_file_upload(self.hass)
        result: ConfigFlowResult | None = None
        errors: dict[str, str] = {}
        placeholders = dict(form.placeholders)
        if user_input is not None:
            connection, point_map, errors = await self._async_prepare(
                descriptor, user_input, placeholders
            )
            if connection is not None:
                result, errors = await self._async_add_connection(
                    descriptor, connection, point_map, placeholders
                )
        return result or self.async_show_form(
            step_id=form.step_id,
            data_schema=self._suggested(
                form_schema(form, accept=descriptor.point_map_formats),
                user_input,
                descriptor,
                typed=True,
            ),
            description_placeholders=placeholders,
            errors=errors,
        )

    async def async_step_dhcp(
        self, discovery_info: DhcpServiceInfo
    ) -> ConfigFlowResult:
        """Handle a device with a known MAC prefix joining the network.

        A known device (its device has this MAC) gets its new address, if it was
        configured by IP address. Anything else is offered only if a source's
        probe finds one of its devices there.
        """
        mac = dr.format_mac(discovery_info.macaddress)
        # Until the device's identity is known, the MAC tells its flows apart
        # (and matches a discovery the user chose to ignore).
        await self.async_set_unique_id(mac)
        self._abort_if_unique_id_configured()
        if (entry := self._entry_of_device(mac)) is not None:
            await self.async_set_unique_id(entry.unique_id)
            host = moved_host(entry.data[CONF_HOST], discovery_info.ip)
            self._abort_if_configured(
                descriptor_of(entry.data), None if host is None else {CONF_HOST: host}
            )
        reason = "cannot_connect"
        session = async_get_clientsession(self.hass)
        for descriptor in sources():
            if descriptor.probe is None:
                continue
            found, host = await descriptor.probe(session, discovery_info.ip)
            if found is None:
                self._discovered = (descriptor, host)
                self.context["title_placeholders"] = {"name": discovery_info.ip}
                return await self.async_step_dhcp_confirm()
            reason = found
        return self.async_abort(reason=reason)

    async def async_step_dhcp_confirm(
        self, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """Ask a discovered device's credentials, then check them."""
        if TYPE_CHECKING:
            assert self._discovered is not None
        descriptor, host = self._discovered
        result: ConfigFlowResult | None = None
        errors: dict[str, str] = {}
        placeholders = {**descriptor.connect.placeholders, CONF_HOST: host}
        if user_input is not None:
            defaults = {
                field.key: field.default
                for field in descriptor.connect.fields
                if field.default is not None
            }
            # A discovered host is one the source found: it needs no preparing
            # beyond the source's own.
            connection = _named(
                descriptor,
                descriptor.prepare({**defaults, CONF_HOST: host, **user_input}),
            )
            result, errors = await self._async_add_connection(
                descriptor, connection, None, placeholders
            )
        return result or self.async_show_form(
            step_id="dhcp_confirm",
            data_schema=self._suggested(
                form_schema(descriptor.credentials), user_input, descriptor, typed=True
            ),
            description_placeholders=placeholders,
            errors=errors,
        )

    def _entry_of_device(self, mac: str) -> ConfigEntry | None:
        """Return the entry of the device with this MAC, if one is configured."""
        connection = (dr.CONNECTION_NETWORK_MAC, mac)
        return next(
            (
                entry
                for entry in self._async_current_entries(include_ignore=False)
                if entry_device(self.hass, entry.entry_id, connection=connection)
            ),
            None,
        )

    async def async_step_reauth(
        self, entry_data: Mapping[str, Any]
    ) -> ConfigFlowResult:
        """Start reauthentication: the device rejected the stored credentials."""
        return await self.async_step_reauth_confirm()

    async def async_step_reauth_confirm(
        self, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """Ask for new credentials and check them on the same device."""
        entry = self._get_reauth_entry()
        descriptor = descriptor_of(entry.data)
        placeholders = {
            **descriptor.connect.placeholders,
            CONF_HOST: entry.data[CONF_HOST],
        }
        result, errors = await self._async_update_same_device(
            entry,
            descriptor,
            None if user_input is None else {**entry.data, **user_input},
            placeholders,
        )
        return result or self.async_show_form(
            step_id=descriptor.words.reauth_step_id,
            data_schema=self._suggested(
                form_schema(descriptor.credentials), entry.data, descriptor
            ),
            description_placeholders=placeholders,
            errors=errors,
        )

    async def async_step_reconfigure(
        self, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """Change where the same device is (and its credentials).

        An empty secret keeps the stored one: moving the device to another
        address does not ask for its password again.
        """
        entry = self._get_reconfigure_entry()
        descriptor = descriptor_of(entry.data)
        form = descriptor.reconfigure
        placeholders = dict(form.placeholders)
        connection = None
        if user_input is not None:
            kept = {
                field.key: entry.data[field.key]
                for field in form.fields
                if field.secret and not user_input.get(field.key)
            }
            prepared, _, errors = await self._async_prepare(
                descriptor, {**user_input, **kept}, placeholders
            )
            if prepared is None:
                return self._reconfigure_form(
                    descriptor, user_input, errors, placeholders
                )
            connection = {
                key: value
                for key, value in entry.data.items()
                if key not in descriptor.connection_keys
            } | prepared
        result, errors = await self._async_update_same_device(
            entry, descriptor, connection, placeholders
        )
        return result or self._reconfigure_form(
            descriptor, user_input or entry.data, errors, placeholders
        )

    def _reconfigure_form(
        self,
        descriptor: SourceDescriptor,
        values: Mapping[str, Any],
        errors: dict[str, str],
        placeholders: dict[str, str],
    ) -> ConfigFlowResult:
        """Show a source's reconfigure form with what was typed or stored."""
        form = descriptor.reconfigure
        return self.async_show_form(
            step_id=form.step_id,
            data_schema=self._suggested(
                form_schema(form, reconfigure=True),
                values,
                descriptor,
                typed=bool(errors),
            ),
            description_placeholders=placeholders,
            errors=errors,
        )

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
        if (file_id := user_input.get(CONF_POINT_MAP)) is not None:
            try:
                point_map = await self._upload.async_read(
                    self.hass, descriptor, file_id
                )
            except PointMapUploadError as err:
                placeholders["error"] = err.message
                return None, None, {CONF_POINT_MAP: err.key}
        try:
            connection = _named(descriptor, descriptor.prepare(form))
        except PlcError as err:
            return None, None, _form_errors(descriptor, err, placeholders)
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
            await _async_stored_map(self.hass, entry),
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
        await self.async_set_unique_id(
            self._unique_id(
                descriptor, await self._known_identity(descriptor, info.identity)
            ),
            raise_on_progress=False,
        )
        self._abort_if_configured(
            descriptor,
            {key: connection[key] for key in descriptor.address if key in connection},
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

    def _abort_if_configured(
        self, descriptor: SourceDescriptor, address: dict[str, Any] | None
    ) -> None:
        """Abort if the device is configured already; store its new address, if any.

        A loaded entry is reloaded by its update listener when the address changed;
        one that is not loaded is reloaded here. The abort says so in the
        source's words (a gateway is no PLC).
        """
        entry = self.hass.config_entries.async_entry_for_domain_unique_id(
            DOMAIN, str(self.unique_id)
        )
        self._abort_if_unique_id_configured(
            updates=address,
            reload_on_update=entry is None
            or entry.state is not ConfigEntryState.LOADED,
            error=descriptor.words.already_configured,
        )

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
        """
        shown = values or {}
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
            return None, _form_errors(descriptor, err, placeholders)
        except Exception:  # noqa: BLE001
            LOGGER.exception("Unexpected error while checking the device")
            return None, {"base": "unknown"}
        finally:
            if source is not None:
                await source.close()


def _form_errors(
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


def _named(descriptor: SourceDescriptor, connection: dict[str, Any]) -> dict[str, Any]:
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


def _takes_upload(descriptor: SourceDescriptor) -> bool:
    """Whether a source's connection form uploads a file."""
    return any(field.kind is FieldKind.POINT_MAP for field in descriptor.connect.fields)


async def _async_setup_file_upload(hass: HomeAssistant) -> None:
    """Set up Home Assistant's file upload, which a map's upload field posts to."""
    await async_setup_component(hass, "file_upload", {})


async def _async_stored_map(hass: HomeAssistant, entry: ConfigEntry) -> PointMap | None:
    """Return the point map an entry stores beside it (None: it has none)."""
    if (map_id := entry.data.get(CONF_POINT_MAP)) is None:
        return None
    return await async_load_point_map(hass, map_id)


class PlcOptionsFlow(OptionsFlow):
    """Polling cadence, which points become entities, a push server; a map's points.

    A source whose points the user supplies starts with a menu: its settings,
    a newer map to upload, and a point to add, change or remove. Every change
    of the map applies at once, in place: points kept keep their entities.
    """

    def __init__(self) -> None:
        """Start with no point chosen yet, and no map uploaded (kept once read)."""
        self._editing: str | None = None
        self._upload = KeptUpload()

    def __getattr__(self, name: str) -> StepHandler:
        """Return the step of a form whose ID is a source's own (its words').

        Each source's options and settings forms have step IDs of their own,
        so that each speaks of its own system: :meth:`async_step_init` and
        :meth:`async_step_settings` answer them.
        """
        step = name.removeprefix("async_step_")
        if step != name:
            for descriptor in sources():
                if step == descriptor.words.options_step_id:
                    return self.async_step_init
                if step == descriptor.words.settings_step_id:
                    return self.async_step_settings
        raise AttributeError(name)

    async def async_step_init(
        self, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """Show the options, or store them (they apply without a restart).

        The form holds what the entry's source can use: the attribute cadence
        for a source that reads attributes again, what becomes of plain
        variables for a source that has them, and a *Push* section for a source
        that may have a push server beside it (checked before it is stored: it
        answers, and it lists this device's points). Nothing turns push on but
        the user.
        """
        descriptor = descriptor_of(self.config_entry.data)
        words = descriptor.words
        if Capability.POINT_MAP in descriptor.capabilities:
            return self.async_show_menu(
                step_id=words.options_step_id, menu_options=MAP_MENU
            )
        result, schema, errors = await self._async_settings(descriptor, user_input)
        # Without a map, the first step is the settings form.
        return result or self.async_show_form(
            step_id=words.settings_step_id, data_schema=schema, errors=errors
        )

    async def async_step_settings(
        self, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """Show or store the options of a source with a map (its menu's first choice)."""
        descriptor = descriptor_of(self.config_entry.data)
        result, schema, errors = await self._async_settings(descriptor, user_input)
        return result or self.async_show_form(
            step_id=descriptor.words.settings_step_id, data_schema=schema, errors=errors
        )

    async def _async_settings(
        self, descriptor: SourceDescriptor, user_input: dict[str, Any] | None
    ) -> tuple[ConfigFlowResult | None, vol.Schema, dict[str, str]]:
        """Store the options submitted, or return the form and its errors."""
        current = PlcOptions.from_entry(self.config_entry)
        errors: dict[str, str] = {}
        if user_input is not None:
            options = PlcOptions.from_form(user_input, None, descriptor.companion)
            if options.push_server not in (None, current.push_server):
                errors = await self._async_check_push_server(descriptor, options)
            if not errors:
                return (
                    self.async_create_entry(data=options.as_dict()),
                    vol.Schema({}),
                    {},
                )
        shown = current.as_dict() if user_input is None else user_input
        schema = settings_schema(descriptor, shown)
        return None, self.add_suggested_values_to_schema(schema, shown), errors

    # --- the points of a map -----------------------------------------------------

    async def async_step_upload(
        self, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """Take a newer map file: points kept keep their entities and history."""
        descriptor = descriptor_of(self.config_entry.data)
        await _async_setup_file_upload(self.hass)
        errors: dict[str, str] = {}
        placeholders = {"error": ""}
        if user_input is not None:
            try:
                point_map = await self._upload.async_read(
                    self.hass, descriptor, user_input[CONF_POINT_MAP]
                )
            except PointMapUploadError as err:
                placeholders["error"] = err.message
                errors = {CONF_POINT_MAP: err.key}
            else:
                errors = await self._async_check_map(
                    descriptor, point_map, placeholders
                )
                if not errors:
                    return await self._async_take_map(point_map)
        return self.async_show_form(
            step_id="upload",
            data_schema=self.add_suggested_values_to_schema(
                vol.Schema(
                    {
                        vol.Required(CONF_POINT_MAP): field_selector(
                            MAP_FIELD, descriptor.point_map_formats
                        )
                    }
                ),
                user_input or {},
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
        found = await _async_stored_map(self.hass, self.config_entry)
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
            return _form_errors(descriptor, err, placeholders, field="base")
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

    async def _async_check_push_server(
        self, descriptor: SourceDescriptor, options: PlcOptions
    ) -> dict[str, str]:
        """Check a push server (the source's companion): it answers and lists this device's points.

        A source of the companion alone reads its points once; they are compared
        with the entry's (when it is loaded):
        another device's share none. Every error is the Push section's: the
        frontend shows it right above the section, next to the Submit button (an
        error of the form sits at its top, out of sight, and one of a field
        inside a section is not shown at all).
        """
        server = descriptor.companion
        assert server is not None
        assert options.push_server is not None
        try:
            connection = server.prepare(options.push_server)
        except PlcError as err:
            rule = server.error_for(err)
            return {CONF_PUSH: rule.key if rule else "unknown"}
        source = server.create(source_context(self.hass), connection, SourceOptions())
        try:
            await source.identify()
            listed = (await source.poll(())).catalogue.points.keys()
        except PlcError as err:
            rule = server.error_for(err)
            if rule is None or rule.logged:
                LOGGER.exception("The push server answered the check with an error")
            return {CONF_PUSH: "unknown" if rule is None else rule.key}
        finally:
            await source.close()
        entry = self.config_entry
        if entry.state is ConfigEntryState.LOADED and listed.isdisjoint(
            entry.runtime_data.data.catalogue.points
        ):
            return {CONF_PUSH: server.other_device}
        return {}


# The composed devices the UI offers (subentry types), and their kinds.
COMPOSED_KINDS: Final[dict[str, DeviceKind]] = {
    "thermostat": DeviceKind.CLIMATE,
    "blind": DeviceKind.COVER,
    "light": DeviceKind.LIGHT,
    "button": DeviceKind.BUTTON,
    "switch": DeviceKind.SWITCH,
}
CONF_KIND: Final = "kind"
CONF_ROLES: Final = "roles"
CONF_NAME: Final = "name"


class CompositionFlow(ConfigSubentryFlow):
    """Add (or change) a typed device made of points the user chooses.

    Each role lists only the points that fit it, shown by title and path; the
    choice is checked as a whole (``pyplc.core.composition.compose``) before it is
    stored. The entry shows the device at once (the other entities stay as
    they are).
    """

    async def async_step_user(
        self, user_input: dict[str, Any] | None = None
    ) -> SubentryFlowResult:
        """Ask for a name and the points of each role.

        Nothing is chosen for the user: the frontend would preselect the first
        point of each required role (the outside temperature as a room's).
        """
        entry = self._loaded_entry()
        composed, errors = self._composed(entry, user_input)
        if composed is not None:
            return self.async_create_entry(title=composed[0], data=composed[1])
        unchosen = {spec.role.value: "" for spec in COMPOSITIONS[self._kind].roles}
        return self.async_show_form(
            step_id="user",
            data_schema=self.add_suggested_values_to_schema(
                self._schema(entry), user_input or unchosen
            ),
            errors=errors,
        )

    async def async_step_reconfigure(
        self, user_input: dict[str, Any] | None = None
    ) -> SubentryFlowResult:
        """Choose other points (a variable vanished with a new program) or a name."""
        entry = self._loaded_entry()
        subentry = self._get_reconfigure_subentry()
        composed, errors = self._composed(entry, user_input)
        if composed is not None:
            return self.async_update_and_abort(
                entry, subentry, title=composed[0], data=composed[1]
            )
        suggested = user_input or {
            CONF_NAME: subentry.title,
            **subentry.data[CONF_ROLES],
        }
        return self.async_show_form(
            step_id="reconfigure",
            data_schema=self.add_suggested_values_to_schema(
                self._schema(entry), suggested
            ),
            errors=errors,
        )

    @property
    def _kind(self) -> DeviceKind:
        return COMPOSED_KINDS[self._subentry_type]

    def _schema(self, entry: ConfigEntry) -> vol.Schema:
        """Return the form: a name, then a list of fitting points per role."""
        points = entry.runtime_data.data.catalogue.points
        fields: dict[Any, Any] = {vol.Required(CONF_NAME): TextSelector()}
        for spec in COMPOSITIONS[self._kind].roles:
            options = [
                SelectOptionDict(value=point.key, label=point_label(point))
                for point in fitting_points(self._kind, spec.role, points)
            ]
            key = (vol.Required if spec.required else vol.Optional)(spec.role.value)
            fields[key] = SelectSelector(
                SelectSelectorConfig(options=options, mode=SelectSelectorMode.DROPDOWN)
            )
        return vol.Schema(fields)

    def _loaded_entry(self) -> ConfigEntry:
        """Return the entry; its points are offered, so it must be loaded."""
        entry = self._get_entry()
        if entry.state is not ConfigEntryState.LOADED:
            raise AbortFlow("entry_not_loaded")
        return entry

    def _composed(
        self, entry: ConfigEntry, user_input: Mapping[str, Any] | None
    ) -> tuple[tuple[str, dict[str, Any]] | None, dict[str, str]]:
        """Return the subentry's title and data, or the form's errors.

        Neither is there before a submit; the choice is checked as a whole.
        """
        if user_input is None:
            return None, {}
        roles = {
            role: key for role, key in user_input.items() if role != CONF_NAME and key
        }
        name = user_input[CONF_NAME].strip()
        if not name:
            return None, {CONF_NAME: "name_missing"}
        try:
            compose(
                self._kind,
                roles,
                entry.runtime_data.data.catalogue.points,
                ident="check",
            )
        except CompositionError as err:
            return None, {str(err.role or "base"): err.problem.value}
        return (name, {CONF_KIND: self._kind.value, CONF_ROLES: roles}), {}


MAP_MENU: Final = ["settings", "upload", "add_point", "edit_point", "remove_point"]
"""The options menu of a source whose points the user supplies."""
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
