"""The user's first hour, in a real browser: onboarding, adding the PLC, using it.

The simulated PLC runs in this process; Home Assistant 2026.10 runs as a separate
process on a fresh configuration; Debian's Chromium, driven through Playwright, clicks
what a user would click. `scripts/test --e2e` runs it. With TECOAPI_SCREENSHOTS=DIR it
also saves the README screenshots there (`scripts/e2e_screenshots`).
"""

import asyncio
from collections.abc import AsyncIterator, Awaitable, Callable
import json
import os
import re
import secrets
from typing import Any, Final
from urllib.parse import urlsplit

import pytest
import yaml

from tests.e2e.conftest import E2E_REQUIRED

if not E2E_REQUIRED:  # required, a missing playwright fails the collection
    pytest.importorskip(
        "playwright", reason="the browser test needs playwright (scripts/test --e2e)"
    )

from playwright.async_api import Page, Route, async_playwright, expect

from tests.conftest import SIM_PASSWORD, SIM_USERNAME
from tests.e2e.configuration import DASHBOARD_TITLE, DEMO_DASHBOARD, REPO_ROOT
from tests.e2e.conftest import ARTIFACTS, bounded, has_failed, real_home_assistant
from tests.e2e.home_assistant import HomeAssistantProcess
from tests.simulator import Simulator

CHROMIUM: Final = "/usr/bin/chromium"
CHROMIUM_FLAGS: Final = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]
SCREENSHOTS_VARIABLE: Final = "TECOAPI_SCREENSHOTS"
# Paths Home Assistant answers by fetching from the internet; only this integration's
# brand images are local (custom_components/tecoapi/brand/).
FORWARDED_PATHS: Final = re.compile(
    r"^/api/(map_tiles/|brands/(?!integration/tecoapi/))"
)
UI_TIMEOUT_MS: Final = 30_000
PLC_TIMEOUT: Final = 30.0

INTEGRATION: Final = REPO_ROOT / "custom_components" / "tecoapi"
MANIFEST: Final = json.loads(
    (INTEGRATION / "manifest.json").read_text(encoding="utf-8")
)
CONFIG_STRINGS: Final = json.loads(
    (INTEGRATION / "translations" / "en.json").read_text(encoding="utf-8")
)["config"]

DASHBOARD: Final = DEMO_DASHBOARD.read_text(encoding="utf-8")
# The view the dashboard opens on: the PLC's house (the next, the Tekon gateway's
# building, needs its gateway, which this test does not add).
# The demo program's points and groups the test uses (tests/simulator/programs/demo.yaml).
LIGHT: Final = "lights[0]"
SETPOINT: Final = "Termostaty.OBYVAK_GTSAP1_THERMOSTAT_setpoint"
BLIND_TARGET: Final = "Stineni.OBYVAK_ZALUZIE_GTSAP1_OPENER_target"
BLIND_POSITION: Final = "Stineni.OBYVAK_ZALUZIE_GTSAP1_OPENER_current"
LIGHT_LEVEL: Final = "OBYVAK_STROP_GTSAP1_LIGHT_tgtlevel"
RGB_LIGHT: Final = "KUCHYNE_LINKA_GTSAP1_LIGHT"
BLIND_SPEED: Final = 20.0
"""How fast the demo's blinds move once the test lets them move as real ones: % a second."""
# A typed light is a device of its own, connected to the PLC, in its room's area.
TYPED_LIGHT: Final = "Chodba light"
GROUPS: Final = ("Lights", "Heating", "Termostaty", "Stínění")
ROOM: Final = "Dětský pokoj"

type Screenshot = Callable[[str], Awaitable[None]]

pytestmark = real_home_assistant


async def _keep_local(route: Route) -> None:
    """Let requests to Home Assistant through; abort anything bound for the internet."""
    url = urlsplit(route.request.url)
    if url.hostname == "127.0.0.1" and not FORWARDED_PATHS.match(url.path):
        await route.continue_()
    else:
        await route.abort("blockedbyclient")


@pytest.fixture
async def page(request: pytest.FixtureRequest) -> AsyncIterator[Page]:
    """A page in headless Chromium, 1280x800, British English in Prague's time zone.

    After a failed test, its last state is saved as e2e-artifacts/failure.png.
    """
    async with async_playwright() as playwright:
        browser = await playwright.chromium.launch(
            executable_path=CHROMIUM, headless=True, args=CHROMIUM_FLAGS
        )
        try:
            context = await browser.new_context(
                viewport={"width": 1280, "height": 800},
                locale="en-GB",
                timezone_id="Europe/Prague",
            )
            await context.route("**/*", _keep_local)
            page = await context.new_page()
            page.set_default_timeout(UI_TIMEOUT_MS)
            expect.set_options(timeout=UI_TIMEOUT_MS)
            yield page
            if has_failed(request):
                ARTIFACTS.mkdir(exist_ok=True)
                await page.screenshot(path=ARTIFACTS / "failure.png")
                (ARTIFACTS / "failure.aria.yaml").write_text(
                    await page.locator("body").aria_snapshot(), encoding="utf-8"
                )
        finally:
            await browser.close()


@pytest.fixture
def screenshot(page: Page) -> Screenshot:
    """Save the page as NAME.png in $TECOAPI_SCREENSHOTS; do nothing when unset."""
    directory = os.environ.get(SCREENSHOTS_VARIABLE)

    async def save(name: str) -> None:
        if directory:
            target = REPO_ROOT / directory
            target.mkdir(parents=True, exist_ok=True)
            await page.screenshot(path=target / f"{name}.png", animations="disabled")

    return save


async def simulated(sim: Simulator, path: str, changed: Callable[[Any], bool]) -> Any:
    """Wait until the PLC's value at `path` satisfies `changed`; return it.

    Rechecked at every request the PLC receives: the integration polls it every few
    seconds, and a write is followed by a refresh.
    """
    async with asyncio.timeout(PLC_TIMEOUT):
        while not changed(value := sim.get_value(path)):
            await sim.wait_for_requests(len(sim.requests) + 1)
    return value


async def onboard(
    page: Page, url: str, name: str, username: str, password: str
) -> None:
    """Create the owner account and accept every other onboarding step as proposed."""
    await page.goto(url)
    await page.get_by_role("button", name="Create my smart home").click()
    for label, value in (
        ("Name*", name),
        ("Username*", username),
        ("Password*", password),
        ("Confirm password*", password),
    ):
        await page.get_by_role("textbox", name=label, exact=True).fill(value)
    await page.get_by_role("button", name="Create account").click()
    for step in (
        page.get_by_role("heading", name="Home location"),
        page.get_by_text("We would like to know the country"),
        page.get_by_role("heading", name=re.compile(r"^Help us (to )?help you$")),
    ):
        await expect(step).to_be_visible()
        await page.get_by_role("button", name="Next").click()
    await expect(page.get_by_role("heading", name="All set!")).to_be_visible()
    await page.get_by_role("button", name="Finish").click()
    await expect(page.get_by_role("heading", name=f"Welcome {name}")).to_be_visible()


async def open_config_flow(page: Page) -> None:
    """Settings → Devices & services → Add integration → the integration → TecoApi."""
    await page.get_by_role("link", name="Settings").click()
    await page.get_by_role("link", name="Devices & services").click()
    await page.get_by_role("button", name="Add integration").click()
    # A Tecomat user searches for the system's name, not the integration's.
    await page.get_by_placeholder("Search for a brand name").fill("Tecomat")
    await page.get_by_role("button", name=MANIFEST["name"], exact=True).click()
    # First, how to reach the PLC: TecoApi, or PLCComS alone.
    menu = CONFIG_STRINGS["step"]["user"]
    await expect(page.get_by_text(menu["title"])).to_be_visible()
    await expect(page.get_by_text(menu["menu_options"]["plccoms"])).to_be_visible()
    await page.get_by_text(menu["menu_options"]["tecoapi"]).click()
    await expect(
        page.get_by_text(CONFIG_STRINGS["step"]["tecoapi"]["title"])
    ).to_be_visible()


async def fill_connection(page: Page, **values: str) -> None:
    """Type into the TecoApi step's fields, found by their translated labels."""
    labels = CONFIG_STRINGS["step"]["tecoapi"]["data"]
    for key, value in values.items():
        await page.get_by_role("textbox", name=f"{labels[key]}*", exact=True).fill(
            value
        )


@bounded
async def test_first_hour(
    simulator: Simulator,
    home_assistant: HomeAssistantProcess,
    page: Page,
    screenshot: Screenshot,
) -> None:
    """Onboard, add the PLC through the UI (a wrong password first), see it, use it."""
    sim = simulator
    # The HTTP settings are in Home Assistant's storage already: no trial to confirm.
    await onboard(
        page, home_assistant.url, "Ada Owner", "ada", secrets.token_urlsafe(16)
    )

    await open_config_flow(page)
    await fill_connection(
        page, host=sim.host, username=SIM_USERNAME, password=f"not-{SIM_PASSWORD}"
    )
    await screenshot("config_flow")
    await page.get_by_role("button", name="Submit").click()
    await expect(page.locator('ha-alert[alert-type="error"]')).to_have_text(
        CONFIG_STRINGS["error"]["invalid_auth"]
    )
    await fill_connection(page, password=SIM_PASSWORD)
    await page.get_by_role("button", name="Submit").click()

    # Home Assistant offers to name the new devices: the PLC, and a device for each
    # group of its program, a room's group already in an area of its name.
    plc_name = f"Tecomat {sim.plc_type}"
    await expect(page.get_by_text("Name and assign")).to_be_visible()
    for name in (plc_name, *GROUPS, ROOM):
        await expect(page.get_by_placeholder(name, exact=True)).to_be_attached()
    await page.get_by_role("button", name="Finish").click()

    # The PLC's device page: its identity, and its own points as entities.
    await open_device(page, plc_name)
    await expect(
        page.get_by_text(f"Serial number: {sim.serial_number}")
    ).to_be_visible()
    await expect(page.get_by_text(sim.plc_type, exact=True).first).to_be_visible()
    await expect(
        page.get_by_role("link", name=re.compile(rf"^{TYPED_LIGHT} "))
    ).to_be_visible()
    await screenshot("device_page")

    # Its groups are devices connected to it (with its lights, blinds and
    # thermostats: more than the page lists at first); a switch toggled on the
    # page of its group reaches the PLC.
    await page.get_by_role("button", name=re.compile(r"devices not shown$")).click()
    for name in GROUPS:
        await expect(
            page.get_by_role("link", name=re.compile(rf"^{name} "))
        ).to_be_visible()
    await page.get_by_role("link", name=re.compile(r"^Lights ")).click()
    await expect(page).to_have_url(re.compile(r"/config/devices/device/"))
    was_on = sim.get_value(f"{LIGHT}.value")
    row = page.locator(
        "hui-toggle-entity-row", has_text=sim.get_value(f"{LIGHT}.attr.title")
    )
    toggle = row.get_by_role("switch")
    await expect(toggle).to_be_checked(checked=was_on)
    await row.locator("ha-switch").click()  # its thumb covers the checkbox
    assert await simulated(sim, f"{LIGHT}.value", lambda on: on != was_on) is not was_on
    await expect(toggle).to_be_checked(checked=not was_on)

    # The demo dashboard renders every card of its first view (the PLC's).
    await page.get_by_role("link", name=DASHBOARD_TITLE).click()
    first_view = yaml.safe_dump(yaml.safe_load(DASHBOARD)["views"][0])
    await expect(page.locator("hui-tile-card")).to_have_count(
        first_view.count("type: tile")
    )
    await expect(page.locator("hui-warning")).to_have_count(0)
    await screenshot("dashboard")

    # A thermostat's target raised there reaches the PLC, and the card shows the target read back.
    tile = page.locator("hui-tile-card", has_text="Living room").filter(
        has=page.locator("hui-target-temperature-card-feature")
    )
    before = sim.get_value(SETPOINT)
    await tile.get_by_role("button", name="increment").click()
    after = await simulated(sim, SETPOINT, lambda value: value != before)
    assert after == before + 0.5
    await expect(tile.locator("hui-target-temperature-card-feature")).to_contain_text(
        re.compile(rf"\b{re.escape(format(after, 'g'))}(\.0+)?\s*°C")
    )

    # A blind closed there is closing at once, while the PLC moves it (as a real
    # blind, 20 % a second: the program's link moves the position to the target),
    # and closed once it is there. The PLC never sets it `moving`: the target apart
    # from the position says it is on its way.
    sim.link_motion.rate = BLIND_SPEED
    tile = page.locator("hui-tile-card", has_text="Living room").filter(
        has=page.locator("hui-cover-open-close-card-feature")
    )
    assert sim.get_value(BLIND_POSITION) > 0
    await tile.get_by_role("button", name="Close cover").click()
    await expect(tile.locator("ha-tile-info")).to_contain_text("Closing")
    assert sim.get_value(BLIND_TARGET) == 0
    await expect(tile.locator("ha-tile-info")).to_contain_text("Closed")
    assert sim.get_value(BLIND_POSITION) == 0

    # The RGB light switched on from its icon, dark (level 0): on at full, not at 0 %.
    tile = page.locator("hui-tile-card", has_text="Kitchen counter")
    assert sim.get_value(f"{RGB_LIGHT}_onoff") is False
    assert sim.get_value(f"{RGB_LIGHT}_dimlevel") == 0
    await tile.locator("ha-tile-icon").click()
    assert await simulated(sim, f"{RGB_LIGHT}_onoff", lambda on: on) is True
    await expect(tile.get_by_role("slider")).to_have_attribute("aria-valuenow", "100")
    await expect(tile.locator("ha-tile-info")).to_contain_text("100")
    assert sim.get_value(f"{RGB_LIGHT}_dimlevel") == 100

    # A light dimmed there by a tenth: the PLC gets the lower level.
    tile = page.locator("hui-tile-card", has_text="Living room ceiling")
    level = sim.get_value(LIGHT_LEVEL)
    slider = tile.get_by_role("slider")
    await slider.focus()
    await slider.press("PageDown")
    dimmed = await simulated(sim, LIGHT_LEVEL, lambda value: value != level)
    assert dimmed == pytest.approx(level - 10, abs=1)
    await expect(tile.locator("ha-tile-info")).to_contain_text(f"{round(dimmed)}")


async def open_device(page: Page, name: str) -> None:
    """Settings → Devices & services → Devices → the device named `name`."""
    await page.get_by_role("link", name="Settings").click()
    await page.get_by_role("link", name="Devices & services").click()
    await page.get_by_role("tab", name="Devices").click()
    await page.get_by_role("textbox").first.fill(name)
    await page.get_by_role("rowheader", name=name, exact=True).click()
    await expect(page).to_have_url(re.compile(r"/config/devices/device/"))
