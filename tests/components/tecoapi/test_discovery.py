"""DHCP discovery: a device configured by its IP address follows it to a new one."""

import pytest

from custom_components.tecoapi.discovery import moved_host


@pytest.mark.parametrize(
    ("stored", "ip", "moved"),
    [
        ("http://10.0.0.7", "10.0.0.9", "http://10.0.0.9"),
        ("https://10.0.0.7:8443", "10.0.0.9", "https://10.0.0.9:8443"),
        ("http://10.0.0.7", "10.0.0.7", None),
        ("http://plc.local", "10.0.0.9", None),
    ],
)
def test_only_an_address_moves_keeping_scheme_and_port(
    stored: str, ip: str, moved: str | None
) -> None:
    """A name follows the device by itself; the same address is no move."""
    assert moved_host(stored, ip) == moved
