"""HACS's repository checks for an integration, on the repository's tree.

HACS (``hacs/integration``, ``custom_components/hacs/validate/``) runs one
validator per rule against a repository; those that read the tree are checked
here, each returning its problems in words:

- ``license``: a licence file GitHub detects, of an OSI-approved licence
  (HACS asks GitHub for its SPDX ID: none, or ``NOASSERTION``, fails);
- ``hacsjson``: ``hacs.json`` exists, holds only HACS's keys with their types,
  a name, and a ``filename`` where ``zip_release`` is set (plus the project's
  own rule: its minimum Home Assistant is the tested floor);
- ``integration_manifest``: the manifest's keys HACS reads (codeowners,
  documentation, domain, issue_tracker, name, version);
- ``brands``: ``brand/icon.png`` beside the manifest (else HACS looks the
  domain up in Home Assistant's brands repository, which a custom integration
  is not in);
- ``information``: a README (or info) file at the root;
- the layout HACS installs from: one integration folder under
  ``custom_components/`` (HACS takes the first it lists) holding the manifest,
  or the integration at the root with ``content_in_root``.

HACS's other validators read GitHub's settings, not the tree (``archived``,
``description``, ``issues``, ``topics``), or apply to other categories
(``images``: plugins and themes); docs/development.md lists the settings.
"""

from collections.abc import Mapping
from pathlib import Path
import re
from typing import Any, Final
from urllib.parse import urlparse

from homeassistant.generated.countries import COUNTRIES

from .common import load_json

HACS_TYPES: Final[dict[str, type | tuple[type, ...]]] = {
    "name": str,
    "content_in_root": bool,
    "zip_release": bool,
    "filename": str,
    "hide_default_branch": bool,
    "country": (str, list),
    "homeassistant": str,
    "render_readme": bool,
    "hacs": str,
    "persistent_directory": str,
}
HACS_KEYS: Final = frozenset(HACS_TYPES)
MANIFEST_TYPES: Final[dict[str, type]] = {
    "codeowners": list,
    "documentation": str,
    "domain": str,
    "issue_tracker": str,
    "name": str,
    "version": str,
}
POPULAR_OSI: Final = frozenset(
    {
        "Apache-2.0",
        "BSD-2-Clause",
        "BSD-3-Clause",
        "CDDL-1.0",
        "EPL-2.0",
        "GPL-2.0",
        "GPL-3.0",
        "LGPL-2.1",
        "LGPL-3.0",
        "MIT",
        "MPL-2.0",
    }
)
"""The OSI's popular licences, which HACS accepts without looking further."""
LICENSE_NAME: Final = re.compile(
    r"^(un)?licen[cs]e(\.(md|markdown|txt|rst))?$|^copying(\.(md|txt))?$",
    re.IGNORECASE,
)
"""File names GitHub's licence detection reads at a repository's root."""
INFORMATION_NAMES: Final = frozenset({"readme", "readme.md", "info", "info.md"})

# What identifies a licence's text (its words, whitespace and case aside): the
# sentences of its grant, its conditions and its disclaimer.
LICENSE_TEXTS: Final[dict[str, tuple[str, ...]]] = {
    "MIT": (
        (
            "permission is hereby granted, free of charge, to any person obtaining a copy "
            'of this software and associated documentation files (the "software"), to '
            "deal in the software without restriction"
        ),
        (
            "the above copyright notice and this permission notice shall be included in "
            "all copies or substantial portions of the software."
        ),
        'the software is provided "as is", without warranty of any kind',
    ),
    "Apache-2.0": (
        "apache license version 2.0, january 2004",
        "terms and conditions for use, reproduction, and distribution",
        "grant of copyright license.",
        "grant of patent license.",
    ),
}


def _words(text: str) -> str:
    return " ".join(text.lower().split())


def license_id(text: str) -> str:
    """The SPDX ID of a licence text, or ``NOASSERTION`` when it is none known."""
    words = _words(text)
    return next(
        (
            spdx
            for spdx, sentences in LICENSE_TEXTS.items()
            if all(sentence in words for sentence in sentences)
        ),
        "NOASSERTION",
    )


def license_files(root: Path) -> list[Path]:
    """The licence files at a repository's root, as GitHub looks for them."""
    return sorted(
        path
        for path in root.iterdir()
        if path.is_file() and LICENSE_NAME.match(path.name)
    )


def license_problems(root: Path) -> list[str]:
    """What HACS's licence check finds: no licence, or one it cannot accept."""
    files = license_files(root)
    if not files:
        return ["The repository has no license"]
    found = {license_id(path.read_text(encoding="utf-8")) for path in files}
    if found == {"NOASSERTION"} or len(found) > 1:
        return ["The repository license could not be identified (SPDX: NOASSERTION)"]
    spdx = found.pop()
    if spdx not in POPULAR_OSI:
        return [f"The repository does not have an OSI-approved license ({spdx})"]
    return []


def hacs_problems(hacs: Mapping[str, Any], floor: str) -> list[str]:
    """What HACS would reject in hacs.json, and a minimum that is not the floor."""
    problems = [
        f"key {key!r} is not one HACS accepts" for key in hacs if key not in HACS_KEYS
    ]
    if not isinstance(hacs.get("name"), str) or not hacs["name"].strip():
        problems.append("'name' is missing or empty")
    problems += [
        f"{key!r} is not a {getattr(kind, '__name__', 'string or a list')}"
        for key, kind in HACS_TYPES.items()
        if key in hacs and key != "name" and not isinstance(hacs[key], kind)
    ]
    countries = hacs.get("country", [])
    countries = [countries] if isinstance(countries, str) else countries
    for country in countries if isinstance(countries, list) else []:
        if str(country).upper() not in COUNTRIES | {"ALL"}:
            problems.append(f"country {country!r} is no ISO 3166 country code")
    if hacs.get("zip_release") and not hacs.get("filename"):
        problems.append("zip_release is True, but filename is not set")
    if hacs.get("homeassistant") != floor:
        problems.append(
            f"'homeassistant' is {hacs.get('homeassistant')!r}, the tested floor is {floor!r}"
        )
    return problems


def _url(value: Any) -> bool:
    parsed = urlparse(str(value))
    return parsed.scheme in {"http", "https"} and bool(parsed.netloc)


def hacs_manifest_problems(manifest: Mapping[str, Any]) -> list[str]:
    """What HACS's manifest check rejects: a key it reads missing or of a wrong kind."""
    problems = []
    for key, kind in MANIFEST_TYPES.items():
        if key not in manifest:
            problems.append(f"manifest.json: {key!r} is missing")
        elif not isinstance(manifest[key], kind):
            problems.append(f"manifest.json: {key!r} is not a {kind.__name__}")
    problems += [
        f"manifest.json: {key!r} is not a URL"
        for key in ("documentation", "issue_tracker")
        if isinstance(manifest.get(key), str) and not _url(manifest[key])
    ]
    return problems


def integration_folder(root: Path, hacs: Mapping[str, Any]) -> Path | None:
    """The folder HACS installs: the root (content_in_root) or custom_components' first."""
    if hacs.get("content_in_root"):
        return root
    parent = root / "custom_components"
    folders = (
        sorted(
            path
            for path in parent.iterdir()
            if path.is_dir() and path.name != "__pycache__"
        )
        if parent.is_dir()
        else []
    )
    return folders[0] if folders else None


def layout_problems(root: Path, hacs: Mapping[str, Any]) -> list[str]:
    """Where HACS finds no integration, or one it would not install whole."""
    folder = integration_folder(root, hacs)
    if folder is None:
        return ["Repository structure is not compliant: no custom_components/<domain>/"]
    problems = []
    if not hacs.get("content_in_root"):
        others = [
            path.name
            for path in (root / "custom_components").iterdir()
            if path.is_dir() and path.name not in {folder.name, "__pycache__"}
        ]
        problems += [
            f"custom_components/{name}/ is a second integration: HACS installs only "
            f"{folder.name}/"
            for name in sorted(others)
        ]
    if not (folder / "manifest.json").is_file():
        problems.append(f"The repository has no 'manifest.json' file in {folder.name}/")
    return problems


def information_problems(root: Path) -> list[str]:
    """HACS's information check: a README or info file at the root."""
    names = {path.name.lower() for path in root.iterdir() if path.is_file()}
    return (
        [] if names & INFORMATION_NAMES else ["The repository has no information file"]
    )


def brand_asset_problems(folder: Path) -> list[str]:
    """HACS's brands check, as a custom integration passes it: brand/icon.png."""
    if (folder / "brand" / "icon.png").is_file():
        return []
    return [
        (
            f"{folder.name}/brand/icon.png is missing: the repository provides no brand "
            "assets (and a custom integration is not in Home Assistant's brands repository)"
        )
    ]


def hacs_repository_problems(root: Path, floor: str) -> list[str]:
    """Every HACS check that reads the tree, on a repository's root."""
    path = root / "hacs.json"
    if not path.is_file():
        return ["The repository has no 'hacs.json' file", *license_problems(root)]
    try:
        hacs = load_json(path)
    except (TypeError, ValueError):
        return ["The repository has an invalid 'hacs.json' file"]
    problems = [f"hacs.json: {problem}" for problem in hacs_problems(hacs, floor)]
    problems += license_problems(root) + information_problems(root)
    problems += layout_problems(root, hacs)
    folder = integration_folder(root, hacs)
    if folder is not None and (folder / "manifest.json").is_file():
        try:
            manifest = load_json(folder / "manifest.json")
        except (TypeError, ValueError):
            return [*problems, "manifest.json is not a JSON object"]
        problems += hacs_manifest_problems(manifest)
        problems += brand_asset_problems(folder)
    return problems
