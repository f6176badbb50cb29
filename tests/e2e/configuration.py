"""The configuration directory of a Home Assistant that runs this integration.

Everything Home Assistant would otherwise look up on the internet (location, time zone,
currency) is given, and only what the demo needs is loaded: `default_config:` would add
integrations that reach out to the internet and packages to install on first start.

The HTTP settings go straight into Home Assistant's storage, where 2026.10 keeps them:
`http:` in configuration.yaml would be read once and leave a repair saying that YAML is
deprecated.

For the demo (`demo`), two choices its owner would make are made beforehand, so that
it starts without errors or repairs that are not this integration's:

- the onboarding steps after the owner's account are done: finishing the core
  configuration step adds integrations that need the internet (met, radio_browser;
  Google's text-to-speech), which log errors offline; the demo's location and units
  are in configuration.yaml anyway;
- the repair saying that Home Assistant Core in a virtual environment is a deprecated
  installation method is ignored, as the owner would with its "Ignore" button: the
  demo runs Home Assistant that way on purpose (it is not a home's installation).

    python -m tests.e2e.configuration CONFIG_DIR --port 8123 --trusted-local-login --demo
"""

import argparse
from collections.abc import Sequence
from datetime import UTC, datetime
import json
from pathlib import Path
import shutil
import sys
from typing import Any, Final

from homeassistant.const import __version__ as ha_version
import yaml

REPO_ROOT: Final = Path(__file__).resolve().parents[2]
DEMO_DASHBOARD: Final = Path(__file__).with_name("demo_dashboard.yaml")
DASHBOARD_FILE: Final = "tecoapi_demo_dashboard.yaml"
DASHBOARD_URL_PATH: Final = "tecoapi-demo"
DASHBOARD_TITLE: Final = "Family house"
LOOPBACK: Final = ("127.0.0.1", "::1")

HTTP_STORE: Final = Path(".storage", "http")
ONBOARDING_STORE: Final = Path(".storage", "onboarding")
ISSUE_STORE: Final = Path(".storage", "repairs.issue_registry")
TEMP_DIR: Final = "tmp"
"""Home Assistant's temporary directory (its TMPDIR), in its configuration directory.

Not the machine's /tmp: another Home Assistant starting or stopping there empties
/tmp/home-assistant-file_upload, and an upload of this one then fails.
"""
# What Home Assistant 2026.10 stores with the address and port: its own defaults.
HTTP_DEFAULTS: Final[dict[str, Any]] = {
    "cors_allowed_origins": ["https://cast.home-assistant.io"],
    "login_attempts_threshold": -1,
    "ip_ban_enabled": True,
    "ssl_profile": "modern",
    "use_x_frame_options": True,
}
# Onboarding's steps after the owner's account, marked done for the demo.
OFFLINE_ONBOARDING_STEPS: Final = ("core_config", "analytics", "integration")
# Repairs the demo's owner has ignored: (domain, issue id).
IGNORED_ISSUES: Final = (("homeassistant", "deprecated_method"),)

HEADER: Final = "# Written by tests/e2e/configuration.py on every start: edit that file, not this.\n"


class ConfigurationError(Exception):
    """An existing configuration directory does not fit what was asked."""


def http_settings(port: int, listen: Sequence[str] = LOOPBACK) -> dict[str, Any]:
    """The HTTP settings: on loopback addresses only, so that no other host can connect."""
    return {"server_host": list(listen), "server_port": port}


def http_settings_in_storage(config_dir: Path) -> dict[str, Any] | None:
    """The HTTP settings Home Assistant keeps in storage, once it moved them there.

    Since 2026.10 Home Assistant reads `http:` from configuration.yaml once, as a trial
    (`pending`) that becomes `stable` when confirmed, and ignores the YAML afterwards.
    Return the settings it will start with, or None while it has not read the YAML.
    """
    try:
        store = json.loads((config_dir / HTTP_STORE).read_text(encoding="utf-8"))
    except FileNotFoundError:
        return None
    data = store["data"]
    if not data.get("yaml_migration_done"):
        return None
    pending = data.get("pending")
    settings: dict[str, Any] = (
        pending if pending and pending.get("error") is None else data["stable"]
    )
    return settings


def configuration(
    *,
    port: int,
    listen: Sequence[str] = LOOPBACK,
    trusted_local_login: bool = False,
    debug: bool = False,
) -> dict[str, Any]:
    """Return configuration.yaml as data (the HTTP settings go to storage).

    With `trusted_local_login`, a browser on this machine signs in without a password
    (the owner is picked for it); it is safe because the HTTP server listens on
    loopback only, so no other host can reach it at all. The password provider stays
    for everything else.
    """
    core: dict[str, Any] = {
        "name": "TecoApi demo",
        "latitude": 50.0755,
        "longitude": 14.4378,
        "elevation": 235,
        "unit_system": "metric",
        "time_zone": "Europe/Prague",
        "currency": "CZK",
        "country": "CZ",
        "language": "en",
    }
    if trusted_local_login:
        core["auth_providers"] = [
            {
                "type": "trusted_networks",
                "trusted_networks": ["127.0.0.1/32", "::1/128"],
                "allow_bypass_login": True,
            },
            {"type": "homeassistant"},
        ]
    return {
        "homeassistant": core,
        "frontend": {},
        "config": {},
        "history": {},
        "logbook": {},
        "energy": {},
        "lovelace": {
            "dashboards": {
                DASHBOARD_URL_PATH: {
                    "mode": "yaml",
                    "filename": DASHBOARD_FILE,
                    "title": DASHBOARD_TITLE,
                    "icon": "mdi:home-thermometer",
                    "show_in_sidebar": True,
                    "require_admin": False,
                }
            }
        },
        "logger": {
            "default": "warning",
            "logs": {"custom_components.tecoapi": "debug" if debug else "info"},
        },
    }


def _write_store(
    config_dir: Path, store: Path, data: dict[str, Any], **versions: int
) -> None:
    """Write one of Home Assistant's storage files as it would."""
    path = config_dir / store
    path.parent.mkdir(parents=True, exist_ok=True)
    content = {**versions, "key": store.name, "data": data}
    path.write_text(json.dumps(content, indent=2), encoding="utf-8")


def store_http_settings(config_dir: Path, settings: dict[str, Any]) -> None:
    """Store the HTTP settings as Home Assistant 2026.10 keeps confirmed ones."""
    stable = {
        **settings,
        **HTTP_DEFAULTS,
        "created_at": datetime.now(UTC).isoformat(),
        "error": None,
        "error_message": None,
    }
    _write_store(
        config_dir,
        HTTP_STORE,
        {"stable": stable, "pending": None, "yaml_migration_done": True},
        version=2,
        minor_version=2,
    )


def write_configuration(
    config_dir: Path,
    *,
    port: int,
    listen: Sequence[str] = LOOPBACK,
    trusted_local_login: bool = False,
    debug: bool = False,
    demo: bool = False,
) -> None:
    """Write configuration.yaml and the demo dashboard, and link the integration in.

    Its own temporary directory (:data:`TEMP_DIR`) is made beside them.

    The HTTP settings are stored unless Home Assistant keeps some already; it raises
    ConfigurationError when those differ from loopback on `port`. With `demo`, a
    directory Home Assistant has not started in yet gets the demo owner's choices
    (see the module docstring).
    """
    config_dir.mkdir(parents=True, exist_ok=True)
    (config_dir / TEMP_DIR).mkdir(exist_ok=True)
    wanted = http_settings(port, listen)
    stored = http_settings_in_storage(config_dir)
    if stored is None:
        store_http_settings(config_dir, wanted)
    elif {key: stored.get(key) for key in wanted} != wanted:
        raise ConfigurationError(
            f"{config_dir} makes Home Assistant listen on "
            f"{stored.get('server_host') or 'every interface'} port "
            f"{stored.get('server_port')}, not on {', '.join(listen)} port "
            f"{port}; it keeps that in {HTTP_STORE} since 2026.10: delete "
            f"{config_dir} to start afresh"
        )
    if demo and not (config_dir / ONBOARDING_STORE).exists():
        _write_store(
            config_dir,
            ONBOARDING_STORE,
            {"done": list(OFFLINE_ONBOARDING_STEPS)},
            version=4,
            minor_version=1,
        )
    if demo and not (config_dir / ISSUE_STORE).exists():
        ignored = [
            {
                "created": datetime.now(UTC).isoformat(),
                "dismissed_version": ha_version,
                "domain": domain,
                "is_persistent": False,
                "issue_id": issue_id,
            }
            for domain, issue_id in IGNORED_ISSUES
        ]
        _write_store(
            config_dir, ISSUE_STORE, {"issues": ignored}, version=1, minor_version=2
        )
    data = configuration(
        port=port, listen=listen, trusted_local_login=trusted_local_login, debug=debug
    )
    (config_dir / "configuration.yaml").write_text(
        HEADER + yaml.safe_dump(data, sort_keys=False, allow_unicode=True),
        encoding="utf-8",
    )
    shutil.copyfile(DEMO_DASHBOARD, config_dir / DASHBOARD_FILE)
    link = config_dir / "custom_components"
    if link.is_symlink() or link.exists():
        link.unlink()
    link.symlink_to(REPO_ROOT / "custom_components", target_is_directory=True)


def main(argv: Sequence[str] | None = None) -> None:
    """Entry point of `python -m tests.e2e.configuration`."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("config_dir", type=Path)
    parser.add_argument("--port", type=int, default=8123)
    parser.add_argument(
        "--trusted-local-login",
        action="store_true",
        help="sign in from this machine without a password (loopback only)",
    )
    parser.add_argument(
        "--debug", action="store_true", help="log the integration at DEBUG"
    )
    parser.add_argument(
        "--demo",
        action="store_true",
        help="the demo owner's choices: onboarding offline, a repair ignored",
    )
    arguments = parser.parse_args(argv)
    try:
        write_configuration(
            arguments.config_dir,
            port=arguments.port,
            trusted_local_login=arguments.trusted_local_login,
            debug=arguments.debug,
            demo=arguments.demo,
        )
    except ConfigurationError as err:
        sys.exit(f"error: {err}")


if __name__ == "__main__":
    main()
