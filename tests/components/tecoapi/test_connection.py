"""The one place that makes an entry's source: its descriptor, Home Assistant's context.

An entry's ``transport`` names its source; one without (stored before there
were others) is TecoApi's. The source is given Home Assistant's shared HTTP
sessions, its clock and executor, and, for a stored entry, a cache beside it.
"""

from datetime import timedelta

from homeassistant.const import (
    CONF_HOST,
    CONF_PASSWORD,
    CONF_USERNAME,
    CONF_VERIFY_SSL,
)
from homeassistant.core import HomeAssistant
from homeassistant.helpers.aiohttp_client import async_get_clientsession
import pytest

from custom_components.tecoapi.connection import (
    create_source,
    descriptor_of,
    source_context,
)
from custom_components.tecoapi.const import (
    CONF_TRANSPORT,
    REQUEST_TIMEOUT,
    STREAM_TIMEOUT,
)
from custom_components.tecoapi.pyplc.core.descriptor import SourceOptions
from custom_components.tecoapi.source_cache import EntryCache


def test_an_entry_s_transport_names_its_source() -> None:
    assert descriptor_of({CONF_TRANSPORT: "tekon"}).name == "tekon"
    assert descriptor_of({CONF_TRANSPORT: "mervis"}).name == "mervis"
    # Stored before there were other sources: TecoApi, which stores no name.
    assert descriptor_of({CONF_HOST: "http://10.0.0.7"}).name == "tecoapi"
    with pytest.raises(KeyError):
        descriptor_of({CONF_TRANSPORT: "a later release's"})


async def test_a_source_gets_home_assistant_s_sessions_clock_and_cache(
    hass: HomeAssistant,
) -> None:
    checking = source_context(hass)
    stored = source_context(hass, "e1")

    assert checking.cache is None
    assert isinstance(stored.cache, EntryCache)
    assert stored.http(True) is async_get_clientsession(hass, verify_ssl=True)
    assert stored.http(False) is async_get_clientsession(hass, verify_ssl=False)
    assert (stored.timeout, stored.stream_timeout) == (REQUEST_TIMEOUT, STREAM_TIMEOUT)
    assert stored.clock().tzinfo is not None
    assert await stored.run_blocking(lambda: 6 * 7) == 42  # type: ignore[misc]


async def test_the_source_is_made_as_the_entry_and_its_options_say(
    hass: HomeAssistant,
) -> None:
    source = create_source(
        hass,
        {
            CONF_HOST: "http://127.0.0.1:1",
            CONF_USERNAME: "u",
            CONF_PASSWORD: "p",
            CONF_VERIFY_SSL: True,
        },
        SourceOptions(metadata_interval=timedelta(seconds=17)),
        "e1",
    )
    try:
        assert source.metadata_interval == timedelta(seconds=17)
        assert source.statistics.polls == 0
    finally:
        await source.close()
