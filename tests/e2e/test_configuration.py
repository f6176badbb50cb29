"""The configuration directory scripts/develop and the browser test give Home Assistant."""

import json
from pathlib import Path
from typing import Any

from homeassistant.const import __version__ as ha_version
import pytest
import yaml

from tests.e2e.configuration import (
    DASHBOARD_FILE,
    DASHBOARD_URL_PATH,
    DEMO_DASHBOARD,
    HTTP_STORE,
    ISSUE_STORE,
    ONBOARDING_STORE,
    REPO_ROOT,
    TEMP_DIR,
    ConfigurationError,
    http_settings,
    http_settings_in_storage,
    write_configuration,
)
from tests.e2e.home_assistant import HomeAssistantProcess


def written(config_dir: Path) -> dict[str, Any]:
    """configuration.yaml as data."""
    data: dict[str, Any] = yaml.safe_load(
        (config_dir / "configuration.yaml").read_text(encoding="utf-8")
    )
    return data


def stored(config_dir: Path, store: Path) -> dict[str, Any]:
    """One of Home Assistant's storage files as data."""
    data: dict[str, Any] = json.loads((config_dir / store).read_text(encoding="utf-8"))
    return data


def store_http_settings(
    config_dir: Path,
    stable: dict[str, Any],
    pending: dict[str, Any] | None = None,
) -> None:
    """Leave `.storage/http` as Home Assistant 2026.10 does once it read the YAML."""
    path = config_dir / HTTP_STORE
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(
        json.dumps(
            {
                "version": 2,
                "key": "http",
                "data": {
                    "stable": {**stable, "error": None},
                    "pending": pending,
                    "yaml_migration_done": True,
                },
            }
        ),
        encoding="utf-8",
    )


def test_fresh_directory(tmp_path: Path) -> None:
    """Loopback only, the password provider alone, the dashboard, the integration."""
    write_configuration(tmp_path, port=18123)

    config = written(tmp_path)
    # In Home Assistant's storage, confirmed: YAML would leave a deprecation repair.
    assert "http" not in config
    settings = http_settings_in_storage(tmp_path)
    assert settings is not None
    assert {key: settings[key] for key in http_settings(18123)} == http_settings(18123)
    http = stored(tmp_path, HTTP_STORE)
    assert (http["version"], http["key"], http["data"]["pending"]) == (2, "http", None)
    assert http["data"]["stable"]["server_host"] == ["127.0.0.1", "::1"]
    assert http["data"]["stable"]["server_port"] == 18123
    assert not (tmp_path / ONBOARDING_STORE).exists()
    assert not (tmp_path / ISSUE_STORE).exists()
    assert "auth_providers" not in config["homeassistant"]
    assert "default_config" not in config
    dashboard = config["lovelace"]["dashboards"][DASHBOARD_URL_PATH]
    assert dashboard["mode"] == "yaml"
    assert dashboard["show_in_sidebar"] is True
    assert (
        tmp_path / dashboard["filename"]
    ).read_bytes() == DEMO_DASHBOARD.read_bytes()
    assert (tmp_path / "custom_components").resolve() == REPO_ROOT / "custom_components"
    assert config["logger"]["logs"] == {"custom_components.tecoapi": "info"}


def test_trusted_local_login(tmp_path: Path) -> None:
    """Passwordless sign-in is offered to loopback addresses only, the password kept."""
    write_configuration(tmp_path, port=8123, trusted_local_login=True, debug=True)

    config = written(tmp_path)
    trusted, password = config["homeassistant"]["auth_providers"]
    assert trusted == {
        "type": "trusted_networks",
        "trusted_networks": ["127.0.0.1/32", "::1/128"],
        "allow_bypass_login": True,
    }
    assert password == {"type": "homeassistant"}
    assert config["logger"]["logs"] == {"custom_components.tecoapi": "debug"}


def test_the_demo_owners_choices(tmp_path: Path) -> None:
    """Onboarding past the owner's step and one repair ignored, before the first start."""
    write_configuration(tmp_path, port=8123, demo=True)

    onboarding = stored(tmp_path, ONBOARDING_STORE)
    assert (onboarding["version"], onboarding["key"]) == (4, "onboarding")
    assert onboarding["data"] == {"done": ["core_config", "analytics", "integration"]}
    issues = stored(tmp_path, ISSUE_STORE)
    assert (issues["key"], issues["minor_version"]) == ("repairs.issue_registry", 2)
    [ignored] = issues["data"]["issues"]
    assert (ignored["domain"], ignored["issue_id"]) == (
        "homeassistant",
        "deprecated_method",
    )
    assert ignored["dismissed_version"] == ha_version

    # Home Assistant's own later state is never overwritten.
    done = {"done": ["user", "core_config", "analytics", "integration"]}
    (tmp_path / ONBOARDING_STORE).write_text(json.dumps({"data": done}), "utf-8")
    write_configuration(tmp_path, port=8123, demo=True)
    assert stored(tmp_path, ONBOARDING_STORE)["data"] == done


def test_rewritten_over_an_earlier_run(tmp_path: Path) -> None:
    """A second start replaces the link and the files the first one wrote."""
    write_configuration(tmp_path, port=8123)
    (tmp_path / DASHBOARD_FILE).write_text("edited", encoding="utf-8")

    write_configuration(tmp_path, port=8123)

    assert "http" not in written(tmp_path)
    assert (tmp_path / DASHBOARD_FILE).read_bytes() == DEMO_DASHBOARD.read_bytes()
    assert (tmp_path / "custom_components").is_symlink()


@pytest.mark.parametrize(
    ("stable", "pending"),
    [
        (http_settings(8123), None),
        ({"server_port": 8123}, {**http_settings(8123), "error": None}),
    ],
    ids=["confirmed", "on trial"],
)
def test_http_settings_in_storage_are_kept(
    tmp_path: Path, stable: dict[str, Any], pending: dict[str, Any] | None
) -> None:
    """Once Home Assistant keeps the right HTTP settings, they are left as they are."""
    store_http_settings(tmp_path, stable, pending)
    before = (tmp_path / HTTP_STORE).read_bytes()

    write_configuration(tmp_path, port=8123)

    assert "http" not in written(tmp_path)
    assert (tmp_path / HTTP_STORE).read_bytes() == before


@pytest.mark.parametrize(
    ("stable", "pending", "port"),
    [
        ({"server_port": 8123, "server_host": ["0.0.0.0"]}, None, 8123),  # noqa: S104
        (http_settings(8123), None, 9123),
        (
            {"server_port": 8123},
            {**http_settings(8123), "error": "not_promoted"},
            8123,
        ),
    ],
    ids=["every interface", "another port", "trial reverted"],
)
def test_other_http_settings_in_storage_refused(
    tmp_path: Path, stable: dict[str, Any], pending: dict[str, Any] | None, port: int
) -> None:
    """Home Assistant would ignore the YAML and listen elsewhere: refuse to go on."""
    store_http_settings(tmp_path, stable, pending)

    with pytest.raises(ConfigurationError, match="delete"):
        write_configuration(tmp_path, port=port)
    assert not (tmp_path / "configuration.yaml").exists()


def test_every_view_s_tab_says_its_title() -> None:
    """A view with an icon shows the icon alone on its tab: the demo's show titles."""
    views = yaml.safe_load(DEMO_DASHBOARD.read_text("utf-8"))["views"]
    assert [view["title"] for view in views] == [
        "Home",
        "Plant & garage",
        "Building",
        "Chata Lipno",
    ]
    assert [view for view in views if "icon" in view] == []


def test_home_assistant_has_a_temporary_directory_of_its_own(tmp_path: Path) -> None:
    """Not /tmp: another Home Assistant there empties home-assistant-file_upload."""
    config_dir = tmp_path / "config"
    write_configuration(config_dir, port=8123)
    assert (config_dir / TEMP_DIR).is_dir()
    process = HomeAssistantProcess(config_dir, 8123, tmp_path / "ha.log")
    assert process.environment["TMPDIR"] == str(config_dir / TEMP_DIR)
    # scripts/develop starts its Home Assistant the same way.
    develop = (REPO_ROOT / "scripts" / "develop").read_text(encoding="utf-8")
    assert f'TMPDIR="$config/{TEMP_DIR}" setsid hass --config "$config"' in develop
