"""Home Assistant as a separate process, the way a user runs it (`hass --config DIR`)."""

import asyncio
import os
from pathlib import Path
import re
import sys
from typing import IO, Final

import aiohttp

from tests.deprecations import DEPRECATED_USE
from tests.e2e.configuration import TEMP_DIR

STARTUP_TIMEOUT: Final = 180.0
STOP_TIMEOUT: Final = 30.0
# How often a starting Home Assistant is asked whether it serves HTTP yet: there is no
# event to wait for across a process boundary, so readiness is polled (with a deadline).
POLL_INTERVAL: Final = 0.25
# Starts Home Assistant (the rest of argv) so that it gets SIGTERM when the process
# that started it dies (PR_SET_PDEATHSIG outlives exec): a test run ended by its
# timeout leaves no Home Assistant behind. argv[1] is the starter's process ID.
DIES_WITH_PARENT: Final = """
import ctypes, os, signal, sys
PR_SET_PDEATHSIG = 1
ctypes.CDLL(None).prctl(PR_SET_PDEATHSIG, signal.SIGTERM)
if os.getppid() != int(sys.argv[1]):
    sys.exit("the process that started Home Assistant is gone")
os.execv(sys.executable, [sys.executable, *sys.argv[2:]])
"""


# A warning or an error logged by the integration, an error another logs about it
# (its entry failed to set up), a traceback through its files, or a deprecation Home
# Assistant reports about it (a warning today, a breakage in a few releases), in
# whichever words and from whichever logger. Another's warning naming it is not
# counted: "Setup of tecoapi is taking over 10 seconds" says more of the machine.
INTEGRATION_TROUBLE: Final = re.compile(
    r"^\S+ \S+ (WARNING|ERROR|CRITICAL) \([^)]*\) \[custom_components\.tecoapi"
    r"|^\S+ \S+ (ERROR|CRITICAL) .*tecoapi"
    r"|custom_components/tecoapi/"
    rf"|{DEPRECATED_USE.pattern}"
)


def integration_trouble(log: str) -> list[str]:
    """The lines of a Home Assistant log that show the integration failing."""
    return [line for line in log.splitlines() if INTEGRATION_TROUBLE.search(line)]


class HomeAssistantError(Exception):
    """Home Assistant did not start, or stopped while it was needed."""


async def wait_until_serving(
    session: aiohttp.ClientSession,
    url: str,
    *,
    process: asyncio.subprocess.Process | None = None,
) -> list[dict[str, object]] | None:
    """Wait until Home Assistant answers; return its onboarding steps.

    Each step is `{"step": NAME, "done": BOOL}`; None once onboarding is over (the
    onboarding API is gone then).
    """
    async with asyncio.timeout(STARTUP_TIMEOUT):
        while True:
            if process is not None and process.returncode is not None:
                raise HomeAssistantError(
                    f"Home Assistant exited with status {process.returncode}"
                )
            try:
                async with session.get(f"{url}/api/onboarding") as response:
                    if response.status == 404:
                        return None
                    if response.status == 200:
                        status: list[dict[str, object]] = await response.json()
                        return status
            except aiohttp.ClientError:
                pass
            await asyncio.sleep(POLL_INTERVAL)


class HomeAssistantProcess:
    """`python -m homeassistant` on a configuration directory, its output appended to a log.

    Runs with `--skip-pip`: everything it needs is installed beforehand (the frontend by
    scripts/e2e_env.sh), so it never reaches for the network.
    """

    def __init__(self, config_dir: Path, port: int, log_path: Path) -> None:
        """Prepare a process for `config_dir`, serving on 127.0.0.1:`port`."""
        self.config_dir = config_dir
        self.port = port
        self.log_path = log_path
        self._process: asyncio.subprocess.Process | None = None
        self._log: IO[bytes] | None = None

    @property
    def environment(self) -> dict[str, str]:
        """Its environment: this one's, with a temporary directory of its own."""
        return {**os.environ, "TMPDIR": str(self.config_dir / TEMP_DIR)}

    @property
    def url(self) -> str:
        """The base URL of the web interface."""
        return f"http://127.0.0.1:{self.port}"

    async def start(self, session: aiohttp.ClientSession) -> None:
        """Start Home Assistant and wait until it serves HTTP."""
        self._log = self.log_path.open("ab")
        self._process = await asyncio.create_subprocess_exec(
            sys.executable,
            "-c",
            DIES_WITH_PARENT,
            str(os.getpid()),
            "-m",
            "homeassistant",
            "--config",
            str(self.config_dir),
            "--skip-pip",
            env=self.environment,
            stdin=asyncio.subprocess.DEVNULL,
            stdout=self._log,
            stderr=asyncio.subprocess.STDOUT,
        )
        try:
            await wait_until_serving(session, self.url, process=self._process)
        except BaseException:
            await self.stop()
            raise

    async def stop(self) -> int | None:
        """Stop Home Assistant (SIGTERM), killing it if it hangs; return its exit status.

        0 is a clean stop; None if it was not running.
        """
        process, self._process = self._process, None
        status = None
        if process is not None:
            if process.returncode is None:
                process.terminate()
                try:
                    async with asyncio.timeout(STOP_TIMEOUT):
                        await process.wait()
                except TimeoutError:
                    process.kill()
                    await process.wait()
            status = process.returncode
        if self._log is not None:
            self._log.close()
            self._log = None
        return status
