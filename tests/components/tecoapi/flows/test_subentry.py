"""Typed devices composed in the UI (config subentries): every step, error and fate.

The family house's plain heating variables become a thermostat, a blind slider a
blind, a light switch a light; a composed device keeps working across program
downloads while its points exist, and a repair issue says which point vanished.
"""

from collections.abc import Callable, Iterator, Mapping
import json
from pathlib import Path
import re
from types import MappingProxyType
from typing import Any, Final

from freezegun.api import FrozenDateTimeFactory
from homeassistant.config_entries import (
    SOURCE_RECONFIGURE,
    SOURCE_USER,
    ConfigSubentry,
)
from homeassistant.const import ATTR_TEMPERATURE, STATE_UNAVAILABLE
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType, InvalidData
from homeassistant.helpers import (
    device_registry as dr,
    entity_registry as er,
    issue_registry as ir,
    translation,
)
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.tecoapi.const import DOMAIN
from custom_components.tecoapi.flows.subentry import COMPOSED_KINDS
from custom_components.tecoapi.issues import COMPOSITION_TEXTS
from custom_components.tecoapi.pyplc.core.composition import COMPOSITIONS
from tests.components.tecoapi.conftest import entity_id_of, poll
from tests.simulator import Program, Simulator

SERIAL = "SD 2080"
THERMOSTAT = {
    "name": "Living room thermostat",
    "temperature": "rooms.livingtemp",
    "setpoint": "heating.livingsetpoint",
}


async def start(
    hass: HomeAssistant, entry: MockConfigEntry, subentry_type: str
) -> dict[str, Any]:
    """Open the "Add a ..." flow of an entry."""
    result = await hass.config_entries.subentries.async_init(
        (entry.entry_id, subentry_type), context={"source": SOURCE_USER}
    )
    return dict(result)


async def compose(
    hass: HomeAssistant,
    entry: MockConfigEntry,
    subentry_type: str,
    data: dict[str, Any],
) -> dict[str, Any]:
    """Add a composed device through the UI flow; wait until its entity is there."""
    result = await start(hass, entry, subentry_type)
    result = dict(
        await hass.config_entries.subentries.async_configure(result["flow_id"], data)
    )
    await hass.async_block_till_done()
    return result


def composed_entity(hass: HomeAssistant, domain: str, entry: MockConfigEntry) -> str:
    """The entity ID of the entry's (only) composed device of a domain."""
    (subentry_id,) = entry.subentries
    return entity_id_of(hass, domain, f"{SERIAL}_composed:{subentry_id}")


async def test_form_lists_only_fitting_points(
    hass: HomeAssistant, demo_entry: MockConfigEntry
) -> None:
    """The setpoint list holds writable numbers, by title and path."""
    result = await start(hass, demo_entry, "thermostat")

    assert result["type"] is FlowResultType.FORM
    assert result["step_id"] == "user"
    fields = {str(key): key for key in result["data_schema"].schema}
    assert set(fields) == {
        "name",
        "temperature",
        "setpoint",
        "heat_mode",
        "cool_mode",
        "heating",
        "cooling",
    }
    setpoints = result["data_schema"].schema[fields["setpoint"]].config["options"]
    labels = {option["value"]: option["label"] for option in setpoints}
    assert labels["heating.livingsetpoint"] == (
        "Living room setpoint (Heating.livingSetpoint)"
    )
    assert "rooms.livingtemp" not in labels  # read-only


async def test_a_thermostat_lists_temperatures_and_chooses_none(
    hass: HomeAssistant, demo_entry: MockConfigEntry
) -> None:
    """The measured temperature lists temperatures only, and none is chosen.

    Humidities and blind positions (numbers in %) are no temperature; the
    frontend would preselect the first point of a required list (the outside
    temperature), so each role starts empty.
    """
    result = await start(hass, demo_entry, "thermostat")

    schema = result["data_schema"].schema
    fields = {str(key): key for key in schema}
    options = schema[fields["temperature"]].config["options"]
    listed = {option["value"] for option in options}
    assert {"rooms.livingtemp", "outsidetemp", "rooms.bedroomtemp"} <= listed
    assert {
        "rooms.livinghumidity",
        "rooms.bathroomhumidity",
        "detskypokoj.blind.position",
        "blinds[0]",
        "energy.powernow",
    }.isdisjoint(listed)
    assert all(
        point.attributes is None or point.attributes.unit in ("°C", "")
        for key in listed
        if (point := demo_entry.runtime_data.data.catalogue.points[key])
    )
    for role in ("temperature", "setpoint"):
        assert fields[role].description == {"suggested_value": ""}


async def test_add_a_thermostat(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    """The thermostat is a device of its own and writes the chosen setpoint."""
    result = await compose(hass, demo_entry, "thermostat", THERMOSTAT)

    assert result["type"] is FlowResultType.CREATE_ENTRY
    (subentry,) = demo_entry.subentries.values()
    assert subentry.title == "Living room thermostat"
    assert subentry.data == {
        "kind": "climate",
        "roles": {
            "temperature": "rooms.livingtemp",
            "setpoint": "heating.livingsetpoint",
        },
    }
    climate = composed_entity(hass, "climate", demo_entry)
    state = hass.states.get(climate)
    assert state.name == "Living room thermostat"
    assert state.attributes["current_temperature"] == 21.8
    registry_entry = er.async_get(hass).async_get(climate)
    assert registry_entry is not None
    assert registry_entry.config_subentry_id == subentry.subentry_id
    device = dr.async_get(hass).async_get(registry_entry.device_id or "")
    assert device is not None
    assert device.name == "Living room thermostat"

    await hass.services.async_call(
        "climate",
        "set_temperature",
        {"entity_id": climate, ATTR_TEMPERATURE: 22.5},
        blocking=True,
    )
    assert simulator.get_value("Heating.livingSetpoint.value") == 22.5


async def test_add_a_blind_a_light_a_button_and_a_switch(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    """Each kind the UI offers makes its entity."""
    await compose(
        hass, demo_entry, "blind", {"name": "Study blind", "position": "blinds[3]"}
    )
    await compose(hass, demo_entry, "light", {"name": "Garden", "onoff": "lights[5]"})
    await compose(
        hass, demo_entry, "button", {"name": "Doorbell", "click_count": "doorbellcount"}
    )
    await compose(
        hass, demo_entry, "switch", {"name": "Boiler", "onoff": "heating.boileron"}
    )

    registry = er.async_get(hass)
    domains = sorted(
        entity.domain
        for entity in er.async_entries_for_config_entry(registry, demo_entry.entry_id)
        if entity.unique_id.startswith(f"{SERIAL}_composed:")
    )
    assert domains == ["cover", "event", "light", "switch"]
    blind = next(
        entity.entity_id
        for entity in er.async_entries_for_config_entry(registry, demo_entry.entry_id)
        if entity.unique_id.startswith(f"{SERIAL}_composed:")
        and entity.domain == "cover"
    )
    await hass.services.async_call(
        "cover",
        "set_cover_position",
        {"entity_id": blind, "position": 25},
        blocking=True,
    )
    assert simulator.get_value("blinds[3].value") == 25


@pytest.mark.parametrize(
    ("subentry_type", "data", "errors"),
    [
        ("thermostat", {**THERMOSTAT, "name": "   "}, {"name": "name_missing"}),
        ("light", {"name": "Nothing chosen"}, {"level": "missing_role"}),
        (
            "light",
            {"name": "Warmth only", "onoff": "lights[0]", "color_temp": "blinds[1]"},
            {"level": "missing_role"},
        ),
        ("button", {"name": "No counter"}, {"click_count": "missing_role"}),
    ],
    ids=["no name", "light without on/off or level", "colour without level", "button"],
)
async def test_errors_and_recovery(
    hass: HomeAssistant,
    demo_entry: MockConfigEntry,
    subentry_type: str,
    data: dict[str, Any],
    errors: dict[str, str],
) -> None:
    """A choice that makes no device shows an error on its field; a good one passes."""
    result = await start(hass, demo_entry, subentry_type)
    result = dict(
        await hass.config_entries.subentries.async_configure(result["flow_id"], data)
    )

    assert result["type"] is FlowResultType.FORM
    assert result["errors"] == errors
    assert not demo_entry.subentries


async def test_a_point_that_does_not_fit_is_not_accepted(
    hass: HomeAssistant, demo_entry: MockConfigEntry
) -> None:
    """Only listed points are accepted: a read-only setpoint is refused by the form."""
    result = await start(hass, demo_entry, "thermostat")

    with pytest.raises(InvalidData):
        await hass.config_entries.subentries.async_configure(
            result["flow_id"], {**THERMOSTAT, "setpoint": "rooms.kitchentemp"}
        )


async def test_composition_needs_a_loaded_plc(
    hass: HomeAssistant, demo_entry: MockConfigEntry
) -> None:
    """The PLC must be loaded: its points are what the form lists."""
    await compose(hass, demo_entry, "thermostat", THERMOSTAT)
    await hass.config_entries.async_unload(demo_entry.entry_id)
    await hass.async_block_till_done()

    result = await start(hass, demo_entry, "thermostat")
    assert result["type"] is FlowResultType.ABORT
    assert result["reason"] == "entry_not_loaded"
    (subentry_id,) = demo_entry.subentries
    result = dict(
        await hass.config_entries.subentries.async_init(
            (demo_entry.entry_id, "thermostat"),
            context={"source": SOURCE_RECONFIGURE, "subentry_id": subentry_id},
        )
    )
    assert result["reason"] == "entry_not_loaded"


async def reconfigure(
    hass: HomeAssistant, entry: MockConfigEntry, data: dict[str, Any] | None
) -> dict[str, Any]:
    """Open the composed thermostat's reconfigure flow, and submit ``data``."""
    (subentry_id,) = entry.subentries
    result = dict(
        await hass.config_entries.subentries.async_init(
            (entry.entry_id, "thermostat"),
            context={"source": SOURCE_RECONFIGURE, "subentry_id": subentry_id},
        )
    )
    if data is not None:
        result = dict(
            await hass.config_entries.subentries.async_configure(
                result["flow_id"], data
            )
        )
        await hass.async_block_till_done()
    return result


async def test_reconfigure_a_composed_device(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    """The form shows the current choice; a new setpoint is used after it."""
    await compose(hass, demo_entry, "thermostat", THERMOSTAT)

    result = await reconfigure(hass, demo_entry, None)
    assert result["step_id"] == "reconfigure"
    suggested = {
        str(key): (key.description or {}).get("suggested_value")
        for key in result["data_schema"].schema
    }
    assert suggested["setpoint"] == "heating.livingsetpoint"
    assert suggested["name"] == "Living room thermostat"

    result = dict(
        await hass.config_entries.subentries.async_configure(
            result["flow_id"], {**THERMOSTAT, "name": "  "}
        )
    )
    assert result["errors"] == {"name": "name_missing"}
    result = dict(
        await hass.config_entries.subentries.async_configure(
            result["flow_id"],
            {**THERMOSTAT, "name": "Bedroom", "setpoint": "heating.bedroomsetpoint"},
        )
    )
    await hass.async_block_till_done()
    assert result["reason"] == "reconfigure_successful"

    climate = composed_entity(hass, "climate", demo_entry)
    await hass.services.async_call(
        "climate",
        "set_temperature",
        {"entity_id": climate, ATTR_TEMPERATURE: 19.0},
        blocking=True,
    )
    assert simulator.get_value("Heating.bedroomSetpoint.value") == 19.0
    assert hass.states.get(climate).name == "Bedroom"


def without_living_setpoint(simulator: Simulator) -> Program:
    """The demo, downloaded again without the living room's setpoint."""
    source = simulator.program.to_mapping()
    del source["variables"]["Heating"]["variables"]["livingSetpoint"]
    return Program.from_mapping(source)


async def test_a_vanished_point_breaks_the_device_until_it_is_reconfigured(
    hass: HomeAssistant,
    simulator: Simulator,
    demo_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """A program without the setpoint: unavailable, and a repair issue names it."""
    await compose(hass, demo_entry, "thermostat", THERMOSTAT)
    climate = composed_entity(hass, "climate", demo_entry)
    (subentry_id,) = demo_entry.subentries
    issue_id = f"composition_broken_{demo_entry.entry_id}_{subentry_id}"

    simulator.load_program(without_living_setpoint(simulator))
    await poll(hass, freezer, 60)

    assert hass.states.get(climate).state == STATE_UNAVAILABLE
    issue = ir.async_get(hass).async_get_issue(DOMAIN, issue_id)
    assert issue is not None
    assert issue.translation_placeholders is not None
    # The role and the button as the form names them (Home Assistant in English).
    assert issue.translation_placeholders["role"] == "Target temperature (setpoint)"
    assert issue.translation_placeholders["change"] == "Change the thermostat"
    assert issue.translation_placeholders["point"] == "heating.livingsetpoint"
    assert issue.translation_placeholders["name"] == "Living room thermostat"
    assert er.async_get(hass).async_get(climate) is not None

    await reconfigure(
        hass, demo_entry, {**THERMOSTAT, "setpoint": "heating.bedroomsetpoint"}
    )

    assert ir.async_get(hass).async_get_issue(DOMAIN, issue_id) is None
    assert hass.states.get(climate).state != STATE_UNAVAILABLE


async def test_a_device_whose_point_comes_back_works_again(
    hass: HomeAssistant,
    simulator: Simulator,
    demo_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """The old program downloaded again: the same entity works, the issue goes."""
    await compose(hass, demo_entry, "thermostat", THERMOSTAT)
    climate = composed_entity(hass, "climate", demo_entry)
    original = simulator.program
    simulator.load_program(without_living_setpoint(simulator))
    await poll(hass, freezer, 60)
    assert hass.states.get(climate).state == STATE_UNAVAILABLE

    simulator.load_program(original)
    await poll(hass, freezer, 60)

    assert hass.states.get(climate).state != STATE_UNAVAILABLE
    assert not [
        issue_id
        for (domain, issue_id) in ir.async_get(hass).issues
        if domain == DOMAIN and issue_id.startswith("composition_broken")
    ]


async def test_removing_the_subentry_removes_the_device(
    hass: HomeAssistant, demo_entry: MockConfigEntry
) -> None:
    """Deleting the composed device takes its entity and device away."""
    await compose(hass, demo_entry, "thermostat", THERMOSTAT)
    climate = composed_entity(hass, "climate", demo_entry)
    (subentry_id,) = demo_entry.subentries

    hass.config_entries.async_remove_subentry(demo_entry, subentry_id)
    await hass.async_block_till_done()

    assert er.async_get(hass).async_get(climate) is None
    assert hass.states.get(climate) is None
    assert demo_entry.runtime_data.data.devices.keys().isdisjoint(
        {f"composed:{subentry_id}"}
    )


TRANSLATIONS: Final = (
    Path(__file__).parents[4] / "custom_components" / DOMAIN / "translations"
)


def strings(language: str) -> dict[str, Any]:
    """The integration's texts in a language, as the file holds them."""
    loaded: dict[str, Any] = json.loads(
        (TRANSLATIONS / f"{language}.json").read_text(encoding="utf-8")
    )
    return loaded


def texts_of(tree: Mapping[str, Any]) -> Iterator[str]:
    """Every text of a translation tree."""
    for value in tree.values():
        if isinstance(value, Mapping):
            yield from texts_of(value)
        else:
            yield value


def with_living_setpoint(
    simulator: Simulator, change: Callable[[dict[str, Any]], object]
) -> Program:
    """The demo downloaded again with its heating variables changed."""
    source = simulator.program.to_mapping()
    change(source["variables"]["Heating"]["variables"])
    return Program.from_mapping(source)


BROKEN_SETPOINTS: Final[Mapping[str, Callable[[dict[str, Any]], object]]] = {
    "composition_missing_point": lambda heating: heating.pop("livingSetpoint"),
    "composition_not_writable": lambda heating: heating["livingSetpoint"]["value"][
        "attr"
    ].update(readOnly=True),
    "composition_wrong_kind": lambda heating: heating["livingSetpoint"].update(
        type="BOOL", value=True
    ),
}
"""How a new program breaks the thermostat's setpoint, by the issue's text."""

FILLED_BY_US: Final = ("role", "change")
"""What the issue fills in from the integration's texts (the rest is the user's
and the program's own: the device's and the entry's names, the variable)."""


async def shown_issue(hass: HomeAssistant, issue: ir.IssueEntry, language: str) -> str:
    """The issue's description as the frontend shows it in a language."""
    texts = await translation.async_get_translations(hass, language, "issues", {DOMAIN})
    key = f"component.{DOMAIN}.issues.{issue.translation_key}.description"
    return texts[key].format(**(issue.translation_placeholders or {}))


@pytest.mark.parametrize("text", BROKEN_SETPOINTS)
async def test_a_broken_device_is_told_in_czech_in_a_czech_home_assistant(
    hass: HomeAssistant,
    simulator: Simulator,
    demo_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
    text: str,
) -> None:
    """Home Assistant in Czech: the repair says what broke in a text of its own,
    and names the role and the button as the Czech form does; no English and no
    raw key is filled in."""
    hass.config.language = "cs"
    await compose(hass, demo_entry, "thermostat", THERMOSTAT)
    (subentry_id,) = demo_entry.subentries

    simulator.load_program(with_living_setpoint(simulator, BROKEN_SETPOINTS[text]))
    await poll(hass, freezer, 60)

    issue = ir.async_get(hass).async_get_issue(
        DOMAIN, f"composition_broken_{demo_entry.entry_id}_{subentry_id}"
    )
    assert issue is not None
    assert issue.translation_key == text
    placeholders = issue.translation_placeholders or {}
    form = strings("cs")["config_subentries"]["thermostat"]
    assert placeholders["role"] == form["step"]["reconfigure"]["data"]["setpoint"]
    assert placeholders["change"] == form["initiate_flow"]["reconfigure"]
    czech, english = set(texts_of(strings("cs"))), set(texts_of(strings("en")))
    for name in FILLED_BY_US:
        assert placeholders[name] in czech - english, (name, placeholders[name])
    shown = await shown_issue(hass, issue, "cs")
    assert "{" not in shown
    assert not re.search(r"\bsetpoint\b", shown), shown
    assert placeholders["point"] == "heating.livingsetpoint"


async def test_a_device_this_version_cannot_make_gets_the_general_text(
    hass: HomeAssistant, demo_entry: MockConfigEntry
) -> None:
    """A device composed with a role this version lacks (a downgrade): the
    general text, which names no role, in Czech as in English."""
    hass.config.language = "cs"
    hass.config_entries.async_add_subentry(
        demo_entry,
        ConfigSubentry(
            data=MappingProxyType(
                {
                    "kind": "climate",
                    "roles": {**THERMOSTAT, "humidity": "rooms.livinghumidity"},
                }
            ),
            subentry_type="thermostat",
            title="Living room thermostat",
            unique_id=None,
        ),
    )
    await hass.async_block_till_done()

    (subentry_id,) = demo_entry.subentries
    issue = ir.async_get(hass).async_get_issue(
        DOMAIN, f"composition_broken_{demo_entry.entry_id}_{subentry_id}"
    )
    assert issue is not None
    assert issue.translation_key == "composition_broken"
    shown = await shown_issue(hass, issue, "cs")
    assert "Living room thermostat" in shown
    assert "humidity" not in shown


def test_every_role_a_broken_device_names_has_a_label_in_each_language() -> None:
    """The role filled in is always its form's label, never its key; each
    problem's text is there in each language."""
    for language in ("en", "cs"):
        texts = strings(language)
        for subentry_type, kind in COMPOSED_KINDS.items():
            form = texts["config_subentries"][subentry_type]
            assert form["initiate_flow"]["reconfigure"]
            labels = form["step"]["reconfigure"]["data"]
            for spec in COMPOSITIONS[kind].roles:
                assert labels[spec.role.value], (language, subentry_type, spec.role)
        for key in COMPOSITION_TEXTS.values():
            assert "{role}" in texts["issues"][key]["description"], (language, key)
