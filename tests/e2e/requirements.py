"""The packages Home Assistant would pip-install on its first start with the demo's configuration.

scripts/develop and the browser test run Home Assistant with `--skip-pip`, offline, so
scripts/develop_env.sh installs them beforehand: the requirements of every integration
it sets up, at Home Assistant's own pins. Those are the integrations configuration.yaml
names (tests/e2e/configuration.py), those Home Assistant always sets up
(homeassistant.bootstrap), this integration, the text-to-speech entry onboarding adds
(google_translate), and all their dependencies; and those of the integrations whose
modules they import without setting them up (IMPORTED_INTEGRATIONS).

Onboarding also adds `met` (weather) and `radio_browser`, which fetch from the internet
as soon as they run: their packages are left out, and onboarding only logs that it
could not add them.

    python -m tests.e2e.requirements [REQUIREMENT...]

prints those of them (and of the extra REQUIREMENTs, `name==version`) that are not
installed at their pinned version, one a line.
"""

from collections.abc import Iterable, Sequence
import importlib.metadata
import json
from pathlib import Path
import sys
from typing import Any, Final

import homeassistant
from homeassistant import bootstrap

from .configuration import REPO_ROOT, configuration

COMPONENTS: Final = Path(homeassistant.__file__).parent / "components"
CUSTOM_COMPONENTS: Final = REPO_ROOT / "custom_components"
# What onboarding adds that runs offline (the other entries it adds need the internet).
ONBOARDING_INTEGRATIONS: Final = frozenset({"google_translate", "shopping_list"})
# Integrations that are not set up but whose module one that is imports: analytics
# imports hassio's (an after-dependency), which imports its client package. The test
# dependencies bring it to the primary environment; the smoke run's has only these.
IMPORTED_INTEGRATIONS: Final = frozenset({"hassio"})


def manifest(domain: str) -> dict[str, Any]:
    """An integration's manifest.json, Home Assistant's or a custom one from this repository."""
    path = COMPONENTS / domain / "manifest.json"
    if not path.exists():
        path = CUSTOM_COMPONENTS / domain / "manifest.json"
    data: dict[str, Any] = json.loads(path.read_text(encoding="utf-8"))
    return data


def configured_domains() -> set[str]:
    """The integrations Home Assistant sets up on the demo's configuration."""
    return (
        set(configuration(port=8123))
        | set(bootstrap.CORE_INTEGRATIONS)
        | set(bootstrap.DEFAULT_INTEGRATIONS)
        | set(bootstrap.FRONTEND_INTEGRATIONS)
        | {path.parent.name for path in CUSTOM_COMPONENTS.glob("*/manifest.json")}
        | ONBOARDING_INTEGRATIONS
    )


def with_dependencies(domains: Iterable[str]) -> set[str]:
    """The integrations and, transitively, the ones they depend on."""
    found: set[str] = set()
    pending = list(domains)
    while pending:
        domain = pending.pop()
        if domain not in found:
            found.add(domain)
            pending.extend(manifest(domain).get("dependencies", []))
    return found


def requirements(domains: Iterable[str]) -> set[str]:
    """The pinned requirements (`name==version`) of the integrations."""
    return {
        requirement
        for domain in domains
        for requirement in manifest(domain).get("requirements", [])
    }


def not_installed(wanted: Iterable[str]) -> list[str]:
    """Those of the requirements that are not installed at their pinned version."""
    missing = []
    for requirement in sorted(wanted):
        name, _, version = requirement.partition("==")
        try:
            installed = importlib.metadata.version(name)
        except importlib.metadata.PackageNotFoundError:
            installed = None
        if installed != version:
            missing.append(requirement)
    return missing


def main(argv: Sequence[str] | None = None) -> None:
    """Entry point of `python -m tests.e2e.requirements`."""
    extra = sys.argv[1:] if argv is None else list(argv)
    wanted = requirements(
        with_dependencies(configured_domains()) | IMPORTED_INTEGRATIONS
    ) | set(extra)
    for requirement in not_installed(wanted):
        print(requirement)


if __name__ == "__main__":
    main()
