"""What the code needs held against a translation: missing, unused, placeholders."""

from scripts.checks.usage import (
    missing_translations,
    placeholder_gaps,
    unused_translations,
)
from tests.checks.synthetic import synthetic_usage


def test_checker_reports_missing_and_unused_translations() -> None:
    usage = synthetic_usage()
    strings = {
        "config": {"step": {"user": {"data": {"host": "Host"}}}},
        "entity": {
            "sensor": {
                "uptime": {"name": "Uptime"},
                "temperature": {"name": "T"},
                "ghost": {"name": "G"},
            }
        },
        "exceptions": {"write_failed": {"message": "m"}, "stale": {"message": "s"}},
    }
    # Present: config.step.user(.data.host), entity.sensor.uptime, write_failed.
    assert missing_translations(usage, strings) == [
        "config.abort.already_configured (used at config_flow:16)",
        "config.abort.already_in_progress (used at config_flow:15)",
        "config.abort.reauth_successful (used at config_flow:30)",
        "config.error.cannot_connect (used at config_flow:17)",
        "config.error.invalid_auth (used at config_flow:18)",
        "config.error.no_input (used at config_flow:55)",
        "config.error.refused_by_plc (used at config_flow:55)",
        "config.error.timeout (used at config_flow:53)",
        "config.flow_title (used at config_flow:22)",
        "config.step.dhcp_confirm (used at config_flow:23)",
        "config.step.reauth_confirm (used at config_flow:31)",
        "config.step.reauth_confirm.data.password (used at config_flow:31)",
        "config.step.reconfigure (used at config_flow:47)",
        "config.step.user.data.password (used at config_flow:19)",
        "entity.switch.boiler (used at sensor:14)",
        "exceptions.out_of_range.message (used at sensor:41)",
        "exceptions.read_only.message (used at sensor:22)",
        "issues.program_changed.title (used at sensor:27)",
        "options.abort.no_options (used at config_flow:36)",
        "options.step.pick (used at config_flow:41)",
        "options.step.pick.data.mode (used at config_flow:41)",
        "selector.mode.options (used at config_flow:39)",
        "selector.mode.options.off (used at config_flow:39)",
        "selector.mode.options.on (used at config_flow:39)",
    ]
    # `temperature` is chosen at runtime from a mapping: its literal counts as a use.
    assert unused_translations(strings, usage) == [
        "entity.sensor.ghost",
        "exceptions.stale",
    ]


def test_checker_reports_placeholders_the_code_does_not_pass() -> None:
    usage = synthetic_usage()
    assert usage.placeholders[("config", "flow_title")] == (
        frozenset({"name"}),
        "config_flow:22",
    )
    strings = {
        "config": {
            "flow_title": "{name} ({host})",
            "step": {"user": {"title": "PLC", "description": "Mark {public_api}"}},
            "error": {"timeout": "No answer in {seconds} s"},
        },
        "exceptions": {
            "out_of_range": {"message": "{value} is above {max_value}"},
            "read_only": {"message": "Read-only"},
        },
    }
    assert placeholder_gaps(usage, strings) == [
        "config.flow_title uses ['host'], not passed at config_flow:22",
        "config.step.user.description uses ['public_api'], not passed at config_flow:19",
        "exceptions.out_of_range.message uses ['max_value'], not passed at sensor:41",
        "config.error.timeout uses ['seconds'], not passed at config_flow:53",
    ]
