"""The options form in a real browser: a Push error shows where the user looks.

A PLCComS server that cannot be reached is refused with an error. As the form's
error it sat at the top of the form, 450 px above the Submit button the user had
just pressed; as the host field's (a field inside a section) the frontend did not
show it at all. As the Push section's, it shows right above that section, by the
button.
"""

import json
import secrets
import socket
from typing import Any, Final

import pytest

from tests.e2e.conftest import E2E_REQUIRED

if not E2E_REQUIRED:  # required, a missing playwright fails the collection
    pytest.importorskip(
        "playwright", reason="the browser test needs playwright (scripts/test --e2e)"
    )

from playwright.async_api import Page, expect

from tests.conftest import SIM_PASSWORD, SIM_USERNAME
from tests.e2e.conftest import bounded, real_home_assistant
from tests.e2e.home_assistant import HomeAssistantProcess
from tests.e2e.test_browser import (  # the browser test's page and steps
    INTEGRATION,
    fill_connection,
    onboard,
    open_config_flow,
    page,  # noqa: F401 (a fixture)
)
from tests.simulator import Simulator

pytestmark = real_home_assistant

OPTIONS_STRINGS: Final[dict[str, Any]] = json.loads(
    (INTEGRATION / "translations" / "en.json").read_text(encoding="utf-8")
)["options"]
PUSH: Final = OPTIONS_STRINGS["step"]["tecoapi"]["sections"]["push"]
ABOVE_PX: Final = 40
"""How far above the Push section's header its error shows (its margin, no more)."""


def closed_port() -> int:
    """A port on 127.0.0.1 where nothing listens."""
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return int(probe.getsockname()[1])


@bounded
async def test_a_push_error_shows_by_the_submit_button(
    simulator: Simulator,
    home_assistant: HomeAssistantProcess,
    page: Page,  # noqa: F811
) -> None:
    """Push to a server that does not answer: the error is next to Submit."""
    await onboard(
        page, home_assistant.url, "Ada Owner", "ada", secrets.token_urlsafe(16)
    )
    await open_config_flow(page)
    await fill_connection(
        page, host=simulator.host, username=SIM_USERNAME, password=SIM_PASSWORD
    )
    await page.get_by_role("button", name="Submit").click()
    await page.get_by_role("button", name="Finish").click()

    await page.goto(f"{home_assistant.url}/config/integrations/integration/tecoapi")
    await page.get_by_role("button", name="Configure").first.click()
    # The options open on the menu; the settings are its first item.
    await page.get_by_text(
        OPTIONS_STRINGS["step"]["tecoapi_menu"]["menu_options"]["settings"]
    ).click()
    await expect(
        page.get_by_text(OPTIONS_STRINGS["step"]["tecoapi"]["title"])
    ).to_be_visible()
    await page.get_by_text(PUSH["name"], exact=True).click()
    await page.get_by_role("textbox", name=PUSH["data"]["host"], exact=True).fill(
        "127.0.0.1"
    )
    await page.get_by_role("spinbutton", name=PUSH["data"]["port"]).fill(
        str(closed_port())
    )
    await page.get_by_role("button", name="Submit").click()

    error = page.locator('ha-alert[alert-type="error"]')
    await expect(error).to_have_text(OPTIONS_STRINGS["error"]["plccoms_cannot_connect"])
    # In sight of the button just pressed, right above the Push section.
    await expect(error).to_be_in_viewport()
    error_box = await error.bounding_box()
    section_box = await page.get_by_text(PUSH["name"], exact=True).bounding_box()
    assert error_box is not None
    assert section_box is not None
    assert 0 <= section_box["y"] - (error_box["y"] + error_box["height"]) < ABOVE_PX
