"""The one place that makes a source of what a config entry stores.

Which source an entry reaches its device with is its ``transport`` (an entry
without one is of the source that never stored one: TecoApi's); the source's
descriptor (``pyplc.core.registry``) makes it. This module gives every source
what Home Assistant has: its shared HTTP sessions, its clock and its executor.
"""

from collections.abc import Mapping
from typing import Any

from homeassistant.core import HomeAssistant
from homeassistant.helpers.aiohttp_client import async_get_clientsession
from homeassistant.util import dt as dt_util

from .const import CONF_TRANSPORT, REQUEST_TIMEOUT, STREAM_TIMEOUT
from .pyplc.core.descriptor import SourceContext, SourceDescriptor, SourceOptions
from .pyplc.core.registry import sources
from .pyplc.core.source import PlcSource
from .source_cache import EntryCache


def descriptor_of(data: Mapping[str, Any]) -> SourceDescriptor:
    """Return the descriptor of the source an entry's data was made with."""
    name = data.get(CONF_TRANSPORT)
    for descriptor in sources():
        if descriptor.name == name or (name is None and not descriptor.stores_name):
            return descriptor
    raise KeyError(name)


def source_context(hass: HomeAssistant, entry_id: str | None = None) -> SourceContext:
    """Return what Home Assistant gives every source it makes.

    The source of a stored entry (``entry_id``) keeps what it learns of its
    device beside the entry; one that checks a form keeps nothing.
    """
    return SourceContext(
        http=lambda verify_ssl: async_get_clientsession(hass, verify_ssl=verify_ssl),
        clock=dt_util.utcnow,
        run_blocking=hass.async_add_executor_job,
        timeout=REQUEST_TIMEOUT,
        stream_timeout=STREAM_TIMEOUT,
        cache=None if entry_id is None else EntryCache(hass, entry_id),
    )


def create_source(
    hass: HomeAssistant,
    data: Mapping[str, Any],
    options: SourceOptions | None = None,
    entry_id: str | None = None,
) -> PlcSource:
    """Return the source that reaches the device the entry data describes.

    ``options`` are what the entry's options tell it (the metadata cadence, a
    push server, the user's point map); ``entry_id`` names the entry whose
    source it is (its cache).
    """
    return descriptor_of(data).create(
        source_context(hass, entry_id), data, options or SourceOptions()
    )
