"""The one place the library's errors become Home Assistant's, translated.

A failed poll is ``ConfigEntryAuthFailed`` (rejected credentials: reauthenticate)
or ``UpdateFailed`` with the failure's key; a failed write or read is a
``ServiceValidationError`` where the user asked wrongly and a
``HomeAssistantError`` where the device failed, each with its placeholders.
"""

from typing import Any, Final

from homeassistant.config_entries import SOURCE_REAUTH
from homeassistant.core import HomeAssistant
from homeassistant.exceptions import (
    ConfigEntryAuthFailed,
    HomeAssistantError,
    ServiceValidationError,
)
from homeassistant.helpers.update_coordinator import UpdateFailed
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.tecoapi.const import DOMAIN
from custom_components.tecoapi.helpers import (
    action_error,
    plc_action,
    update_error,
    variable_list_failure,
)
from custom_components.tecoapi.messages import error_detail, error_text
from custom_components.tecoapi.pyplc.core import exceptions as plc
from custom_components.tecoapi.pyplc.core.appliances import MissingPointError

PATH: Final = "Heating.livingSetpoint"


@pytest.mark.parametrize(
    ("error", "raised", "key"),
    [
        (plc.PlcAuthenticationError("401"), ConfigEntryAuthFailed, "auth_failed"),
        (plc.PlcUnreachableError("no route"), UpdateFailed, "plc_unreachable"),
        (plc.PlcConnectionError("refused"), UpdateFailed, "cannot_connect"),
        (plc.VariableListTooLargeError("big"), UpdateFailed, "variable_list_too_big"),
        (
            plc.VariableListUnreadableError("no"),
            UpdateFailed,
            "variable_list_unreadable",
        ),
        (plc.PlcResponseError("500"), UpdateFailed, "plc_error"),
        (plc.PlcError("odd"), UpdateFailed, "unknown_error"),
    ],
    ids=lambda value: type(value).__name__ if isinstance(value, Exception) else None,
)
def test_a_failed_poll_is_translated(
    error: plc.PlcError, raised: type[Exception], key: str
) -> None:
    result = update_error(error)

    assert type(result) is raised
    assert getattr(result, "translation_domain", None) == DOMAIN
    assert getattr(result, "translation_key", None) == key
    placeholders = getattr(result, "translation_placeholders", None) or {}
    # What the library says of the failure, in its words (no Home Assistant here:
    # the library's English), never the raw exception's own message.
    assert placeholders.get("error", str(error.text())) in {
        error_text(None, error),
        error_detail(None, error),
    }


def test_only_the_list_of_variables_names_its_failure() -> None:
    assert variable_list_failure(plc.VariableListTooLargeError("x")) == (
        "variable_list_too_big"
    )
    assert variable_list_failure(plc.VariableListUnreadableError("x")) == (
        "variable_list_unreadable"
    )
    assert variable_list_failure(plc.PlcResponseError("x")) is None


@pytest.mark.parametrize(
    ("error", "user", "key", "shown"),
    [
        (plc.ReadOnlyError(PATH, 1), True, "read_only", {"value": "1"}),
        (
            plc.OutOfRangeError(PATH, 40, 5.0, 35.5),
            True,
            "out_of_range",
            {"min_value": "5", "max_value": "35.5"},
        ),
        (plc.NotAsciiError(PATH, "ž"), True, "not_ascii", {"path": PATH}),
        (
            plc.NotEncodableError(PATH, "ж", "cp1250"),
            True,
            "not_encodable",
            {"encoding": "cp1250"},
        ),
        (
            plc.DateTooEarlyError(PATH, 1, "1970-01-01"),
            True,
            "date_too_early",
            {"earliest": "1970-01-01"},
        ),
        (
            plc.DurationOutOfRangeError(PATH, 1, "24:00"),
            True,
            "duration_out_of_range",
            {"longest": "24:00"},
        ),
        (plc.InvalidValueError(PATH, "x", "no"), True, "invalid_value", {}),
        (plc.WritesDisabledError("off"), False, "writes_disabled", {}),
        (
            plc.ValueRejectedError("no", path=PATH, value=1, code="7"),
            True,
            "value_rejected",
            {},
        ),
        (plc.InvalidPathError("bad"), True, "invalid_path", {}),
        (plc.VariableNotFoundError("gone", path=PATH), False, "write_failed", {}),
        (plc.PlcAuthenticationError("401"), False, "auth_failed", {}),
        (plc.PlcConnectionError("refused"), False, "write_failed", {}),
        (MissingPointError("heating.gone"), True, "variable_not_found", {}),
    ],
    ids=lambda value: type(value).__name__ if isinstance(value, Exception) else None,
)
def test_a_failed_write_of_a_point_is_translated(
    error: plc.PlcError | MissingPointError,
    user: bool,
    key: str,
    shown: dict[str, str],
) -> None:
    """What the user asked wrongly is a validation error, the rest a device's."""
    result = action_error(error, operation="write", path=PATH, value=1)

    assert isinstance(result, ServiceValidationError) is user
    assert result.translation_domain == DOMAIN
    assert result.translation_key == key
    assert shown.items() <= (result.translation_placeholders or {}).items()


@pytest.mark.parametrize(
    ("operation", "error", "key"),
    [
        (
            "write_variable",
            plc.VariableNotFoundError("gone", path=PATH),
            "variable_not_found",
        ),
        (
            "read_variable",
            plc.VariableNotFoundError("gone", path=PATH),
            "variable_not_found",
        ),
        ("read_variable", plc.PlcConnectionError("refused"), "read_failed"),
        ("write_variable", plc.PlcConnectionError("refused"), "write_failed"),
    ],
)
def test_an_action_names_the_variable_the_device_lacks(
    operation: str, error: plc.PlcError, key: str
) -> None:
    """A variable the device lacks is the user's mistake in an action only."""
    result = action_error(error, operation=operation, path=PATH)

    assert result.translation_key == key
    assert (result.translation_placeholders or {})["path"] == PATH
    assert isinstance(result, ServiceValidationError) is (key == "variable_not_found")


def test_a_missing_point_names_its_key() -> None:
    result = action_error(MissingPointError("heating.gone"), operation="write", path="")

    assert result.translation_placeholders == {"path": "heating.gone"}


async def test_an_action_refused_for_credentials_starts_the_reauthentication(
    hass: HomeAssistant,
) -> None:
    signed_in = {"host": "http://127.0.0.1:1", "username": "u", "password": "p"}
    entry = MockConfigEntry(domain=DOMAIN, data=signed_in)
    entry.add_to_hass(hass)

    def refused(error: Exception) -> Any:
        with plc_action(hass, entry, operation="read_variable", path=PATH):
            raise error

    with pytest.raises(HomeAssistantError) as raised:
        refused(plc.PlcConnectionError("refused"))
    assert raised.value.translation_key == "read_failed"
    await hass.async_block_till_done()
    assert not list(entry.async_get_active_flows(hass, {SOURCE_REAUTH}))

    with pytest.raises(HomeAssistantError) as raised:
        refused(plc.PlcAuthenticationError("401"))
    assert raised.value.translation_key == "auth_failed"
    await hass.async_block_till_done()
    assert len(list(entry.async_get_active_flows(hass, {SOURCE_REAUTH}))) == 1
