"""The Czech texts read as Czech: one term per concept, counts that need no declension.

`docs/development.md` (*The Czech texts*) holds the glossary this file reads: no
Czech text says a rejected word, and where an English text says a term, its
Czech text says the Czech one.
"""

from collections.abc import Iterator, Mapping
import json
from pathlib import Path
import re
from typing import Any, Final, NamedTuple

import pytest

REPO: Final = Path(__file__).resolve().parent.parent
TRANSLATIONS: Final = REPO / "custom_components" / "tecoapi" / "translations"
GLOSSARY_HEADING: Final = "## The Czech texts"
PLACEHOLDER: Final = re.compile(r"\{\w+\}")
COUNTS: Final = ("points", "entities", "skipped", "count")
"""The placeholders the code fills with a number (a map's counts, its points)."""


class Term(NamedTuple):
    """A row of the glossary: the English terms, the Czech ones, the rejected."""

    english: tuple[str, ...]
    czech: tuple[str, ...]
    rejected: tuple[str, ...]


def texts(language: str) -> dict[str, str]:
    """Every text of a translation, by its dotted key."""
    tree = json.loads((TRANSLATIONS / f"{language}.json").read_text(encoding="utf-8"))

    def walk(node: Mapping[str, Any], path: str) -> Iterator[tuple[str, str]]:
        for key, value in node.items():
            if isinstance(value, Mapping):
                yield from walk(value, f"{path}{key}.")
            else:
                yield f"{path}{key}", value

    return dict(walk(tree, ""))


def glossary() -> list[Term]:
    """The glossary's rows, each cell's words in backticks."""
    text = (REPO / "docs" / "development.md").read_text(encoding="utf-8")
    _, found, section = text.partition(f"\n{GLOSSARY_HEADING}\n")
    assert found, f"docs/development.md has no section {GLOSSARY_HEADING!r}"
    section = section.split("\n## ", 1)[0]
    terms = []
    for line in section.splitlines():
        cells = [cell.strip() for cell in line.strip().strip("|").split("|")]
        if len(cells) != 3 or cells[0] in ("English", "---"):
            continue
        words = [tuple(re.findall(r"`([^`]+)`", cell)) for cell in cells]
        terms.append(Term(*words))
    return terms


def pattern(word: str) -> re.Pattern[str]:
    """A glossary word as a whole word, `*` any ending, letter case aside."""
    body = r"\w*".join(re.escape(part) for part in word.split("*"))
    return re.compile(rf"(?<!\w){body}(?!\w)", re.IGNORECASE)


def said(words: tuple[str, ...], text: str) -> bool:
    """Whether a text (its placeholders aside) says one of the words."""
    bare = PLACEHOLDER.sub(" ", text)
    return any(pattern(word).search(bare) for word in words)


def test_the_glossary_has_terms_and_rejected_words() -> None:
    terms = glossary()
    assert sum(1 for term in terms if term.english and term.czech) >= 10
    assert sum(len(term.rejected) for term in terms) >= 10


def test_no_czech_text_says_a_rejected_word() -> None:
    czech = texts("cs")
    found = [
        f"{key}: {word!r} in {text!r}"
        for term in glossary()
        for word in term.rejected
        for key, text in czech.items()
        if said((word,), text)
    ]
    assert found == []


def test_where_english_says_a_term_czech_says_its_czech_term() -> None:
    english, czech = texts("en"), texts("cs")
    found = [
        f"{key}: {term.english} without {term.czech}: {czech[key]!r}"
        for term in glossary()
        if term.english and term.czech
        for key, text in english.items()
        if said(term.english, text) and not said(term.czech, czech[key])
    ]
    assert found == []


@pytest.mark.parametrize("language", ["en", "cs"])
def test_a_count_stands_where_no_word_agrees_with_it(language: str) -> None:
    """A number is shown after a colon (*načteno bodů: 3*), never before a word
    that would have to be declined with it (*3 bodů*, *1 points*)."""
    counted = re.compile(rf"\{{({'|'.join(COUNTS)})\}} ?[^\W\d_]")
    found = [
        f"{key}: {text!r}"
        for key, text in texts(language).items()
        if counted.search(text)
    ]
    assert found == []
