"""Reading a Home Assistant log for trouble caused by the integration."""

import pytest

from tests.deprecations import DEPRECATED_USE, DEPRECATION_WORDING
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
2026-11-21 14:25:38.005 WARNING (MainThread) [homeassistant.setup] Setup of tecoapi is taking over 10 seconds.
2026-11-21 14:25:38.006 ERROR (MainThread) [homeassistant.config_entries] Error setting up entry Tecomat CP-2080 for tecoapi
2026-11-21 14:25:38.007 WARNING (MainThread) [custom_components.tecoapi.coordinator] The PLC Tecomat CP-2080 rejected the stored credentials; sign in again
"""


def test_integration_trouble() -> None:
    """Its warnings, errors and tracebacks, others' errors naming it; not its INFO lines.

    Not others' errors or warnings, even a warning naming it (a slow setup).
    """
    assert integration_trouble(LOG) == [
        "2026-11-21 14:25:36.002 ERROR (MainThread) [custom_components.tecoapi.coordinator] Unexpected error fetching Tecomat CP-2080 data",
        '  File "/tmp/pytest-of-root/pytest-1/config/custom_components/tecoapi/switch.py", line 40, in async_turn_on',
        "2026-11-21 14:25:38.004 CRITICAL (MainThread) [custom_components.tecoapi] Gave up",
        "2026-11-21 14:25:38.006 ERROR (MainThread) [homeassistant.config_entries] Error setting up entry Tecomat CP-2080 for tecoapi",
        "2026-11-21 14:25:38.007 WARNING (MainThread) [custom_components.tecoapi.coordinator] The PLC Tecomat CP-2080 rejected the stored credentials; sign in again",
    ]


# What Home Assistant 2026.11.0 logged on a start of scripts/smoke with the thermostat
# class before it gave the native_* names: three lines, copied from the log.
CLIMATE_2026_11 = [
    "2026-11-26 07:12:03.857+00:00 WARNING (ImportExecutor_0) [custom_components.tecoapi.climate] custom_components.tecoapi.climate::PlcClimate provides the deprecated _attr_temperature_unit, this will stop working in Home Assistant 2027.11, use _attr_native_temperature_unit instead, please report it to the custom integration author",
    "2026-11-26 07:12:03.857+00:00 WARNING (ImportExecutor_0) [custom_components.tecoapi.climate] custom_components.tecoapi.climate::PlcClimate provides the deprecated current_temperature, this will stop working in Home Assistant 2027.11, use native_current_temperature instead, please report it to the custom integration author",
    "2026-11-26 07:12:03.857+00:00 WARNING (ImportExecutor_0) [custom_components.tecoapi.climate] custom_components.tecoapi.climate::PlcClimate provides the deprecated target_temperature, this will stop working in Home Assistant 2027.11, use native_target_temperature instead, please report it to the custom integration author",
]


def test_the_2026_11_deprecations_are_trouble() -> None:
    """Each line is caught by the log check and, as a record, by the tests' guard."""
    assert integration_trouble("\n".join(CLIMATE_2026_11)) == CLIMATE_2026_11
    for line in CLIMATE_2026_11:
        logger, message = (
            line.split("] ", 1)[0].rsplit("[", 1)[1],
            line.split("] ", 1)[1],
        )
        assert DEPRECATED_USE.search(f"[{logger}] {message}")
        # The message alone names the class: the guard does not need the logger.
        assert DEPRECATED_USE.search(message)


@pytest.mark.parametrize("wording", DEPRECATION_WORDING)
def test_every_wording_of_a_deprecation_counts_where_it_names_the_integration(
    wording: str,
) -> None:
    """Whoever logs it: the integration's logger, or a message naming it."""
    ours = f"[homeassistant.helpers.frame] Detected code in tecoapi that {wording} X"
    assert DEPRECATED_USE.search(ours)
    assert DEPRECATED_USE.search(ours.upper())
    assert integration_trouble(
        f"2026-11-26 07:40:12.346 WARNING (MainThread) [custom_components.tecoapi] {wording}"
    )
    # Another integration's deprecation is not this one's.
    assert not DEPRECATED_USE.search(
        f"[custom_components.other.climate] OtherClimate {wording} X"
    )
