"""Each system's forms speak of that system only (issue #29).

For each source, its config flow (the form, a failed connection, the entry,
the same device again, reconfiguration, reauthentication where it signs in) and
its options flow (the form, or the menu and each form behind it, and an error)
are walked against its simulator, as a user would: behind a menu, each form,
a point's form (chosen in "Change a point") and a refused upload. Every text
those steps show is looked up in both translations, as the frontend does: the
step's title, description, field labels and help, its errors (and the texts
they fill in), its menu's choices, the labels of its choices (a selector's
translation key), an abort's reason, a new entry's message. None may be
missing or speak of another system, the options' title names the system, and
the upload form is titled as the menu's choice that opens it.
"""

from collections.abc import (
    AsyncIterator,
    Awaitable,
    Callable,
    Iterable,
    Iterator,
    Mapping,
)
import json
from pathlib import Path
import re
from typing import Any, Final

from homeassistant.config_entries import (
    SOURCE_REAUTH,
    SOURCE_RECONFIGURE,
    SOURCE_USER,
    ConfigEntry,
)
from homeassistant.const import (
    CONF_HOST,
    CONF_PASSWORD,
    CONF_PORT,
    CONF_SCAN_INTERVAL,
    CONF_USERNAME,
    CONF_VERIFY_SSL,
)
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
from homeassistant.helpers.selector import SelectSelector
import pytest
from pytest_homeassistant_custom_component.typing import ClientSessionGenerator

from custom_components.tecoapi.connection import descriptor_of
from custom_components.tecoapi.const import (
    CONF_ATTRIBUTE_INTERVAL,
    CONF_DEVICES,
    CONF_PLAIN_VARIABLES,
    CONF_PUSH,
    DOMAIN,
    DeviceGrouping,
    PlainVariables,
)
from custom_components.tecoapi.flows.base import async_stored_map
from custom_components.tecoapi.flows.options import PlcOptionsFlow
from custom_components.tecoapi.flows.point_class import CLASS_STEP
from custom_components.tecoapi.flows.point_map import (
    CONF_POINT,
    REMOVE_CONFIRM_STEP,
    form_values,
)
from custom_components.tecoapi.helpers import update_error
from custom_components.tecoapi.pyplc.core import exceptions as plc
from custom_components.tecoapi.pyplc.core.descriptor import CONF_POINT_MAP, Words
from custom_components.tecoapi.pyplc.core.pointmap import PointMap
from custom_components.tecoapi.pyplc.core.registry import sources
from tests.components.tecoapi.memory_house import upload
from tests.conftest import SIM_PASSWORD, SIM_USERNAME
from tests.simulator import Simulator
from tests.simulator.fpi4c import EXAMPLE_CSV, FpI4cSimulator, demo_stations
from tests.simulator.mervis import MervisSimulator, house
from tests.simulator.plccoms import PlcComsServer
from tests.simulator.tekon import TekonGateway

pytestmark = pytest.mark.usefixtures("mock_setup_entry")

TRANSLATIONS: Final = (
    Path(__file__).parents[3] / "custom_components" / DOMAIN / "translations"
)
LANGUAGES: Final = ("en", "cs")
MERVIS_USER: Final = "panel"
MERVIS_PASSWORD: Final = "Heslo-123"

TECOMAT_WORDS: Final = (".vlist", "Mervis", "FP-I4C", "Tekon", "gateway", "brán")
NOT_TECOMAT: Final = (
    "TecoApi",
    "PLCComS",
    "T_ApiObject",
    "program instance",
    "instance programu",
    "serial number",
    "výrobní číslo",
    "PLC's web server",
    "webový server PLC",
)
DENIED: Final[Mapping[str, tuple[str, ...]]] = {
    "tecoapi": (*TECOMAT_WORDS, "file you supplied", "souboru, který jste dodali"),
    "plccoms": (*TECOMAT_WORDS, "file you supplied", "souboru, který jste dodali"),
    "mervis": (*NOT_TECOMAT, "FP-I4C", "Tekon", "gateway", "brán", "register map"),
    "fpi4c": (
        *NOT_TECOMAT,
        # Types FP-I4C does not have (Tecomat's and Mervis's; its DT is a
        # register area, its DT100 a point).
        "DATE",
        "TOD",
        "TIME",
        "struct",
        "struktur",
        ".vlist",
        "Mervis",
        "Tekon",
        "hw.",
        "function block",
    ),
    "tekon": (
        *NOT_TECOMAT,
        "struct",
        "struktur",
        ".vlist",
        "Mervis",
        "FP-I4C",
        "register map",
        "hw.",
        "file you supplied",
        "souboru, který jste dodali",
        "PLC",
    ),
}
"""Words of other systems, which a system's forms must not say.

A Mervis project has structs of its own (their members sit on the device of
the top-level name): only Tecomat's program instances are denied to it.
"""
OWN_NAME: Final[Mapping[str, str]] = {
    "tecoapi": "TecoApi",
    "plccoms": "PLCComS",
    "mervis": "Mervis",
    "fpi4c": "FP-I4C",
    "tekon": "Tekon",
}
"""What the options' title says."""


def translations(language: str) -> dict[str, Any]:
    loaded: dict[str, Any] = json.loads(
        (TRANSLATIONS / f"{language}.json").read_text(encoding="utf-8")
    )
    return loaded


def lookup(strings: Mapping[str, Any], *path: str) -> Any:
    """Return the text (or tree) at a path, None where there is none."""
    found: Any = strings
    for key in path:
        if not isinstance(found, Mapping) or key not in found:
            return None
        found = found[key]
    return found


def fields(schema: Any) -> Iterator[tuple[tuple[str, ...], str, Any]]:
    """Each field of a form: the section it is in, its key and its selector."""
    for marker, value in schema.schema.items():
        inner = getattr(value, "schema", None)
        if inner is not None and hasattr(inner, "schema"):
            for key, selector in inner.schema.items():
                yield ("sections", str(marker)), str(key), selector
        else:
            yield (), str(marker), value


class Shown:
    """The texts a user was shown, per language, with where each comes from."""

    def __init__(self) -> None:
        self.texts: dict[str, list[tuple[str, str]]] = {lang: [] for lang in LANGUAGES}
        self.options_titles: dict[str, list[str]] = {lang: [] for lang in LANGUAGES}
        # A menu's choice, its label and the title of the form it opens.
        self.choices: dict[str, list[tuple[str, Any, Any]]] = {
            lang: [] for lang in LANGUAGES
        }

    def add(self, section: str, result: Mapping[str, Any]) -> None:
        """Add what a flow's step shows (as the frontend looks its texts up)."""
        for language in LANGUAGES:
            strings = translations(language)[section]
            self._add(language, section, strings, result)

    def add_choice(
        self,
        section: str,
        menu: Mapping[str, Any],
        option: str,
        form: Mapping[str, Any],
    ) -> None:
        """Add a menu's choice and the form it opened (its title must say the same)."""
        for language in LANGUAGES:
            steps = translations(language)[section]["step"]
            self.choices[language].append(
                (
                    f"{section}.step.{menu['step_id']}.menu_options.{option}",
                    lookup(steps, menu["step_id"], "menu_options", option),
                    lookup(steps, form["step_id"], "title"),
                )
            )

    def _add(
        self,
        language: str,
        section: str,
        strings: Mapping[str, Any],
        result: Mapping[str, Any],
    ) -> None:
        texts = self.texts[language]
        kind = result["type"]
        if kind is FlowResultType.ABORT:
            key = result["reason"]
            texts.append((f"{section}.abort.{key}", lookup(strings, "abort", key)))
            return
        if kind is FlowResultType.CREATE_ENTRY:
            if (key := result.get("description")) is not None:
                where = f"{section}.create_entry.{key}"
                texts.append((where, lookup(strings, "create_entry", key)))
            return
        step = result["step_id"]
        where = f"{section}.step.{step}"
        for part in ("title", "description"):
            if (text := lookup(strings, "step", step, part)) is not None:
                texts.append((f"{where}.{part}", text))
        if section == "options" and not step.endswith("upload"):
            title = lookup(strings, "step", step, "title")
            # The point forms' titles say what they change, not the system.
            if (
                not step.endswith(
                    ("point", "point_confirm", "point_class", "point_override")
                )
                and step != "remove_overrides"
            ):
                self.options_titles[language].append(title or "")
        if kind is FlowResultType.MENU:
            for option in result["menu_options"]:
                label = lookup(strings, "step", step, "menu_options", option)
                texts.append((f"{where}.menu_options.{option}", label))
            return
        sections = set()
        for within, key, selector in fields(result["data_schema"]):
            if within:
                sections.add(within)
            # Every field has a label (None: no text); its help is optional.
            label = lookup(strings, "step", step, *within, "data", key)
            texts.append((f"{where}.{'.'.join((*within, 'data', key))}", label))
            help_text = lookup(strings, "step", step, *within, "data_description", key)
            if help_text is not None:
                texts.append((f"{where}.data_description.{key}", help_text))
            config = getattr(selector, "config", {})
            if isinstance(selector, SelectSelector) and config.get("translation_key"):
                labels_key = config["translation_key"]
                labels = lookup(
                    translations(language), "selector", labels_key, "options"
                )
                for option in config["options"]:
                    value = option if isinstance(option, str) else option["value"]
                    texts.append(
                        (f"selector.{labels_key}.{value}", lookup(labels, str(value)))
                    )
        for within in sections:
            name = lookup(strings, "step", step, *within, "name")
            texts.append((f"{where}.{'.'.join(within)}.name", name))
        for error in (result.get("errors") or {}).values():
            texts.append((f"{section}.error.{error}", lookup(strings, "error", error)))
        # What an error fills in (a refused file's own message) is shown too.
        if result.get("errors"):
            for name, value in (result.get("description_placeholders") or {}).items():
                texts.append((f"{where}.placeholder.{name}", str(value)))

    def problems(self, system: str) -> list[str]:
        """What speaks of another system, is missing, or renders as italics."""
        found: list[str] = []
        for language, texts in self.texts.items():
            for where, text in texts:
                if text is None:
                    found.append(f"{language} {where}: no text")
                    continue
                found += [
                    f"{language} {where} says {word!r}: {text}"
                    for word in DENIED[system]
                    if re.search(rf"(?<![\w-]){re.escape(word)}", text)
                ]
                if "*" in re.sub(r"`[^`]*`", "", text):
                    found.append(f"{language} {where}: a pattern outside backticks")
            titles = self.options_titles[language]
            if not titles or not all(OWN_NAME[system] in title for title in titles):
                found.append(f"{language} options titles {titles} lack its name")
            found += [
                f"{language} {where} {label!r} opens a form titled {title!r}"
                for where, label, title in self.choices[language]
                if label != title
            ]
        return found


async def flow(
    hass: HomeAssistant, shown: Shown, step: str, data: dict[str, Any] | None = None
) -> dict[str, Any]:
    """Open the config flow, choose a source and fill its form (if ``data``)."""
    result = await hass.config_entries.flow.async_init(
        DOMAIN, context={"source": SOURCE_USER}
    )
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {"next_step_id": step}
    )
    shown.add("config", result)
    if data is not None:
        result = await hass.config_entries.flow.async_configure(result["flow_id"], data)
        await hass.async_block_till_done()
        shown.add("config", result)
    return dict(result)


async def add_once(
    hass: HomeAssistant,
    shown: Shown,
    system: str,
    failing: dict[str, Any],
    form: dict[str, Any],
    *,
    again: dict[str, Any] | None = None,
) -> ConfigEntry:
    """A failing form shows its errors, the form adds the device, the same
    device once more (``again``: the form with a file of its own) aborts."""
    failed = await flow(hass, shown, system, failing)
    assert failed["errors"], failed
    entry = created(await flow(hass, shown, system, form))
    result = await flow(hass, shown, system, form if again is None else again)
    assert result["type"] is FlowResultType.ABORT
    return entry


async def submit_to_its_end(
    hass: HomeAssistant, shown: Shown, result: Any, data: dict[str, Any]
) -> None:
    """Keep the form shown, submit it, keep what ends the flow (an abort)."""
    shown.add("config", result)
    result = await hass.config_entries.flow.async_configure(result["flow_id"], data)
    await hass.async_block_till_done()
    shown.add("config", result)
    assert result["type"] is FlowResultType.ABORT


async def reconfigure(
    hass: HomeAssistant, shown: Shown, entry: ConfigEntry, data: dict[str, Any]
) -> None:
    """Show an entry's reconfigure form, then submit it."""
    result = await hass.config_entries.flow.async_init(
        DOMAIN, context={"source": SOURCE_RECONFIGURE, "entry_id": entry.entry_id}
    )
    await submit_to_its_end(hass, shown, result, data)


async def reauthenticate(
    hass: HomeAssistant, shown: Shown, entry: ConfigEntry, data: dict[str, Any]
) -> None:
    """Show an entry's sign-in form, then submit it."""
    result = await hass.config_entries.flow.async_init(
        DOMAIN,
        context={"source": SOURCE_REAUTH, "entry_id": entry.entry_id},
        data=dict(entry.data),
    )
    await submit_to_its_end(hass, shown, result, data)


async def options(
    hass: HomeAssistant,
    shown: Shown,
    entry: ConfigEntry,
    submit: dict[str, Any] | None = None,
    refused: str | None = None,
) -> None:
    """Show the options: the form (then ``submit`` in it, if any), or the menu.

    Behind a menu, each form it offers is shown (the settings with ``submit``
    in it, if any), and a point's form (its first point chosen in "Change a
    point"), submitted as it is, and its device class's (a first point that
    takes one), the confirmation of removing the first point (not confirmed);
    ``refused`` is the ID of an uploaded file the upload form must refuse (its
    error is shown). A step that needs the entry loaded (a discovered point's
    change) shows why it cannot be taken.
    """
    manager = hass.config_entries.options
    result = await manager.async_init(entry.entry_id)
    shown.add("options", result)
    if result["type"] is FlowResultType.FORM:
        if submit is not None:
            result = await manager.async_configure(result["flow_id"], submit)
            assert result["type"] is FlowResultType.FORM
            assert result["errors"]
            shown.add("options", result)
        return
    for option in result["menu_options"]:
        opened = await manager.async_init(entry.entry_id)
        opened = await manager.async_configure(
            opened["flow_id"], {"next_step_id": option}
        )
        shown.add("options", opened)
        if option == "upload":
            shown.add_choice("options", result, option, opened)
        if option == "settings" and submit is not None:
            opened = await manager.async_configure(opened["flow_id"], submit)
            assert opened["type"] is FlowResultType.FORM
            assert opened["errors"]
            shown.add("options", opened)
        if opened["type"] is FlowResultType.ABORT:
            continue
        words = descriptor_of(entry.data).words
        first = (await async_stored_map(hass, entry) or PointMap(())).points[:1]
        if option == "edit_point":
            opened = await manager.async_configure(
                opened["flow_id"], {CONF_POINT: [first[0].key]}
            )
            assert opened["step_id"] == words.point_step_id, opened
            shown.add("options", opened)
            opened = await manager.async_configure(
                opened["flow_id"], form_values(first[0])
            )
            assert opened["step_id"] == CLASS_STEP, opened
            shown.add("options", opened)
        if option == "add_point":
            assert opened["step_id"] == words.add_point_step_id, opened
        if option == "remove_point":
            opened = await manager.async_configure(
                opened["flow_id"], {CONF_POINT: [first[0].key]}
            )
            assert opened["step_id"] == REMOVE_CONFIRM_STEP, opened
            shown.add("options", opened)
        if option == "upload" and refused is not None:
            opened = await manager.async_configure(
                opened["flow_id"], {CONF_POINT_MAP: refused}
            )
            assert opened["errors"], opened
            shown.add("options", opened)
        manager.async_abort(opened["flow_id"])


def created(result: Mapping[str, Any]) -> ConfigEntry:
    assert result["type"] is FlowResultType.CREATE_ENTRY, result
    entry: ConfigEntry = result["result"]
    return entry


@pytest.fixture
async def coms(simulator: Simulator) -> AsyncIterator[PlcComsServer]:
    async with PlcComsServer(simulator, scan_interval=None) as server:
        yield server


@pytest.fixture
def bad_file(
    hass: HomeAssistant, hass_client: ClientSessionGenerator
) -> Callable[[str], Awaitable[str]]:
    """Upload a file no system reads as a map (a refused upload); return its ID."""

    async def bad(name: str) -> str:
        return await upload(hass, hass_client, name, "not a map\x00\n;;;\n")

    return bad


def assert_speaks_of_its_own(shown: Shown, system: str) -> None:
    problems = shown.problems(system)
    assert problems == [], "\n".join(problems)


async def test_tecoapi_speaks_of_tecomat_tecoapi(
    hass: HomeAssistant, simulator: Simulator, closed_port: str
) -> None:
    shown = Shown()
    form = {
        CONF_HOST: simulator.host,
        CONF_USERNAME: SIM_USERNAME,
        CONF_PASSWORD: SIM_PASSWORD,
        CONF_VERIFY_SSL: True,
    }
    entry = await add_once(
        hass, shown, "tecoapi", {**form, CONF_HOST: closed_port}, form
    )
    await reconfigure(hass, shown, entry, form)
    await reauthenticate(
        hass, shown, entry, {CONF_USERNAME: SIM_USERNAME, CONF_PASSWORD: SIM_PASSWORD}
    )
    # Push to a server that does not answer: the Push section's error.
    await options(
        hass,
        shown,
        entry,
        {
            CONF_SCAN_INTERVAL: 5,
            CONF_ATTRIBUTE_INTERVAL: 60,
            CONF_PLAIN_VARIABLES: PlainVariables.DISABLED,
            CONF_DEVICES: DeviceGrouping.GROUPS,
            CONF_PUSH: {
                CONF_HOST: "127.0.0.1",
                CONF_PORT: int(closed_port.rpartition(":")[2]),
            },
        },
    )
    assert_speaks_of_its_own(shown, "tecoapi")


async def test_plccoms_speaks_of_tecomat_plccoms(
    hass: HomeAssistant, coms: PlcComsServer
) -> None:
    shown = Shown()
    form = {CONF_HOST: "127.0.0.1", CONF_PORT: coms.port}
    entry = await add_once(
        hass, shown, "plccoms", {**form, CONF_HOST: "a host/path"}, form
    )
    await reconfigure(hass, shown, entry, form)
    await options(hass, shown, entry)
    assert_speaks_of_its_own(shown, "plccoms")


@pytest.mark.usefixtures("socket_enabled", "uploads")
async def test_mervis_speaks_of_mervis(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    closed_port: str,
    bad_file: Callable[[str], Awaitable[str]],
) -> None:
    shown = Shown()
    sim = MervisSimulator(house(), username=MERVIS_USER, password=MERVIS_PASSWORD)
    await sim.start()
    try:
        vlist = Path(__file__).parents[2] / "simulator" / "mervis" / "house.vlist"
        text = vlist.read_text(encoding="utf-8")
        form = {
            CONF_HOST: sim.host,
            CONF_USERNAME: MERVIS_USER,
            CONF_PASSWORD: MERVIS_PASSWORD,
            CONF_VERIFY_SSL: True,
        }

        async def with_file(**changes: Any) -> dict[str, Any]:
            file_id = await upload(hass, hass_client, "house.vlist", text)
            return {**form, CONF_POINT_MAP: file_id, **changes}

        entry = await add_once(
            hass,
            shown,
            "mervis",
            await with_file(host=closed_port),
            await with_file(),
            again=await with_file(),
        )
        await reconfigure(hass, shown, entry, form)
        await reauthenticate(
            hass,
            shown,
            entry,
            {CONF_USERNAME: MERVIS_USER, CONF_PASSWORD: MERVIS_PASSWORD},
        )
        await options(hass, shown, entry, refused=await bad_file("house.vlist"))
    finally:
        await sim.stop()
    assert_speaks_of_its_own(shown, "mervis")
    assert any(".error." in where for where, _ in shown.texts["en"])


@pytest.mark.usefixtures("socket_enabled", "uploads")
async def test_fpi4c_speaks_of_the_gateway_and_its_stations(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    closed_port: str,
    bad_file: Callable[[str], Awaitable[str]],
) -> None:
    shown = Shown()
    async with FpI4cSimulator(demo_stations(), station=1) as gateway:
        text = EXAMPLE_CSV.read_text(encoding="utf-8")

        async def with_file(host: str) -> dict[str, Any]:
            file_id = await upload(hass, hass_client, "map.csv", text)
            return {CONF_HOST: host, CONF_POINT_MAP: file_id}

        entry = await add_once(
            hass,
            shown,
            "fpi4c",
            await with_file(closed_port),
            await with_file(gateway.url),
            again=await with_file(gateway.url),
        )
        await reconfigure(hass, shown, entry, {CONF_HOST: gateway.url})
        await options(hass, shown, entry, refused=await bad_file("map.csv"))
    assert_speaks_of_its_own(shown, "fpi4c")
    assert any(".error." in where for where, _ in shown.texts["en"])


async def test_tekon_speaks_of_the_gateway_and_the_building(
    hass: HomeAssistant, socket_enabled: None, closed_port: str
) -> None:
    shown = Shown()
    async with TekonGateway() as gateway:
        form = {CONF_HOST: gateway.url, CONF_VERIFY_SSL: True}
        entry = await add_once(
            hass, shown, "tekon", {**form, CONF_HOST: f"http://{closed_port}"}, form
        )
        await reconfigure(hass, shown, entry, form)
        await options(hass, shown, entry)
    assert_speaks_of_its_own(shown, "tekon")
    # Behind its own menu, the form of its own step ID is submitted.
    result = await hass.config_entries.options.async_init(entry.entry_id)
    assert result["step_id"] == "tekon_menu"
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {"next_step_id": "settings"}
    )
    assert result["step_id"] == "tekon"
    result = await hass.config_entries.options.async_configure(
        result["flow_id"],
        {CONF_SCAN_INTERVAL: 2, CONF_DEVICES: DeviceGrouping.SINGLE},
    )
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert entry.options[CONF_SCAN_INTERVAL] == 2
    assert entry.options[CONF_DEVICES] == DeviceGrouping.SINGLE


def test_the_options_answer_only_their_sources_step_ids() -> None:
    """Another name is no step: Home Assistant refuses a step that is none."""
    flow = PlcOptionsFlow()
    assert hasattr(flow, "async_step_fpi4c_settings")
    assert not hasattr(flow, "async_step_nothing")
    assert not hasattr(flow, "nothing")


def test_the_deny_lists_cover_every_source() -> None:
    """A source added later gets its own words here too."""
    names: Iterable[str] = (descriptor.name for descriptor in sources())
    assert set(names) == set(DENIED) == set(OWN_NAME)


def test_settings_are_on_the_first_step_unless_they_have_their_own() -> None:
    """A source without a map shows its settings on its first step (no "settings")."""
    assert Words().settings_step_id == "init"
    assert Words(options_step_id="tekon").settings_step_id == "tekon"
    own = Words(options_step_id="mervis", settings_step_id="mervis_settings")
    assert own.settings_step_id == "mervis_settings"
    for descriptor in sources():
        assert descriptor.words.settings_step_id, descriptor.name


@pytest.mark.parametrize(
    "error",
    [
        plc.PlcConnectionError("connection refused"),
        plc.PlcAuthenticationError("401"),
        plc.PlcResponseError("500"),
        plc.PlcError("something else"),
    ],
    ids=type,
)
def test_a_failed_poll_speaks_of_no_one_system(error: plc.PlcError) -> None:
    """Every system's failed poll shows these texts: no system's own device word.

    (A PLC behind a server that answers, PLCComS's or an FP-I4C gateway's, is a
    PLC for each system that shows it.)
    """
    raised = update_error(error)
    key = getattr(raised, "translation_key", None)
    assert key is not None
    for language in ("en", "cs"):
        message = lookup(translations(language), "exceptions", key, "message")
        assert message, (language, key)
        for word in ("PLC", "TecoApi", "gateway", "brán", "controller", "jednotk"):
            assert word not in message, (language, key, word)
