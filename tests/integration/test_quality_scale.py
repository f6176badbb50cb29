"""quality_scale.yaml lists every rule of the Integration Quality Scale, honestly."""

from pathlib import Path
from typing import Final

import pytest
import yaml

QUALITY_SCALE: Final = (
    Path(__file__).resolve().parents[2]
    / "custom_components"
    / "tecoapi"
    / "quality_scale.yaml"
)

# The rules of Home Assistant's Integration Quality Scale, Bronze to Platinum
# (hassfest's script/hassfest/quality_scale.py is not installed here).
RULES: Final = {
    "bronze": [
        "action-setup",
        "appropriate-polling",
        "brands",
        "common-modules",
        "config-flow-test-coverage",
        "config-flow",
        "dependency-transparency",
        "docs-actions",
        "docs-high-level-description",
        "docs-installation-instructions",
        "docs-removal-instructions",
        "entity-event-setup",
        "entity-unique-id",
        "has-entity-name",
        "runtime-data",
        "test-before-configure",
        "test-before-setup",
        "unique-config-entry",
    ],
    "silver": [
        "action-exceptions",
        "config-entry-unloading",
        "docs-configuration-parameters",
        "docs-installation-parameters",
        "entity-unavailable",
        "integration-owner",
        "log-when-unavailable",
        "parallel-updates",
        "reauthentication-flow",
        "test-coverage",
    ],
    "gold": [
        "devices",
        "diagnostics",
        "discovery-update-info",
        "discovery",
        "docs-data-update",
        "docs-examples",
        "docs-known-limitations",
        "docs-supported-devices",
        "docs-supported-functions",
        "docs-troubleshooting",
        "docs-use-cases",
        "dynamic-devices",
        "entity-category",
        "entity-device-class",
        "entity-disabled-by-default",
        "entity-translations",
        "exception-translations",
        "icon-translations",
        "reconfiguration-flow",
        "repair-issues",
        "stale-devices",
    ],
    "platinum": ["async-dependency", "inject-websession", "strict-typing"],
}


@pytest.fixture(scope="module")
def rules() -> dict[str, object]:
    """The rules section of quality_scale.yaml."""
    data = yaml.safe_load(QUALITY_SCALE.read_text(encoding="utf-8"))
    assert isinstance(data, dict)
    assert set(data) == {"rules"}
    section = data["rules"]
    assert isinstance(section, dict)
    return section


def test_every_rule_is_listed(rules: dict[str, object]) -> None:
    """All rules of every tier, nothing else."""
    expected = {rule for tier in RULES.values() for rule in tier}
    assert set(rules) == expected


def test_statuses_are_known_and_explained(rules: dict[str, object]) -> None:
    """done, exempt or todo; an exemption or a todo says why."""
    for rule, value in rules.items():
        if isinstance(value, str):
            assert value == "done", rule
            continue
        assert isinstance(value, dict), rule
        assert set(value) <= {"status", "comment"}, rule
        assert value["status"] in {"done", "exempt", "todo"}, rule
        if value["status"] != "done":
            assert str(value.get("comment", "")).strip(), rule
