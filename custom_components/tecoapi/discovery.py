"""DHCP discovery: is the device behind a MAC address a TecoApi PLC, and where.

Home Assistant offers a device whose MAC starts with a Teco a.s. prefix
(``00:0A:14``) or with ``F8:DC:7A``, the prefix of the manual's example PLC,
which belongs to Variscite, a maker of CPU modules used in other products too.
So before the user is asked for credentials the device must show itself as a
TecoApi server: an unauthenticated ``GET /TecoApi/GetInfo`` answered with a 401
challenge for the ``TecoApi`` realm. Discovery looks at plain HTTP on port 80;
a PLC serving only HTTPS or another port is added by hand.
"""

from enum import StrEnum
from ipaddress import ip_address
from typing import Final

import aiohttp
from homeassistant.core import HomeAssistant
from homeassistant.helpers.aiohttp_client import async_get_clientsession
from yarl import URL

from .pyplc import normalize_host
from .pyplc.tecomat.tecoapi.auth import is_tecoapi_challenge

HTTP_PORT: Final = 80
PROBE_TIMEOUT: Final = aiohttp.ClientTimeout(total=10)


class Probe(StrEnum):
    """What answered at a discovered address."""

    TECOAPI = "tecoapi"
    NOT_TECOAPI = "not_tecoapi"
    UNREACHABLE = "cannot_connect"


def discovered_host(ip: str) -> str:
    """Return the base URL of a discovered PLC's TecoApi (plain HTTP, port 80)."""
    return normalize_host(f"{ip}:{HTTP_PORT}")


def moved_host(stored: str, ip: str) -> str | None:
    """Return the stored base URL with a new address, or None if nothing moves.

    Scheme and port stay. A PLC configured by name is left alone: its name
    follows it to the new address.
    """
    url = URL(stored)
    try:
        ip_address(url.host or "")
    except ValueError:
        return None
    if url.host == ip:
        return None
    return str(url.with_host(ip))


async def async_probe(hass: HomeAssistant, base_url: str) -> Probe:
    """Ask, without credentials, whether a TecoApi server answers at ``base_url``."""
    session = async_get_clientsession(hass)
    try:
        async with session.get(
            f"{base_url}/TecoApi/GetInfo",
            allow_redirects=False,
            timeout=PROBE_TIMEOUT,
        ) as response:
            status = response.status
            challenges = response.headers.getall("WWW-Authenticate", [])
    except (aiohttp.ClientError, TimeoutError):
        return Probe.UNREACHABLE
    if status == 401 and is_tecoapi_challenge(challenges):
        return Probe.TECOAPI
    return Probe.NOT_TECOAPI
