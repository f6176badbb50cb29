"""The library's texts in the reader's words (messages.py): no English inside Czech.

Every text the library writes for a user has a key; each key is a text of the
integration's translations, in English as the library writes it and in Czech
with the same placeholders. With Home Assistant's language set to Czech,
what the code fills into a form's error, a repair or an error message (its
``{error}``, ``{message}``, ``{points}``) says no English word of the
library's texts and no raw key: only the device's own words stay as it says
them, behind *zařízení hlásí:* (the device says:). Against the simulators
(TecoApi, an FP-I4C gateway) and the memory source.
"""

from collections.abc import Iterator, Mapping
import json
from pathlib import Path
import re
from typing import Any, Final

from freezegun.api import FrozenDateTimeFactory
from homeassistant.const import CONF_HOST
from homeassistant.core import HomeAssistant
from homeassistant.exceptions import HomeAssistantError
from homeassistant.helpers import issue_registry as ir
import pytest
from pytest_homeassistant_custom_component.typing import ClientSessionGenerator

from custom_components.tecoapi.const import DOMAIN
from custom_components.tecoapi.messages import async_load_texts, quality_text, said
from custom_components.tecoapi.pyplc import PointQuality, Quality
from custom_components.tecoapi.pyplc.core.descriptor import CONF_POINT_MAP
from custom_components.tecoapi.pyplc.core.exceptions import PlcConnectionError
from custom_components.tecoapi.pyplc.core.pointmap.csvmap import MIN_ABOVE_MAX
from custom_components.tecoapi.pyplc.core.registry import sources
from custom_components.tecoapi.pyplc.core.texts import TEMPLATES, Text
from custom_components.tecoapi.pyplc.mervis.source import WRONG_LENGTH
from tests.components.tecoapi import fpi4c_gateway
from tests.components.tecoapi.conftest import make_entry, poll, setup_entry
from tests.components.tecoapi.memory_house import (
    add_house,
    choose,
    open_options,
    start_memory_flow,
    upload,
)
from tests.components.tecoapi.test_services import write
from tests.fake_source import DEVICES, house_device
from tests.simulator import Simulator
from tests.simulator.fpi4c import FpI4cSimulator

TRANSLATIONS: Final = (
    Path(__file__).parents[3] / "custom_components" / DOMAIN / ("translations")
)
PLACEHOLDER: Final = re.compile(r"\{(\w+)\}")
WORD: Final = re.compile(r"[^\W\d_]{3,}")
DEVICE_WORDS: Final = re.compile(r"zařízení hlásí: [^)]*")
"""The device's own words: after "the device says:", to the end of the parentheses."""
QUOTED: Final = re.compile(r"„[^“]*“|'[^']*'")
"""What a text quotes: the file's own column names, the values the user typed."""
IDENTIFIER: Final = re.compile(r"(?<!\w)[A-Z][A-Z0-9_]*(?!\w)")
"""A type's or an area's name (``DATE_AND_TIME``, ``BOOL``): a system's word."""


def translation(language: str) -> dict[str, Any]:
    result: dict[str, Any] = json.loads(
        (TRANSLATIONS / f"{language}.json").read_text(encoding="utf-8")
    )
    return result


def library_texts() -> dict[str, str]:
    """Every text the library writes for a user, by key (each system imported)."""
    assert list(sources())  # the systems' modules, and their texts, loaded
    return {key: template.english for key, template in TEMPLATES.items()}


def words(text: str) -> set[str]:
    return {word.lower() for word in WORD.findall(PLACEHOLDER.sub(" ", text))}


def all_texts(node: Mapping[str, Any]) -> Iterator[str]:
    for value in node.values():
        if isinstance(value, Mapping):
            yield from all_texts(value)
        else:
            yield value


def english_words() -> set[str]:
    """The words of the library's English texts that no Czech text says."""
    english = translation("en")["exceptions"]
    found = set().union(*(words(english[key]["message"]) for key in library_texts()))
    czech = set().union(*(words(text) for text in all_texts(translation("cs"))))
    return found - czech


ENGLISH: Final = english_words()


def english_in(text: str) -> set[str]:
    """The library's English words in a Czech text (the device's words, quotes aside)."""
    bare = IDENTIFIER.sub(" ", QUOTED.sub(" ", DEVICE_WORDS.sub(" ", text)))
    return words(bare) & ENGLISH


def assert_czech(text: str) -> None:
    """A text the code filled: Czech, no English word of the library's, no raw key."""
    assert text.strip(), text
    assert not english_in(text), (text, english_in(text))
    assert not [key for key in TEMPLATES if re.search(rf"\b{key}\b", text)], text


@pytest.fixture
def czech(hass: HomeAssistant) -> None:
    """Home Assistant speaks Czech, as it does before the entries are set up."""
    hass.config.language = "cs"


# --- every text translated -----------------------------------------------------------


def test_every_library_text_is_translated_with_its_placeholders() -> None:
    """English as the library writes it; Czech with the same placeholders, no English."""
    english = translation("en")["exceptions"]
    czech = translation("cs")["exceptions"]
    texts = library_texts()
    assert len(texts) > 80
    assert {key: english[key]["message"] for key in texts} == texts
    for key, text in texts.items():
        message = czech[key]["message"]
        assert set(PLACEHOLDER.findall(message)) == set(PLACEHOLDER.findall(text)), key
        assert message != text or not words(text), key
        assert not english_in(message), (key, message)


def test_the_check_finds_english_and_raw_keys() -> None:
    """The check is not blind: the library's English, a key; the device's own pass."""
    assert english_in("řádek 3, sloupec „type“: unknown type 'QWORD'") == {"unknown"}
    assert english_in("the file holds no point") >= {"file", "holds"}
    assert english_in("zařízení hlásí: 500.012: Reading of public file failed") == set()
    with pytest.raises(AssertionError):
        assert_czech("map_unknown_type")


# --- what the code fills, in Czech ---------------------------------------------------


@pytest.mark.usefixtures("memory", "czech")
async def test_a_map_s_and_a_point_s_errors_are_czech(
    hass: HomeAssistant, hass_client: ClientSessionGenerator
) -> None:
    """The row and column of a file's error, and why; a point form's error."""
    house_device()
    result = await start_memory_flow(hass)
    file_id = await upload(
        hass, hass_client, "map.csv", "name,address,type\nA,m1,QWORD\n"
    )
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {CONF_HOST: "MEM-0001", CONF_POINT_MAP: file_id}
    )
    assert result["errors"] == {CONF_POINT_MAP: "point_map_invalid"}
    error = result["description_placeholders"]["error"]
    assert error.startswith("řádek 2, sloupec „type“: neznámý typ 'QWORD' (známé: ")
    assert_czech(error)
    hass.config_entries.flow.async_abort(result["flow_id"])

    entry = (await add_house(hass, hass_client))["result"]
    for point, field in (
        (
            {"id": "x", "name": "X", "address": "m40", "type": "INT", "scale": 0.0},
            "scale",
        ),
        ({"id": "x", "name": "X", "address": "m-40", "type": "INT"}, "address"),
        ({"id": "boiler_temp", "name": "X", "address": "m40", "type": "INT"}, "id"),
    ):
        result = await choose(
            hass, await open_options(hass, entry.entry_id), "add_point"
        )
        result = await hass.config_entries.options.async_configure(
            result["flow_id"], point
        )
        assert result["errors"] == {field: "point_invalid"}
        assert_czech(result["description_placeholders"]["error"])


@pytest.mark.usefixtures("uploads", "czech")
async def test_a_gateway_s_refusals_are_its_own_words_in_czech(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    gateway: FpI4cSimulator,
    freezer: FrozenDateTimeFactory,
) -> None:
    """A typed address its PLC lacks, and the points it refuses while it runs."""
    entry = await fpi4c_gateway.add_gateway(hass, hass_client, gateway)
    result = await fpi4c_gateway.options_step(hass, entry, "add_point")
    result = await hass.config_entries.options.async_configure(
        result["flow_id"],
        {
            "id": "far",
            "name": "Far",
            "address": "R9999F",
            "type": "BOOL",
            "device": "2",
        },
    )
    assert result["errors"] == {"address": "fpi4c_point_refused"}
    error = result["description_placeholders"]["error"]
    assert error.startswith("zařízení hlásí: err_code 61: ")
    assert_czech(error)
    hass.config_entries.options.async_abort(result["flow_id"])
    for step, point in (
        ("add_point", {"id": "y", "name": "Y", "address": "DT10", "type": "BOOL"}),
        (
            "add_point",
            {"id": "y", "name": "Y", "address": "DT10", "type": "INT", "device": "x"},
        ),
    ):
        result = await fpi4c_gateway.options_step(hass, entry, step)
        result = await hass.config_entries.options.async_configure(
            result["flow_id"], point
        )
        assert result["errors"], point
        assert_czech(result["description_placeholders"]["error"])
        hass.config_entries.options.async_abort(result["flow_id"])

    gateway.item_errors[1, "DT210"] = (61, "Data error")
    await poll(hass, freezer)
    issue = ir.async_get(hass).async_get_issue(
        DOMAIN, f"points_refused_{entry.entry_id}"
    )
    assert issue is not None
    assert issue.translation_key == "fpi4c_points_refused"
    assert issue.translation_placeholders is not None
    (line,) = issue.translation_placeholders["points"].splitlines()
    assert line.endswith("DT210: zařízení hlásí: err_code 61: Data error")
    assert_czech(line)


@pytest.mark.usefixtures("czech")
@pytest.mark.parametrize(
    ("path", "value", "error"),
    [
        ("Heating.livingSetpoint.value", '"warm"', ("invalid_value", "error")),
        ("lights[0].value", "1", ("invalid_value", "error")),
        ("doorbellCount", "-5", ("value_rejected", "message")),
    ],
)
async def test_a_write_s_reason_is_czech(
    hass: HomeAssistant,
    simulator: Simulator,
    path: str,
    value: str,
    error: tuple[str, str],
) -> None:
    """Why a value does not fit (the library's check, or the PLC's refusal).

    ``error``: the error's key and the placeholder that says why.
    """
    key, placeholder = error
    entry = await setup_entry(hass, make_entry(simulator))

    with pytest.raises(HomeAssistantError) as raised:
        await write(hass, entry.entry_id, path, value)

    assert raised.value.translation_key == key
    assert raised.value.translation_placeholders is not None
    assert_czech(raised.value.translation_placeholders[placeholder])


@pytest.mark.usefixtures("czech")
async def test_a_failed_poll_says_why_in_czech(
    hass: HomeAssistant, simulator: Simulator, freezer: FrozenDateTimeFactory
) -> None:
    """A device that stops answering: the error's {error} is Czech."""
    entry = await setup_entry(hass, make_entry(simulator))
    simulator.faults.drop_connection = True
    await poll(hass, freezer, 60)

    failed = entry.runtime_data.last_exception
    assert failed is not None
    assert failed.translation_key == "cannot_connect"
    assert failed.translation_placeholders["error"] == said(
        hass, PlcConnectionError("x").text()
    )
    assert_czech(failed.translation_placeholders["error"])


@pytest.mark.usefixtures("memory", "czech")
async def test_a_memory_device_gone_says_why_in_czech(
    hass: HomeAssistant, hass_client: ClientSessionGenerator
) -> None:
    entry = (await add_house(hass, hass_client))["result"]
    DEVICES["MEM-0001"].fail = PlcConnectionError("No memory device 'MEM-0001'")
    await entry.runtime_data.async_refresh()

    failed = entry.runtime_data.last_exception
    assert failed is not None
    assert_czech(failed.translation_placeholders["error"])


@pytest.mark.usefixtures("memory", "czech")
async def test_a_source_s_reason_for_a_point_is_czech_and_the_device_s_is_its_own(
    hass: HomeAssistant, hass_client: ClientSessionGenerator
) -> None:
    """A Mervis variable answered at another length; a device's own reason."""
    await add_house(hass, hass_client)  # the texts loaded in Home Assistant's language
    mine = PointQuality(quality=Quality.BAD, reason="wrong length", text=WRONG_LENGTH())
    theirs = PointQuality(quality=Quality.BAD, reason="error: unknown variable")

    assert quality_text(hass, mine) == (
        "řídicí jednotka vrátila jinou délku, než má proměnná"
    )
    assert quality_text(hass, theirs) == "zařízení hlásí: error: unknown variable"


# --- what a text falls back to -------------------------------------------------------


async def test_a_text_is_the_library_s_english_where_no_translation_is_at_hand(
    hass: HomeAssistant,
) -> None:
    """Outside Home Assistant, in a language not loaded yet, or a broken translation."""
    text = WRONG_LENGTH()
    assert said(None, text) == str(text)
    hass.config.language = "de"  # none loaded
    assert said(hass, text) == str(text)

    hass.config.language = "cs"
    await async_load_texts(hass)
    assert said(hass, text) == "řídicí jednotka vrátila jinou délku, než má proměnná"
    # A text without a parameter its translation says keeps the placeholder.
    assert said(hass, Text(MIN_ABOVE_MAX)) == "{min} je vyšší než maximum {max}"
