"""manifest.json: hassfest's manifest checks and the loader's version rule."""

import ast
from collections.abc import Mapping
from pathlib import Path
import re
from typing import Any, Final

from awesomeversion import AwesomeVersion, AwesomeVersionStrategy
from awesomeversion.exceptions import AwesomeVersionException

from .common import simple_assignment

MANIFEST_KEYS: Final = frozenset(
    {
        "domain",
        "name",
        "after_dependencies",
        "bluetooth",
        "codeowners",
        "config_flow",
        "dependencies",
        "dhcp",
        "disabled",
        "documentation",
        "homekit",
        "import_executor",
        "integration_type",
        "iot_class",
        "issue_tracker",
        "loggers",
        "mqtt",
        "preview_features",
        "quality_scale",
        "requirements",
        "single_config_entry",
        "ssdp",
        "usb",
        "version",
        "zeroconf",
    }
)
INTEGRATION_TYPES: Final = frozenset(
    {"device", "entity", "hardware", "helper", "hub", "service", "system", "virtual"}
)
DHCP_MATCHER_KEYS: Final = frozenset({"hostname", "macaddress", "registered_devices"})
# Home Assistant's loader blocks a custom integration whose version is none of these.
VERSION_STRATEGIES: Final = [
    AwesomeVersionStrategy.CALVER,
    AwesomeVersionStrategy.SEMVER,
    AwesomeVersionStrategy.SIMPLEVER,
    AwesomeVersionStrategy.BUILDVER,
    AwesomeVersionStrategy.PEP440,
]


def _manifest_sort_key(key: str) -> tuple[int, str]:
    return {"domain": (0, ""), "name": (1, "")}.get(key, (2, key))


def manifest_problems(
    manifest: Mapping[str, Any], *, directory: str, const_domain: str | None
) -> list[str]:
    """What hassfest (or the loader, for the version) would reject in manifest.json."""
    problems: list[str] = []
    keys = list(manifest)
    if keys != sorted(keys, key=_manifest_sort_key):
        problems.append(
            f"keys are not 'domain', 'name', then alphabetical: {', '.join(keys)}"
        )
    problems += [
        f"key {key!r} is not a manifest key" for key in keys if key not in MANIFEST_KEYS
    ]

    required: dict[str, type] = {
        "domain": str,
        "name": str,
        "codeowners": list,
        "config_flow": bool,
        "documentation": str,
        "integration_type": str,
        "iot_class": str,
        "issue_tracker": str,
        "loggers": list,
        "requirements": list,
        "version": str,
    }
    for key, kind in required.items():
        if key not in manifest:
            problems.append(f"{key!r} is missing")
        elif not isinstance(manifest[key], kind):
            problems.append(f"{key!r} is not a {kind.__name__}")
    if not problems:
        problems += _manifest_value_problems(manifest, directory, const_domain)
    return problems


def _manifest_value_problems(
    manifest: Mapping[str, Any], directory: str, const_domain: str | None
) -> list[str]:
    problems: list[str] = []
    if manifest["domain"] != directory:
        problems.append(
            f"domain {manifest['domain']!r} is not the directory {directory!r}"
        )
    if const_domain is not None and manifest["domain"] != const_domain:
        problems.append(
            f"domain {manifest['domain']!r} is not const.DOMAIN {const_domain!r}"
        )
    if manifest["config_flow"] is not True:
        problems.append("'config_flow' is not true")
    if manifest["iot_class"] != "local_polling":
        problems.append(
            f"'iot_class' is {manifest['iot_class']!r}, not 'local_polling'"
        )
    if manifest["integration_type"] not in INTEGRATION_TYPES:
        problems.append(
            f"'integration_type' {manifest['integration_type']!r} is unknown"
        )
    problems += [
        f"{key!r} is not an https URL"
        for key in ("documentation", "issue_tracker")
        if not manifest[key].startswith("https://")
    ]
    if not manifest["codeowners"] or not all(
        isinstance(owner, str) and owner.startswith("@")
        for owner in manifest["codeowners"]
    ):
        problems.append("'codeowners' must name at least one @owner")
    problems += [
        f"{key!r} must be a list of non-empty strings"
        for key in ("loggers", "requirements")
        if not all(isinstance(item, str) and item for item in manifest[key])
    ]
    try:
        AwesomeVersion(manifest["version"], ensure_strategy=VERSION_STRATEGIES)
    except AwesomeVersionException:
        problems.append(f"version {manifest['version']!r} is not a valid version")
    for matcher in manifest.get("dhcp", []):
        problems += _dhcp_matcher_problems(matcher)
    return problems


def _dhcp_matcher_problems(matcher: Any) -> list[str]:
    if not isinstance(matcher, Mapping) or not matcher:
        return [f"dhcp matcher {matcher!r} is not a non-empty object"]
    problems = [
        f"dhcp matcher key {key!r} is unknown"
        for key in matcher
        if key not in DHCP_MATCHER_KEYS
    ]
    mac = matcher.get("macaddress")
    if mac is not None and not re.fullmatch(r"[0-9A-F]{6}[0-9A-F*?]*", str(mac)):
        problems.append(
            f"dhcp macaddress {mac!r} is not upper-case hex without separators"
        )
    hostname = matcher.get("hostname")
    if hostname is not None and hostname != str(hostname).lower():
        problems.append(f"dhcp hostname {hostname!r} is not lower case")
    return problems


def const_domain(const_py: Path) -> str | None:
    """The `DOMAIN` string assigned at module level in const.py, if there is one."""
    if not const_py.is_file():
        return None
    for node in ast.parse(const_py.read_text(encoding="utf-8")).body:
        target, value = simple_assignment(node)
        if (
            target == "DOMAIN"
            and isinstance(value, ast.Constant)
            and isinstance(value.value, str)
        ):
            return value.value
    return None
