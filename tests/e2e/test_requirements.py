"""What scripts/develop_env.sh installs for Home Assistant's first start with the demo."""

import importlib.metadata

from homeassistant import bootstrap
import pytest

from tests.e2e.requirements import (
    configured_domains,
    main,
    manifest,
    not_installed,
    requirements,
    with_dependencies,
)


def test_domains_include_what_home_assistant_sets_up() -> None:
    """The configured integrations, the default ones, this one, onboarding's offline ones."""
    domains = configured_domains()
    assert {"frontend", "lovelace", "energy", "logger"} <= domains  # configuration.yaml
    assert set(bootstrap.DEFAULT_INTEGRATIONS) <= domains
    assert {"tecoapi", "google_translate"} <= domains
    assert {"met", "radio_browser"}.isdisjoint(domains)  # they need the internet


def test_dependencies_are_followed_to_the_end() -> None:
    """tts needs ffmpeg; each integration found has its dependencies found too."""
    domains = with_dependencies({"tts"})
    assert {"tts", "ffmpeg", "http"} <= domains
    everything = with_dependencies(configured_domains())
    for domain in everything:
        assert set(manifest(domain).get("dependencies", [])) <= everything


def test_requirements_are_the_manifests_pins() -> None:
    """The requirements of the integrations and their dependencies, as pinned."""
    wanted = requirements(with_dependencies({"tts"}))
    assert set(manifest("tts")["requirements"]) <= wanted
    assert set(manifest("ffmpeg")["requirements"]) <= wanted  # a dependency's
    everything = requirements(with_dependencies(configured_domains()))
    assert set(manifest("frontend")["requirements"]) <= everything
    assert all(requirement.count("==") == 1 for requirement in everything)


def test_main_asks_for_what_the_integrations_import(
    capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """hassio's client package, which analytics imports though hassio is not set up."""
    monkeypatch.setattr("tests.e2e.requirements.not_installed", sorted)
    main([])
    printed = capsys.readouterr().out.split()
    assert set(manifest("hassio")["requirements"]) <= set(printed)


def test_not_installed() -> None:
    """A package at another version, or absent, is reported; one at its pin is not."""
    pinned = f"pytest=={importlib.metadata.version('pytest')}"
    other = "pytest==0.0.1"
    absent = "tecoapi-no-such-package==1.0"
    assert not_installed([pinned, other, absent]) == [other, absent]


def test_main_prints_the_missing_extra(capsys: pytest.CaptureFixture[str]) -> None:
    """An extra requirement that is not installed is printed with the others."""
    main(["tecoapi-no-such-package==1.0"])
    printed = capsys.readouterr().out.split()
    assert "tecoapi-no-such-package==1.0" in printed
    assert not_installed(printed) == printed
