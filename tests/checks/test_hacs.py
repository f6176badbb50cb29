"""hacs_problems: keys HACS rejects, a missing name, a minimum that is not the floor."""

from scripts.checks.hacs import hacs_problems


def test_checker_hacs_rejects_unknown_keys_missing_name_and_wrong_floor() -> None:
    assert hacs_problems({"name": "X", "homeassistant": "2026.2.0"}, "2026.2.0") == []
    assert hacs_problems(
        {"domains": ["sensor"], "homeassistant": "2025.1.0"}, "2026.2.0"
    ) == [
        "key 'domains' is not one HACS accepts",
        "'name' is missing or empty",
        "'homeassistant' is '2025.1.0', the tested floor is '2026.2.0'",
    ]
