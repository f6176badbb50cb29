"""The options flow: polling cadence, which points become entities, push.

What the form holds follows the entry's source's capabilities
(``options.settings_schema``); a source whose points the user supplies starts
with a menu whose other choices edit its map (:mod:`.point_map`), and one that
discovers its points with a menu whose other choices change them
(:mod:`.point_override`).
"""

from typing import Any, Final, override

from homeassistant.config_entries import ConfigEntryState, ConfigFlowResult

from ..compat import vol
from ..connection import descriptor_of, source_context
from ..const import CONF_PUSH, LOGGER
from ..options import PlcOptions, settings_schema, stored_options
from ..pyplc import PlcError
from ..pyplc.core.descriptor import Capability, SourceDescriptor, SourceOptions
from .base import StepHandler
from .point_map import PointMapOptionsFlow
from .point_override import PointOverrideOptionsFlow

MAP_MENU: Final = ["settings", "upload", "add_point", "edit_point", "remove_point"]
"""The options menu of a source whose points the user supplies."""
OVERRIDE_MENU: Final = ["settings", "override_point", "remove_overrides"]
"""The options menu of a source that discovers its points."""


class PlcOptionsFlow(PointOverrideOptionsFlow, PointMapOptionsFlow):
    """Polling cadence, which points become entities, a push server; the points.

    A source whose points the user supplies starts with a menu: its settings,
    a newer map to upload, and a point to add, change or remove. Every change
    of the map applies at once, in place: points kept keep their entities. A
    source that discovers its points starts with a menu too: its settings, and
    a point to change or to return to what its device says.
    """

    @override
    def _source_step(
        self, descriptor: SourceDescriptor, step: str
    ) -> StepHandler | None:
        """Return the step of a form whose ID is a source's own (its words').

        Each source's options, settings and upload forms, and its forms of one
        point, have step IDs of their own, so that each speaks of its own
        system: :meth:`async_step_init`, :meth:`async_step_settings`,
        :meth:`async_step_upload`, :meth:`async_step_add_point` and
        :meth:`async_step_point` answer them.
        """
        words = descriptor.words
        if step == words.options_step_id:
            return self.async_step_init
        if step == words.settings_step_id:
            return self.async_step_settings
        if step == words.upload_step_id:
            return self.async_step_upload
        if step == words.add_point_step_id:
            return self.async_step_add_point
        if step == words.point_step_id:
            return self.async_step_point
        return None

    async def async_step_init(
        self, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """Show the options' menu; its first choice is the settings.

        The settings form (:meth:`async_step_settings`) holds what the entry's
        source can use: the attribute cadence for a source that reads
        attributes again, what becomes of plain variables for a source that has
        them, and a *Push* section for a source that may have a push server
        beside it (checked before it is stored: it answers, and it lists this
        device's points). Nothing turns push on but the user. The options apply
        without a restart.
        """
        descriptor = descriptor_of(self.config_entry.data)
        if Capability.POINT_MAP in descriptor.capabilities:
            menu = MAP_MENU
        else:
            menu = OVERRIDE_MENU
        return self.async_show_menu(
            step_id=descriptor.words.options_step_id, menu_options=menu
        )

    async def async_step_settings(
        self, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """Show or store the settings (the menu's first choice)."""
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
                    self.async_create_entry(data=stored_options(descriptor, options)),
                    vol.Schema({}),
                    {},
                )
        shown = current.as_dict() if user_input is None else user_input
        schema = settings_schema(descriptor, shown)
        return None, self.add_suggested_values_to_schema(schema, shown), errors

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
