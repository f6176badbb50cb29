"""A small synthetic integration for the code reader: a config flow, const, a platform.

Its line numbers are part of what the tests expect (`config_flow:16`): edit the
sources only together with those tests.
"""

from typing import Final

from scripts.checks.reader import read_usage
from scripts.checks.usage import TranslationUsage

DOMAIN: Final = "tecoapi"


FLOW_SOURCE: Final = """
import voluptuous as vol
from homeassistant.config_entries import ConfigFlow, OptionsFlow
from homeassistant.const import CONF_HOST, CONF_PASSWORD

from .const import DOMAIN, ERROR_AUTH

STEP_USER = vol.Schema({vol.Required(CONF_HOST): str, vol.Required(CONF_PASSWORD): str})


class PlcConfigFlow(ConfigFlow, domain=DOMAIN):
    async def async_step_user(self, user_input=None):
        errors = {}
        if user_input is not None:
            await self.async_set_unique_id("serial")
            self._abort_if_unique_id_configured()
            errors["base"] = "cannot_connect"
            errors[CONF_PASSWORD] = ERROR_AUTH
        return self.async_show_form(step_id="user", data_schema=STEP_USER, errors=errors)

    async def async_step_dhcp(self, discovery_info):
        self.context["title_placeholders"] = {"name": "PLC"}
        return self.async_show_form(step_id="dhcp_confirm")

    async def async_step_reauth(self, entry_data):
        return await self.async_step_reauth_confirm()

    async def async_step_reauth_confirm(self, user_input=None):
        if user_input is not None:
            return self.async_update_reload_and_abort(self._entry, data_updates=user_input)
        return self.async_show_form(data_schema=vol.Schema({vol.Required("password"): str}))


class PlcOptionsFlow(OptionsFlow):
    async def async_step_init(self, user_input=None):
        return self.async_abort(reason="no_options")

    async def async_step_pick(self, user_input=None):
        choice = SelectSelectorConfig(options=["on", "off"], translation_key="mode")
        schema = vol.Schema({vol.Required("mode"): SelectSelector(choice)})
        return self.async_show_form(step_id="pick", data_schema=schema)


class SecondFlow(PlcConfigFlow):
    async def async_step_reconfigure(self, user_input=None):
        info, errors = await self._async_try(user_input)
        return self.async_show_form(step_id="reconfigure", errors=errors)

    async def _async_try(self, user_input):
        try:
            return await probe(user_input), {}
        except OSError:
            return None, {"base": "timeout"}
        except ValueError:
            return None, {"base": "refused_by_plc" if user_input else "no_input"}
"""

CONST_SOURCE: Final = """
from typing import Final

DOMAIN: Final = "tecoapi"
ERROR_AUTH: Final = "invalid_auth"
SERVICE_WRITE: Final = "write_variable"
"""

PLATFORM_SOURCE: Final = """
from homeassistant.components.sensor import SensorEntity, SensorEntityDescription
from homeassistant.components.switch import SwitchEntity
from homeassistant.exceptions import HomeAssistantError, ServiceValidationError
from homeassistant.helpers import issue_registry as ir

from .const import DOMAIN, SERVICE_WRITE

UPTIME = SensorEntityDescription(key="uptime", translation_key="uptime")
KINDS = {"temp": "temperature"}


class Boiler(SwitchEntity):
    _attr_translation_key = "boiler"


class Point(SensorEntity):
    def __init__(self, point):
        self._attr_translation_key = KINDS.get(point.kind)

    async def write(self):
        raise ServiceValidationError(translation_domain=DOMAIN, translation_key="read_only")


async def async_setup(hass):
    hass.services.async_register(DOMAIN, SERVICE_WRITE, handler)
    ir.async_create_issue(hass, DOMAIN, "x", translation_key="program_changed")
    raise HomeAssistantError(translation_domain=DOMAIN, translation_key="write_failed")


def _validation_error(translation_key, placeholders):
    return ServiceValidationError(
        translation_domain=DOMAIN,
        translation_key=translation_key,
        translation_placeholders=placeholders,
    )


def check(value):
    if value > 3:
        raise _validation_error("out_of_range", {"value": value})
"""


def synthetic_usage() -> TranslationUsage:
    """What the three modules above need, read as the integration's would be."""
    return read_usage(
        {"config_flow": FLOW_SOURCE, "const": CONST_SOURCE, "sensor": PLATFORM_SOURCE},
        domain=DOMAIN,
    )
