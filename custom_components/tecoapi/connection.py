"""The one place that builds a PLC source from what a config entry stores."""

from collections.abc import Mapping
from datetime import timedelta
from typing import Any

from homeassistant.const import CONF_HOST, CONF_PASSWORD, CONF_USERNAME, CONF_VERIFY_SSL
from homeassistant.core import HomeAssistant
from homeassistant.helpers.aiohttp_client import async_get_clientsession
from homeassistant.util import dt as dt_util

from .const import DEFAULT_ATTRIBUTE_INTERVAL, REQUEST_TIMEOUT
from .pytecoapi import TecoApiClient
from .pytecoapi.session import TecoApiSession

CONNECTION_KEYS = (CONF_HOST, CONF_USERNAME, CONF_PASSWORD, CONF_VERIFY_SSL)
"""The entry data a source is built from: a change needs a new source."""


def create_source(
    hass: HomeAssistant,
    data: Mapping[str, Any],
    *,
    metadata_interval: timedelta = DEFAULT_ATTRIBUTE_INTERVAL,
) -> TecoApiSession:
    """Return the source that reaches the PLC the entry data describes.

    It shares Home Assistant's HTTP session, keeps time by Home Assistant's clock
    and plans its reads in Home Assistant's executor.
    """
    verify_ssl: bool = data[CONF_VERIFY_SSL]
    client = TecoApiClient(
        async_get_clientsession(hass, verify_ssl=verify_ssl),
        data[CONF_HOST],
        data[CONF_USERNAME],
        data[CONF_PASSWORD],
        verify_ssl=verify_ssl,
        timeout=REQUEST_TIMEOUT,
    )
    return TecoApiSession(
        client,
        metadata_interval=metadata_interval,
        clock=dt_util.utcnow,
        run_blocking=hass.async_add_executor_job,
    )
