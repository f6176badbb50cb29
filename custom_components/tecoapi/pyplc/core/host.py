"""Turn what a user types as the PLC's host into the client's base URL."""

import asyncio
import ipaddress
import re
import socket
from typing import Final

from yarl import URL

from .exceptions import InvalidHostError

_SCHEMES: Final = {"http": 80, "https": 443}
_HOSTNAME_LABEL = re.compile(r"(?!-)[A-Za-z0-9_-]{1,63}(?<!-)")
_PORT = re.compile(r"[0-9]{1,5}")


def normalize_host(host: str, default_port: int | None = None) -> str:
    """Return the base URL for a host field such as ``plc.local:8080``.

    Accepted: an IPv4/IPv6 address or a hostname, an optional ``:port`` and an
    optional ``http://`` or ``https://`` prefix (default ``http``), one trailing
    ``/`` at most. The result is ``scheme://host[:port]`` with the scheme and
    hostname in lower case, IPv6 in brackets and a default port dropped:
    ``"http://192.168.1.10"``, ``"http://plc.local:8080"``, ``"https://[fe80::1]"``.
    Paths, query strings, fragments, user info, other schemes and anything that
    is not a host raise :class:`InvalidHostError`. A host without a port gets
    ``default_port`` where one is given (a device whose service is not on the
    scheme's port).
    """
    text = host.strip()
    scheme = "http"
    if "://" in text:
        scheme, _, text = text.partition("://")
        scheme = scheme.lower()
        if scheme not in _SCHEMES:
            raise InvalidHostError(f"Unsupported scheme {scheme!r}")
    text = text.removesuffix("/")
    if not text:
        raise InvalidHostError("The host is empty")
    for char, what in (
        ("/", "a path"),
        ("?", "a query string"),
        ("#", "a fragment"),
        ("@", "user info"),
        ("%", "a percent sign"),
    ):
        if char in text:
            raise InvalidHostError(f"The host must not contain {what}")
    if any(char.isspace() for char in text):
        raise InvalidHostError("The host must not contain spaces")

    hostname, port = _split_port(text)
    hostname = _normalize_hostname(hostname)
    if port is None:
        port = default_port
    if port is None or port == _SCHEMES[scheme]:
        return f"{scheme}://{hostname}"
    return f"{scheme}://{hostname}:{port}"


def _split_port(text: str) -> tuple[str, int | None]:
    """Split ``host[:port]`` (IPv6 in brackets, or bare without a port)."""
    if text.startswith("["):
        address, bracket, rest = text[1:].partition("]")
        if not bracket:
            raise InvalidHostError("Unbalanced brackets in the host")
        if rest and not rest.startswith(":"):
            raise InvalidHostError("Unexpected text after the IPv6 address")
        return f"[{address}]", _parse_port(rest[1:]) if rest else None
    if text.count(":") > 1:
        return f"[{text}]", None
    hostname, colon, port = text.partition(":")
    return hostname, _parse_port(port) if colon else None


def _parse_port(port: str) -> int:
    """Parse a TCP port number 1..65535."""
    if not _PORT.fullmatch(port) or not 0 < int(port) < 65536:
        raise InvalidHostError(f"Invalid port {port!r}")
    return int(port)


def _normalize_hostname(hostname: str) -> str:
    """Validate an IP address or DNS name and return it in canonical form."""
    if hostname.startswith("["):
        try:
            address = ipaddress.IPv6Address(hostname[1:-1])
        except ValueError as err:
            raise InvalidHostError(f"Invalid IPv6 address {hostname}") from err
        return f"[{address.compressed}]"
    try:
        return str(ipaddress.IPv4Address(hostname))
    except ValueError:
        pass
    name = hostname.removesuffix(".").lower()
    if (
        not name
        or len(name) > 253
        or not all(_HOSTNAME_LABEL.fullmatch(label) for label in name.split("."))
        or re.fullmatch(r"[0-9.]+", name)
    ):
        raise InvalidHostError(f"Invalid host name {hostname!r}")
    return name


# A host name (RFC 1123 labels).
_HOST_NAME: Final = re.compile(
    r"[A-Za-z0-9](?:[A-Za-z0-9-]{0,62})(?:\.[A-Za-z0-9-]{1,63})*\.?"
)


def is_host_name(host: str) -> bool:
    """Whether ``host`` is an IP address or a host name, with nothing around it."""
    try:
        ipaddress.ip_address(host)
    except ValueError:
        return _HOST_NAME.fullmatch(host) is not None
    return True


async def resolved_identity(identity: str) -> str:
    """Return an address identity with its host name resolved: one device, one identity.

    ``localhost:2000`` is ``127.0.0.1:2000``, as typed either way (an IPv4
    address first). An address stays; a name that does not resolve stays too.
    """
    url = URL(f"http://{identity}")
    host = url.host or ""
    try:
        ipaddress.ip_address(host)
    except ValueError:
        pass
    else:
        return identity
    try:
        found = await asyncio.get_running_loop().getaddrinfo(
            host, url.port, type=socket.SOCK_STREAM
        )
    except OSError:
        return identity
    if not found:
        return identity
    family, *_, address = min(found, key=lambda item: item[0] is not socket.AF_INET)
    resolved = str(address[0])
    shown = f"[{resolved}]" if family is socket.AF_INET6 else resolved
    return f"{shown}:{url.port}{url.path if url.path != '/' else ''}"
