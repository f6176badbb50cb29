"""Fixtures for the client tests: sessions, clients and simulators of every setup."""

from collections.abc import AsyncIterator, Awaitable, Callable
import contextlib
import datetime as dt
import ipaddress
from pathlib import Path
import ssl
from typing import Any

import aiohttp
from cryptography import x509
from cryptography.hazmat.primitives import hashes, serialization
from cryptography.hazmat.primitives.asymmetric import ec
from cryptography.x509.oid import NameOID
import pytest

from custom_components.tecoapi.pytecoapi import TecoApiClient
from tests.conftest import SIM_PASSWORD, SIM_USERNAME
from tests.simulator import Simulator

type StartSimulator = Callable[..., Awaitable[Simulator]]


class HeaderLog:
    """The Authorization headers a session sent, in order (from a trace config)."""

    def __init__(self) -> None:
        self.authorizations: list[str | None] = []
        self.accepts: list[str | None] = []
        self.trace = aiohttp.TraceConfig()
        self.trace.on_request_headers_sent.append(self._sent)

    async def _sent(
        self,
        session: aiohttp.ClientSession,
        context: Any,
        params: aiohttp.TraceRequestHeadersSentParams,
    ) -> None:
        self.authorizations.append(params.headers.get("Authorization"))
        self.accepts.append(params.headers.get("Accept"))


@pytest.fixture
def header_log() -> HeaderLog:
    return HeaderLog()


@pytest.fixture
async def session(header_log: HeaderLog) -> AsyncIterator[aiohttp.ClientSession]:
    """A plain aiohttp session, as Home Assistant would inject one."""
    async with aiohttp.ClientSession(trace_configs=[header_log.trace]) as session:
        yield session


def make_client(
    session: aiohttp.ClientSession, sim: Simulator, **options: Any
) -> TecoApiClient:
    """A client of a simulator with the test credentials."""
    return TecoApiClient(session, sim.url, SIM_USERNAME, SIM_PASSWORD, **options)


@pytest.fixture
def client(session: aiohttp.ClientSession, simulator: Simulator) -> TecoApiClient:
    """A client of the demo simulator."""
    return make_client(session, simulator)


@pytest.fixture
def manual_client(
    session: aiohttp.ClientSession, manual_simulator: Simulator
) -> TecoApiClient:
    """A client of the manual's simulator."""
    return make_client(session, manual_simulator)


@pytest.fixture
async def start_simulator(socket_enabled: None) -> AsyncIterator[StartSimulator]:
    """Start simulators of any setup on 127.0.0.1; all are stopped afterwards."""
    async with contextlib.AsyncExitStack() as stack:

        async def start(
            program: Any = "manual",
            *,
            ssl_context: ssl.SSLContext | None = None,
            **options: Any,
        ) -> Simulator:
            options.setdefault("username", SIM_USERNAME)
            options.setdefault("password", SIM_PASSWORD)
            sim = Simulator(program, **options)
            await sim.start(ssl_context=ssl_context)
            stack.push_async_callback(sim.stop)
            return sim

        yield start


@pytest.fixture(scope="session")
def certificate(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    """A self-signed certificate for 127.0.0.1 and its key (PEM files)."""
    directory = tmp_path_factory.mktemp("tls")
    key = ec.generate_private_key(ec.SECP256R1())
    name = x509.Name([x509.NameAttribute(NameOID.COMMON_NAME, "127.0.0.1")])
    now = dt.datetime.now(dt.UTC)
    certificate = (
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
        .sign(key, hashes.SHA256())
    )
    certificate_path = directory / "plc.pem"
    key_path = directory / "plc.key"
    certificate_path.write_bytes(certificate.public_bytes(serialization.Encoding.PEM))
    key_path.write_bytes(
        key.private_bytes(
            serialization.Encoding.PEM,
            serialization.PrivateFormat.PKCS8,
            serialization.NoEncryption(),
        )
    )
    return certificate_path, key_path


@pytest.fixture
def server_tls(certificate: tuple[Path, Path]) -> ssl.SSLContext:
    """The PLC's side of TLS with the self-signed certificate."""
    context = ssl.create_default_context(ssl.Purpose.CLIENT_AUTH)
    context.load_cert_chain(*certificate)
    return context
