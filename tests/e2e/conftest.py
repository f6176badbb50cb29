"""Fixtures for the browser test: a real Home Assistant process, and where its output goes.

The browser fixtures live in test_browser.py, which skips itself where playwright is
not installed (the floor environment); this file must import without it.
"""

import asyncio
from collections.abc import (
    AsyncIterator,
    Awaitable,
    Callable,
    Coroutine,
    Generator,
    Iterator,
)
import functools
import importlib.util
import os
from pathlib import Path
import shutil
from typing import Any, Final

import aiohttp
from homeassistant.const import MAJOR_VERSION, MINOR_VERSION
import pytest

from tests.e2e.configuration import REPO_ROOT, write_configuration
from tests.e2e.home_assistant import HomeAssistantProcess, integration_trouble

# The Home Assistant log and, after a failure, the last page (gitignored).
ARTIFACTS: Final = REPO_ROOT / "e2e-artifacts"
PHASE_REPORTS: Final = pytest.StashKey[dict[str, pytest.TestReport]]()

# scripts/test --e2e (and so CI) sets TECOAPI_E2E=required: then the tests that start
# Home Assistant as a process must run, and a missing piece fails them.
E2E_REQUIRED: Final = os.environ.get("TECOAPI_E2E") == "required"
# How long one of them may take, in seconds (they take 20-40 s): the test itself is
# cancelled after TEST_TIMEOUT, so that its fixtures still stop Home Assistant and the
# browser; should the event loop itself hang, pytest-timeout ends the whole run after
# RUN_TIMEOUT (setup and teardown included), so that CI fails instead of hanging.
TEST_TIMEOUT: Final = 240.0
RUN_TIMEOUT: Final = 600.0


def home_assistant_missing() -> str | None:
    """Why Home Assistant cannot run as a process here; None if it can.

    It runs on the primary target only (the floor's Python 3.13.0 is older than Home
    Assistant 2026.2 accepts), with the packages scripts/test --e2e installs.
    """
    if (MAJOR_VERSION, MINOR_VERSION) < (2026, 10):
        return "runs Home Assistant 2026.10 (the primary target)"
    if importlib.util.find_spec("hass_frontend") is None:
        return "needs Home Assistant's frontend (scripts/test --e2e installs it)"
    return None


HOME_ASSISTANT_MISSING: Final = home_assistant_missing()

# The marks of a test that starts Home Assistant as a process: skipped where it cannot
# run, unless required. pytest-timeout's default method (a signal) cannot interrupt
# the event loop safely: it left a run hanging in tests; the thread method ends the
# process.
real_home_assistant: Final = [
    pytest.mark.e2e,
    pytest.mark.skipif(
        HOME_ASSISTANT_MISSING is not None and not E2E_REQUIRED,
        reason=HOME_ASSISTANT_MISSING or "",
    ),
    pytest.mark.timeout(RUN_TIMEOUT, method="thread"),
]


def bounded[**P](
    test: Callable[P, Awaitable[None]],
) -> Callable[P, Coroutine[Any, Any, None]]:
    """Cancel an end-to-end test that runs longer than TEST_TIMEOUT (a failure)."""

    @functools.wraps(test)
    async def run(*args: P.args, **kwargs: P.kwargs) -> None:
        async with asyncio.timeout(TEST_TIMEOUT):
            await test(*args, **kwargs)

    return run


@pytest.fixture(autouse=True)
def _home_assistant_can_run(request: pytest.FixtureRequest) -> None:
    """Fail a required end-to-end test at once when Home Assistant cannot run here."""
    if request.node.get_closest_marker("e2e") and HOME_ASSISTANT_MISSING:
        pytest.fail(f"scripts/test --e2e: this test {HOME_ASSISTANT_MISSING}")


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
