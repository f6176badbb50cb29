"""HACS's checks on a repository's tree: a planted fault for each rule.

A small repository that passes them all is written to a folder; each test breaks
one thing as a careless change would, and the check says what HACS says.
"""

import json
from pathlib import Path
import shutil
from typing import Any, Final

import pytest

from scripts.checks.hacs import (
    hacs_problems,
    hacs_repository_problems,
    license_id,
)

REPO: Final = Path(__file__).resolve().parents[2]
FLOOR: Final = "2026.2.0"
HACS: Final = {"name": "Demo", "homeassistant": FLOOR, "render_readme": True}
MANIFEST: Final = {
    "domain": "demo",
    "name": "Demo",
    "codeowners": ["@someone"],
    "documentation": "https://example.com/demo",
    "issue_tracker": "https://example.com/demo/issues",
    "version": "1.0.0",
}


def repository(root: Path, *, hacs: Any = HACS, manifest: Any = MANIFEST) -> Path:
    """A repository HACS accepts, with hacs.json and the manifest as given."""
    integration = root / "custom_components" / "demo"
    (integration / "brand").mkdir(parents=True)
    (integration / "brand" / "icon.png").write_bytes(b"")
    (integration / "manifest.json").write_text(json.dumps(manifest), "utf-8")
    (root / "hacs.json").write_text(json.dumps(hacs), "utf-8")
    (root / "README.md").write_text("# Demo\n", "utf-8")
    shutil.copy(REPO / "LICENSE", root / "LICENSE")
    return root


def test_checker_hacs_passes_a_repository_it_accepts(tmp_path: Path) -> None:
    assert hacs_repository_problems(repository(tmp_path), FLOOR) == []


def test_checker_hacs_rejects_unknown_keys_missing_name_and_wrong_floor() -> None:
    assert hacs_problems({"name": "X", "homeassistant": "2026.2.0"}, "2026.2.0") == []
    assert hacs_problems(
        {"domains": ["sensor"], "homeassistant": "2025.1.0"}, "2026.2.0"
    ) == [
        "key 'domains' is not one HACS accepts",
        "'name' is missing or empty",
        "'homeassistant' is '2025.1.0', the tested floor is '2026.2.0'",
    ]


@pytest.mark.parametrize(
    ("hacs", "expected"),
    [
        ({**HACS, "render_readme": "yes"}, ["'render_readme' is not a bool"]),
        ({**HACS, "country": 5}, ["'country' is not a string or a list"]),
        (
            {**HACS, "country": ["CZ", "XX"]},
            ["country 'XX' is no ISO 3166 country code"],
        ),
        ({**HACS, "country": "cz"}, []),
        (
            {**HACS, "zip_release": True},
            ["zip_release is True, but filename is not set"],
        ),
        ({**HACS, "zip_release": True, "filename": "demo.zip"}, []),
    ],
)
def test_checker_hacs_json_types_countries_and_zip_release(
    hacs: dict[str, Any], expected: list[str]
) -> None:
    assert hacs_problems(hacs, FLOOR) == expected


def test_checker_hacs_without_hacs_json(tmp_path: Path) -> None:
    (repository(tmp_path) / "hacs.json").unlink()
    assert hacs_repository_problems(tmp_path, FLOOR) == [
        "The repository has no 'hacs.json' file"
    ]


def test_checker_hacs_json_that_is_no_object(tmp_path: Path) -> None:
    repository(tmp_path, hacs=["Demo"])
    assert hacs_repository_problems(tmp_path, FLOOR) == [
        "The repository has an invalid 'hacs.json' file"
    ]


def test_checker_hacs_without_a_licence(tmp_path: Path) -> None:
    (repository(tmp_path) / "LICENSE").unlink()
    assert hacs_repository_problems(tmp_path, FLOOR) == [
        "The repository has no license"
    ]


def test_checker_hacs_with_a_licence_nobody_can_identify(tmp_path: Path) -> None:
    repository(tmp_path)
    (tmp_path / "LICENSE").write_text("All rights reserved. Ask us.\n", "utf-8")
    assert hacs_repository_problems(tmp_path, FLOOR) == [
        "The repository license could not be identified (SPDX: NOASSERTION)"
    ]


def test_checker_hacs_licence_file_names_and_texts(tmp_path: Path) -> None:
    repository(tmp_path)
    (tmp_path / "LICENSE").rename(tmp_path / "LICENCE.md")
    assert hacs_repository_problems(tmp_path, FLOOR) == []
    mit = (REPO / "LICENSE").read_text("utf-8")
    assert license_id(mit) == "MIT"
    # Reflowed and in other case, the same licence.
    assert license_id(" ".join(mit.upper().split())) == "MIT"
    # Its conditions cut away, no longer MIT.
    assert license_id(mit.split("The above copyright")[0]) == "NOASSERTION"
    apache = (
        "Apache License\nVersion 2.0, January 2004\n"
        "TERMS AND CONDITIONS FOR USE, REPRODUCTION, AND DISTRIBUTION\n"
        "2. Grant of Copyright License. ...\n3. Grant of Patent License. ...\n"
    )
    assert license_id(apache) == "Apache-2.0"


def test_checker_hacs_without_a_readme(tmp_path: Path) -> None:
    (repository(tmp_path) / "README.md").rename(tmp_path / "ABOUT.md")
    assert hacs_repository_problems(tmp_path, FLOOR) == [
        "The repository has no information file"
    ]


def test_checker_hacs_takes_info_md_for_a_readme(tmp_path: Path) -> None:
    (repository(tmp_path) / "README.md").rename(tmp_path / "info.md")
    assert hacs_repository_problems(tmp_path, FLOOR) == []


def test_checker_hacs_without_an_integration_folder(tmp_path: Path) -> None:
    shutil.rmtree(repository(tmp_path) / "custom_components")
    assert hacs_repository_problems(tmp_path, FLOOR) == [
        "Repository structure is not compliant: no custom_components/<domain>/"
    ]


def test_checker_hacs_with_two_integration_folders(tmp_path: Path) -> None:
    (repository(tmp_path) / "custom_components" / "zzz").mkdir()
    assert hacs_repository_problems(tmp_path, FLOOR) == [
        "custom_components/zzz/ is a second integration: HACS installs only demo/"
    ]


def test_checker_hacs_without_a_manifest(tmp_path: Path) -> None:
    (repository(tmp_path) / "custom_components" / "demo" / "manifest.json").unlink()
    assert hacs_repository_problems(tmp_path, FLOOR) == [
        "The repository has no 'manifest.json' file in demo/"
    ]


def test_checker_hacs_with_content_in_root(tmp_path: Path) -> None:
    repository(tmp_path, hacs={**HACS, "content_in_root": True})
    assert hacs_repository_problems(tmp_path, FLOOR) == [
        "The repository has no 'manifest.json' file in " + f"{tmp_path.name}/"
    ]


@pytest.mark.parametrize(
    ("manifest", "expected"),
    [
        (
            {key: value for key, value in MANIFEST.items() if key != "version"},
            ["manifest.json: 'version' is missing"],
        ),
        (
            {**MANIFEST, "codeowners": "@someone"},
            ["manifest.json: 'codeowners' is not a list"],
        ),
        (
            {**MANIFEST, "issue_tracker": "github issues"},
            ["manifest.json: 'issue_tracker' is not a URL"],
        ),
        (
            {key: value for key, value in MANIFEST.items() if key != "domain"},
            ["manifest.json: 'domain' is missing"],
        ),
    ],
)
def test_checker_hacs_manifest_keys(
    tmp_path: Path, manifest: dict[str, Any], expected: list[str]
) -> None:
    assert hacs_repository_problems(repository(tmp_path, manifest=manifest), FLOOR) == (
        expected
    )


def test_checker_hacs_without_brand_images(tmp_path: Path) -> None:
    icon = repository(tmp_path) / "custom_components" / "demo" / "brand" / "icon.png"
    icon.unlink()
    assert hacs_repository_problems(tmp_path, FLOOR) == [
        (
            "demo/brand/icon.png is missing: the repository provides no brand assets "
            "(and a custom integration is not in Home Assistant's brands repository)"
        )
    ]
