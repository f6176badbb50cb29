"""Config flow: every source's forms, built from its descriptor.

Home Assistant looks here for the domain's config flow, its options flow and
its subentry flows; their steps live in :mod:`.flows` (one module per job, on a
base the config and options flows share). What Home Assistant's quality scale
reads in this file is defined here (``hassfest`` reads it with ``ast``, not
what it imports): the steps a user starts (``async_step_user``), that Home
Assistant starts (``async_step_reauth``, ``async_step_reconfigure``), the check
that a device is configured once (the unique ID), and the options flow's
factory taking the typed entry; each step hands over to :mod:`.flows`
(``scripts/checks/quality_scale.py`` reads this file as core does). The first step offers each source the
library knows (``pyplc.core.registry``); its connection, reconfiguration and
sign-in forms are made of the fields its descriptor declares, its errors are
the ones its descriptor maps failures to, and what its options offer follows
its capabilities. No step is written for one source: adding a source adds its
forms by itself (compare ``zha``'s radio types).
"""

from collections.abc import Mapping
from typing import Any, override

from homeassistant.config_entries import (
    ConfigEntry,
    ConfigEntryState,
    ConfigFlowResult,
    ConfigSubentryFlow,
    OptionsFlow,
)
from homeassistant.core import callback

from .const import DOMAIN, ENTRY_MINOR_VERSION, ENTRY_VERSION
from .coordinator import PlcConfigEntry
from .flows.config import ConfigFlowSteps
from .flows.options import PlcOptionsFlow
from .flows.subentry import COMPOSED_KINDS, CompositionFlow
from .pyplc.core.descriptor import SourceDescriptor

__all__ = ["CompositionFlow", "PlcConfigFlow", "PlcOptionsFlow"]


class PlcConfigFlow(ConfigFlowSteps, domain=DOMAIN):
    """Add a device through one of the sources the library knows."""

    VERSION = ENTRY_VERSION
    MINOR_VERSION = ENTRY_MINOR_VERSION

    @override
    async def async_step_user(
        self, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """Ask which way into the device: a menu of the sources the library knows."""
        return await super().async_step_user(user_input)

    @override
    async def async_step_reauth(
        self, entry_data: Mapping[str, Any]
    ) -> ConfigFlowResult:
        """Ask for new credentials: the device rejected the stored ones."""
        return await super().async_step_reauth(entry_data)

    @override
    async def async_step_reconfigure(
        self, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """Change where the same device is (and its credentials)."""
        return await super().async_step_reconfigure(user_input)

    @override
    async def _async_abort_if_configured(
        self,
        descriptor: SourceDescriptor,
        unique_id: str | None,
        address: dict[str, Any] | None,
        *,
        raise_on_progress: bool = True,
    ) -> None:
        """Take the device's unique ID; abort if an entry has it already.

        The entry that has it keeps the new ``address``, if any: a loaded entry
        is reloaded by its update listener when the address changed, one that
        is not loaded is reloaded here. The abort says so in the source's words
        (a gateway is no PLC).
        """
        await self.async_set_unique_id(unique_id, raise_on_progress=raise_on_progress)
        entry = self.hass.config_entries.async_entry_for_domain_unique_id(
            DOMAIN, str(self.unique_id)
        )
        self._abort_if_unique_id_configured(
            updates=address,
            reload_on_update=entry is None
            or entry.state is not ConfigEntryState.LOADED,
            error=descriptor.words.already_configured,
        )

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
    def async_get_options_flow(config_entry: PlcConfigEntry) -> OptionsFlow:
        """Options: polling cadence, which points become entities, push."""
        return PlcOptionsFlow()
