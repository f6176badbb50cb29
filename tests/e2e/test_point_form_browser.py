"""Each map system's point form in a real browser, as its user sees it.

A Mervis controller and an FP-I4C gateway (their simulators, in this process)
are added through Home Assistant's REST API; the browser then opens each
entry's *Configure → Add a point*: the form speaks its system's words (a Mervis
address is ``CommUid[offset,length]``, an FP-I4C's ``DT100``), and a screenshot
of it is kept (e2e-artifacts/point_form_<system>.png, and in
$TECOAPI_SCREENSHOTS when set). *Change a point* searches its list as one
types, and offers to add nothing typed.
"""

import json
import os
from pathlib import Path
import secrets
from typing import Any, Final

import aiohttp
import pytest

from tests.e2e.conftest import E2E_REQUIRED

if not E2E_REQUIRED:  # required, a missing playwright fails the collection
    pytest.importorskip(
        "playwright", reason="the browser test needs playwright (scripts/test --e2e)"
    )

from playwright.async_api import Page, expect

from tests.e2e.conftest import ARTIFACTS, bounded, real_home_assistant
from tests.e2e.home_assistant import HomeAssistantProcess
from tests.e2e.provision import DOMAIN, HomeAssistantApi, MervisAccess
from tests.e2e.test_browser import (  # the browser test's page and steps
    INTEGRATION,
    SCREENSHOTS_VARIABLE,
    onboard,
    page,  # noqa: F401 (a fixture)
)
from tests.simulator.fpi4c import EXAMPLE_CSV, FpI4cSimulator, demo_stations
from tests.simulator.mervis import MervisSimulator, house

pytestmark = real_home_assistant

OPTIONS: Final[dict[str, Any]] = json.loads(
    (INTEGRATION / "translations" / "en.json").read_text(encoding="utf-8")
)["options"]
OWNER: Final = "ada"
MERVIS_USER: Final = "panel"
MERVIS_PASSWORD: Final = "Heslo-123"
VLIST: Final = Path(__file__).parents[1] / "simulator" / "mervis" / "house.vlist"
FORM_HEIGHT: Final = 2200
"""The page's height for a screenshot: the whole point form, without scrolling."""


async def open_options(tab: Page, url: str, title: str, system: str) -> None:
    """Settings → the integration → the entry titled so → Configure: its menu."""
    await tab.goto(f"{url}/config/integrations/integration/{DOMAIN}")
    row = tab.locator("ha-config-entry-row").filter(has_text=title)
    await row.get_by_role("button", name="Configure").click()
    await expect(tab.get_by_text(OPTIONS["step"][system]["title"])).to_be_visible()


async def keep_screenshot(tab: Page, name: str) -> None:
    """Save the page as NAME.png in e2e-artifacts/, and in $TECOAPI_SCREENSHOTS."""
    directories = [ARTIFACTS]
    if shown := os.environ.get(SCREENSHOTS_VARIABLE):
        directories.append(INTEGRATION.parents[1] / shown)
    for directory in directories:
        directory.mkdir(parents=True, exist_ok=True)
        await tab.screenshot(path=directory / f"{name}.png", animations="disabled")


async def shows_the_point_form(tab: Page, system: str, examples: list[str]) -> None:
    """Add a point: the form in the system's own words, its examples in its help."""
    menu = OPTIONS["step"][system]["menu_options"]
    await tab.get_by_text(menu["add_point"], exact=True).click()
    form = OPTIONS["step"][f"{system}_add_point"]
    await expect(tab.get_by_text(form["title"], exact=True)).to_be_visible()
    await expect(tab.get_by_text(form["description"])).to_be_visible()
    for example in examples:
        await expect(tab.get_by_text(example, exact=True).first).to_be_visible()
    # No free text for the device class: that is the next step's list.
    await expect(tab.get_by_text("Device class", exact=True)).to_have_count(0)
    await tab.set_viewport_size({"width": 1280, "height": FORM_HEIGHT})
    await keep_screenshot(tab, f"point_form_{system}")
    await tab.set_viewport_size({"width": 1280, "height": 800})


@bounded
async def test_each_map_system_s_point_form_speaks_its_words(
    socket_enabled: None,
    home_assistant: HomeAssistantProcess,
    page: Page,  # noqa: F811
) -> None:
    password = secrets.token_urlsafe(16)
    await onboard(page, home_assistant.url, "Ada Owner", OWNER, password)
    async with (
        MervisSimulator(
            house(), username=MERVIS_USER, password=MERVIS_PASSWORD
        ) as mervis,
        FpI4cSimulator(demo_stations(), station=1) as gateway,
        aiohttp.ClientSession() as session,
    ):
        api = HomeAssistantApi(session, home_assistant.url)
        await api.sign_in(await api.password_code(OWNER, password))
        mervis_title = await api.add_mervis(
            MervisAccess(
                host=mervis.host,
                username=MERVIS_USER,
                password=MERVIS_PASSWORD,
                vlist=VLIST,
                content=VLIST.read_bytes(),
            )
        )
        gateway_title = await api.add_integration(
            DOMAIN,
            {"host": gateway.url, "point_map": await api.upload(EXAMPLE_CSV)},
            menu_choice="fpi4c",
        )
        await api.wait_until_loaded(DOMAIN)

        await open_options(page, home_assistant.url, mervis_title, "mervis")
        await shows_the_point_form(page, "mervis", ["6003[9,4]", "Kotel"])
        # Past the end of the boiler's block: refused with the controller's reason.
        labels = OPTIONS["step"]["mervis_add_point"]["data"]
        for field, value in (
            ("id", "kotel.test"),
            ("name", "Test"),
            ("address", "6003[60,1]"),
        ):
            await page.get_by_role("textbox", name=f"{labels[field]}*").fill(value)
        await page.get_by_role("button", name="Submit").click()
        refused = OPTIONS["error"]["mervis_point_refused"].split("(")[0].strip()
        await expect(page.get_by_text(refused)).to_be_visible()
        await expect(page.get_by_text("error: unknown variable")).to_be_visible()
        # A variable it reads: its class next, among Home Assistant's own.
        await page.get_by_role("textbox", name=f"{labels['address']}*").fill(
            "6003[8,1]"
        )
        await page.get_by_role("button", name="Submit").click()
        title = OPTIONS["step"]["point_class"]["title"]
        await expect(
            page.get_by_text(title.format(point="Test (kotel.test)"))
        ).to_be_visible()
        await page.get_by_label("Device class").click()
        await expect(page.get_by_text("Moisture", exact=True)).to_be_visible()
        await keep_screenshot(page, "point_class_mervis")
        await page.keyboard.press("Escape")
        await page.keyboard.press("Escape")

        # Change a point: the list searches, and adds nothing typed.
        await open_options(page, home_assistant.url, mervis_title, "mervis")
        menu = OPTIONS["step"]["mervis"]["menu_options"]
        await page.get_by_text(menu["edit_point"], exact=True).click()
        await page.get_by_role("button", name="Point", exact=True).click()
        first = "Hw neuron l203 di 1.01 (hw.neuron_l203_di_1.01)"
        await expect(page.get_by_text(first)).to_be_visible()  # the list is open
        await page.keyboard.type("starts")
        await expect(page.get_by_text("Kotel starts (kotel.starts)")).to_be_visible()
        await expect(page.get_by_text(first)).to_have_count(0)  # filtered
        await expect(page.get_by_text("Add custom item")).to_have_count(0)
        await keep_screenshot(page, "point_picker_mervis")
        await page.keyboard.press("Escape")
        await page.keyboard.press("Escape")

        await open_options(page, home_assistant.url, gateway_title, "fpi4c")
        await shows_the_point_form(page, "fpi4c", ["DT100", "R1A", "2 Garage"])
