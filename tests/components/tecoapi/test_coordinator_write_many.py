"""A device's command is one batch: ``coordinator.async_write_many``.

Every value of the batch is checked before anything is sent: a refused one is
the translated validation error naming the refused point, and neither the PLC
nor Home Assistant changes. The values of a batch the PLC took are shown at
once. A failure on the wire is a ``HomeAssistantError``; rejected credentials
start the reauthentication, as every write's. Against the simulated PLC over
HTTP (TecoApi: one SetObject of the batch's members, one GetObject back).
"""

from typing import Any, Final

from homeassistant.config_entries import SOURCE_REAUTH
from homeassistant.core import HomeAssistant
from homeassistant.exceptions import HomeAssistantError, ServiceValidationError
import pytest

from custom_components.tecoapi.const import DOMAIN
from custom_components.tecoapi.coordinator import PlcCoordinator
from tests.components.tecoapi.conftest import make_entry, setup_entry
from tests.simulator import Simulator

LIVING: Final = "heating.livingsetpoint"
BEDROOM: Final = "heating.bedroomsetpoint"
MESSAGE: Final = "displaymessage"
ALARM: Final = "alarmarmed"
LIVING_ENTITY: Final = "number.heating_living_room_setpoint"
BEDROOM_ENTITY: Final = "number.heating_bedroom_setpoint"
VARIABLES: Final = {
    LIVING: "Heating.livingSetpoint.value",
    BEDROOM: "Heating.bedroomSetpoint.value",
    MESSAGE: "displayMessage.value",
    ALARM: "alarmArmed",
}
WRITES: Final = frozenset({"SetObject", "PutObject"})


async def _coordinator(hass: HomeAssistant, plc: Simulator) -> PlcCoordinator:
    entry = await setup_entry(hass, make_entry(plc))
    coordinator: PlcCoordinator = entry.runtime_data
    return coordinator


def _held(plc: Simulator, *keys: str) -> list[Any]:
    return [plc.get_value(VARIABLES[key]) for key in keys]


def _writes(plc: Simulator) -> list[str]:
    return [record.service for record in plc.requests if record.service in WRITES]


async def test_a_batch_is_written_in_one_request_and_shown(
    hass: HomeAssistant, plc: Simulator
) -> None:
    coordinator = await _coordinator(hass, plc)
    plc.clear_requests()

    await coordinator.async_write_many({LIVING: 24.5, BEDROOM: 17.5})

    assert _held(plc, LIVING, BEDROOM) == [24.5, 17.5]
    assert _writes(plc) == ["SetObject"]
    assert hass.states.get(LIVING_ENTITY).state == "24.5"
    assert hass.states.get(BEDROOM_ENTITY).state == "17.5"
    assert coordinator.data.values[LIVING] == 24.5
    assert coordinator.data.values[BEDROOM] == 17.5


async def test_an_empty_batch_sends_nothing(
    hass: HomeAssistant, plc: Simulator
) -> None:
    coordinator = await _coordinator(hass, plc)
    plc.clear_requests()

    await coordinator.async_write_many({})

    assert plc.requests == []


@pytest.mark.parametrize(
    ("batch", "refused", "translation_key"),
    [
        ({LIVING: 24.5, BEDROOM: 99.0}, BEDROOM, "out_of_range"),
        ({BEDROOM: 20.0, LIVING: "warm"}, LIVING, "invalid_value"),
        ({LIVING: 24.5, MESSAGE: "Příliš žluťoučký kůň"}, MESSAGE, "not_ascii"),
        ({LIVING: 24.5, ALARM: "maybe"}, ALARM, "invalid_value"),
    ],
    ids=["out of range", "wrong kind", "not ascii", "a variable's own path"],
)
async def test_a_refused_value_names_its_point_and_changes_nothing(
    hass: HomeAssistant,
    plc: Simulator,
    batch: dict[str, Any],
    refused: str,
    translation_key: str,
) -> None:
    coordinator = await _coordinator(hass, plc)
    held = _held(plc, *batch)
    shown = hass.states.get(LIVING_ENTITY).state
    plc.clear_requests()

    with pytest.raises(ServiceValidationError) as raised:
        await coordinator.async_write_many(batch)

    assert raised.value.translation_domain == DOMAIN
    assert raised.value.translation_key == translation_key
    placeholders = raised.value.translation_placeholders or {}
    assert placeholders["path"] == coordinator.data.catalogue.points[refused].path
    assert placeholders["value"] == str(batch[refused])
    assert plc.requests == []
    assert _held(plc, *batch) == held
    assert hass.states.get(LIVING_ENTITY).state == shown


async def test_a_value_the_plc_refuses_names_its_point(
    hass: HomeAssistant, plc: Simulator
) -> None:
    """The PLC's refusal names a member of the point (``.value``): its point is told."""
    coordinator = await _coordinator(hass, plc)
    too_long = "x" * 100  # displayMessage is a STRING[64]: the PLC refuses it
    held = plc.get_value(VARIABLES[MESSAGE])

    with pytest.raises(ServiceValidationError) as raised:
        await coordinator.async_write_many({LIVING: 24.5, MESSAGE: too_long})

    assert raised.value.translation_key == "value_rejected"
    placeholders = raised.value.translation_placeholders or {}
    assert placeholders["path"] == coordinator.data.catalogue.points[MESSAGE].path
    assert plc.get_value(VARIABLES[MESSAGE]) == held


@pytest.mark.usefixtures("short_timeout")
async def test_a_failure_on_the_wire_is_a_plc_error(
    hass: HomeAssistant, plc: Simulator
) -> None:
    coordinator = await _coordinator(hass, plc)
    held = _held(plc, LIVING, BEDROOM)
    plc.faults.http_500 = True

    with pytest.raises(HomeAssistantError) as raised:
        await coordinator.async_write_many({LIVING: 24.5, BEDROOM: 17.5})

    assert not isinstance(raised.value, ServiceValidationError)
    assert raised.value.translation_key == "write_failed"
    # Nothing names a point: the batch's first is told.
    placeholders = raised.value.translation_placeholders or {}
    assert placeholders["path"] == coordinator.data.catalogue.points[LIVING].path
    assert _held(plc, LIVING, BEDROOM) == held
    assert coordinator.source.statistics.failed_writes == 1


async def test_rejected_credentials_start_the_reauthentication(
    hass: HomeAssistant, plc: Simulator
) -> None:
    coordinator = await _coordinator(hass, plc)
    plc.password = "changed-on-the-plc"

    with pytest.raises(HomeAssistantError) as raised:
        await coordinator.async_write_many({LIVING: 24.5, BEDROOM: 17.5})

    assert raised.value.translation_key == "auth_failed"
    await hass.async_block_till_done()
    flows = hass.config_entries.flow.async_progress_by_handler(DOMAIN)
    assert [flow["context"]["source"] for flow in flows] == [SOURCE_REAUTH]
