"""Fixtures and a raw HTTP helper for the simulator's own tests."""

import base64
from collections.abc import AsyncIterator, Mapping
from dataclasses import dataclass
import datetime as dt
import ipaddress
import json
from pathlib import Path
import ssl
import textwrap
from typing import Any

import aiohttp
from cryptography import x509
from cryptography.hazmat.primitives import hashes, serialization
from cryptography.hazmat.primitives.asymmetric import ec
from cryptography.x509.oid import NameOID
import pytest
from yarl import URL

from tests.conftest import SIM_PASSWORD, SIM_USERNAME
from tests.simulator import Simulator

CRLF = "\r\n"


@dataclass(frozen=True, slots=True)
class Reply:
    """What came back from the simulator, unparsed."""

    status: int
    headers: Mapping[str, str]
    body: bytes
    challenges: list[str]

    def json(self) -> Any:
        """The body as JSON."""
        return json.loads(self.body)

    @property
    def error_code(self) -> str:
        """The `error.code` of an error body."""
        return str(self.json()["error"]["code"])

    @property
    def error_message(self) -> str:
        """The `error.message` of an error body."""
        return str(self.json()["error"]["message"])


def basic_authorization(username: str, password: str) -> str:
    """An `Authorization: Basic ...` value."""
    return "Basic " + base64.b64encode(f"{username}:{password}".encode()).decode()


def manual_text(text: str) -> bytes:
    """A JSON body as printed in the manual: dedented, CRLF lines, final CRLF."""
    lines = textwrap.dedent(text).strip("\n").split("\n")
    return (CRLF.join(line.rstrip() for line in lines) + CRLF).encode()


async def fetch(
    session: aiohttp.ClientSession,
    sim: Simulator,
    target: str,
    *,
    method: str = "GET",
    data: bytes | None = None,
    headers: Mapping[str, str] | None = None,
    basic: bool = True,
) -> Reply:
    """Send `target` exactly as written (no re-encoding), with Basic credentials."""
    sent = dict(headers or {})
    if basic:
        sent.setdefault(
            "Authorization", basic_authorization(SIM_USERNAME, SIM_PASSWORD)
        )
    async with session.request(
        method, URL(sim.url + target, encoded=True), data=data, headers=sent
    ) as response:
        return Reply(
            response.status,
            response.headers,
            await response.read(),
            response.headers.getall("WWW-Authenticate", []),
        )


@dataclass(frozen=True, slots=True)
class Certificate:
    """A self-signed certificate for 127.0.0.1 and its key, as PEM files."""

    cert: Path
    key: Path

    def server_context(self) -> ssl.SSLContext:
        """What the simulator serves HTTPS with."""
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
    name = x509.Name([x509.NameAttribute(NameOID.COMMON_NAME, "127.0.0.1")])
    now = dt.datetime.now(dt.UTC)
    cert = (
        x509.CertificateBuilder()
        .subject_name(name)
        .issuer_name(name)
        .public_key(key.public_key())
        .serial_number(x509.random_serial_number())
        .not_valid_before(now - dt.timedelta(days=1))
        .not_valid_after(now + dt.timedelta(days=1))
        .add_extension(
            x509.SubjectAlternativeName(
                [x509.IPAddress(ipaddress.ip_address("127.0.0.1"))]
            ),
            critical=False,
        )
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


@pytest.fixture
async def session() -> AsyncIterator[aiohttp.ClientSession]:
    """A plain aiohttp session."""
    async with aiohttp.ClientSession() as client:
        yield client


@pytest.fixture
async def manual_plc(socket_enabled: None) -> AsyncIterator[Simulator]:
    """The manual's program, offering Basic and Digest (the manual's examples use Basic)."""
    sim = Simulator("manual", username=SIM_USERNAME, password=SIM_PASSWORD, auth="both")
    await sim.start()
    try:
        yield sim
    finally:
        await sim.stop()


@pytest.fixture
async def demo_plc(socket_enabled: None) -> AsyncIterator[Simulator]:
    """The demo program, offering Basic and Digest."""
    sim = Simulator("demo", username=SIM_USERNAME, password=SIM_PASSWORD, auth="both")
    await sim.start()
    try:
        yield sim
    finally:
        await sim.stop()
