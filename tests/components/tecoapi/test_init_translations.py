"""The integration's texts as Home Assistant loads them, in each language it ships.

Home Assistant checks a translation's placeholders against the English text's
with Python's format-string parser when it loads it, and logs an error for a
text it cannot parse (an ICU plural, ``{count, plural, one {…} other {…}}``) or
whose placeholders differ (it then drops the text). The Czech texts decline no
count for that reason (docs/development.md, *The Czech texts*).
"""

import json
import logging
from pathlib import Path
from typing import Final

from homeassistant.core import HomeAssistant
from homeassistant.helpers import translation
import pytest

from custom_components.tecoapi.const import DOMAIN

TRANSLATIONS: Final = (
    Path(__file__).parents[3] / "custom_components" / DOMAIN / "translations"
)


@pytest.mark.parametrize("language", ["en", "cs"])
async def test_each_text_loads_without_an_error(
    hass: HomeAssistant, caplog: pytest.LogCaptureFixture, language: str
) -> None:
    """Every category loads with every text, and no error is logged."""
    shipped = json.loads((TRANSLATIONS / f"{language}.json").read_text("utf-8"))
    with caplog.at_level(logging.ERROR):
        for category, tree in shipped.items():
            texts = await translation.async_get_translations(
                hass, language, category, {DOMAIN}
            )
            assert len(texts) == count(tree), category
    errors = [r.getMessage() for r in caplog.records if r.levelno >= logging.ERROR]
    assert errors == []


def count(tree: object) -> int:
    """How many texts a translation tree holds."""
    if isinstance(tree, dict):
        return sum(count(value) for value in tree.values())
    return 1
