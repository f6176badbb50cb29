"""Fixtures for the browser test: a real Home Assistant process, and where its output goes.

The browser fixtures live in test_browser.py, which skips itself where playwright is
not installed (the floor environment); this file must import without it.
"""

from collections.abc import AsyncIterator, Generator, Iterator
import importlib.util
from pathlib import Path
import shutil
from typing import Final

import aiohttp
from homeassistant.const import MAJOR_VERSION, MINOR_VERSION
import pytest

from tests.e2e.configuration import REPO_ROOT, write_configuration
from tests.e2e.home_assistant import HomeAssistantProcess, integration_trouble

# The Home Assistant log and, after a failure, the last page (gitignored).
ARTIFACTS: Final = REPO_ROOT / "e2e-artifacts"
PHASE_REPORTS: Final = pytest.StashKey[dict[str, pytest.TestReport]]()

# The tests that start Home Assistant as a process: the primary target only (the
# floor's Python 3.13.0 is older than Home Assistant 2026.2 accepts), with the
# packages scripts/test --e2e installs.
real_home_assistant: Final = pytest.mark.skipif(
    (MAJOR_VERSION, MINOR_VERSION) < (2026, 10)
    or importlib.util.find_spec("hass_frontend") is None,
    reason="runs Home Assistant 2026.10 with its frontend (scripts/test --e2e)",
)


@pytest.hookimpl(wrapper=True)
def pytest_runtest_makereport(
    item: pytest.Item, call: pytest.CallInfo[None]
) -> Generator[None, pytest.TestReport, pytest.TestReport]:
    """Remember each phase's report on the test item (a fixture asks if it failed)."""
    report = yield
    item.stash.setdefault(PHASE_REPORTS, {})[report.when] = report
    return report


def has_failed(request: pytest.FixtureRequest) -> bool:
    """Whether the test using a fixture failed (or never ran), at the fixture's teardown."""
    reports = request.node.stash.get(PHASE_REPORTS, {})
    return "call" not in reports or reports["call"].failed


@pytest.fixture
def home_assistant_log(
    request: pytest.FixtureRequest, tmp_path: Path
) -> Iterator[Path]:
    """Where Home Assistant's output goes: it must show no error of the integration.

    Kept in e2e-artifacts/ if the test fails.
    """
    log = tmp_path / "home-assistant.log"
    yield log
    if has_failed(request) and log.exists():
        ARTIFACTS.mkdir(exist_ok=True)
        shutil.copyfile(log, ARTIFACTS / log.name)
    assert integration_trouble(log.read_text("utf-8")) == []


@pytest.fixture
async def home_assistant(
    socket_enabled: None,
    unused_tcp_port: int,
    tmp_path: Path,
    home_assistant_log: Path,
) -> AsyncIterator[HomeAssistantProcess]:
    """A fresh Home Assistant with this integration, on 127.0.0.1 only, not onboarded.

    Afterwards it must stop cleanly (exit status 0).
    """
    config_dir = tmp_path / "config"
    write_configuration(config_dir, port=unused_tcp_port, listen=("127.0.0.1",))
    process = HomeAssistantProcess(config_dir, unused_tcp_port, home_assistant_log)
    try:
        async with aiohttp.ClientSession() as session:
            await process.start(session)
        yield process
    finally:
        status = await process.stop()
    assert status == 0, f"Home Assistant did not stop cleanly (exit status {status})"
