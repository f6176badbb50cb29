"""`python -m tests.simulator`: started as a real process, queried, steered, stopped."""

import asyncio
from collections.abc import AsyncIterator
from pathlib import Path
import re
import signal
import sys

import aiohttp
import pytest

from tests.conftest import Certificate
from tests.simulator.__main__ import build_simulator, parse_arguments

pytestmark = pytest.mark.usefixtures("socket_enabled")

REPOSITORY = Path(__file__).resolve().parents[2]
URL = re.compile(rb"Serving (https?://127\.0\.0\.1:\d+)/TecoApi/ ")
# A safety net so a broken simulator fails the test instead of hanging it.
LINE_TIMEOUT = 60


class SimulatorProcess:
    """The simulator as a child process, with its console on stdin."""

    def __init__(self, process: asyncio.subprocess.Process, url: str) -> None:
        self.process = process
        self.url = url

    async def command(self, line: str) -> str:
        assert self.process.stdin is not None
        assert self.process.stdout is not None
        self.process.stdin.write(line.encode() + b"\n")
        await self.process.stdin.drain()
        reply = await asyncio.wait_for(self.process.stdout.readline(), LINE_TIMEOUT)
        return reply.decode().strip()

    async def finish(self) -> tuple[int, str]:
        _, errors = await asyncio.wait_for(self.process.communicate(), LINE_TIMEOUT)
        assert self.process.returncode is not None
        return self.process.returncode, errors.decode()


async def launch(*arguments: str) -> asyncio.subprocess.Process:
    return await asyncio.create_subprocess_exec(
        sys.executable,
        "-m",
        "tests.simulator",
        *arguments,
        cwd=REPOSITORY,
        stdin=asyncio.subprocess.PIPE,
        stdout=asyncio.subprocess.PIPE,
        stderr=asyncio.subprocess.PIPE,
    )


async def started(*arguments: str) -> SimulatorProcess:
    process = await launch("--port", "0", *arguments)
    assert process.stdout is not None
    first_line = await asyncio.wait_for(process.stdout.readline(), LINE_TIMEOUT)
    match = URL.search(first_line)
    assert match is not None, first_line
    return SimulatorProcess(process, match.group(1).decode())


@pytest.fixture
async def manual_process() -> AsyncIterator[SimulatorProcess]:
    running = await started(
        "--program",
        "manual",
        "--user",
        "jmeno",
        "--password",
        "heslo",
        "--auth",
        "both",
    )
    yield running
    if running.process.returncode is None:
        running.process.kill()
        await running.process.wait()


async def get_json(url: str, *, ssl: object = True) -> tuple[int, dict[str, object]]:
    middleware = aiohttp.DigestAuthMiddleware("jmeno", "heslo")
    async with (
        aiohttp.ClientSession(middlewares=(middleware,)) as client,
        client.get(url, ssl=ssl) as response,  # type: ignore[arg-type]
    ):
        return response.status, await response.json(content_type=None)


async def test_serves_and_is_steered_from_the_console(
    manual_process: SimulatorProcess,
) -> None:
    status, info = await get_json(manual_process.url + "/TecoApi/GetInfo")
    assert status == 200
    assert info["plc"]["type"] == "CP-W32"  # type: ignore[index]

    assert await manual_process.command("mode HALT") == "ok"
    _, info = await get_json(manual_process.url + "/TecoApi/GetInfo")
    assert info["plc"]["mode"] == "HALT"  # type: ignore[index]

    assert await manual_process.command("fault http_500 on") == "ok"
    status, error = await get_json(manual_process.url + "/TecoApi/GetInfo")
    assert (status, error["error"]["code"]) == (500, "500.012")  # type: ignore[index]

    assert await manual_process.command("clear") == "ok"
    assert await manual_process.command("set plcType 42") == "ok"
    assert await manual_process.command("get plcType") == "42"
    assert (await manual_process.command("nonsense")).startswith(
        "error: unknown command"
    )

    assert await manual_process.command("quit") == ""
    code, log = await manual_process.finish()
    assert code == 0
    assert "GET /TecoApi/GetInfo -> 200" in log
    assert "GET /TecoApi/GetInfo -> 500" in log
    assert "heslo" not in log


async def test_stops_on_sigterm(manual_process: SimulatorProcess) -> None:
    manual_process.process.send_signal(signal.SIGTERM)

    code, _ = await manual_process.finish()

    assert code == 0


async def test_command_line_options() -> None:
    running = await started(
        "--program", "generated:40:1",
        "--user", "jmeno",
        "--password", "heslo",
        "--mode", "ERR",
        "--hide", "Heating",
        "--latency-ms", "1",
        "--latency-per-item-ms", "0.01",
        "--fault", "http_500",
        "--fault-count", "1",
        "--no-console",
    )  # fmt: skip
    try:
        failed, _ = await get_json(running.url + "/TecoApi/GetInfo")
        status, info = await get_json(running.url + "/TecoApi/GetInfo")
        _, names = await get_json(running.url + "/TecoApi/GetList")
    finally:
        running.process.send_signal(signal.SIGINT)
        code, _ = await running.finish()

    assert (failed, status) == (500, 200)
    assert info["plc"]["mode"] == "ERR "  # type: ignore[index]
    assert info["plc"]["userProg"]["name"] == "GENERATED_40 v1.0"  # type: ignore[index]
    assert "Heating" not in names
    assert code == 0


async def test_https(certificate: Certificate) -> None:
    running = await started(
        "--program", "manual",
        "--user", "jmeno",
        "--password", "heslo",
        "--tls-cert", str(certificate.cert),
        "--tls-key", str(certificate.key),
        "--no-console",
    )  # fmt: skip
    try:
        status, _ = await get_json(
            running.url + "/TecoApi/GetInfo", ssl=certificate.client_context()
        )
    finally:
        running.process.terminate()
        await running.finish()

    assert running.url.startswith("https://")
    assert status == 200


async def test_an_unknown_program_fails() -> None:
    process = await launch("--program", "nowhere.yaml", "--port", "0")

    _, errors = await asyncio.wait_for(process.communicate(), LINE_TIMEOUT)

    assert process.returncode == 1
    assert b"error: no program 'nowhere.yaml'" in errors


def test_real_device_options() -> None:
    sim = build_simulator(
        parse_arguments(
            [
                "--text-encoding",
                "windows-1250",
                "--short-reals",
                "--exact-service-names",
                "--fault",
                "endless_body",
                "--link-rate",
                "20",
            ]
        )
    )
    assert sim.link_motion.rate == 20.0

    faults = sim.faults
    assert (faults.text_encoding, faults.short_reals, faults.exact_service_names) == (
        "windows-1250",
        True,
        True,
    )
    assert faults.endless_body is True
    defaults = build_simulator(parse_arguments([])).faults
    assert (defaults.text_encoding, defaults.short_reals) == ("utf-8", False)
    assert defaults.exact_service_names is False
    assert build_simulator(parse_arguments([])).link_motion.rate is None


def test_tls_options_go_together() -> None:
    with pytest.raises(SystemExit):
        parse_arguments(["--tls-cert", "plc.crt"])


def test_defaults() -> None:
    arguments = parse_arguments([])

    assert (arguments.program, arguments.port, arguments.auth) == (
        "demo",
        8080,
        "digest",
    )
    assert (arguments.user, arguments.password, arguments.host) == (
        "admin",
        "secret",
        "127.0.0.1",
    )
