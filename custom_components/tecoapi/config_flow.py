"""Config flow: every source's forms, built from its descriptor.

Home Assistant looks here for the domain's config flow, its options flow and
its subentry flows; their steps live in :mod:`.flows` (one module per job, on a
base the config and options flows share). The first step offers each source the
library knows (``pyplc.core.registry``); its connection, reconfiguration and
sign-in forms are made of the fields its descriptor declares, its errors are
the ones its descriptor maps failures to, and what its options offer follows
its capabilities. No step is written for one source: adding a source adds its
forms by itself (compare ``zha``'s radio types).
"""

from typing import override

from homeassistant.config_entries import ConfigEntry, ConfigSubentryFlow, OptionsFlow
from homeassistant.core import callback

from .const import DOMAIN, ENTRY_MINOR_VERSION, ENTRY_VERSION
from .flows.config import ConfigFlowSteps
from .flows.options import PlcOptionsFlow
from .flows.subentry import COMPOSED_KINDS, CompositionFlow

__all__ = ["CompositionFlow", "PlcConfigFlow", "PlcOptionsFlow"]


class PlcConfigFlow(ConfigFlowSteps, domain=DOMAIN):
    """Add a device through one of the sources the library knows."""

    VERSION = ENTRY_VERSION
    MINOR_VERSION = ENTRY_MINOR_VERSION

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
