"""quality_scale.yaml lists every rule of the Integration Quality Scale, each one backed.

A rule marked done is backed by a check here (``@backs``), by existing tests that
prove it or by the documentation's sections that say it (both listed in
quality_scale_backing.yaml: a proving test deleted or renamed, or a heading
dropped, fails here); an exemption by a check that its reason still holds. The
finders the checks use (tests/quality_scale.py) are each shown to find a planted
fault.
"""

from collections.abc import Callable
import importlib
import json
from pathlib import Path
import sys
import tomllib
from typing import Any, Final

from homeassistant import exceptions
from homeassistant.config_entries import ConfigEntryNotReady
from homeassistant.const import EntityCategory
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import AbortFlow
from homeassistant.exceptions import HomeAssistantError
from homeassistant.helpers import entity_registry as er
from homeassistant.helpers.aiohttp_client import async_get_clientsession
from homeassistant.helpers.entity import Entity
from homeassistant.helpers.typing import UNDEFINED
from homeassistant.helpers.update_coordinator import DataUpdateCoordinator
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry
import yaml

from custom_components.tecoapi import PLATFORMS
from custom_components.tecoapi.config_flow import PlcConfigFlow
from custom_components.tecoapi.connection import source_context
from custom_components.tecoapi.const import (
    DEFAULT_ATTRIBUTE_INTERVAL,
    DEFAULT_SCAN_INTERVAL,
    MAX_SCAN_INTERVAL,
    MIN_SCAN_INTERVAL,
)
from custom_components.tecoapi.coordinator import PlcConfigEntry, PlcCoordinator
from custom_components.tecoapi.device_info import KIND_NAMES
from custom_components.tecoapi.sensor import STATUS_SENSORS, PlcStatusSensor
from tests.quality_scale import (
    HA_MODULES,
    INTEGRATION,
    PACKAGE,
    ROOT,
    blocking_io,
    entity_class_problems,
    entity_classes,
    entity_descriptions,
    hass_data_uses,
    icons_in_code,
    missing_parallel_updates,
    missing_tests,
    module_name,
    platform_modules,
    section,
    untranslated_errors,
)


def _load(path: Path) -> Any:
    text = path.read_text(encoding="utf-8")
    return json.loads(text) if path.suffix == ".json" else yaml.safe_load(text)


SCALE: Final = _load(INTEGRATION / "quality_scale.yaml")
BACKING: Final = _load(Path(__file__).with_name("quality_scale_backing.yaml"))
MANIFEST: Final = _load(INTEGRATION / "manifest.json")
EN: Final = _load(INTEGRATION / "translations" / "en.json")
ICONS: Final = _load(INTEGRATION / "icons.json")
PYPROJECT: Final = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))

# hassfest's rules, Bronze to Platinum (home-assistant/core,
# script/hassfest/quality_scale.py, ALL_RULES); hassfest is not installed here.
RULES: Final = {
    "bronze": [
        "action-setup", "appropriate-polling", "brands", "common-modules",
        "config-flow", "config-flow-test-coverage", "dependency-transparency",
        "docs-actions", "docs-conditions", "docs-high-level-description",
        "docs-installation-instructions", "docs-removal-instructions",
        "docs-triggers", "entity-event-setup", "entity-unique-id",
        "has-entity-name", "runtime-data", "test-before-configure",
        "test-before-setup", "unique-config-entry",
    ],
    "silver": [
        "action-exceptions", "config-entry-unloading",
        "docs-configuration-parameters", "docs-installation-parameters",
        "entity-unavailable", "integration-owner", "log-when-unavailable",
        "parallel-updates", "reauthentication-flow", "test-coverage",
    ],
    "gold": [
        "devices", "diagnostics", "discovery", "discovery-update-info",
        "docs-data-update", "docs-examples", "docs-known-limitations",
        "docs-supported-devices", "docs-supported-functions",
        "docs-troubleshooting", "docs-use-cases", "dynamic-devices",
        "entity-category", "entity-device-class", "entity-disabled-by-default",
        "entity-translations", "exception-translations", "icon-translations",
        "reconfiguration-flow", "repair-issues", "stale-devices",
    ],
    "platinum": ["async-dependency", "inject-websession", "strict-typing"],
}  # fmt: skip

CHECKED: Final[dict[str, list[str]]] = {}
"""Rule -> the checks in this file that back it."""


def backs[T: Callable[..., Any]](*rules: str) -> Callable[[T], T]:
    """Mark a test as a check that backs ``rules``."""

    def mark(test: T) -> T:
        for rule in rules:
            CHECKED.setdefault(rule, []).append(test.__name__)
        return test

    return mark


def _statuses() -> dict[str, str]:
    return {
        rule: value if isinstance(value, str) else value["status"]
        for rule, value in SCALE["rules"].items()
    }


# ---------------------------------------------------------------------------
# The list, and what backs each rule


def test_every_rule_is_listed() -> None:
    """All rules of every tier, nothing else."""
    assert set(_statuses()) == {rule for tier in RULES.values() for rule in tier}


def test_statuses_pass_hassfest_s_schema() -> None:
    """done or todo (alone or with a comment); exempt always with its reason."""
    assert set(SCALE) == {"rules"}
    for rule, value in SCALE["rules"].items():
        if isinstance(value, str):
            assert value in {"done", "todo"}, rule
            continue
        assert set(value) == {"status", "comment"}, rule
        assert value["status"] in {"done", "exempt", "todo"}, rule
        assert str(value["comment"]).strip(), rule


def test_every_done_or_exempt_rule_is_backed() -> None:
    """Nothing is claimed unchecked, and nothing checked is left unclaimed."""
    statuses = _statuses()
    claimed = {rule for rule, status in statuses.items() if status != "todo"}
    proven, documented = set(BACKING["proven_by"]), set(BACKING["documented"])
    assert proven | documented | set(CHECKED) == claimed
    # An exemption is backed by a check that its reason holds, not by a proof.
    exempt = {rule for rule, status in statuses.items() if status == "exempt"}
    assert exempt.isdisjoint(proven | documented)


@pytest.mark.parametrize("rule", sorted(BACKING["proven_by"]))
def test_the_proving_tests_exist(rule: str) -> None:
    assert missing_tests(BACKING["proven_by"][rule]) == []


@pytest.mark.parametrize("rule", sorted(BACKING["documented"]))
def test_the_documentation_says_it(rule: str) -> None:
    for place in BACKING["documented"][rule]:
        text = section(place["page"], place["heading"])
        assert text is not None, place
        assert text.strip(), place
        says = [
            fact for fact in place.get("says", []) if fact.lower() not in text.lower()
        ]
        assert says == [], place


# ---------------------------------------------------------------------------
# Checks of the code and the documentation


@backs("docs-installation-parameters")
@pytest.mark.parametrize("step", sorted(BACKING["forms"]))
def test_each_form_s_fields_are_documented(step: str) -> None:
    """Every field of a source's form is named where the form is explained."""
    text = section(**BACKING["forms"][step])
    assert text is not None
    labels = EN["config"]["step"][step]["data"].values()
    assert [label for label in labels if label.lower() not in text.lower()] == []


@backs("parallel-updates")
def test_every_platform_sets_parallel_updates() -> None:
    """0 where the coordinator polls (read-only platforms), 1 where entities write."""
    modules = platform_modules()
    assert missing_parallel_updates(modules) == []
    read_only = {"binary_sensor", "event", "sensor"}
    assert {name: module.PARALLEL_UPDATES for name, module in modules.items()} == {
        name: 0 if name in read_only else 1 for name in modules
    }


@backs("has-entity-name", "common-modules")
def test_entities_share_the_base_and_have_entity_names() -> None:
    """Every entity derives from entity.py's base; the coordinator is coordinator.py's."""
    classes = list(entity_classes())
    assert len(classes) > len(PLATFORMS)
    assert entity_class_problems(classes) == []
    assert issubclass(PlcCoordinator, DataUpdateCoordinator)
    assert PlcCoordinator.__module__ == f"{PACKAGE}.coordinator"


@backs("runtime-data")
def test_runtime_data_lives_on_the_typed_entry() -> None:
    """No hass.data; the entry is ConfigEntry[PlcCoordinator], filled at setup."""
    for module in HA_MODULES:
        assert hass_data_uses(module.read_text(encoding="utf-8")) == [], module.name
    assert PlcConfigEntry.__value__.__args__ == (PlcCoordinator,)
    setup = (INTEGRATION / "__init__.py").read_text(encoding="utf-8")
    assert "    entry.runtime_data = coordinator\n" in setup


@backs("config-flow")
def test_the_config_flow_describes_every_field() -> None:
    """Set up in the UI; every field of a config or subentry form is described."""
    assert MANIFEST["config_flow"] is True
    assert PlcConfigFlow.__module__ == f"{PACKAGE}.config_flow"
    steps = [
        ("config", step, strings) for step, strings in EN["config"]["step"].items()
    ]
    steps += [
        (kind, step, strings)
        for kind, flow in EN["config_subentries"].items()
        for step, strings in flow["step"].items()
    ]
    assert len(steps) > 10
    for flow, step, strings in steps:
        for part in (strings, *strings.get("sections", {}).values()):
            described = set(part.get("data_description", {}))
            assert set(part.get("data", {})) == described, (flow, step)


@backs("entity-translations", "entity-category", "icon-translations")
def test_status_entities_are_translated_diagnostics_with_icons() -> None:
    """The integration's own entities: a translated name, diagnostic, an icon."""
    descriptions = entity_descriptions()
    assert {d.translation_key for _, d in descriptions} >= {"mode", "running_problem"}
    for platform, description in descriptions:
        key = description.translation_key
        assert key is not None, description.key
        assert description.name is UNDEFINED, key
        assert EN["entity"][platform][key]["name"], key
        assert description.entity_category is EntityCategory.DIAGNOSTIC, key
        assert ICONS["entity"][platform][key]["default"].startswith("mdi:"), key
    # A typed device is named by translation: its kind in its room (or group).
    for kind in {*KIND_NAMES.values(), "gate"}:
        assert "{room}" in EN["device"][f"{kind}_in"]["name"], kind
        assert "{room}" in EN["device"][f"{kind}_in_of_plc"]["name"], kind


@backs("icon-translations")
def test_no_icon_is_set_in_code() -> None:
    """Icons come from icons.json (or the device class), the actions' too."""
    for module in HA_MODULES:
        assert icons_in_code(module.read_text(encoding="utf-8")) == [], module.name
    actions = _load(INTEGRATION / "services.yaml")
    assert set(ICONS["services"]) == set(actions)


@backs("exception-translations")
def test_every_error_the_integration_raises_is_translated() -> None:
    for module in HA_MODULES:
        namespace = vars(importlib.import_module(module_name(module)))
        source = module.read_text(encoding="utf-8")
        assert untranslated_errors(source, namespace) == [], module.name


@backs("entity-event-setup")
async def test_entities_listen_from_added_to_removed(
    hass: HomeAssistant, demo_entry: MockConfigEntry
) -> None:
    """An entity made subscribes to nothing; one removed stops listening."""
    coordinator = demo_entry.runtime_data

    def listeners() -> int:
        return len(list(coordinator.async_contexts()))

    listening = listeners()
    PlcStatusSensor(coordinator, STATUS_SENSORS[0])
    assert listeners() == listening
    er.async_get(hass).async_remove("sensor.tecomat_cp_2080_mode")
    await hass.async_block_till_done()
    assert listeners() == listening - 1


@backs("appropriate-polling")
def test_polling_defaults() -> None:
    """Values every 5 s (1-300 s in the options), the slow attributes every 60 s."""
    assert DEFAULT_SCAN_INTERVAL.total_seconds() == 5
    assert MIN_SCAN_INTERVAL.total_seconds() == 1
    assert MAX_SCAN_INTERVAL.total_seconds() == 300
    assert DEFAULT_ATTRIBUTE_INTERVAL.total_seconds() == 60


@backs("discovery", "integration-owner")
def test_the_manifest_declares_discovery_and_owners() -> None:
    assert {"macaddress": "000A14*"} in MANIFEST["dhcp"]
    assert callable(getattr(PlcConfigFlow, "async_step_dhcp", None))
    assert MANIFEST["codeowners"]
    assert all(owner.startswith("@") for owner in MANIFEST["codeowners"])


@backs("inject-websession")
async def test_sources_use_home_assistant_s_session(hass: HomeAssistant) -> None:
    """Every source gets Home Assistant's shared session; nothing makes its own."""
    context = source_context(hass)
    assert context.http(True) is async_get_clientsession(hass)
    assert context.http(False) is async_get_clientsession(hass, verify_ssl=False)
    for module in INTEGRATION.rglob("*.py"):
        source = module.read_text(encoding="utf-8")
        assert "ClientSession(" not in source, module
        assert "async_create_clientsession" not in source, module
    clients = [
        *INTEGRATION.glob("pyplc/*/client.py"),
        *INTEGRATION.glob("pyplc/*/*/client.py"),
    ]
    http = [c for c in clients if "import aiohttp" in c.read_text(encoding="utf-8")]
    assert len(http) == 4
    for client in http:
        assert "session: aiohttp.ClientSession," in client.read_text(encoding="utf-8")


@backs("async-dependency")
def test_the_library_is_asyncio() -> None:
    """The library does its I/O with asyncio and aiohttp, never a blocking client."""
    for module in (INTEGRATION / "pyplc").rglob("*.py"):
        assert blocking_io(module.read_text(encoding="utf-8")) == [], module


@backs("strict-typing")
def test_mypy_is_strict_over_the_whole_integration() -> None:
    """mypy --strict checks the integration and its library, nothing relaxed."""
    mypy = PYPROJECT["tool"]["mypy"]
    assert mypy["strict"] is True
    assert PACKAGE in mypy["packages"]
    for override in mypy.get("overrides", []):
        assert not any(m.startswith("custom_components") for m in override["module"])


@backs("test-coverage", "config-flow-test-coverage")
def test_coverage_is_enforced() -> None:
    """The suite fails under 95 %, and under 100 % of config_flow.py or of flows/."""
    assert PYPROJECT["tool"]["coverage"]["report"]["fail_under"] >= 95
    script = (ROOT / "scripts" / "test").read_text(encoding="utf-8")
    commands = " ".join(script.replace("\\\n", " ").split())  # lines continued
    assert "tecoapi_exec primary python -m pytest" in commands
    assert "--cov --cov-report" in commands
    assert (
        "tecoapi_exec primary python -m coverage report "
        "--include=custom_components/tecoapi/config_flow.py --fail-under=100"
    ) in commands
    assert (
        "tecoapi_exec primary python -m coverage report "
        "--include='custom_components/tecoapi/flows/*.py' --fail-under=100"
    ) in commands


@backs("dependency-transparency", "docs-triggers", "docs-conditions")
def test_the_exemptions_still_hold() -> None:
    """No requirement (the library ships inside); no trigger or condition to describe."""
    assert MANIFEST["requirements"] == []
    assert (INTEGRATION / "pyplc" / "README.md").is_file()
    for name in ("trigger", "condition", "device_trigger", "device_condition"):
        assert not (INTEGRATION / f"{name}.py").exists(), name


# ---------------------------------------------------------------------------
# Each finder finds a planted fault


def test_a_missing_or_renamed_proving_test_is_found() -> None:
    here = "tests/components/tecoapi/test_quality_scale.py"
    assert missing_tests(
        [
            f"{here}::test_every_rule_is_listed",
            f"{here}::test_the_proving_tests_exist[devices]",
            f"{here}::test_that_was_renamed",
            "tests/components/tecoapi/test_gone.py::test_a",
        ]
    ) == [
        f"{here}::test_that_was_renamed",
        "tests/components/tecoapi/test_gone.py::test_a",
    ]


def test_a_platform_without_parallel_updates_is_found(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A copy of sensor.py without its PARALLEL_UPDATES."""
    source = (INTEGRATION / "sensor.py").read_text(encoding="utf-8")
    assert "\nPARALLEL_UPDATES = 0\n" in source
    planted = type(importlib)(f"{PACKAGE}.planted_sensor")
    planted.__package__ = PACKAGE
    monkeypatch.setitem(sys.modules, planted.__name__, planted)  # for its dataclasses
    exec(source.replace("\nPARALLEL_UPDATES = 0\n", "\n"), vars(planted))  # noqa: S102
    assert missing_parallel_updates({"sensor": planted}) == ["sensor"]


def test_an_entity_without_a_name_or_the_base_is_found() -> None:
    class Planted(Entity):
        pass

    assert entity_class_problems([Planted]) == [
        "Planted does not derive from PlcEntity",
        "Planted does not set has_entity_name",
    ]


def test_untranslated_errors_hass_data_icons_and_blocking_io_are_found() -> None:
    source = (
        "import requests\n"
        "def f(hass):\n"
        "    hass.data[DOMAIN] = 1\n"
        "    raise HomeAssistantError('no translation')\n"
        "def g(self):\n"
        "    self.hass.data.get(DOMAIN)\n"
        "    self._attr_icon = 'mdi:x'\n"
        "    time.sleep(1)\n"
        "    raise HomeAssistantError(translation_domain=D, translation_key='k')\n"
        "    raise ConfigEntryNotReady\n"
        "    raise exceptions.HomeAssistantError('x')\n"
        "    raise ConfigEntryNotReady(translation_domain=D, translation_key=None)\n"
        "    raise exceptions.ConfigEntryError(translation_domain=D, translation_key=k)\n"
        "    raise AbortFlow('already_configured')\n"
        "    raise err\n"
    )
    namespace = {
        "HomeAssistantError": HomeAssistantError,
        "ConfigEntryNotReady": ConfigEntryNotReady,
        "AbortFlow": AbortFlow,
        "exceptions": exceptions,
    }
    assert untranslated_errors(source, namespace) == [
        "line 4: HomeAssistantError",
        "line 10: ConfigEntryNotReady",
        "line 11: exceptions.HomeAssistantError",
        "line 12: ConfigEntryNotReady",
    ]
    assert hass_data_uses(source) == [3, 6]
    assert icons_in_code(source) == [7]
    assert sorted(blocking_io(source)) == [1, 8]


def test_a_heading_s_section_ends_at_the_next_of_its_level(tmp_path: Path) -> None:
    (tmp_path / "p.md").write_text("# T\nintro\n## A\na\n### B\n#hash\n## C\nc\n")
    assert section("p.md", "T", tmp_path) == "intro"
    assert section("p.md", "A", tmp_path) == "a\n### B\n#hash"
    assert section("p.md", "Z", tmp_path) is None
