"""The config flow's steps: a device added, discovered, signed in again, moved.

The first step offers each source the library knows (``pyplc.core.registry``);
its connection, reconfiguration and sign-in forms are made of the fields its
descriptor declares, its errors are the ones its descriptor maps failures to.
No step is written for one source: adding a source adds its forms here by
itself (compare ``zha``'s radio types). A source that takes a point map asks
for it as an uploaded file (Home Assistant's ``file_upload``, as ``knx``
imports an ETS project).
"""

from collections.abc import Mapping
from functools import partial
from typing import TYPE_CHECKING, Any, override

from homeassistant.config_entries import ConfigEntry, ConfigFlowResult
from homeassistant.const import CONF_HOST
from homeassistant.helpers import device_registry as dr
from homeassistant.helpers.aiohttp_client import async_get_clientsession
from homeassistant.helpers.service_info.dhcp import DhcpServiceInfo

from ..compat import entry_device
from ..connection import descriptor_of
from ..discovery import moved_host
from ..forms import form_schema
from ..pyplc.core.descriptor import FieldKind, SourceDescriptor
from ..pyplc.core.registry import sources
from .base import StepHandler, async_setup_file_upload
from .device import DeviceConfigFlow, named


class ConfigFlowSteps(DeviceConfigFlow):
    """Add a device through one of the sources the library knows.

    Home Assistant's flow (``config_flow.PlcConfigFlow``) is this one,
    registered for the domain.
    """

    def __init__(self) -> None:
        """Start a flow; a discovered device's source and address wait for its confirm.

        An uploaded map is kept for the flow's life (its file is gone once read);
        a typed secret is shown again after an error, unless the device refused it.
        """
        super().__init__()
        self._discovered: tuple[SourceDescriptor, str] | None = None

    @override
    async def async_step_user(
        self, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """Ask which way into the device: one choice per source."""
        return self.async_show_menu(
            step_id="user",
            menu_options=[descriptor.connect.step_id for descriptor in sources()],
        )

    @override
    def _source_step(
        self, descriptor: SourceDescriptor, step: str
    ) -> StepHandler | None:
        """Return the step of a source's form: ``async_step_<its step ID>``.

        A source's connection form is its own step; its reconfigure form's ID is
        answered by :meth:`async_step_reconfigure`, its sign-in form's (its
        words' ``reauth_step_id``) by :meth:`async_step_reauth_confirm`.
        """
        if step == descriptor.connect.step_id:
            return partial(self._async_step_connect, descriptor)
        if step == descriptor.reconfigure.step_id:
            return self.async_step_reconfigure
        if step == descriptor.words.reauth_step_id:
            return self.async_step_reauth_confirm
        return None

    async def _async_step_connect(
        self, descriptor: SourceDescriptor, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """Ask for a source's connection, then check it on the device."""
        form = descriptor.connect
        if _takes_upload(descriptor):
            await async_setup_file_upload(self.hass)
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
                form_schema(
                    form,
                    accept=descriptor.point_map_formats,
                    uploaded=self._upload.map is not None,
                ),
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
            host = moved_host(entry.data[CONF_HOST], discovery_info.ip)
            await self._async_abort_if_configured(
                descriptor_of(entry.data),
                entry.unique_id,
                None if host is None else {CONF_HOST: host},
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
            connection = named(
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


def _takes_upload(descriptor: SourceDescriptor) -> bool:
    """Whether a source's connection form uploads a file."""
    return any(field.kind is FieldKind.POINT_MAP for field in descriptor.connect.fields)
