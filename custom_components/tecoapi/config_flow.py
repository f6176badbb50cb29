"""Config flow for the Tecomat TecoApi integration."""

from collections.abc import Mapping, Sequence
from ipaddress import ip_address
import re
from typing import TYPE_CHECKING, Any, Final, override

from homeassistant.config_entries import (
    ConfigEntry,
    ConfigEntryState,
    ConfigFlow,
    ConfigFlowResult,
    ConfigSubentryFlow,
    OptionsFlow,
    SubentryFlowResult,
)
from homeassistant.const import (
    CONF_HOST,
    CONF_PASSWORD,
    CONF_PORT,
    CONF_USERNAME,
    CONF_VERIFY_SSL,
)
from homeassistant.core import callback
from homeassistant.data_entry_flow import AbortFlow, SectionConfig, section
from homeassistant.helpers import device_registry as dr
from homeassistant.helpers.selector import (
    BooleanSelector,
    SelectOptionDict,
    SelectSelector,
    SelectSelectorConfig,
    SelectSelectorMode,
    TextSelector,
    TextSelectorConfig,
    TextSelectorType,
)
from homeassistant.helpers.service_info.dhcp import DhcpServiceInfo

from .compat import entry_device, vol
from .connection import create_source, transport_of
from .const import (
    CONF_PLCCOMS_HOST,
    CONF_PLCCOMS_PORT,
    CONF_PUSH,
    CONF_TRANSPORT,
    DEFAULT_PLCCOMS_PORT,
    DOMAIN,
    LOGGER,
    Transport,
)
from .discovery import Probe, async_probe, discovered_host, moved_host
from .options import OPTIONS_SCHEMA, PORT_SELECTOR, PUSH_SCHEMA, TecoApiOptions
from .pytecoapi import (
    InvalidHostError,
    NoPublicVariablesError,
    NotAPlcError,
    PlcAuthenticationError,
    PlcConnectionError,
    PlcError,
    PlcInfo,
    PlcResponseError,
    PlcTlsError,
    Point,
    normalize_host,
)
from .pytecoapi.devices import (
    COMPOSITIONS,
    CompositionError,
    DeviceKind,
    compose,
    fitting_points,
)
from .reconcile import entry_title

if TYPE_CHECKING:
    from .pytecoapi.source import PlcSource

# A host name (RFC 1123 labels); PLCComS takes no scheme, port or path in it.
HOST_NAME: Final = re.compile(
    r"[A-Za-z0-9](?:[A-Za-z0-9-]{0,62})(?:\.[A-Za-z0-9-]{1,63})*\.?"
)

# Shown in forms as the directive to write in Mosaic; braces cannot appear in a
# translation string, where they mark placeholders.
FORM_PLACEHOLDERS: Final = {"public_api": "{PUBLIC_API}"}

HOST_SELECTOR: Final = TextSelector()
USERNAME_SELECTOR: Final = TextSelector(
    TextSelectorConfig(type=TextSelectorType.TEXT, autocomplete="username")
)
PASSWORD_SELECTOR: Final = TextSelector(
    TextSelectorConfig(type=TextSelectorType.PASSWORD, autocomplete="current-password")
)

CONNECTION_SCHEMA: Final = vol.Schema(
    {
        vol.Required(CONF_HOST): HOST_SELECTOR,
        vol.Required(CONF_USERNAME): USERNAME_SELECTOR,
        vol.Required(CONF_PASSWORD): PASSWORD_SELECTOR,
        vol.Required(CONF_VERIFY_SSL, default=True): BooleanSelector(),
    }
)
# Reconfiguring keeps the stored password unless another one is typed.
RECONFIGURE_SCHEMA: Final = vol.Schema(
    {
        vol.Required(CONF_HOST): HOST_SELECTOR,
        vol.Required(CONF_USERNAME): USERNAME_SELECTOR,
        vol.Optional(CONF_PASSWORD): PASSWORD_SELECTOR,
        vol.Required(CONF_VERIFY_SSL, default=True): BooleanSelector(),
    }
)
PLCCOMS_SCHEMA: Final = vol.Schema(
    {
        vol.Required(CONF_HOST): HOST_SELECTOR,
        vol.Required(CONF_PORT, default=DEFAULT_PLCCOMS_PORT): PORT_SELECTOR,
    }
)
CREDENTIALS_SCHEMA: Final = vol.Schema(
    {
        vol.Required(CONF_USERNAME): USERNAME_SELECTOR,
        vol.Required(CONF_PASSWORD): PASSWORD_SELECTOR,
    }
)


class TecoApiConfigFlow(ConfigFlow, domain=DOMAIN):
    """Set up a Tecomat PLC from its address and TecoApi credentials."""

    VERSION = 1

    def __init__(self) -> None:
        """Start a flow; a discovered PLC's address is kept for its confirm step."""
        self._discovered_host: str | None = None

    @classmethod
    @callback
    @override
    def async_get_supported_subentry_types(
        cls, config_entry: ConfigEntry
    ) -> dict[str, type[ConfigSubentryFlow]]:
        """Typed devices composed from the PLC's points: one subentry each."""
        return dict.fromkeys(COMPOSED_KINDS, CompositionFlow)

    @staticmethod
    @callback
    @override
    def async_get_options_flow(config_entry: ConfigEntry) -> OptionsFlow:
        """Options: polling cadence and which variables become entities."""
        return TecoApiOptionsFlow()

    @override
    async def async_step_user(
        self, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """Ask how to reach the PLC: its web server (TecoApi) or PLCComS alone."""
        return self.async_show_menu(
            step_id="user", menu_options=[Transport.TECOAPI, Transport.PLCCOMS]
        )

    async def async_step_tecoapi(
        self, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """Ask for the PLC's address and credentials, then check them on the PLC."""
        connection = None if user_input is None else _normalized(user_input)
        result, errors = await self._async_add_connection(connection, (CONF_HOST,))
        return result or self.async_show_form(
            step_id="tecoapi",
            data_schema=self._suggested(CONNECTION_SCHEMA, user_input),
            description_placeholders=FORM_PLACEHOLDERS,
            errors=errors,
        )

    async def async_step_plccoms(
        self, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """Ask for a PLCComS server's address, then check it lists the PLC's variables.

        PLCComS has no authentication: the form says so.
        """
        connection = None if user_input is None else _plccoms_connection(user_input)
        result, errors = await self._async_add_connection(
            connection, (CONF_HOST, CONF_PORT)
        )
        return result or self.async_show_form(
            step_id="plccoms",
            data_schema=self._suggested(PLCCOMS_SCHEMA, user_input),
            errors=errors,
        )

    async def async_step_dhcp(
        self, discovery_info: DhcpServiceInfo
    ) -> ConfigFlowResult:
        """Handle a device with a Teco MAC prefix joining the network.

        A known PLC (its device has this MAC) gets its new address, if it was
        configured by IP address. Anything else is offered only if it answers as
        a TecoApi server.
        """
        mac = dr.format_mac(discovery_info.macaddress)
        # Until the serial number is known, the MAC tells this PLC's flows apart
        # (and matches a discovery the user chose to ignore).
        await self.async_set_unique_id(mac)
        self._abort_if_unique_id_configured()
        if (entry := self._entry_of_device(mac)) is not None:
            await self.async_set_unique_id(entry.unique_id)
            host = moved_host(entry.data[CONF_HOST], discovery_info.ip)
            self._abort_if_configured(None if host is None else {CONF_HOST: host})
        base_url = discovered_host(discovery_info.ip)
        probe = await async_probe(self.hass, base_url)
        if probe is not Probe.TECOAPI:
            return self.async_abort(reason=probe.value)
        self._discovered_host = base_url
        self.context["title_placeholders"] = {"name": discovery_info.ip}
        return await self.async_step_dhcp_confirm()

    async def async_step_dhcp_confirm(
        self, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """Ask a discovered PLC's TecoApi credentials, then check them."""
        host = self._discovered_host
        if TYPE_CHECKING:
            assert host is not None
        connection = (
            None
            if user_input is None
            else {CONF_HOST: host, CONF_VERIFY_SSL: True, **user_input}
        )
        result, errors = await self._async_add_connection(connection, (CONF_HOST,))
        return result or self.async_show_form(
            step_id="dhcp_confirm",
            data_schema=self._suggested(CREDENTIALS_SCHEMA, user_input),
            description_placeholders={**FORM_PLACEHOLDERS, CONF_HOST: host},
            errors=errors,
        )

    def _entry_of_device(self, mac: str) -> ConfigEntry | None:
        """Return the entry of the PLC device with this MAC, if one is configured."""
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
        """Start reauthentication: the PLC rejected the stored credentials."""
        return await self.async_step_reauth_confirm()

    async def async_step_reauth_confirm(
        self, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """Ask for new credentials and check them on the same PLC."""
        entry = self._get_reauth_entry()
        result, errors = await self._async_update_same_plc(
            entry, None if user_input is None else {**entry.data, **user_input}
        )
        return result or self.async_show_form(
            step_id="reauth_confirm",
            data_schema=self._suggested(CREDENTIALS_SCHEMA, entry.data),
            description_placeholders={
                **FORM_PLACEHOLDERS,
                CONF_HOST: entry.data[CONF_HOST],
            },
            errors=errors,
        )

    async def async_step_reconfigure(
        self, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """Change the address or credentials of the same PLC.

        An empty password keeps the stored one: moving the PLC to another address
        does not ask for it again.
        """
        entry = self._get_reconfigure_entry()
        plccoms = transport_of(entry.data) is Transport.PLCCOMS
        connection = None
        if user_input is not None and plccoms:
            connection = _plccoms_connection(user_input)
        elif user_input is not None:
            password = user_input.get(CONF_PASSWORD) or entry.data[CONF_PASSWORD]
            connection = _normalized({**user_input, CONF_PASSWORD: password})
        result, errors = await self._async_update_same_plc(entry, connection)
        if result is not None:
            return result
        if plccoms:
            return self.async_show_form(
                step_id="reconfigure_plccoms",
                data_schema=self._suggested(PLCCOMS_SCHEMA, user_input or entry.data),
                errors=errors,
            )
        return self.async_show_form(
            step_id="reconfigure",
            data_schema=self._suggested(RECONFIGURE_SCHEMA, user_input or entry.data),
            description_placeholders=FORM_PLACEHOLDERS,
            errors=errors,
        )

    async def async_step_reconfigure_plccoms(
        self, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """Change the address of a PLCComS entry's server (the same PLC)."""
        return await self.async_step_reconfigure(user_input)

    async def _async_update_same_plc(
        self, entry: ConfigEntry, connection: dict[str, Any] | None
    ) -> tuple[ConfigFlowResult | None, dict[str, str]]:
        """Check a new connection of an entry's PLC and store it (reauth, reconfigure).

        Returns the flow's end, or the form's errors (none while nothing was
        submitted). It must reach the same PLC (serial number). A loaded entry is
        reloaded by its update listener; one that is not loaded (setup failed) is
        reloaded here.
        """
        if connection is None:
            return None, {}
        info, errors = await self._async_try_connect(connection)
        if info is None:
            return None, errors
        await self.async_set_unique_id(info.serial_number)
        self._abort_if_unique_id_mismatch(reason="wrong_device")
        if entry.state is ConfigEntryState.LOADED:
            return self.async_update_and_abort(entry, data=connection), {}
        return self.async_update_reload_and_abort(entry, data=connection), {}

    async def _async_add_connection(
        self, connection: dict[str, Any] | None, address: Sequence[str]
    ) -> tuple[ConfigFlowResult | None, dict[str, str]]:
        """Check a new PLC's connection and add its entry (new, add and DHCP steps).

        Returns the flow's end, or the form's errors (none while nothing was
        submitted). A PLC configured already keeps its entry, with the connection's
        ``address`` keys stored in it.
        """
        if connection is None:
            return None, {}
        info, errors = await self._async_try_connect(connection)
        if info is None:
            return None, errors
        await self.async_set_unique_id(info.serial_number, raise_on_progress=False)
        self._abort_if_configured({key: connection[key] for key in address})
        return self.async_create_entry(title=entry_title(info), data=connection), {}

    def _abort_if_configured(self, address: dict[str, Any] | None) -> None:
        """Abort if the PLC is configured already; store its new address, if any.

        A loaded entry is reloaded by its update listener when the address changed;
        one that is not loaded is reloaded here.
        """
        entry = self.hass.config_entries.async_entry_for_domain_unique_id(
            DOMAIN, str(self.unique_id)
        )
        self._abort_if_unique_id_configured(
            updates=address,
            reload_on_update=entry is None
            or entry.state is not ConfigEntryState.LOADED,
        )

    def _suggested(
        self, schema: vol.Schema, values: Mapping[str, Any] | None
    ) -> vol.Schema:
        """Return the form's schema showing what was typed or stored, but the password."""
        return self.add_suggested_values_to_schema(
            schema,
            {
                key: value
                for key, value in (values or {}).items()
                if key != CONF_PASSWORD
            },
        )

    async def _async_try_connect(
        self, connection: Mapping[str, Any]
    ) -> tuple[PlcInfo | None, dict[str, str]]:
        """Return the PLC's info, or the form errors explaining why there is none.

        The source is closed again: a PLCComS check leaves no connection open.
        """
        plccoms = transport_of(connection) is Transport.PLCCOMS
        if plccoms and not _is_host_name(connection[CONF_HOST]):
            return None, {CONF_HOST: "invalid_plccoms_host"}
        source: PlcSource | None = None
        try:
            source = create_source(self.hass, connection)
            return await source.identify(), {}
        except InvalidHostError:
            return None, {CONF_HOST: "invalid_host"}
        except PlcTlsError:
            return None, {"base": "tls_not_trusted"}
        except PlcConnectionError:
            return None, {
                "base": "plccoms_cannot_connect" if plccoms else "cannot_connect"
            }
        except NoPublicVariablesError:
            return None, {
                "base": "plccoms_no_variables" if plccoms else "no_public_variables"
            }
        except PlcAuthenticationError:
            return None, {"base": "invalid_auth"}
        except NotAPlcError:
            return None, {"base": "not_tecoapi"}
        except PlcResponseError:
            LOGGER.exception("The PLC answered the connection check with an error")
            return None, {"base": "unknown"}
        except Exception:  # noqa: BLE001
            LOGGER.exception("Unexpected error while checking the PLC")
            return None, {"base": "unknown"}
        finally:
            if source is not None:
                await source.close()


class TecoApiOptionsFlow(OptionsFlow):
    """Polling cadence, which PLC variables become entities, and push (PLCComS)."""

    async def async_step_init(
        self, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """Show the options, or store them (they apply without a restart).

        A TecoApi entry's form has a *Push* section: a PLCComS server beside
        TecoApi, checked before it is stored (it answers, and it lists this
        PLC's variables). Nothing turns it on but the user.
        """
        entry = self.config_entry
        tecoapi = transport_of(entry.data) is Transport.TECOAPI
        current = TecoApiOptions.from_entry(entry)
        errors: dict[str, str] = {}
        if user_input is not None:
            options = TecoApiOptions.from_form(
                {**user_input, **user_input.get(CONF_PUSH, {})}
            )
            if tecoapi and options.plccoms not in (None, current.plccoms):
                errors = await self._async_check_plccoms(options)
            if not errors:
                return self.async_create_entry(data=options.as_dict())
        shown = current.as_dict() if user_input is None else user_input
        push = {
            key: shown.get(CONF_PUSH, shown).get(key)
            for key in (CONF_PLCCOMS_HOST, CONF_PLCCOMS_PORT)
        }
        schema = OPTIONS_SCHEMA
        if tecoapi:
            # Folded away while push is off.
            folded = SectionConfig(collapsed=not push[CONF_PLCCOMS_HOST])
            schema = schema.extend(
                {vol.Required(CONF_PUSH): section(PUSH_SCHEMA, folded)}
            )
        suggested = {**shown, CONF_PUSH: push}
        return self.async_show_form(
            step_id="init",
            data_schema=self.add_suggested_values_to_schema(schema, suggested),
            errors=errors,
        )

    async def _async_check_plccoms(self, options: TecoApiOptions) -> dict[str, str]:
        """Check a PLCComS server for push: it answers and lists this PLC's variables.

        Its variables (read once, T_ApiObjects grouped as TecoApi shows them) are
        compared with the entry's (when it is loaded): another PLC's share none.
        Every error is the Push section's: the frontend shows it right above the
        section, next to the Submit button (an error of the form sits at its top,
        out of sight, and one of a field inside a section is not shown at all).
        """
        host, port = options.plccoms or ("", 0)
        if not _is_host_name(host):
            return {CONF_PUSH: "invalid_plccoms_host"}
        source = create_source(
            self.hass,
            {CONF_TRANSPORT: Transport.PLCCOMS, CONF_HOST: host, CONF_PORT: port},
        )
        try:
            await source.identify()
            listed = (await source.poll(())).catalogue.points.keys()
        except PlcConnectionError:
            return {CONF_PUSH: "plccoms_cannot_connect"}
        except NoPublicVariablesError:
            return {CONF_PUSH: "plccoms_no_variables"}
        except PlcError:
            LOGGER.exception("The PLCComS server answered the check with an error")
            return {CONF_PUSH: "unknown"}
        finally:
            await source.close()
        entry = self.config_entry
        if entry.state is ConfigEntryState.LOADED and listed.isdisjoint(
            entry.runtime_data.data.catalogue.points
        ):
            return {CONF_PUSH: "plccoms_other_plc"}
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
    choice is checked as a whole (``pytecoapi.devices.compose``) before it is
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
                SelectOptionDict(value=point.key, label=_point_label(point))
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


def _point_label(point: Point) -> str:
    """How a point is offered in a list: its title and its path."""
    title = point.meta.title.strip() if point.meta is not None else ""
    return f"{title} ({point.path})" if title else point.path


def _normalized(user_input: Mapping[str, Any]) -> dict[str, Any]:
    """Return the submitted connection with the host as a base URL, if it is one.

    An invalid host stays as typed; the connection check reports it on the field.
    """
    try:
        host = normalize_host(user_input[CONF_HOST])
    except InvalidHostError:
        host = user_input[CONF_HOST]
    return {**user_input, CONF_HOST: host}


def _plccoms_connection(user_input: Mapping[str, Any]) -> dict[str, Any]:
    """Return a PLCComS entry's data from the submitted host and port."""
    return {
        CONF_TRANSPORT: Transport.PLCCOMS.value,
        CONF_HOST: str(user_input[CONF_HOST]).strip(),
        CONF_PORT: int(user_input[CONF_PORT]),
    }


def _is_host_name(host: str) -> bool:
    """Whether ``host`` is an IP address or a host name, with nothing around it."""
    try:
        ip_address(host)
    except ValueError:
        return HOST_NAME.fullmatch(host) is not None
    return True
