"""A real Home Assistant instance for the benchmark, made the way the tests make one."""

from collections import Counter
from collections.abc import AsyncIterator, Iterator
from contextlib import asynccontextmanager, contextmanager
from dataclasses import dataclass, field
import tempfile
from types import MappingProxyType
from typing import Any, Final
from unittest.mock import PropertyMock, patch

from aiohttp.resolver import ThreadedResolver
from homeassistant import loader
from homeassistant.config_entries import ConfigEntryState
from homeassistant.const import (
    CONF_HOST,
    CONF_PASSWORD,
    CONF_SCAN_INTERVAL,
    CONF_USERNAME,
    CONF_VERIFY_SSL,
    EVENT_STATE_CHANGED,
)
from homeassistant.core import Event, HomeAssistant, callback
from homeassistant.helpers import frame
from homeassistant.helpers.entity import Entity
from pytest_homeassistant_custom_component.common import (
    MockConfigEntry,
    async_test_home_assistant,
)

from custom_components.tecoapi.const import (
    CONF_ATTRIBUTE_INTERVAL,
    CONF_PLAIN_VARIABLES,
    DOMAIN,
    MAX_ATTRIBUTE_INTERVAL,
    MAX_SCAN_INTERVAL,
    PlainVariables,
)


class _PlainResolver(ThreadedResolver):
    """The resolver the `mock_zeroconf_resolver` fixture stands in with, as a class."""

    async def real_close(self) -> None:
        """Close (Home Assistant calls this name when it stops)."""
        await self.close()


@asynccontextmanager
async def bench_home_assistant() -> AsyncIterator[HomeAssistant]:
    """A running Home Assistant with a throwaway config directory; stopped after.

    As in the tests, the shared aiohttp session resolves names with a plain resolver
    instead of zeroconf's (which would need the network integration).
    """
    resolver = _PlainResolver()
    with (
        tempfile.TemporaryDirectory(prefix="tecoapi-bench-") as config_dir,
        patch(
            "homeassistant.helpers.aiohttp_client._async_make_resolver",
            return_value=resolver,
        ),
    ):
        async with async_test_home_assistant(config_dir=config_dir) as hass:
            # As the `enable_custom_integrations` fixture: find custom_components.
            hass.data.pop(loader.DATA_CUSTOM_COMPONENTS, None)
            frame.async_setup(hass)
            try:
                yield hass
            finally:
                for entry in hass.config_entries.async_entries():
                    if entry.state is ConfigEntryState.LOADED:
                        await hass.config_entries.async_unload(entry.entry_id)
                await hass.async_stop(force=True)


BENCH_OPTIONS: Final = MappingProxyType(
    {
        CONF_SCAN_INTERVAL: int(MAX_SCAN_INTERVAL.total_seconds()),
        CONF_ATTRIBUTE_INTERVAL: int(MAX_ATTRIBUTE_INTERVAL.total_seconds()),
        CONF_PLAIN_VARIABLES: PlainVariables.ENABLED.value,
    }
)
"""Options that poll only when told to, every variable an entity (see bench_entry)."""


def bench_entry(url: str, username: str, password: str, serial: str) -> MockConfigEntry:
    """A config entry polling only when told to, every variable an entity.

    The polling and attribute intervals are the longest allowed, so that only the
    benchmark's own refreshes poll (all of them value polls); plain variables are
    enabled so that every point of the PLC has an entity.
    """
    return MockConfigEntry(
        domain=DOMAIN,
        title="Benchmark PLC",
        unique_id=serial,
        data={
            CONF_HOST: url,
            CONF_USERNAME: username,
            CONF_PASSWORD: password,
            CONF_VERIFY_SSL: True,
        },
        options=dict(BENCH_OPTIONS),
    )


@contextmanager
def all_entities_enabled() -> Iterator[None]:
    """Create every entity enabled, as the `entity_registry_enabled_by_default` fixture."""
    with patch.object(
        Entity,
        "entity_registry_enabled_default",
        new_callable=PropertyMock,
        return_value=True,
    ):
        yield


@dataclass(slots=True)
class StateWrites:
    """Entity state writes (`async_write_ha_state` calls) and state changes seen."""

    by_entity: Counter[str] = field(default_factory=Counter)
    changes: int = 0

    @property
    def writes(self) -> int:
        """State writes of all entities."""
        return self.by_entity.total()


@contextmanager
def counting_state_writes(hass: HomeAssistant) -> Iterator[StateWrites]:
    """Count every entity's state writes and the state machine's state changes."""
    counts = StateWrites()
    original = Entity.async_write_ha_state

    @callback
    def counted(entity: Entity) -> None:
        counts.by_entity[entity.entity_id] += 1
        original(entity)

    @callback
    def state_changed(event: Event[Any]) -> None:
        counts.changes += 1

    unsubscribe = hass.bus.async_listen(EVENT_STATE_CHANGED, state_changed)
    try:
        with patch.object(Entity, "async_write_ha_state", counted):
            yield counts
    finally:
        unsubscribe()
