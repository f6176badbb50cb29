"""Add integration finds the integration by a word of each system's user.

Home Assistant's dialog reads only the start of a custom integration's name (see
tests/add_integration_search.py), so the name leads with one word for each system.
"""

import json

import pytest

from tests.add_integration_search import (
    FOUND_WITHIN,
    MANIFEST,
    REPO_ROOT,
    SEARCH_WORDS,
    listed,
)


@pytest.mark.parametrize(("system", "word"), SEARCH_WORDS.items())
def test_each_system_is_found_by_its_users_word(system: str, word: str) -> None:
    """Typing the word shows the integration first or second (behind a brand of it)."""
    names = listed(word)
    assert MANIFEST["name"] in names[:FOUND_WITHIN], (
        f"{word!r}, the word of a {system} user, lists {names}"
    )


@pytest.mark.parametrize(
    ("word", "others"),
    [
        # Seen in the dialog of Home Assistant 2026.10 (issue 29, and a browser run).
        ("Unipi", ["Ubiquiti"]),
        ("Panasonic", ["Panasonic"]),
        ("Mervis", ["Supervisord"]),
        ("Tecomat", []),
        ("Foxtrot", []),
    ],
)
def test_the_model_lists_what_the_dialog_listed(word: str, others: list[str]) -> None:
    """Besides this integration, the model finds what the real dialog found."""
    assert [name for name in listed(word) if name != MANIFEST["name"]] == others


@pytest.mark.parametrize(("start", "found"), [(20, True), (21, False)])
def test_a_word_counts_only_near_the_names_start(start: int, found: bool) -> None:
    """A word typed right finds a name only where it starts within 20 characters."""
    name = "-" * start + "Tekon"
    assert (name in listed("Tekon", name=name)) is found


def test_hacs_shows_the_same_name() -> None:
    """HACS lists the integration under the manifest's name."""
    hacs = json.loads((REPO_ROOT / "hacs.json").read_text("utf-8"))
    assert hacs["name"] == MANIFEST["name"]


def test_the_readme_says_which_words_find_it() -> None:
    """A paragraph of the README gives the name and, in bold, every system's word."""
    readme = (REPO_ROOT / "README.md").read_text("utf-8")
    paragraphs = [" ".join(paragraph.split()) for paragraph in readme.split("\n\n")]
    told = [
        paragraph
        for paragraph in paragraphs
        if "Add integration" in paragraph and MANIFEST["name"] in paragraph
    ]
    assert told, "no paragraph says what to type in Add integration"
    for word in SEARCH_WORDS.values():
        assert f"**{word}**" in told[0], f"{word} is not in {told[0]!r}"
