"""The actions tecoapi.read_variable and tecoapi.write_variable."""

from typing import Any

from homeassistant.config_entries import SOURCE_REAUTH
from homeassistant.const import ATTR_CONFIG_ENTRY_ID
from homeassistant.core import HomeAssistant, ServiceResponse
from homeassistant.exceptions import HomeAssistantError, ServiceValidationError
from homeassistant.setup import async_setup_component
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.tecoapi.const import DOMAIN
from tests.simulator import Simulator

SETPOINT = "number.heating_living_room_setpoint"


async def read(hass: HomeAssistant, entry_id: str, path: str) -> ServiceResponse:
    """Call tecoapi.read_variable and return its response."""
    return await hass.services.async_call(
        DOMAIN,
        "read_variable",
        {ATTR_CONFIG_ENTRY_ID: entry_id, "path": path},
        blocking=True,
        return_response=True,
    )


async def write(hass: HomeAssistant, entry_id: str, path: str, value: Any) -> None:
    """Call tecoapi.write_variable."""
    await hass.services.async_call(
        DOMAIN,
        "write_variable",
        {ATTR_CONFIG_ENTRY_ID: entry_id, "path": path, "value": value},
        blocking=True,
    )


async def test_actions_exist_without_any_entry(hass: HomeAssistant) -> None:
    """Registered when the integration is set up, before any PLC is."""
    assert await async_setup_component(hass, DOMAIN, {})

    assert hass.services.has_service(DOMAIN, "read_variable")
    assert hass.services.has_service(DOMAIN, "write_variable")


@pytest.mark.parametrize(
    ("path", "value"),
    [
        ("outsideTemp.value", 4.5),
        ("OUTSIDETEMP.VALUE", 4.5),
        ("lights[1].value", True),
        ("Heating.nextService.value", "2026-10-01"),
        ("doorbellCount", 1287),
        (
            "blinds[2]",
            {
                "value": 40,
                "attr": {
                    "enable": True,
                    "visibility": True,
                    "readOnly": False,
                    "title": "Bedroom blind",
                    "minValue": 0.0,
                    "maxValue": 100.0,
                    "units": "%",
                },
            },
        ),
        ("ventilation.filter.lastChange", "2025-11-02"),
    ],
)
async def test_read_variable(
    hass: HomeAssistant, demo_entry: MockConfigEntry, path: str, value: Any
) -> None:
    """Any public variable, in any letter case, as the PLC's JSON."""
    assert await read(hass, demo_entry.entry_id, path) == {
        "path": path,
        "value": value,
    }


async def test_read_a_whole_struct(
    hass: HomeAssistant, demo_entry: MockConfigEntry
) -> None:
    """A T_ApiObject read whole: value and attributes."""
    response = await read(hass, demo_entry.entry_id, "Heating.livingSetpoint")

    assert response is not None
    assert response["value"]["value"] == 21.5
    assert response["value"]["attr"]["title"] == "Living room setpoint"


@pytest.mark.parametrize(
    ("path", "translation_key"),
    [
        ("", "invalid_path"),
        ("  ", "invalid_path"),
        ("Heating..livingSetpoint", "invalid_path"),
        (".outsideTemp", "invalid_path"),
        ("[1]", "invalid_path"),
        ("lights[x]", "invalid_path"),
        ("lights[1", "invalid_path"),
        ("noSuchVariable", "variable_not_found"),
        ("outsideTemp.noSuchMember", "variable_not_found"),
        ("lights[9].value", "variable_not_found"),
        ("a" * 300, "invalid_path"),
    ],
)
async def test_read_bad_paths(
    hass: HomeAssistant,
    simulator: Simulator,
    demo_entry: MockConfigEntry,
    path: str,
    translation_key: str,
) -> None:
    """What is no path is refused here; what the PLC does not have, by the PLC."""
    with pytest.raises(ServiceValidationError) as raised:
        await read(hass, demo_entry.entry_id, path)

    assert raised.value.translation_domain == DOMAIN
    assert raised.value.translation_key == translation_key


async def test_unknown_and_unloaded_entries(
    hass: HomeAssistant, demo_entry: MockConfigEntry
) -> None:
    """An entry ID that is no TecoApi PLC, or a PLC that is not loaded."""
    other = MockConfigEntry(domain="other_integration")
    other.add_to_hass(hass)
    for entry_id in ("no-such-entry", other.entry_id):
        with pytest.raises(ServiceValidationError) as raised:
            await read(hass, entry_id, "outsideTemp")
        assert raised.value.translation_key == "entry_not_found"
        assert raised.value.translation_placeholders == {"entry_id": entry_id}

    await hass.config_entries.async_unload(demo_entry.entry_id)
    for call in (
        read(hass, demo_entry.entry_id, "outsideTemp"),
        write(hass, demo_entry.entry_id, "outsideTemp.value", 1),
    ):
        with pytest.raises(ServiceValidationError) as raised:
            await call
        assert raised.value.translation_key == "entry_not_loaded"


async def test_read_failures_on_the_plc(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    """A PLC error: HomeAssistantError; rejected credentials: also reauth."""
    simulator.faults.http_500 = True
    with pytest.raises(HomeAssistantError) as raised:
        await read(hass, demo_entry.entry_id, "outsideTemp")
    assert not isinstance(raised.value, ServiceValidationError)
    assert raised.value.translation_key == "read_failed"
    assert demo_entry.runtime_data.source.recent_errors[-1].operation == "read"

    simulator.faults.clear()
    simulator.faults.drop_connection = True
    with pytest.raises(HomeAssistantError) as raised:
        await read(hass, demo_entry.entry_id, "outsideTemp")
    assert not isinstance(raised.value, ServiceValidationError)
    assert raised.value.translation_key == "read_failed"

    simulator.faults.clear()
    simulator.password = "revoked"
    with pytest.raises(HomeAssistantError) as raised:
        await read(hass, demo_entry.entry_id, "outsideTemp")
    assert raised.value.translation_key == "auth_failed"
    await hass.async_block_till_done()
    assert [
        flow["context"]["source"]
        for flow in hass.config_entries.flow.async_progress_by_handler(DOMAIN)
    ] == [SOURCE_REAUTH]


async def test_write_a_known_point(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    """A point's path (its own or its .value): written like the entity, shown at once."""
    await write(hass, demo_entry.entry_id, "Heating.livingSetpoint.value", "22.5")

    assert simulator.get_value("Heating.livingSetpoint.value") == 22.5
    assert hass.states.get(SETPOINT).state == "22.5"

    # From YAML a number arrives typed; the object's own path means its value.
    await write(hass, demo_entry.entry_id, "heating.LIVINGSETPOINT", 23)

    assert simulator.get_value("Heating.livingSetpoint.value") == 23.0
    assert hass.states.get(SETPOINT).state == "23.0"

    await write(
        hass, demo_entry.entry_id, "Heating.nightSetback.value", '"23:15:00.000"'
    )
    assert simulator.get_value("Heating.nightSetback.value") == "23:15:00.000"


@pytest.mark.parametrize(
    ("path", "value", "translation_key"),
    [
        ("Heating.livingSetpoint.value", "40", "out_of_range"),
        ("outsideTemp.value", "5", "read_only"),
        ("Heating.livingSetpoint.value", '"warm"', "invalid_value"),
        ("lights[0].value", "1", "invalid_value"),
        ("Heating.livingSetpoint.value", "warm", "invalid_json"),
        ("Heating.livingSetpoint.value", "{", "invalid_json"),
        ("Heating.livingSetpoint.value", "NaN", "invalid_value"),
        ("noSuchVariable", "1", "variable_not_found"),
        ("Heating..x", "1", "invalid_path"),
        ("a" * 70, "1", "invalid_path"),
        ("a" * 300, "1", "value_rejected"),
        ("doorbellCount", "-5", "value_rejected"),
    ],
)
async def test_write_refused(
    hass: HomeAssistant,
    simulator: Simulator,
    demo_entry: MockConfigEntry,
    *,
    path: str,
    value: str,
    translation_key: str,
) -> None:
    """Bad input is a ServiceValidationError, and the PLC keeps its values."""
    before = simulator.get_value("Heating.livingSetpoint.value")

    with pytest.raises(ServiceValidationError) as raised:
        await write(hass, demo_entry.entry_id, path, value)

    assert raised.value.translation_domain == DOMAIN
    assert raised.value.translation_key == translation_key
    assert simulator.get_value("Heating.livingSetpoint.value") == before
    assert simulator.get_value("outsideTemp.value") == 4.5
    assert simulator.get_value("doorbellCount") == 1287
    assert simulator.get_value("lights[0].value") is False


async def test_an_out_of_range_value_is_refused_with_its_translated_message(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    """The refusal carries what the frontend translates: its domain, key and values."""
    with pytest.raises(ServiceValidationError) as raised:
        await write(hass, demo_entry.entry_id, "Heating.livingSetpoint.value", "40")

    assert raised.value.translation_domain == DOMAIN
    assert raised.value.translation_key == "out_of_range"
    assert raised.value.translation_placeholders == {
        "path": "Heating.livingSetpoint.value",
        "value": "40",
        "min_value": "15",
        "max_value": "28",
    }
    # The English text, as the frontend shows it (Home Assistant drops the full stop).
    assert str(raised.value) == (
        "40 is outside the allowed range of Heating.livingSetpoint.value (15 to 28)"
    )
    assert simulator.get_value("Heating.livingSetpoint.value") == 21.5


async def test_write_other_variables(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    """Plain variables and whole structures: the PLC judges them."""
    await write(hass, demo_entry.entry_id, "installerNote", '"Serviced 2026-03"')
    assert simulator.get_value("installerNote") == "Serviced 2026-03"

    simulator.clear_requests()
    await write(
        hass,
        demo_entry.entry_id,
        "ventilation.filter",
        {"lastChange": "2026-03-14"},
    )
    assert simulator.requests[0].service == "PutObject"
    assert simulator.get_value("ventilation.filter.lastChange") == "2026-03-14"
    assert simulator.get_value("ventilation.filter.clogged.value") is False


async def test_write_failures_on_the_plc(
    hass: HomeAssistant, simulator: Simulator, demo_entry: MockConfigEntry
) -> None:
    """A PutObject or SetObject the PLC does not take: HomeAssistantError."""
    simulator.faults.http_500 = True
    for path, value in (
        ("ventilation.filter", {"lastChange": "2026-03-14"}),
        ("installerNote", '"x"'),
    ):
        with pytest.raises(HomeAssistantError) as raised:
            await write(hass, demo_entry.entry_id, path, value)
        assert not isinstance(raised.value, ServiceValidationError)
        assert raised.value.translation_key == "write_failed"
    assert simulator.get_value("ventilation.filter.lastChange") == "2025-11-02"
    assert simulator.get_value("installerNote") == "Serviced by Novak Elektro"

    simulator.faults.clear()
    simulator.faults.drop_connection = True
    for path, value in (
        ("ventilation.filter", {"lastChange": "2026-03-14"}),
        ("installerNote", '"x"'),
    ):
        with pytest.raises(HomeAssistantError) as raised:
            await write(hass, demo_entry.entry_id, path, value)
        assert not isinstance(raised.value, ServiceValidationError)
        assert raised.value.translation_key == "write_failed"

    simulator.faults.clear()
    simulator.password = "revoked"
    with pytest.raises(HomeAssistantError) as raised:
        await write(hass, demo_entry.entry_id, "installerNote", '"x"')
    assert raised.value.translation_key == "auth_failed"


async def test_write_to_a_point_that_is_gone(
    hass: HomeAssistant, demo_entry: MockConfigEntry
) -> None:
    """The write path refuses a key that is no (longer a) point."""
    with pytest.raises(ServiceValidationError) as raised:
        await demo_entry.runtime_data.async_write("no.such.point", 1)

    assert raised.value.translation_key == "variable_not_found"
