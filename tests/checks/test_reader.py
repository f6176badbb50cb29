"""read_usage: what a module asks of its translations and services.yaml, read with ast."""

from typing import Final

from scripts.checks.reader import read_usage
from scripts.checks.usage import Forwarding, missing_translations
from tests.checks.synthetic import DOMAIN, synthetic_usage


def test_checker_reads_flows_entities_exceptions_issues_and_actions() -> None:
    usage = synthetic_usage()
    assert usage.problems == []
    assert sorted(usage.required) == [
        ("config", "abort", "already_configured"),
        ("config", "abort", "already_in_progress"),
        ("config", "abort", "reauth_successful"),
        ("config", "error", "cannot_connect"),
        ("config", "error", "invalid_auth"),
        ("config", "error", "no_input"),
        ("config", "error", "refused_by_plc"),
        ("config", "error", "timeout"),
        ("config", "flow_title"),
        ("config", "step", "dhcp_confirm"),
        ("config", "step", "reauth_confirm"),
        ("config", "step", "reauth_confirm", "data", "password"),
        ("config", "step", "reconfigure"),
        ("config", "step", "user"),
        ("config", "step", "user", "data", "host"),
        ("config", "step", "user", "data", "password"),
        ("entity", "sensor", "uptime"),
        ("entity", "switch", "boiler"),
        ("exceptions", "out_of_range", "message"),
        ("exceptions", "read_only", "message"),
        ("exceptions", "write_failed", "message"),
        ("issues", "program_changed", "title"),
        ("options", "abort", "no_options"),
        ("options", "step", "pick"),
        ("options", "step", "pick", "data", "mode"),
        ("selector", "mode", "options"),
        ("selector", "mode", "options", "off"),
        ("selector", "mode", "options", "on"),
    ]
    # The key reaches ServiceValidationError through a helper's parameter.
    assert usage.forwarded == {
        "_validation_error": Forwarding(
            ("translation_key", 0),
            ("placeholders", 1),
            ("exceptions", None, "message"),
        )
    }
    assert set(usage.services) == {"write_variable"}
    assert usage.services["write_variable"].startswith("sensor:")


SECTION_FLOW_SOURCE: Final = """
import voluptuous as vol
from homeassistant.data_entry_flow import section

INNER = vol.Schema({vol.Optional("plccoms_host"): str})


class Options(OptionsFlow):
    async def async_step_init(self, user_input=None):
        schema = OUTER.extend({vol.Required("push"): section(INNER, {})})
        return self.async_show_form(step_id="init", data_schema=schema)


OUTER = vol.Schema({vol.Required("scan_interval"): int})
"""


def test_checker_puts_a_form_section_s_fields_under_sections() -> None:
    usage = read_usage({"config_flow": SECTION_FLOW_SOURCE}, domain=DOMAIN)
    assert usage.problems == []
    assert sorted(usage.required) == [
        ("options", "step", "init"),
        ("options", "step", "init", "data", "scan_interval"),
        ("options", "step", "init", "sections", "push", "data", "plccoms_host"),
    ]


def test_checker_reads_a_schema_imported_from_a_sibling_module() -> None:
    usage = read_usage(
        {
            "options": 'import voluptuous as vol\nFORM = vol.Schema({vol.Required("devices"): str})\n',
            "config_flow": (
                "from .options import FORM\n\n\n"
                "class Options(OptionsFlow):\n"
                "    async def async_step_init(self, user_input=None):\n"
                '        return self.async_show_form(step_id="init", data_schema=FORM)\n'
            ),
        },
        domain=DOMAIN,
    )
    assert usage.problems == []
    assert sorted(usage.required) == [
        ("options", "step", "init"),
        ("options", "step", "init", "data", "devices"),
    ]


def test_checker_leaves_home_assistants_own_keys_to_it() -> None:
    """An error raised with Home Assistant's strings needs none of the integration's."""
    usage = read_usage(
        {
            "compat": (
                "def unload(done):\n"
                "    if not done:\n"
                "        raise ConfigEntryError(\n"
                "            translation_domain=HOMEASSISTANT_DOMAIN,\n"
                "            translation_key='unload_platforms_failed',\n"
                "        )\n"
                "    raise ConfigEntryError(translation_domain=DOMAIN, translation_key='ours')\n"
            )
        },
        domain=DOMAIN,
    )
    assert missing_translations(usage, {}) == [
        "exceptions.ours.message (used at compat:7)"
    ]


def test_checker_knows_its_domain_by_name_too() -> None:
    """`translation_domain="tecoapi"` is the integration's; another name is not."""
    usage = read_usage(
        {
            "compat": (
                "def fail():\n"
                "    raise HomeAssistantError(translation_domain='other', translation_key='theirs')\n"
                "    raise HomeAssistantError(translation_domain='tecoapi', translation_key='ours')\n"
            )
        },
        domain="tecoapi",
    )
    assert missing_translations(usage, {}) == [
        "exceptions.ours.message (used at compat:3)"
    ]


def test_checker_reports_uses_it_cannot_place() -> None:
    usage = read_usage(
        {
            "helpers": 'def f(hass):\n    hass.services.async_register("d", name_of(), h)\n'
            '    return self.async_abort(reason="x")\n'
            'DESC = Something(translation_key="k")\n'
        },
        domain=DOMAIN,
    )
    assert usage.problems == [
        "helpers:2: cannot read the action name registered by async_register()",
        "helpers:3: async_abort() outside a config or options flow",
        "helpers:4: cannot tell the entity platform of translation_key 'k'",
    ]
