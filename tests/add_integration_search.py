"""Home Assistant's *Add integration* search, modelled: what a user finds by a word.

The dialog of Home Assistant 2026.10 (hass_frontend 20260930.5, the add-integration
dialog's `_filterIntegrations`) searches every brand and integration Home Assistant
describes (`homeassistant/generated/integrations.json`, and a custom integration's
manifest `name` and `domain`) with Fuse.js 7.5: keys `name` and `domain` (weight 5),
a brand's `integrations` (2), `supported_by` and `iot_standards` (1); threshold 0.2,
case and diacritics ignored, Fuse's default location 0 and distance 100. It lists
three groups, each in Fuse's order: what can be added, then what is set up in YAML
only, then helpers.

Fuse's rules, as its documentation states them: a word placed in a text with some
errors (edits) from some start scores errors / the word's length + start / 100, the
best placement counting where it scores at most 0.2 (so a word typed right counts
only where it starts within the first 20 characters); a text equal to the word
scores 0, and none scores less than 0.001 otherwise. An entry's score is the product,
over every text of a key that matches, of that score to the power of the key's share
of the weights times round(1 / sqrt(words in the text), 3) (a score of 0 counts as
2**-52); lower is listed first, ties in the list's order (the core's entries before a
custom integration).

Checked twice: over Home Assistant 2026.10's descriptions, with this integration's
name and with the one before, it listed 643 words and phrases (each system's words,
words, beginnings and two-word phrases of the core's names, misspellings of them) in
exactly Fuse.js 7.5.0's order; and the browser test (tests/e2e/test_search_browser.py)
compares its lists with what the dialog shows.
"""

from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass
import functools
import json
import math
from pathlib import Path
import sys
from typing import Any, Final
import unicodedata

import homeassistant.components
import homeassistant.generated

REPO_ROOT: Final = Path(__file__).resolve().parent.parent
MANIFEST: Final[dict[str, Any]] = json.loads(
    (REPO_ROOT / "custom_components" / "tecoapi" / "manifest.json").read_text("utf-8")
)

SEARCH_WORDS: Final = {
    "Tecomat": "Tecomat",
    "Mervis": "Unipi",
    "Panasonic FP": "Panasonic",
    "Tekon": "Tekon",
}
"""The word each system's user types to find the integration (the README says them)."""
FOUND_WITHIN: Final = 2
"""The row of the list the integration shows in, at the latest, for each of them."""

KEY_WEIGHTS: Final = {
    "name": 5,
    "domain": 5,
    "integrations": 2,
    "supported_by": 1,
    "iot_standards": 1,
}
THRESHOLD: Final = 0.2
DISTANCE: Final = 100
LONGEST_WORD: Final = 32
"""Fuse searches a longer pattern in pieces, which this model does not."""
ZERO: Final = sys.float_info.epsilon
# Letters ignoreDiacritics folds that have no combining mark to drop.
FOLDED_LETTERS: Final = str.maketrans(
    {"ł": "l", "đ": "d", "ø": "o", "ħ": "h", "ŧ": "t", "ı": "i", "ß": "ss"}
)


@dataclass(frozen=True, slots=True)
class Row:
    """An entry of the dialog's list, with the texts its search reads."""

    name: str
    domain: str
    integrations: tuple[str, ...] = ()
    supported_by: str | None = None
    iot_standards: tuple[str, ...] = ()

    def texts(self) -> Iterator[tuple[str, str]]:
        """(key, text) for each text the search reads, one per item of a list."""
        yield "name", self.name
        yield "domain", self.domain
        for integration in self.integrations:
            yield "integrations", integration
        if self.supported_by is not None:
            yield "supported_by", self.supported_by
        for standard in self.iot_standards:
            yield "iot_standards", standard


def _title(domain: str) -> str:
    """The English name of a core integration whose name is translated, as shown."""
    translations = (
        Path(homeassistant.components.__path__[0]) / domain / "translations" / "en.json"
    )
    if translations.is_file():
        title = json.loads(translations.read_text("utf-8")).get("title")
        if isinstance(title, str) and title:
            return title
    return domain


def _named(domain: str, description: Mapping[str, Any]) -> str:
    return str(description.get("name") or _title(domain))


def _supporting(
    integrations: Mapping[str, Any], domain: str
) -> Mapping[str, Any] | None:
    """The description of `domain`, at the top or inside a brand."""
    if domain in integrations:
        return dict(integrations[domain])
    for description in integrations.values():
        if domain in description.get("integrations", {}):
            return dict(description["integrations"][domain])
    return None


@functools.cache
def dialog_rows(name: str) -> tuple[tuple[Row, ...], tuple[Row, ...], tuple[Row, ...]]:
    """The dialog's three groups, with this integration called `name`.

    Home Assistant describes a custom integration after the core's (the loader's
    async_get_integration_descriptions); the frontend leaves out hardware.
    """
    core = json.loads(
        (Path(homeassistant.generated.__path__[0]) / "integrations.json").read_text(
            "utf-8"
        )
    )
    integrations = {
        domain: description
        for domain, description in core["integration"].items()
        if domain != MANIFEST["domain"]
    }
    integrations[MANIFEST["domain"]] = {
        "config_flow": MANIFEST["config_flow"],
        "integration_type": MANIFEST["integration_type"],
        "name": name,
    }
    addable: list[Row] = []
    yaml_only: list[Row] = []
    for domain, description in integrations.items():
        kind = description.get("integration_type")
        if kind == "hardware":
            continue
        if kind is None:  # a brand, or a standard
            if "integrations" in description or "iot_standards" in description:
                addable.append(
                    Row(
                        _named(domain, description),
                        domain,
                        integrations=tuple(
                            _named(member, member_description)
                            for member, member_description in description.get(
                                "integrations", {}
                            ).items()
                        ),
                        iot_standards=tuple(description.get("iot_standards", ())),
                    )
                )
            continue
        if not any(
            description.get(key)
            for key in ("config_flow", "iot_standards", "supported_by")
        ):
            yaml_only.append(Row(_named(domain, description), domain))
            continue
        supported_by = description.get("supported_by")
        supporter = (
            _supporting(integrations, supported_by) if supported_by else description
        )
        if supporter is None:
            continue
        addable.append(
            Row(
                _named(domain, description),
                domain,
                supported_by=supported_by,
                iot_standards=tuple(supporter.get("iot_standards", ())),
            )
        )
    helpers = tuple(
        Row(_named(domain, description), domain)
        for domain, description in core["helper"].items()
    )
    return tuple(addable), tuple(yaml_only), helpers


def _fold(text: str) -> str:
    """Lower case, without diacritics (isCaseSensitive false, ignoreDiacritics)."""
    decomposed = unicodedata.normalize("NFD", text.lower())
    bare = "".join(char for char in decomposed if not unicodedata.combining(char))
    return bare.translate(FOLDED_LETTERS)


def _closeness(word: str, text: str) -> float | None:
    """Fuse's score of a folded word in a folded text; None where it does not match.

    Read backwards, the word may end anywhere in the text: one pass of the edit
    distance then gives, for each position, the fewest edits of a placement of the
    word that starts there.
    """
    if word == text:
        return 0.0
    backwards = word[::-1]
    # edits[i]: fewest edits of the word's last i letters against the text read so far,
    # ending at the character just read (the word's own end may lie anywhere after).
    edits = list(range(len(word) + 1))
    best: float | None = None
    for read, char in enumerate(reversed(text), start=1):
        current = [0]
        for i, letter in enumerate(backwards, start=1):
            current.append(
                min(
                    edits[i] + 1,
                    current[i - 1] + 1,
                    edits[i - 1] + (letter != char),
                )
            )
        edits = current
        score = edits[-1] / len(word) + (len(text) - read) / DISTANCE
        if score <= THRESHOLD and (best is None or score < best):
            best = score
    return None if best is None else max(best, 0.001)


def _field_norm(text: str) -> float:
    """How much a match in `text` weighs: less the more words the text has."""
    return round(1000 / math.sqrt(max(len(text.split()), 1))) / 1000


def search(rows: Sequence[Row], word: str) -> list[Row]:
    """The rows Fuse finds for `word`, best first."""
    assert 2 <= len(word) <= LONGEST_WORD, f"the model takes no word like {word!r}"
    pattern = _fold(word)
    total = sum(KEY_WEIGHTS.values())
    found: list[tuple[float, int, Row]] = []
    for place, row in enumerate(rows):
        score: float | None = None
        for key, text in row.texts():
            closeness = _closeness(pattern, _fold(text))
            if closeness is None:
                continue
            weight = KEY_WEIGHTS[key] / total * _field_norm(text)
            score = (1.0 if score is None else score) * (closeness or ZERO) ** weight
        if score is not None:
            found.append((score, place, row))
    found.sort(key=lambda scored: scored[:2])
    return [row for _, _, row in found]


def listed(word: str, name: str = MANIFEST["name"]) -> list[str]:
    """The names the dialog lists, in order, when `word` is typed into its search."""
    return [row.name for rows in dialog_rows(name) for row in search(rows, word)]
