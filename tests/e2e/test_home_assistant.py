"""Reading a Home Assistant log for trouble caused by the integration."""

from tests.e2e.home_assistant import integration_trouble

LOG = """\
2026-11-21 14:25:33.954 WARNING (SyncWorker_0) [homeassistant.loader] We found a custom integration tecoapi which has not been tested by Home Assistant.
2026-11-21 14:25:34.163 ERROR (MainThread) [haffmpeg.core] FFmpeg fails [Errno 2] No such file or directory: 'ffmpeg'
  File "/opt/tecoapi/venv-primary/lib/python3.14/site-packages/haffmpeg/core.py", line 130, in open
2026-11-21 14:25:35.001 INFO (MainThread) [custom_components.tecoapi.coordinator] Polling 54 points
2026-11-21 14:25:36.002 ERROR (MainThread) [custom_components.tecoapi.coordinator] Unexpected error fetching Tecomat CP-2080 data
2026-11-21 14:25:37.003 ERROR (MainThread) [homeassistant] Error doing job: Task exception was never retrieved
  File "/tmp/pytest-of-root/pytest-1/config/custom_components/tecoapi/switch.py", line 40, in async_turn_on
2026-11-21 14:25:38.004 CRITICAL (MainThread) [custom_components.tecoapi] Gave up
"""


def test_integration_trouble() -> None:
    """Its errors and tracebacks through its files; not others', not its INFO lines."""
    assert integration_trouble(LOG) == [
        "2026-11-21 14:25:36.002 ERROR (MainThread) [custom_components.tecoapi.coordinator] Unexpected error fetching Tecomat CP-2080 data",
        '  File "/tmp/pytest-of-root/pytest-1/config/custom_components/tecoapi/switch.py", line 40, in async_turn_on',
        "2026-11-21 14:25:38.004 CRITICAL (MainThread) [custom_components.tecoapi] Gave up",
    ]
