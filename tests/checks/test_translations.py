"""Translation files: keys in step, usable strings, the same placeholders."""

from scripts.checks.translations import (
    placeholder_differences,
    structure_differences,
    translation_string_problems,
)


def test_checker_translation_trees_must_match() -> None:
    en_tree = {"config": {"error": {"cannot_connect": "x", "invalid_auth": "y"}}}
    cs_tree = {
        "config": {"error": {"cannot_connect": "x", "unknown": "z"}},
        "title": "t",
    }
    assert structure_differences(en_tree, cs_tree, "en", "cs") == [
        "config.error.invalid_auth is in en but not in cs",
        "config.error.unknown is in cs but not in en",
        "title is in cs but not in en",
    ]
    assert structure_differences({"a": "x"}, {"a": {"b": "x"}}, "en", "cs") == [
        "a.b is in cs but not in en",
        "a is a string in one file and an object in the other",
    ]


def test_checker_translation_strings_must_be_usable() -> None:
    tree = {
        "config": {
            "step": {
                "user": {"title": "", "description": " padded", "data": {"Host": "ok"}}
            },
            "error": {
                "Bad_Key": "x",
                "ref": "[%key:common::config_flow::error::cannot_connect%]",
            },
            "abort": {
                "quoted": "Device '{name}' exists",
                "html": "See <b>this</b>",
                "num": 3,
            },
        }
    }
    assert translation_string_problems(tree, "en.json") == [
        "en.json: key config.error.Bad_Key is not a valid translation key",
        "en.json: config.step.user.title is empty",
        "en.json: config.step.user.description has leading or trailing whitespace",
        "en.json: config.error.ref uses a [%key:…%] reference, which custom integrations do not resolve",
        "en.json: config.abort.quoted puts a placeholder in single quotes",
        "en.json: config.abort.html contains HTML",
        "en.json: config.abort.num is not a string",
    ]


def test_checker_placeholders_must_match_per_key() -> None:
    en_tree = {"a": "Connect to {host}", "b": "{count} points", "c": "plain"}
    cs_tree = {"a": "Připojit k {hostname}", "b": "{count} bodů", "c": "prostý"}
    assert placeholder_differences(en_tree, cs_tree, "en", "cs") == [
        "a: en has ['host'], cs has ['hostname']"
    ]
