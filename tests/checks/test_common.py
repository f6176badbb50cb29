"""The shared helpers: files that must hold objects, key paths, `*` steps."""

import ast
from pathlib import Path

import pytest

from scripts.checks.common import (
    ANY_KEY,
    dotted,
    has_path,
    key_paths,
    leaves,
    load_json,
    load_yaml,
    simple_assignment,
)


def test_checker_files_must_hold_an_object(tmp_path: Path) -> None:
    (tmp_path / "ok.json").write_text('{"a": 1}', encoding="utf-8")
    (tmp_path / "list.json").write_text("[1]", encoding="utf-8")
    (tmp_path / "empty.yaml").write_text("", encoding="utf-8")
    (tmp_path / "list.yaml").write_text("- a\n", encoding="utf-8")
    assert load_json(tmp_path / "ok.json") == {"a": 1}
    assert load_yaml(tmp_path / "empty.yaml") == {}
    with pytest.raises(TypeError, match=r"list\.json is not a JSON object"):
        load_json(tmp_path / "list.json")
    with pytest.raises(TypeError, match=r"list\.yaml is not a mapping"):
        load_yaml(tmp_path / "list.yaml")


def test_checker_walks_nested_objects_by_key_path() -> None:
    tree = {"config": {"step": {"user": {"title": "T"}}, "abort": {}}, "title": "X"}
    assert key_paths(tree) == {
        ("config",),
        ("config", "step"),
        ("config", "step", "user"),
        ("config", "step", "user", "title"),
        ("config", "abort"),
        ("title",),
    }
    assert list(leaves(tree)) == [
        (("config", "step", "user", "title"), "T"),
        (("title",), "X"),
    ]
    assert has_path(tree, ("config", "step", "user"))
    assert not has_path(tree, ("config", "step", "reauth"))
    assert not has_path(tree, ("title", "more"))
    assert dotted(("config", "step", "user")) == "config.step.user"


def test_checker_any_key_needs_the_path_under_every_key() -> None:
    """A subentry flow's key is needed under every subentry type, and one at least."""
    both = {"a": {"step": {"x": "1"}}, "b": {"step": {"x": "2"}}}
    one = {"a": {"step": {"x": "1"}}, "b": {"step": {}}}
    assert has_path(
        {"config_subentries": both}, ("config_subentries", ANY_KEY, "step", "x")
    )
    assert not has_path(
        {"config_subentries": one}, ("config_subentries", ANY_KEY, "step", "x")
    )
    assert not has_path(
        {"config_subentries": {}}, ("config_subentries", ANY_KEY, "step")
    )


def test_checker_reads_simple_assignments_only() -> None:
    plain, annotated, pair, bare = ast.parse(
        "A = 1\nB: int = 2\nC, D = 3, 4\nE: int\n"
    ).body
    assert [simple_assignment(node)[0] for node in (plain, annotated, pair, bare)] == [
        "A",
        "B",
        None,
        None,
    ]
