"""The repository passes what HACS's and hassfest's validators check.

Neither validator runs here (no network, no Docker), so the checkers of
scripts/checks check what they check, plus what Home Assistant's own test suite
checks at runtime for core integrations: every translation key the code uses exists
in translations/en.json and cs.json, and translations, icons, services and brand
images agree with each other and with the code. Each checker returns a list of
problems in words, so a failing test names all of them at once; tests/checks shows
each rule can fail on small bad inputs.
"""

from http import HTTPStatus
from pathlib import Path
import re
import tomllib
from typing import Final

from homeassistant.core import HomeAssistant
from homeassistant.setup import async_setup_component
import pytest
from pytest_homeassistant_custom_component.typing import ClientSessionGenerator

from custom_components.tecoapi import pyplc
from custom_components.tecoapi.pyplc.core import registry
from scripts.checks.brand import brand_problems
from scripts.checks.common import JsonObject, load_json, load_yaml
from scripts.checks.descriptors import descriptor_usage
from scripts.checks.hacs import (
    hacs_problems,
    hacs_repository_problems,
    license_id,
)
from scripts.checks.icons import icon_problems
from scripts.checks.manifest import const_domain, manifest_problems
from scripts.checks.quality_scale import (
    VALIDATORS,
    Integration,
    quality_scale_problems,
)
from scripts.checks.reader import read_usage
from scripts.checks.services import service_problems
from scripts.checks.translations import (
    placeholder_differences,
    structure_differences,
    translation_string_problems,
)
from scripts.checks.usage import (
    TranslationUsage,
    integration_sources,
    missing_translations,
    placeholder_gaps,
    unused_translations,
)

REPO: Final = Path(__file__).resolve().parent.parent
INTEGRATION: Final = REPO / "custom_components" / "tecoapi"
TRANSLATIONS: Final = INTEGRATION / "translations"
BRAND: Final = INTEGRATION / "brand"

# The oldest Home Assistant the test suite runs on (the floor target).
TESTED_FLOOR: Final = "2026.2.0"


@pytest.fixture(scope="module")
def manifest() -> JsonObject:
    return load_json(INTEGRATION / "manifest.json")


@pytest.fixture(scope="module")
def en() -> JsonObject:
    path = TRANSLATIONS / "en.json"
    assert path.is_file(), "translations/en.json is missing"
    return load_json(path)


@pytest.fixture(scope="module")
def cs() -> JsonObject:
    path = TRANSLATIONS / "cs.json"
    assert path.is_file(), "translations/cs.json is missing"
    return load_json(path)


@pytest.fixture(scope="module")
def usage() -> TranslationUsage:
    found = read_usage(integration_sources(INTEGRATION), domain=INTEGRATION.name)
    descriptor_usage(found, registry.sources())
    return found


@pytest.fixture(scope="module")
def services_yaml() -> JsonObject:
    path = INTEGRATION / "services.yaml"
    return load_yaml(path) if path.is_file() else {}


def test_hacs_json_has_only_accepted_keys_and_the_tested_floor() -> None:
    assert hacs_problems(load_json(REPO / "hacs.json"), TESTED_FLOOR) == []


def test_hacs_s_checks_of_the_tree_pass() -> None:
    """The licence, hacs.json, the manifest's keys, the brand icon, the README, the layout."""
    assert hacs_repository_problems(REPO, TESTED_FLOOR) == []


def test_the_licence_is_the_one_both_pyprojects_declare() -> None:
    """LICENSE is MIT, as pyproject.toml and the library's say; the library ships a copy."""
    text = (REPO / "LICENSE").read_text(encoding="utf-8")
    library = INTEGRATION / "pyplc"
    for pyproject in (REPO / "pyproject.toml", library / "pyproject.toml"):
        project = tomllib.loads(pyproject.read_text(encoding="utf-8"))["project"]
        assert project["license"] == license_id(text), pyproject
        assert project["license-files"] == ["LICENSE"], pyproject
    assert (library / "LICENSE").read_text(encoding="utf-8") == text


CHANGELOG: Final = REPO / "CHANGELOG.md"
RELEASE: Final = re.compile(
    r"^## \[(\d+\.\d+\.\d+)\] - (\d{4}-\d{2}-\d{2}|not yet released)$", re.MULTILINE
)
KINDS: Final = {"Added", "Changed", "Deprecated", "Removed", "Fixed", "Security"}


def _version(path: Path) -> str:
    return str(tomllib.loads(path.read_text(encoding="utf-8"))["project"]["version"])


def _numbers(version: str) -> tuple[int, ...]:
    return tuple(int(part) for part in version.split("."))


def test_the_version_is_one_in_the_manifest_pyproject_and_changelog(
    manifest: JsonObject,
) -> None:
    """manifest.json, pyproject.toml and the changelog's newest entry say one version.

    The README and the upgrade notes name it; the entry says which pyplc it ships
    (the library's own version, its pyproject's and ``pyplc.__version__``).
    """
    text = CHANGELOG.read_text(encoding="utf-8")
    releases = RELEASE.findall(text)
    newest = releases[0][0]
    assert manifest["version"] == _version(REPO / "pyproject.toml") == newest
    library = _version(INTEGRATION / "pyplc" / "pyproject.toml")
    assert pyplc.__version__ == library
    entry = text.split("\n## [", 2)[1]
    assert f"Ships `pyplc` {library}." in entry
    assert f"**{newest}**" in (REPO / "README.md").read_text(encoding="utf-8")
    upgrading = (REPO / "docs" / "upgrading.md").read_text(encoding="utf-8")
    assert f"this version is {newest}." in upgrading


def test_the_changelog_keeps_a_changelog_s_form() -> None:
    """Every release newest first, dated (only the newest may be not yet released).

    Each has its link, its changes under Keep a Changelog's kinds, and (but the
    first) its upgrade notes in docs/upgrading.md.
    """
    text = CHANGELOG.read_text(encoding="utf-8")
    releases = RELEASE.findall(text)
    versions = [version for version, _ in releases]
    assert versions[-3:] == ["0.3.0", "0.2.0", "0.1.0"]
    assert versions == sorted(versions, key=_numbers, reverse=True)
    assert _numbers(versions[0]) > _numbers("0.3.0")
    assert all(date != "not yet released" for _, date in releases[1:])
    headings = re.findall(r"^## .*$", text, re.MULTILINE)
    assert len(headings) == len(releases)  # no heading of another form
    kinds = set(re.findall(r"^### (.+)$", text, re.MULTILINE))
    assert kinds <= KINDS
    entries = text.split("\n## [")[1:]
    for version, entry in zip(versions, entries, strict=True):
        assert f"\n[{version}]: https://github.com/" in text, version
        if version != "0.1.0":
            assert "](docs/upgrading.md#upgrading-from-" in entry, version


def test_manifest_passes_hassfest_rules(manifest: JsonObject) -> None:
    assert (
        manifest_problems(
            manifest,
            directory=INTEGRATION.name,
            const_domain=const_domain(INTEGRATION / "const.py"),
        )
        == []
    )


def test_manifest_promises_a_config_flow_that_exists(manifest: JsonObject) -> None:
    assert manifest.get("config_flow") is True
    assert (INTEGRATION / "config_flow.py").is_file()


def test_home_assistant_s_quality_scale_validators_pass() -> None:
    """Each rule marked done that core validates, read where core reads it.

    The steps and the unique-ID check in config_flow.py (not only in flows/),
    the typed entry of the options flow's factory, and the rest of core's
    validators (scripts/checks/quality_scale.py).
    """
    integration = Integration.read(INTEGRATION, REPO / "pyproject.toml")
    # Every rule core validates is one this integration claims: none goes unread.
    assert set(VALIDATORS) <= integration.rules_done
    assert quality_scale_problems(integration) == []


def test_translations_en_and_cs_have_the_same_keys(
    en: JsonObject, cs: JsonObject
) -> None:
    assert structure_differences(en, cs, "en.json", "cs.json") == []


def test_translation_strings_are_valid(en: JsonObject, cs: JsonObject) -> None:
    assert (
        translation_string_problems(en, "en.json")
        + translation_string_problems(cs, "cs.json")
        == []
    )


def test_translations_use_the_same_placeholders(en: JsonObject, cs: JsonObject) -> None:
    assert placeholder_differences(en, cs, "en.json", "cs.json") == []


def test_strings_json_matches_en(en: JsonObject) -> None:
    path = INTEGRATION / "strings.json"
    if not path.is_file():
        pytest.skip("no strings.json (optional for custom integrations)")
    assert structure_differences(load_json(path), en, "strings.json", "en.json") == []


def test_code_reads_cleanly_for_translation_keys(usage: TranslationUsage) -> None:
    assert usage.problems == []


def test_every_translation_key_the_code_uses_exists(
    usage: TranslationUsage, en: JsonObject, cs: JsonObject
) -> None:
    assert missing_translations(usage, en) == []
    assert missing_translations(usage, cs) == []


def test_code_passes_every_placeholder_its_strings_use(
    usage: TranslationUsage, en: JsonObject, cs: JsonObject
) -> None:
    assert placeholder_gaps(usage, en) + placeholder_gaps(usage, cs) == []


def test_no_entity_exception_or_issue_translation_is_unused(
    usage: TranslationUsage, en: JsonObject
) -> None:
    assert unused_translations(en, usage) == []


def test_actions_agree_with_services_yaml_and_translations(
    usage: TranslationUsage, services_yaml: JsonObject, en: JsonObject
) -> None:
    if not services_yaml and not usage.services:
        pytest.skip("the integration registers no actions")
    assert service_problems(services_yaml, en, usage.services) == []


def test_icons_refer_to_existing_entities_and_actions(
    services_yaml: JsonObject, en: JsonObject
) -> None:
    path = INTEGRATION / "icons.json"
    if not path.is_file():
        pytest.skip("no icons.json")
    assert icon_problems(load_json(path), en, services_yaml) == []


def test_brand_images_follow_the_brand_rules() -> None:
    assert brand_problems(BRAND) == []


async def test_home_assistant_serves_the_brand_images(
    hass: HomeAssistant,
    enable_custom_integrations: None,
    hass_client: ClientSessionGenerator,
) -> None:
    """Home Assistant's own brands endpoint serves the files, not the CDN."""
    pytest.importorskip(
        "homeassistant.components.brands",
        reason="this Home Assistant does not serve brand images of custom integrations",
    )
    assert await async_setup_component(hass, "brands", {})
    client = await hass_client()
    shipped = sorted(path.name for path in BRAND.iterdir())
    # dark_icon.png is not shipped: Home Assistant falls back to icon.png.
    for name, source in [(name, name) for name in shipped] + [
        ("dark_icon.png", "icon.png")
    ]:
        response = await client.get(
            f"/api/brands/integration/tecoapi/{name}", params={"placeholder": "no"}
        )
        assert response.status == HTTPStatus.OK, name
        assert await response.read() == (BRAND / source).read_bytes(), name
