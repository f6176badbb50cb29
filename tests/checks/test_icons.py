"""icon_problems: icons of entities and actions that exist, mdi: names."""

from scripts.checks.icons import icon_problems


def test_checker_icons_must_refer_to_existing_keys() -> None:
    icons = {
        "entity": {
            "sensor": {
                "uptime": {"default": "mdi:timer"},
                "ghost": {"default": "timer"},
            }
        },
        "services": {"refresh": "mdi:refresh"},
        "unknown": {},
    }
    strings = {"entity": {"sensor": {"uptime": {"name": "Uptime"}}}}
    assert icon_problems(icons, strings, {"write_variable": {}}) == [
        "icons.json section 'unknown' is not checked here",
        "icon for entity.sensor.ghost has no entity translation",
        "icon for action 'refresh' that services.yaml lacks",
        "action 'write_variable' has no icon",
        "entity.sensor.ghost.default: 'timer' is not an mdi: icon",
    ]
