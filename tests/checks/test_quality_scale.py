"""quality_scale_problems: each rule core validates, failing on its planted fault.

A small integration that passes every rule is written to a folder; each test
changes one file of it as a careless change would, and the rule says what core's
validator says (the rule's name, the file).
"""

from collections.abc import Mapping
import json
from pathlib import Path
from typing import Any, Final

import pytest

from scripts.checks.quality_scale import (
    VALIDATORS,
    Integration,
    quality_scale_problems,
    rules_done,
)

MANIFEST: Final = {"domain": "demo", "config_flow": True, "dhcp": [{"hostname": "x*"}]}
PYPROJECT: Final = {
    "tool": {"mypy": {"strict": True, "packages": ["custom_components.demo"]}}
}

INIT: Final = """
from homeassistant.config_entries import ConfigEntry
from homeassistant.core import HomeAssistant

type DemoConfigEntry = ConfigEntry[object]


async def async_setup(hass, config):
    hass.services.async_register("demo", "poke", handler)
    return True


async def async_setup_entry(hass: HomeAssistant, entry: DemoConfigEntry) -> bool:
    coordinator = Coordinator(hass, entry)
    await coordinator.async_config_entry_first_refresh()
    entry.runtime_data = coordinator
    return True


async def async_unload_entry(hass: HomeAssistant, entry: DemoConfigEntry) -> bool:
    return True
"""
CONFIG_FLOW: Final = """
from homeassistant.config_entries import ConfigFlow
from .flows import Steps
from . import DemoConfigEntry


class DemoFlow(Steps, ConfigFlow, domain="demo"):
    async def async_step_user(self, user_input=None):
        return await super().async_step_user(user_input)

    async def async_step_reauth(self, entry_data):
        return await super().async_step_reauth(entry_data)

    async def async_step_reconfigure(self, user_input=None):
        return await super().async_step_reconfigure(user_input)

    async def _claim(self, unique_id):
        await self.async_set_unique_id(unique_id)
        self._abort_if_unique_id_configured()

    @staticmethod
    def async_get_options_flow(config_entry: DemoConfigEntry):
        return Options()
"""
DIAGNOSTICS: Final = """
async def async_get_config_entry_diagnostics(hass, entry: DemoConfigEntry):
    return {}
"""
ENTITY: Final = """
from homeassistant.helpers.entity import Entity


class DemoEntity(Entity):
    _attr_has_entity_name = True
"""
SENSOR: Final = """
from homeassistant.components.sensor import SensorEntity
from .entity import DemoEntity

PARALLEL_UPDATES = 0


async def async_setup_entry(hass, entry: DemoConfigEntry, add_entities):
    add_entities([DemoSensor()])


class DemoSensor(DemoEntity, SensorEntity):
    pass
"""
FILES: Final = {
    "__init__.py": INIT,
    "config_flow.py": CONFIG_FLOW,
    "diagnostics.py": DIAGNOSTICS,
    "entity.py": ENTITY,
    "sensor.py": SENSOR,
}


def integration(
    root: Path,
    changes: Mapping[str, str | None] | None = None,
    *,
    manifest: Mapping[str, Any] = MANIFEST,
    pyproject: Mapping[str, Any] = PYPROJECT,
) -> Integration:
    """The demo integration, with files replaced (None: removed)."""
    path = root / "custom_components" / "demo"
    path.mkdir(parents=True)
    (path / "manifest.json").write_text(json.dumps(manifest), encoding="utf-8")
    for name, text in {**FILES, **(changes or {})}.items():
        if text is not None:
            (path / name).write_text(text, encoding="utf-8")
    return Integration(
        path=path,
        manifest=manifest,
        rules_done=frozenset(VALIDATORS),
        pyproject=pyproject,
    )


def problems(root: Path, **kwargs: Any) -> list[str]:
    return quality_scale_problems(integration(root, **kwargs))


def test_checker_quality_scale_passes_an_integration_that_keeps_every_rule(
    tmp_path: Path,
) -> None:
    assert problems(tmp_path) == []


def test_checker_quality_scale_reads_the_rules_marked_done() -> None:
    assert rules_done(
        {
            "rules": {
                "config-flow": "done",
                "brands": {"status": "done", "comment": "x"},
                "discovery": {"status": "exempt", "comment": "x"},
                "diagnostics": "todo",
            }
        }
    ) == {"config-flow", "brands"}


def test_checker_quality_scale_runs_only_the_rules_marked_done(tmp_path: Path) -> None:
    demo = integration(tmp_path, {"config_flow.py": None})
    todo = Integration(demo.path, demo.manifest, frozenset({"diagnostics"}))
    assert quality_scale_problems(todo) == []


def without(text: str, *lines: str) -> str:
    for line in lines:
        assert line in text
        text = text.replace(line, "")
    return text


@pytest.mark.parametrize(
    ("changes", "expected"),
    [
        pytest.param(
            {"config_flow.py": None},
            [
                "config-flow: config_flow.py is missing",
                "discovery: config_flow.py is missing",
                "reauthentication-flow: config_flow.py is missing",
                "reconfiguration-flow: config_flow.py is missing",
                "unique-config-entry: config_flow.py is missing",
            ],
            id="no config_flow.py",
        ),
        pytest.param(
            # The steps live in another module only (config_flow.py re-exports).
            {"config_flow.py": "from .flows import DemoFlow, Options\n"},
            [
                "config-flow: config_flow.py defines no `async_step_user`",
                "reauthentication-flow: config_flow.py defines no `async_step_reauth`",
                (
                    "reconfiguration-flow: config_flow.py defines no "
                    "`async_step_reconfigure`"
                ),
                (
                    "unique-config-entry: config_flow.py calls neither "
                    "_async_abort_entries_match nor both async_set_unique_id and "
                    "_abort_if_unique_id_configured"
                ),
            ],
            id="steps only in flows/",
        ),
        pytest.param(
            {
                "config_flow.py": without(
                    CONFIG_FLOW, "        self._abort_if_unique_id_configured()\n"
                )
            },
            [
                (
                    "unique-config-entry: config_flow.py calls neither "
                    "_async_abort_entries_match nor both async_set_unique_id and "
                    "_abort_if_unique_id_configured"
                )
            ],
            id="unique ID set, never checked",
        ),
        pytest.param(
            {
                "config_flow.py": CONFIG_FLOW.replace(
                    "config_entry: DemoConfigEntry", "config_entry: ConfigEntry"
                )
            },
            [
                (
                    "runtime-data: async_get_options_flow does not take a typed config "
                    "entry (XxxConfigEntry) in config_flow.py (DemoFlow)"
                )
            ],
            id="options flow factory takes a plain ConfigEntry",
        ),
        pytest.param(
            {"__init__.py": without(INIT, "    entry.runtime_data = coordinator\n")},
            ["runtime-data: async_setup_entry does not set entry.runtime_data"],
            id="runtime_data never set",
        ),
        pytest.param(
            {
                "__init__.py": INIT.replace(
                    "async_unload_entry(hass: HomeAssistant, entry: DemoConfigEntry)",
                    'async_unload_entry(hass: HomeAssistant, entry: "DemoConfigEntry")',
                )
            },
            [
                (
                    "runtime-data: async_unload_entry does not take a typed config entry "
                    "(XxxConfigEntry) in __init__.py"
                )
            ],
            id="a quoted annotation is no typed entry",
        ),
        pytest.param(
            {
                "sensor.py": SENSOR.replace(
                    "entry: DemoConfigEntry", "entry: ConfigEntry"
                )
            },
            [
                (
                    "runtime-data: async_setup_entry does not take a typed config entry "
                    "(XxxConfigEntry) in sensor.py"
                )
            ],
            id="a platform takes a plain ConfigEntry",
        ),
        pytest.param(
            {"diagnostics.py": DIAGNOSTICS.replace("entry: DemoConfigEntry", "entry")},
            [
                (
                    "runtime-data: async_get_config_entry_diagnostics does not take a "
                    "typed config entry (XxxConfigEntry) in diagnostics.py"
                )
            ],
            id="diagnostics take an untyped entry",
        ),
        pytest.param(
            {
                "__init__.py": without(
                    INIT, "    await coordinator.async_config_entry_first_refresh()\n"
                )
            },
            [
                (
                    "test-before-setup: the integration raises none of "
                    "ConfigEntryAuthFailed, ConfigEntryError, ConfigEntryNotReady"
                )
            ],
            id="no first refresh, no setup error",
        ),
        pytest.param(
            {"diagnostics.py": "async def diagnostics(hass, entry):\n    return {}\n"},
            [
                (
                    "diagnostics: diagnostics.py defines none of "
                    "async_get_config_entry_diagnostics, async_get_device_diagnostics"
                )
            ],
            id="diagnostics under another name",
        ),
        pytest.param(
            {"diagnostics.py": None},
            ["diagnostics: diagnostics.py is missing"],
            id="no diagnostics.py",
        ),
        pytest.param(
            {
                "__init__.py": INIT.replace(
                    "    entry.runtime_data = coordinator\n",
                    "    entry.runtime_data = coordinator\n"
                    '    hass.services.async_register("demo", "poke", handler)\n',
                )
            },
            ["action-setup: __init__.py registers actions in async_setup_entry"],
            id="an action registered per entry",
        ),
        pytest.param(
            {
                "sensor.py": SENSOR.replace(
                    "    add_entities([DemoSensor()])\n",
                    "    add_entities([DemoSensor()])\n"
                    "    platform.async_register_entity_service('poke', {}, 'poke')\n",
                )
            },
            ["action-setup: sensor.py registers actions in async_setup_entry"],
            id="an entity action registered per entry",
        ),
        pytest.param(
            {
                "__init__.py": INIT.replace(
                    "async def async_unload_entry", "async def unload_entry"
                )
            },
            ["config-entry-unloading: __init__.py defines no async_unload_entry"],
            id="no async_unload_entry",
        ),
        pytest.param(
            {
                "sensor.py": SENSOR.replace(
                    "PARALLEL_UPDATES = 0", "PARALLEL_UPDATES: int = 0"
                )
            },
            ["parallel-updates: sensor.py does not set PARALLEL_UPDATES"],
            id="PARALLEL_UPDATES annotated (core does not see it)",
        ),
        pytest.param(
            {
                "entity.py": ENTITY.replace(
                    "_attr_has_entity_name = True", "_attr_has_entity_name = False"
                )
            },
            [
                "has-entity-name: DemoEntity does not set _attr_has_entity_name = True",
                "has-entity-name: DemoSensor does not set _attr_has_entity_name = True",
            ],
            id="entities not named by has_entity_name",
        ),
    ],
)
def test_checker_quality_scale_finds_each_planted_fault(
    tmp_path: Path, changes: dict[str, str | None], expected: list[str]
) -> None:
    assert problems(tmp_path, changes=changes) == expected


def test_checker_quality_scale_discovery_from_the_manifest_or_a_step(
    tmp_path: Path,
) -> None:
    no_discovery = {"domain": "demo", "config_flow": True}
    assert problems(tmp_path / "a", manifest=no_discovery) == [
        "discovery: neither the manifest nor config_flow.py declares a way of discovery"
    ]
    with_step = CONFIG_FLOW.replace(
        "    async def _claim",
        "    async def async_step_zeroconf(self, info):\n"
        "        return None\n\n    async def _claim",
    )
    assert (
        problems(
            tmp_path / "b", manifest=no_discovery, changes={"config_flow.py": with_step}
        )
        == []
    )


def test_checker_quality_scale_config_flow_in_the_manifest(tmp_path: Path) -> None:
    assert problems(tmp_path, manifest={**MANIFEST, "config_flow": False}) == [
        "config-flow: manifest.json does not set config_flow"
    ]


def test_checker_quality_scale_single_config_entry_needs_no_unique_id(
    tmp_path: Path,
) -> None:
    flow = without(CONFIG_FLOW, "        self._abort_if_unique_id_configured()\n")
    single = {**MANIFEST, "single_config_entry": True}
    assert problems(tmp_path, manifest=single, changes={"config_flow.py": flow}) == []


def test_checker_quality_scale_abort_entries_match_is_a_unique_check(
    tmp_path: Path,
) -> None:
    flow = CONFIG_FLOW.replace(
        "        await self.async_set_unique_id(unique_id)\n"
        "        self._abort_if_unique_id_configured()\n",
        "        self._async_abort_entries_match({'host': unique_id})\n",
    )
    assert problems(tmp_path, changes={"config_flow.py": flow}) == []


@pytest.mark.parametrize(
    ("mypy", "expected"),
    [
        (
            {"packages": ["custom_components.demo"]},
            ["strict-typing: pyproject.toml's [tool.mypy] is not strict = true"],
        ),
        (
            {"strict": True, "packages": ["scripts"]},
            ["strict-typing: mypy does not check custom_components.demo"],
        ),
        ({"strict": True, "files": ["custom_components/demo"]}, []),
        (
            {
                "strict": True,
                "packages": ["custom_components.demo"],
                "overrides": [
                    {"module": "custom_components.demo.sensor", "ignore_errors": True}
                ],
            },
            ["strict-typing: a mypy override relaxes custom_components.demo.sensor"],
        ),
    ],
)
def test_checker_quality_scale_strict_typing_reads_the_project_s_mypy(
    tmp_path: Path, mypy: dict[str, Any], expected: list[str]
) -> None:
    assert problems(tmp_path, pyproject={"tool": {"mypy": mypy}}) == expected


def test_checker_quality_scale_typed_entries_only_with_strict_typing(
    tmp_path: Path,
) -> None:
    """Core reads the annotations only where strict-typing is done."""
    demo = integration(
        tmp_path,
        {
            "config_flow.py": CONFIG_FLOW.replace(
                "config_entry: DemoConfigEntry", "config_entry: ConfigEntry"
            )
        },
    )
    loose = Integration(demo.path, demo.manifest, frozenset({"runtime-data"}))
    assert quality_scale_problems(loose) == []
