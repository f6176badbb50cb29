"""Shared fixtures: a simulated Tecomat PLC on 127.0.0.1 and its TLS certificate."""

from collections.abc import AsyncIterator
from datetime import UTC, datetime, timedelta
from ipaddress import ip_address
from pathlib import Path
import ssl
from typing import NamedTuple

from cryptography import x509
from cryptography.hazmat.primitives import hashes, serialization
from cryptography.hazmat.primitives.asymmetric import ec
from cryptography.x509.oid import NameOID
import pytest

# phcc ships its own top-level `custom_components` package; importing ours here,
# with the project root first on sys.path (pytest `pythonpath = .`), makes Home
# Assistant find this integration.
import custom_components.tecoapi  # noqa: F401
from tests.simulator import Simulator

SIM_USERNAME = "admin"
SIM_PASSWORD = "s3cret-Pa55"


@pytest.fixture
async def simulator(socket_enabled: None) -> AsyncIterator[Simulator]:
    """A running simulator with the `demo` program, Digest auth, on 127.0.0.1."""
    async with Simulator("demo", username=SIM_USERNAME, password=SIM_PASSWORD) as sim:
        yield sim


@pytest.fixture
async def manual_simulator(socket_enabled: None) -> AsyncIterator[Simulator]:
    """A running simulator with the manual's example program."""
    async with Simulator("manual", username=SIM_USERNAME, password=SIM_PASSWORD) as sim:
        yield sim


class Certificate(NamedTuple):
    """A self-signed certificate for 127.0.0.1 and its key, as PEM files."""

    cert: Path
    key: Path

    def server_context(self) -> ssl.SSLContext:
        """What a simulated PLC serves HTTPS with."""
        context = ssl.create_default_context(ssl.Purpose.CLIENT_AUTH)
        context.load_cert_chain(self.cert, self.key)
        return context

    def client_context(self) -> ssl.SSLContext:
        """A client context trusting only this certificate."""
        return ssl.create_default_context(cafile=str(self.cert))


@pytest.fixture(scope="session")
def certificate(tmp_path_factory: pytest.TempPathFactory) -> Certificate:
    """A self-signed certificate made for this test session."""
    key = ec.generate_private_key(ec.SECP256R1())
    name = x509.Name([x509.NameAttribute(NameOID.COMMON_NAME, "Tecomat test PLC")])
    now = datetime.now(UTC)
    # Valid for years either way: a test may freeze the clock far from today.
    cert = (
        x509.CertificateBuilder()
        .subject_name(name)
        .issuer_name(name)
        .public_key(key.public_key())
        .serial_number(x509.random_serial_number())
        .not_valid_before(now - timedelta(days=3650))
        .not_valid_after(now + timedelta(days=3650))
        .add_extension(
            x509.SubjectAlternativeName([x509.IPAddress(ip_address("127.0.0.1"))]),
            critical=False,
        )
        # Its own issuer: a client may trust it as the only CA (client_context).
        .add_extension(x509.BasicConstraints(ca=True, path_length=None), critical=True)
        .sign(key, hashes.SHA256())
    )
    directory = tmp_path_factory.mktemp("tls")
    cert_path, key_path = directory / "plc.crt", directory / "plc.key"
    cert_path.write_bytes(cert.public_bytes(serialization.Encoding.PEM))
    key_path.write_bytes(
        key.private_bytes(
            serialization.Encoding.PEM,
            serialization.PrivateFormat.PKCS8,
            serialization.NoEncryption(),
        )
    )
    return Certificate(cert_path, key_path)
