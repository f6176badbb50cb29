"""Texts: writable string points."""

import logging
from typing import Any

from homeassistant.components.number import DOMAIN as NUMBER_DOMAIN
from homeassistant.components.text import (
    ATTR_MAX,
    ATTR_PATTERN,
    ATTR_VALUE,
    DOMAIN as TEXT_DOMAIN,
    SERVICE_SET_VALUE,
)
from homeassistant.const import ATTR_ENTITY_ID
from homeassistant.core import HomeAssistant
from homeassistant.exceptions import ServiceValidationError
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry
from pytest_homeassistant_custom_component.typing import WebSocketGenerator
from syrupy.assertion import SnapshotAssertion

from custom_components.tecoapi.const import DOMAIN
from tests.components.tecoapi import memory_house
from tests.components.tecoapi.conftest import snapshot_entities
from tests.fake_source import MemoryDevice
from tests.simulator import Simulator

MESSAGE = "text.tecomat_cp_2080_hall_display_message"


@pytest.mark.primary_only
@pytest.mark.parametrize("program_entry", ["demo"], indirect=True)
@pytest.mark.usefixtures("entity_registry_enabled_by_default")
async def test_texts(
    hass: HomeAssistant, program_entry: MockConfigEntry, snapshot: SnapshotAssertion
) -> None:
    """Every text of the demo (the manual has none): registry entry and state."""
    await snapshot_entities(hass, snapshot, program_entry, "text")


async def set_text(hass: HomeAssistant, value: str) -> None:
    """Call text.set_value on the hall display message."""
    await hass.services.async_call(
        TEXT_DOMAIN,
        SERVICE_SET_VALUE,
        {ATTR_ENTITY_ID: MESSAGE, ATTR_VALUE: value},
        blocking=True,
    )


@pytest.mark.usefixtures("demo_entry")
async def test_setting_text_writes_the_plc(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    """A new message reaches the PLC, quotes and ampersands intact."""
    attributes = hass.states.get(MESSAGE).attributes
    assert attributes[ATTR_MAX] == 255
    # No pattern: Home Assistant would show its regular expression to the user.
    assert attributes[ATTR_PATTERN] is None

    await set_text(hass, 'Dinner at 7 & "bring wine"')

    assert simulator.get_value("displayMessage.value") == 'Dinner at 7 & "bring wine"'
    assert hass.states.get(MESSAGE).state == 'Dinner at 7 & "bring wine"'


@pytest.mark.usefixtures("demo_entry")
async def test_a_text_longer_than_its_string_is_refused_saying_how_long(
    hass: HomeAssistant, simulator: Simulator
) -> None:
    """The message is a STRING[64]; TecoApi does not say so before a write.

    GetList names roots, GetObject answers values and ``attr`` has no length:
    the entity allows the 255 characters any STRING may have. The PLC refuses
    80 (400.015, naming the type); the user is told the variable's length and
    the text's, the text said once.
    """
    assert hass.states.get(MESSAGE).attributes[ATTR_MAX] == 255
    text = "x" * 80

    with pytest.raises(ServiceValidationError) as raised:
        await set_text(hass, text)

    assert raised.value.translation_key == "value_rejected"
    assert raised.value.translation_placeholders["message"] == (
        "the variable is a STRING[64], at most 64 characters; the text has 80"
    )
    assert str(raised.value).count(text) == 1
    assert simulator.get_value("displayMessage.value") == "Welcome home"
    await set_text(hass, "y" * 64)
    assert simulator.get_value("displayMessage.value") == "y" * 64


@pytest.mark.usefixtures("demo_entry")
async def test_non_ascii_text_is_refused(
    hass: HomeAssistant, simulator: Simulator, caplog: pytest.LogCaptureFixture
) -> None:
    """Czech text: a translated error says the PLC takes ASCII only; nothing is sent.

    Nothing is logged at error level either (a refused value is the user's to fix).
    """
    simulator.clear_requests()

    with pytest.raises(ServiceValidationError) as raised:
        await set_text(hass, "Večeře je hotová")

    assert raised.value.translation_domain == DOMAIN
    assert raised.value.translation_key == "not_ascii"
    assert "ASCII" in str(raised.value)
    assert "Večeře je hotová" in str(raised.value)
    assert simulator.requests == []
    assert simulator.get_value("displayMessage.value") == "Welcome home"
    assert hass.states.get(MESSAGE).state == "Welcome home"
    assert [
        record.getMessage()
        for record in caplog.records
        if record.levelno >= logging.ERROR
    ] == []


async def test_coordinator_refuses_non_ascii_too(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    """The write path validates on its own: a translated validation error."""
    with pytest.raises(ServiceValidationError) as raised:
        await demo_entry.runtime_data.async_write("displaymessage", "Večeře")

    assert raised.value.translation_domain == DOMAIN
    assert raised.value.translation_key == "not_ascii"
    assert simulator.get_value("displayMessage.value") == "Welcome home"


@pytest.mark.usefixtures("demo_entry")
async def test_non_ascii_text_from_the_frontend_is_refused_translated(
    hass: HomeAssistant,
    hass_ws_client: WebSocketGenerator,
    simulator: Simulator,
    caplog: pytest.LogCaptureFixture,
) -> None:
    """The frontend's path (a websocket call_service): the user reads why, translated.

    How Home Assistant's websocket API logs a refused call is Home Assistant's
    to decide: this integration's refusal is logged as Home Assistant logs its
    own (a number set beyond its range, refused by the number platform), not
    lowered or dropped by a filter of ours.
    """
    client = await hass_ws_client(hass)
    number = next(
        state
        for state in hass.states.async_all(NUMBER_DOMAIN)
        if state.attributes.get(ATTR_MAX) is not None
    )

    async def call(domain: str, target: str, value: Any) -> dict[str, Any]:
        caplog.clear()
        await client.send_json_auto_id(
            {
                "type": "call_service",
                "domain": domain,
                "service": SERVICE_SET_VALUE,
                "target": {ATTR_ENTITY_ID: target},
                "service_data": {ATTR_VALUE: value},
            }
        )
        answer: dict[str, Any] = await client.receive_json()
        assert not answer["success"]
        assert answer["error"]["code"] == "service_validation_error"
        return answer["error"]

    def websocket_levels() -> list[int]:
        return [
            record.levelno
            for record in caplog.records
            if record.name.startswith("homeassistant.components.websocket_api")
        ]

    theirs = await call(
        NUMBER_DOMAIN, number.entity_id, number.attributes[ATTR_MAX] + 1
    )
    assert theirs["translation_domain"] == NUMBER_DOMAIN
    their_levels = websocket_levels()
    assert their_levels

    ours = await call(TEXT_DOMAIN, MESSAGE, "Večeře je hotová")

    assert ours["translation_domain"] == DOMAIN
    assert ours["translation_key"] == "not_ascii"
    assert ours["translation_placeholders"]["value"] == "Večeře je hotová"
    assert ours["message"]  # the frontend shows the translated text
    assert simulator.get_value("displayMessage.value") == "Welcome home"
    assert websocket_levels() == their_levels


# --- the memory house (memory_house.py): through the in-memory source ---------


async def test_text_keeps_to_its_length(
    hass: HomeAssistant, house: MemoryDevice
) -> None:
    assert memory_house.state(hass, "text", "display_text").state == "Hello"
    await memory_house.call(
        hass, "text", "set_value", "display_text", value="Dobrý den"
    )
    assert house.values["m6"] == "Dobrý den"
    # The text entity's length is the type's: Home Assistant refuses before
    # the write path is asked.
    assert memory_house.state(hass, "text", "display_text").attributes["max"] == 16
    with pytest.raises(ValueError, match="too long"):
        await memory_house.call(
            hass, "text", "set_value", "display_text", value="x" * 17
        )
    assert house.values["m6"] == "Dobrý den"
