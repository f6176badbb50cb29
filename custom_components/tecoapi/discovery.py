"""DHCP discovery: where a known device moved to.

Whether a device that joined the network is one a source speaks to is the
source's to say (its descriptor's ``probe``). A known device found at a new IP
address keeps its entry; its stored address follows the move here.
"""

from ipaddress import ip_address

from yarl import URL


def moved_host(stored: str, ip: str) -> str | None:
    """Return the stored base URL with a new address, or None if nothing moves.

    Scheme and port stay. A device configured by name is left alone: its name
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
