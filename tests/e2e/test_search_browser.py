"""Add integration in a real browser: each system's user finds the integration.

Each system's word is typed into the dialog's search; the dialog must list exactly
what the model of its search (tests/add_integration_search.py) lists, in that order,
with this integration first or second.
"""

import json
import secrets

import pytest

from tests.e2e.conftest import E2E_REQUIRED

if not E2E_REQUIRED:  # required, a missing playwright fails the collection
    pytest.importorskip(
        "playwright", reason="the browser test needs playwright (scripts/test --e2e)"
    )

from playwright.async_api import Page, expect

from tests.add_integration_search import FOUND_WITHIN, MANIFEST, SEARCH_WORDS, listed
from tests.e2e.conftest import bounded, real_home_assistant
from tests.e2e.home_assistant import HomeAssistantProcess
from tests.e2e.test_browser import (  # the browser test's page and steps
    onboard,
    page,  # noqa: F401 (a fixture)
)

pytestmark = real_home_assistant


def exactly(names: list[str]) -> str:
    """An ARIA snapshot of the dialog's list holding these rows and no other."""
    rows = "".join(
        f"\n  - listitem:\n    - button {json.dumps(name)}" for name in names
    )
    return f"- list:\n  - /children: equal{rows}"


@bounded
async def test_each_system_finds_the_integration_by_its_word(
    home_assistant: HomeAssistantProcess,
    page: Page,  # noqa: F811
) -> None:
    """Tecomat, Unipi, Tekon, Panasonic: the integration is in the first two rows."""
    await onboard(
        page, home_assistant.url, "Ada Owner", "ada", secrets.token_urlsafe(16)
    )
    await page.get_by_role("link", name="Settings").click()
    await page.get_by_role("link", name="Devices & services").click()
    await page.get_by_role("button", name="Add integration").click()
    search = page.get_by_placeholder("Search for a brand name")
    rows = page.locator("dialog-add-integration ha-list-virtualized")

    before: list[str] | None = None  # unfiltered, the list has hundreds of rows
    for system, word in SEARCH_WORDS.items():
        names = listed(word)
        assert MANIFEST["name"] in names[:FOUND_WITHIN], f"{system}: {word} {names}"
        # The list left from the word before must not pass for this one's.
        assert names != before, f"{word} lists what the word before it did"
        await search.fill(word)
        await expect(rows).to_match_aria_snapshot(exactly(names))
        before = names
