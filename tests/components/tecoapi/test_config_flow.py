"""What Home Assistant finds in ``config_flow``: the flows of the domain.

The config flow is the domain's, of this release's entry version; its options
flow is the integration's; each kind of typed device the user composes is a
subentry flow. (The steps themselves are tested under ``flows/``.)
"""

from homeassistant.config_entries import HANDLERS
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.tecoapi.config_flow import (
    CompositionFlow,
    PlcConfigFlow,
    PlcOptionsFlow,
)
from custom_components.tecoapi.const import DOMAIN, ENTRY_MINOR_VERSION, ENTRY_VERSION
from custom_components.tecoapi.flows.subentry import COMPOSED_KINDS


def test_the_domain_s_flows_are_registered() -> None:
    entry = MockConfigEntry(domain=DOMAIN)

    assert HANDLERS[DOMAIN] is PlcConfigFlow
    assert (PlcConfigFlow.VERSION, PlcConfigFlow.MINOR_VERSION) == (
        ENTRY_VERSION,
        ENTRY_MINOR_VERSION,
    )
    assert isinstance(PlcConfigFlow.async_get_options_flow(entry), PlcOptionsFlow)
    subentries = PlcConfigFlow.async_get_supported_subentry_types(entry)
    assert set(subentries) == set(COMPOSED_KINDS)
    assert set(subentries.values()) == {CompositionFlow}
