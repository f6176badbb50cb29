"""Host normalisation: what a user types becomes a base URL, or a clear error."""

import pytest

from custom_components.tecoapi.pyplc import InvalidHostError, PlcError, normalize_host


@pytest.mark.parametrize(
    ("host", "base_url"),
    [
        ("192.168.1.10", "http://192.168.1.10"),
        ("  192.168.1.10  ", "http://192.168.1.10"),
        ("plc.local:8080", "http://plc.local:8080"),
        ("PLC.Local", "http://plc.local"),
        ("https://host", "https://host"),
        ("HTTPS://host:443", "https://host"),
        ("http://host:80/", "http://host"),
        ("http://10.0.0.1:8443", "http://10.0.0.1:8443"),
        ("https://plc.example.com:4443/", "https://plc.example.com:4443"),
        ("fe80::1", "http://[fe80::1]"),
        ("[2001:db8::0:1]:8080", "http://[2001:db8::1]:8080"),
        ("https://[::1]", "https://[::1]"),
        ("my_plc", "http://my_plc"),
    ],
)
def test_hosts_are_normalised(host: str, base_url: str) -> None:
    assert normalize_host(host) == base_url


@pytest.mark.parametrize(
    "host",
    [
        "",
        "   ",
        "http://",
        "192.168.1.10/TecoApi",
        "plc.local/path/",
        "plc.local?x=1",
        "plc.local#top",
        "user:pass@plc.local",
        "ftp://plc.local",
        "plc.local:0",
        "plc.local:65536",
        "plc.local:http",
        "plc local",
        "-plc.local",
        "plc..local",
        "300.1.2.3",
        "[fe80::1",
        "[fe80::1]x",
        "[not-an-address]",
        "fe80::1%eth0",
        "plcé.local",
    ],
)
def test_garbage_is_rejected(host: str) -> None:
    with pytest.raises(InvalidHostError):
        normalize_host(host)


def test_invalid_host_error_is_a_client_error_and_a_value_error() -> None:
    with pytest.raises(PlcError):
        normalize_host("a/b")
    with pytest.raises(ValueError, match="path"):
        normalize_host("a/b")


@pytest.mark.parametrize(
    ("host", "base_url"),
    [
        ("gw", "http://gw:2000"),
        ("https://gw/", "https://gw:2000"),
        ("fe80::1", "http://[fe80::1]:2000"),
        ("gw:8080", "http://gw:8080"),
        ("http://gw:80", "http://gw"),
        ("[::1]:443", "http://[::1]:443"),
    ],
)
def test_a_host_without_a_port_gets_the_default_port(host: str, base_url: str) -> None:
    """A port typed wins, the scheme's own included (it is dropped as ever)."""
    assert normalize_host(host, default_port=2000) == base_url
