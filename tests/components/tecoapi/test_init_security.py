"""Security: credentials never shown, names and values never alter a request."""

import base64
from collections.abc import AsyncIterator, Iterable
import json
import logging
from typing import Any, Final
from urllib.parse import unquote

from freezegun.api import FrozenDateTimeFactory
from homeassistant.components.text import (
    ATTR_VALUE,
    DOMAIN as TEXT_DOMAIN,
    SERVICE_SET_VALUE,
)
from homeassistant.config_entries import SOURCE_REAUTH, ConfigEntryState
from homeassistant.const import (
    ATTR_CONFIG_ENTRY_ID,
    ATTR_ENTITY_ID,
    CONF_PASSWORD,
    CONF_USERNAME,
)
from homeassistant.core import HomeAssistant
from homeassistant.exceptions import HomeAssistantError, ServiceValidationError
from homeassistant.helpers import issue_registry as ir
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.tecoapi.const import DOMAIN
from custom_components.tecoapi.diagnostics import async_get_config_entry_diagnostics
from tests.components.tecoapi.conftest import (
    FROZEN_TIME,
    add_tecoapi,
    entity_id_of,
    make_entry,
    poll,
    setup_entry,
)
from tests.conftest import SIM_PASSWORD, SIM_USERNAME
from tests.simulator import Program, Simulator

NEW_PASSWORD: Final = "n3w-Pa55-after-revoke"
SETPOINT = "number.heating_living_room_setpoint"


def basic_token(username: str, password: str) -> str:
    """The credentials as an HTTP Basic ``Authorization`` token."""
    return base64.b64encode(f"{username}:{password}".encode()).decode()


SECRETS: Final = (
    SIM_PASSWORD,
    NEW_PASSWORD,
    f"{SIM_USERNAME}:{SIM_PASSWORD}",
    f"{SIM_USERNAME}:{NEW_PASSWORD}",
    basic_token(SIM_USERNAME, SIM_PASSWORD),
    basic_token(SIM_USERNAME, NEW_PASSWORD),
)


def leaks(texts: Iterable[str]) -> list[str]:
    """Every (secret, text start) where a text holds a credential."""
    return [
        f"{secret!r} in {text[:80]!r}"
        for text in texts
        for secret in SECRETS
        if secret in text
    ]


def test_the_scan_finds_a_credential() -> None:
    """The scan is not blind: each form of the credentials is found."""
    header = f"Authorization: Basic {basic_token(SIM_USERNAME, SIM_PASSWORD)}"
    assert len(leaks([header, f"password={NEW_PASSWORD}"])) == 2
    assert leaks(["admin", "Digest realm=TecoApi"]) == []


def error_texts(error: BaseException) -> list[str]:
    """What an exception shows: its text, repr, placeholders, and its causes'."""
    texts: list[str] = []
    current: BaseException | None = error
    while current is not None:
        texts += [str(current), repr(current)]
        placeholders = getattr(current, "translation_placeholders", None)
        if placeholders:
            texts.append(json.dumps(placeholders))
        current = current.__cause__ or current.__context__
    return texts


@pytest.fixture
async def plc(
    request: pytest.FixtureRequest, socket_enabled: None
) -> AsyncIterator[Simulator]:
    """The demo PLC with the authentication the test asks for."""
    sim = Simulator(
        "demo", username=SIM_USERNAME, password=SIM_PASSWORD, auth=request.param
    )
    await sim.start()
    try:
        yield sim
    finally:
        await sim.stop()


@pytest.mark.parametrize("plc", ["digest", "basic"], indirect=True)
async def test_a_whole_session_never_shows_the_credentials(
    hass: HomeAssistant,
    plc: Simulator,
    freezer: FrozenDateTimeFactory,
    caplog: pytest.LogCaptureFixture,
) -> None:
    """Setup, polls, writes, failures, an action, diagnostics, reauth, unload at DEBUG."""
    caplog.set_level(logging.DEBUG)  # the root logger: aiohttp's and HA's included
    logging.getLogger("aiohttp").setLevel(logging.DEBUG)
    freezer.move_to(FROZEN_TIME)
    texts: list[str] = []

    # Set up from the UI, as a user would.
    result = await add_tecoapi(hass, plc.host)
    await hass.async_block_till_done()
    entry = result["result"]
    assert entry.state is ConfigEntryState.LOADED
    assert plc.requests[-1].authorized
    texts += [entry.title, json.dumps(result["description_placeholders"])]

    # Polls, a write, a failed write, a failed poll and its recovery.
    await poll(hass, freezer)
    await hass.services.async_call(
        "number", "set_value", {ATTR_ENTITY_ID: SETPOINT, "value": 22.0}, blocking=True
    )
    plc.faults.http_500 = True
    with pytest.raises(HomeAssistantError) as failed_write:
        await hass.services.async_call(
            "number",
            "set_value",
            {ATTR_ENTITY_ID: SETPOINT, "value": 23.0},
            blocking=True,
        )
    texts += error_texts(failed_write.value)
    plc.faults.http_500 = False
    plc.faults.drop_connection = True
    await poll(hass, freezer)
    plc.faults.clear()
    await poll(hass, freezer)

    # An action, one that fails, and the diagnostics download.
    response = await hass.services.async_call(
        DOMAIN,
        "read_variable",
        {ATTR_CONFIG_ENTRY_ID: entry.entry_id, "path": "outsideTemp"},
        blocking=True,
        return_response=True,
    )
    texts.append(json.dumps(response))
    plc.faults.http_500 = True
    with pytest.raises(HomeAssistantError) as failed_read:
        await hass.services.async_call(
            DOMAIN,
            "read_variable",
            {ATTR_CONFIG_ENTRY_ID: entry.entry_id, "path": "outsideTemp"},
            blocking=True,
            return_response=True,
        )
    texts += error_texts(failed_read.value)
    plc.faults.clear()
    texts.append(
        json.dumps(await async_get_config_entry_diagnostics(hass, entry), default=str)
    )

    # The password is changed on the PLC: reauth, and a new password.
    plc.password = NEW_PASSWORD
    await poll(hass, freezer)
    assert entry.state is ConfigEntryState.LOADED
    texts += error_texts(entry.runtime_data.last_exception)
    flows = [
        flow
        for flow in hass.config_entries.flow.async_progress_by_handler(DOMAIN)
        if flow["context"]["source"] == SOURCE_REAUTH
    ]
    assert len(flows) == 1
    texts.append(json.dumps(flows, default=str))
    result = await hass.config_entries.flow.async_configure(
        flows[0]["flow_id"],
        {CONF_USERNAME: SIM_USERNAME, CONF_PASSWORD: NEW_PASSWORD},
    )
    assert result["reason"] == "reauth_successful"
    await hass.async_block_till_done()
    assert entry.state is ConfigEntryState.LOADED
    await poll(hass, freezer)
    assert plc.requests[-1].authorized

    assert await hass.config_entries.async_unload(entry.entry_id)
    await hass.async_block_till_done()

    texts += [entry.title, str(entry.reason)]
    texts += [repr(state) for state in hass.states.async_all()]
    texts += [
        json.dumps(issue.to_json(), default=str)
        for issue in ir.async_get(hass).issues.values()
    ]
    texts += [
        record.getMessage() + (record.exc_text or "") for record in caplog.records
    ]
    texts.append(caplog.text)
    # The log did see the session: the client's requests, the reauth.
    assert "rejected the stored credentials" in caplog.text
    assert leaks(texts) == []


# --- names and values cannot alter a request ----------------------------------------

TRICKY: Final = 'a&b=c #d "e" f+g%20'
NON_ASCII: Final = "Teplota ve sklepě"
NOTE_ID = "SEC 1_cellar.note"


@pytest.fixture
async def tricky_entry(
    hass: HomeAssistant, socket_enabled: None
) -> AsyncIterator[tuple[Simulator, MockConfigEntry]]:
    """A PLC whose program holds texts with characters that mean something in URLs."""
    source = Program.from_mapping(
        {
            "plc": {
                "family": "Fx2",
                "type": "CP-2080",
                "serialNumber": "SEC 1",
                "version": "Fx2 CP2080I v1.1",
                "mac": "00-0A-14-00-00-01",
            },
            "program": {"name": "TRICKY", "compiled": "2026-03-14T09:00:00.000Z"},
            "variables": {
                "Cellar": {
                    "program": "prgCellar",
                    "variables": {
                        "note": {
                            "type": "T_ApiObject OF STRING[80]",
                            "value": {
                                "value": TRICKY,
                                "attr": {
                                    "enable": True,
                                    "visibility": True,
                                    "readOnly": False,
                                    "title": "Cellar note",
                                },
                            },
                        },
                        "label": {"type": "STRING[80]", "value": "a=b&c=d"},
                        "setpoint": {"type": "REAL", "value": 12.5},
                    },
                },
                "units": {
                    "type": "T_ApiObject",
                    "value": {
                        "value": 3.5,
                        "attr": {
                            "enable": True,
                            "visibility": True,
                            "readOnly": True,
                            "title": "Teplota & vlhkost #1",
                            "units": "°C",
                        },
                    },
                },
            },
        }
    )
    sim = Simulator(source, username=SIM_USERNAME, password=SIM_PASSWORD)
    await sim.start()
    try:
        yield sim, await setup_entry(hass, make_entry(sim))
    finally:
        await sim.stop()


def values_of(sim: Simulator) -> dict[str, Any]:
    """Every variable the tests could change by accident."""
    return {
        path: sim.get_value(path)
        for path in (
            "Cellar.note.value",
            "Cellar.label",
            "Cellar.setpoint",
            "units.value",
            "units.attr.title",
        )
    }


def query_names(query: str) -> list[str]:
    """The names of a GetObject/SetObject query as the PLC splits them."""
    return [unquote(piece.partition("=")[0]) for piece in query.split("&")]


async def test_tricky_texts_are_read_exactly(
    hass: HomeAssistant, tricky_entry: tuple[Simulator, MockConfigEntry]
) -> None:
    """Values and titles with &, =, #, quotes, spaces and non-ASCII arrive intact."""
    state = hass.states.get(entity_id_of(hass, "text", NOTE_ID))
    assert state.state == TRICKY
    units = hass.states.get("sensor.tecomat_cp_2080_teplota_vlhkost_1")
    assert units.name == "Tecomat CP-2080 Teplota & vlhkost #1"
    assert units.attributes["unit_of_measurement"] == "°C"


@pytest.mark.parametrize(
    "text", ["x&Cellar.setpoint=99", 'say "hi" # now', "= & = &", "100% + 1"]
)
async def test_written_texts_stay_one_parameter(
    hass: HomeAssistant,
    tricky_entry: tuple[Simulator, MockConfigEntry],
    text: str,
) -> None:
    """A text entity writes exactly its own variable, whatever the text holds."""
    sim, _entry = tricky_entry
    note = entity_id_of(hass, "text", NOTE_ID)
    expected = values_of(sim) | {"Cellar.note.value": text}
    sim.clear_requests()

    await hass.services.async_call(
        TEXT_DOMAIN,
        SERVICE_SET_VALUE,
        {ATTR_ENTITY_ID: note, ATTR_VALUE: text},
        blocking=True,
    )

    assert values_of(sim) == expected
    assert hass.states.get(note).state == text
    write = sim.requests[0]
    assert write.service == "SetObject"
    assert query_names(write.query) == ["Cellar.note.value"]


async def test_non_ascii_is_refused_before_sending(
    hass: HomeAssistant, tricky_entry: tuple[Simulator, MockConfigEntry]
) -> None:
    """The PLC takes ASCII only: the action refuses, nothing reaches the PLC."""
    sim, entry = tricky_entry
    before = values_of(sim)
    sim.clear_requests()

    with pytest.raises(ServiceValidationError) as raised:
        await hass.services.async_call(
            DOMAIN,
            "write_variable",
            {
                ATTR_CONFIG_ENTRY_ID: entry.entry_id,
                "path": "Cellar.label",
                "value": json.dumps(NON_ASCII),
            },
            blocking=True,
        )

    assert raised.value.translation_key == "not_ascii"
    assert sim.requests == []
    assert values_of(sim) == before


async def test_action_writes_tricky_text_to_one_variable(
    hass: HomeAssistant, tricky_entry: tuple[Simulator, MockConfigEntry]
) -> None:
    """write_variable: a text full of URL syntax lands in the named variable only."""
    sim, entry = tricky_entry
    expected = values_of(sim) | {"Cellar.label": "k=v&Cellar.setpoint=1#x"}
    sim.clear_requests()

    await hass.services.async_call(
        DOMAIN,
        "write_variable",
        {
            ATTR_CONFIG_ENTRY_ID: entry.entry_id,
            "path": "Cellar.label",
            "value": '"k=v&Cellar.setpoint=1#x"',
        },
        blocking=True,
    )

    assert values_of(sim) == expected
    assert query_names(sim.requests[0].query) == ["Cellar.label"]


@pytest.mark.parametrize(
    "path",
    [
        "Cellar.label&Cellar.setpoint",
        "Cellar.label#Cellar.setpoint",
        "Cellar.setpoint=5",
        'Cellar."label"',
        "Cellar.label Cellar.setpoint",
        "Cellar.štítek",
    ],
)
async def test_crafted_paths_name_one_variable(
    hass: HomeAssistant,
    tricky_entry: tuple[Simulator, MockConfigEntry],
    path: str,
) -> None:
    """read_variable with URL syntax in the path: one name, which the PLC rejects."""
    sim, entry = tricky_entry
    before = values_of(sim)
    sim.clear_requests()

    with pytest.raises(ServiceValidationError) as raised:
        await hass.services.async_call(
            DOMAIN,
            "read_variable",
            {ATTR_CONFIG_ENTRY_ID: entry.entry_id, "path": path},
            blocking=True,
            return_response=True,
        )

    assert raised.value.translation_key == "variable_not_found"
    assert [request.service for request in sim.requests] == ["GetObject"]
    assert sim.requests[0].status == 400
    assert query_names(sim.requests[0].query) == [path]
    assert values_of(sim) == before
