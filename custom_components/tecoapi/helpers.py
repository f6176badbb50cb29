"""One place where the library's errors become Home Assistant's.

The library's exception classes say what happened; this module decides how Home
Assistant shows it: ``ServiceValidationError`` for what the user asked wrongly,
``HomeAssistantError`` for what failed on the PLC's side, ``UpdateFailed`` and
``ConfigEntryAuthFailed`` for polling. Every message is translated, and so is
what it says of the failure (``{error}``: the library's text in Home
Assistant's language, the device's own words after it, :mod:`.messages`).
"""

from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

from homeassistant.config_entries import ConfigEntry
from homeassistant.core import HomeAssistant, async_get_hass_or_none
from homeassistant.exceptions import (
    ConfigEntryAuthFailed,
    HomeAssistantError,
    ServiceValidationError,
)
from homeassistant.helpers.update_coordinator import UpdateFailed

from .const import DOMAIN
from .messages import device_says, error_detail, error_text, said
from .pyplc.core import exceptions as plc


def variable_list_failure(err: plc.PlcError) -> str | None:
    """Return the translation key of a failure to serve the list of public variables.

    None for any other failure. The same key names the failed poll's error and
    the repair issue it raises: the list is too big, or the device cannot read it.
    """
    if isinstance(err, plc.VariableListTooLargeError):
        return "variable_list_too_big"
    if isinstance(err, plc.VariableListUnreadableError):
        return "variable_list_unreadable"
    return None


def update_error(err: plc.PlcError) -> Exception:
    """Return the error a failed poll or discovery raises to the coordinator."""
    hass = async_get_hass_or_none()
    error = error_text(hass, err)
    if isinstance(err, plc.PlcAuthenticationError):
        return ConfigEntryAuthFailed(
            translation_domain=DOMAIN, translation_key="auth_failed"
        )
    if isinstance(err, plc.PlcUnreachableError):
        return UpdateFailed(
            translation_domain=DOMAIN,
            translation_key="plc_unreachable",
            translation_placeholders={"error": error_detail(hass, err)},
        )
    if isinstance(err, plc.PlcConnectionError):
        return UpdateFailed(
            translation_domain=DOMAIN,
            translation_key="cannot_connect",
            translation_placeholders={"error": error},
        )
    if (key := variable_list_failure(err)) is not None:
        return UpdateFailed(
            translation_domain=DOMAIN,
            translation_key=key,
            translation_placeholders={"error": error_detail(hass, err)},
        )
    if isinstance(err, plc.PlcResponseError):
        return UpdateFailed(
            translation_domain=DOMAIN,
            translation_key="plc_error",
            translation_placeholders={"error": error},
        )
    return UpdateFailed(
        translation_domain=DOMAIN,
        translation_key="unknown_error",
        translation_placeholders={"error": error},
    )


def action_error(
    err: plc.PlcError,
    *,
    operation: str,
    path: str,
    value: Any = None,
) -> HomeAssistantError:
    """Return the translated error of a failed read or write of ``path``.

    ``operation`` is ``write`` (an entity's write to its point), ``write_variable``
    or ``read_variable`` (the actions, which take any path). A variable the PLC
    does not know is the user's mistake in an action, but a PLC failure for an
    entity's point: the point was there when the entity was made. A point the
    source's catalogue does not have (gone from it, or a typed device's role
    without one: ``MissingPointError``, refused before anything is sent) is not
    found, by its key, whatever the operation.
    """
    hass = async_get_hass_or_none()
    placeholders = {"path": path, "value": str(value)}
    if isinstance(err, plc.MissingPointError):
        return validation_error("variable_not_found", {"path": err.key})
    if isinstance(err, plc.ReadOnlyError):
        return validation_error("read_only", placeholders)
    if isinstance(err, plc.OutOfRangeError):
        return validation_error(
            "out_of_range",
            placeholders
            | {"min_value": f"{err.min_value:g}", "max_value": f"{err.max_value:g}"},
        )
    if isinstance(err, plc.NotAsciiError):
        return validation_error("not_ascii", placeholders)
    if isinstance(err, plc.NotEncodableError):
        return validation_error(
            "not_encodable", placeholders | {"encoding": err.encoding}
        )
    if isinstance(err, plc.DateTooEarlyError):
        return validation_error(
            "date_too_early", placeholders | {"earliest": err.earliest}
        )
    if isinstance(err, plc.DurationOutOfRangeError):
        return validation_error(
            "duration_out_of_range", placeholders | {"longest": err.longest}
        )
    if isinstance(err, plc.InvalidValueError | plc.InvalidWriteError):
        return validation_error(
            "invalid_value", placeholders | {"error": said(hass, err.text())}
        )
    if isinstance(err, plc.WritesDisabledError):
        return plc_error("writes_disabled", {"path": path})
    if isinstance(err, plc.ValueRejectedError):
        # Why, where the source could tell; else the device's own words.
        if err.why is None and err.said:
            why = device_says(hass, err.said)
        else:
            why = said(hass, err.text())
        return validation_error("value_rejected", placeholders | {"message": why})
    if isinstance(err, plc.InvalidPathError):
        return validation_error("invalid_path", {"path": path})
    if isinstance(err, plc.VariableNotFoundError) and operation != "write":
        return validation_error("variable_not_found", {"path": path})
    if isinstance(err, plc.PlcAuthenticationError):
        return plc_error("auth_failed", {})
    if operation == "read_variable":
        return plc_error("read_failed", {"path": path, "error": error_text(hass, err)})
    return plc_error("write_failed", placeholders | {"error": error_text(hass, err)})


@contextmanager
def plc_action(
    hass: HomeAssistant,
    entry: ConfigEntry[Any],
    *,
    operation: str,
    path: str,
    value: Any = None,
) -> Iterator[None]:
    """Turn a library error raised inside into Home Assistant's error.

    Rejected credentials also start the reauthentication of ``entry``.
    """
    try:
        yield
    except plc.PlcError as err:
        if isinstance(err, plc.PlcAuthenticationError):
            entry.async_start_reauth(hass)
        raise action_error(err, operation=operation, path=path, value=value) from err


def validation_error(
    translation_key: str, placeholders: dict[str, str]
) -> ServiceValidationError:
    """Return a translated error for something the user asked wrongly."""
    return ServiceValidationError(
        translation_domain=DOMAIN,
        translation_key=translation_key,
        translation_placeholders=placeholders,
    )


def plc_error(translation_key: str, placeholders: dict[str, str]) -> HomeAssistantError:
    """Return a translated error for something that failed on the PLC's side."""
    return HomeAssistantError(
        translation_domain=DOMAIN,
        translation_key=translation_key,
        translation_placeholders=placeholders,
    )
