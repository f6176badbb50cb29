"""manifest_problems and const_domain: what hassfest or the loader would reject."""

from pathlib import Path
from typing import Final

from scripts.checks.common import JsonObject
from scripts.checks.manifest import const_domain, manifest_problems

GOOD_MANIFEST: Final[JsonObject] = {
    "domain": "tecoapi",
    "name": "Tecomat TecoApi",
    "codeowners": ["@someone"],
    "config_flow": True,
    "dhcp": [{"macaddress": "F8DC7A*"}],
    "documentation": "https://example.org/docs",
    "integration_type": "device",
    "iot_class": "local_polling",
    "issue_tracker": "https://example.org/issues",
    "loggers": ["custom_components.tecoapi"],
    "requirements": [],
    "version": "0.1.0",
}


def test_checker_manifest_accepts_a_good_manifest() -> None:
    assert (
        manifest_problems(GOOD_MANIFEST, directory="tecoapi", const_domain="tecoapi")
        == []
    )


def test_checker_manifest_rejects_wrong_key_order() -> None:
    name_first = {"name": GOOD_MANIFEST["name"], **GOOD_MANIFEST}
    assert manifest_problems(name_first, directory="tecoapi", const_domain=None) == [
        (
            "keys are not 'domain', 'name', then alphabetical: name, domain, "
            "codeowners, config_flow, dhcp, documentation, integration_type, "
            "iot_class, issue_tracker, loggers, requirements, version"
        )
    ]
    unsorted = {**GOOD_MANIFEST}
    unsorted["codeowners"] = unsorted.pop("codeowners")
    assert any(
        "alphabetical" in problem
        for problem in manifest_problems(
            unsorted, directory="tecoapi", const_domain=None
        )
    )


def test_checker_manifest_rejects_missing_keys_and_bad_values() -> None:
    missing = {key: value for key, value in GOOD_MANIFEST.items() if key != "version"}
    assert manifest_problems(missing, directory="tecoapi", const_domain=None) == [
        "'version' is missing"
    ]
    bad = {
        **GOOD_MANIFEST,
        "dhcp": [{"macaddress": "f8:dc:7a:*", "vendor": "Teco"}],
        "iot_class": "cloud_polling",
        "version": "latest",
    }
    assert manifest_problems(bad, directory="teco", const_domain="other") == [
        "domain 'tecoapi' is not the directory 'teco'",
        "domain 'tecoapi' is not const.DOMAIN 'other'",
        "'iot_class' is 'cloud_polling', not 'local_polling'",
        "version 'latest' is not a valid version",
        "dhcp matcher key 'vendor' is unknown",
        "dhcp macaddress 'f8:dc:7a:*' is not upper-case hex without separators",
    ]
    assert manifest_problems(
        {**GOOD_MANIFEST, "colour": "blue"}, directory="tecoapi", const_domain=None
    ) == [
        "keys are not 'domain', 'name', then alphabetical: "
        + ", ".join([*GOOD_MANIFEST, "colour"]),
        "key 'colour' is not a manifest key",
    ]


def test_checker_const_domain_reads_the_module_constant(tmp_path: Path) -> None:
    const_py = tmp_path / "const.py"
    const_py.write_text(
        'from typing import Final\n\nDOMAIN: Final = "tecoapi"\n', encoding="utf-8"
    )
    assert const_domain(const_py) == "tecoapi"
    assert const_domain(tmp_path / "absent.py") is None
