"""The one place that builds a PLC source from what a config entry stores."""

from collections.abc import Mapping
from datetime import timedelta
from typing import Any

from homeassistant.const import (
    CONF_HOST,
    CONF_PASSWORD,
    CONF_PORT,
    CONF_USERNAME,
    CONF_VERIFY_SSL,
)
from homeassistant.core import HomeAssistant
from homeassistant.helpers.aiohttp_client import async_get_clientsession
from homeassistant.util import dt as dt_util

from .const import (
    CONF_TRANSPORT,
    DEFAULT_ATTRIBUTE_INTERVAL,
    PLCCOMS_TIMEOUT,
    REQUEST_TIMEOUT,
    Transport,
)
from .pyplc.core.source import PlcSource
from .pyplc.tecomat import (
    PlcComsClient,
    PlcComsSource,
    PushedTecoApiSession,
    TecoApiClient,
    TecoApiSession,
)

CONNECTION_KEYS = (
    CONF_TRANSPORT,
    CONF_HOST,
    CONF_PORT,
    CONF_USERNAME,
    CONF_PASSWORD,
    CONF_VERIFY_SSL,
)
"""The entry data a source is built from: a change needs a new source."""


def transport_of(data: Mapping[str, Any]) -> Transport:
    """Return how an entry reaches its PLC (entries of 0.1 are TecoApi)."""
    return Transport(data.get(CONF_TRANSPORT, Transport.TECOAPI))


def create_source(
    hass: HomeAssistant,
    data: Mapping[str, Any],
    *,
    metadata_interval: timedelta = DEFAULT_ATTRIBUTE_INTERVAL,
    plccoms: tuple[str, int] | None = None,
) -> PlcSource:
    """Return the source that reaches the PLC the entry data describes.

    TecoApi alone; TecoApi with ``plccoms`` (host, port) pushing the values, when
    the user switched push on; or, for a PLCComS entry, PLCComS alone. It shares
    Home Assistant's HTTP session, keeps time by Home Assistant's clock and plans
    its reads in Home Assistant's executor.
    """
    if transport_of(data) is Transport.PLCCOMS:
        return PlcComsSource(
            PlcComsClient(data[CONF_HOST], data[CONF_PORT], timeout=PLCCOMS_TIMEOUT),
            metadata_interval=metadata_interval,
            clock=dt_util.utcnow,
        )
    verify_ssl: bool = data[CONF_VERIFY_SSL]
    client = TecoApiClient(
        async_get_clientsession(hass, verify_ssl=verify_ssl),
        data[CONF_HOST],
        data[CONF_USERNAME],
        data[CONF_PASSWORD],
        verify_ssl=verify_ssl,
        timeout=REQUEST_TIMEOUT,
    )
    if plccoms is not None:
        return PushedTecoApiSession(
            client,
            PlcComsClient(*plccoms, timeout=PLCCOMS_TIMEOUT),
            metadata_interval=metadata_interval,
            clock=dt_util.utcnow,
            run_blocking=hass.async_add_executor_job,
        )
    return TecoApiSession(
        client,
        metadata_interval=metadata_interval,
        clock=dt_util.utcnow,
        run_blocking=hass.async_add_executor_job,
    )
