"""service_problems: registered actions, services.yaml and translations agree."""

from typing import TYPE_CHECKING

from scripts.checks.services import service_problems

if TYPE_CHECKING:
    from scripts.checks.common import JsonObject


def test_checker_services_must_agree_everywhere() -> None:
    services_yaml: JsonObject = {
        "write_variable": {
            "fields": {"name": {}, "value": {}, "advanced": {"fields": {"timeout": {}}}}
        },
        "orphan": {},
    }
    strings = {
        "services": {
            "write_variable": {
                "name": "Write",
                "description": "",
                "fields": {
                    "name": {"name": "N", "description": "D"},
                    "value": {"name": "V"},
                    "extra": {},
                },
            },
            "gone": {"name": "g", "description": "d"},
        }
    }
    registered = {"write_variable": "services:1", "refresh": "services:2"}
    assert service_problems(services_yaml, strings, registered) == [
        "action 'refresh' is registered but not in services.yaml",
        "action 'orphan' is in services.yaml but never registered",
        "action 'orphan' has no translation",
        "translated action 'gone' is not in services.yaml",
        "action 'write_variable' has no translated description",
        "field write_variable.timeout has no translation",
        "translated field write_variable.extra is not in services.yaml",
        "field write_variable.value has no translated description",
    ]
