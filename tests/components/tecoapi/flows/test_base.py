"""What the config and options flows share: a source's own steps, its form errors.

A form whose step ID a source names is answered by the step its flow says;
another name is no step. A failure shows as the error its descriptor maps it
to, on its field, with what its message names of it; one no rule maps is
logged and shown as unknown.
"""

from typing import Final

from homeassistant.const import CONF_HOST
from homeassistant.core import HomeAssistant
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.tecoapi.const import CONF_TRANSPORT, DOMAIN
from custom_components.tecoapi.flows.base import async_stored_map, form_errors
from custom_components.tecoapi.flows.options import PlcOptionsFlow
from custom_components.tecoapi.point_maps import async_save_point_map
from custom_components.tecoapi.pyplc.core import exceptions as plc
from custom_components.tecoapi.pyplc.core.descriptor import CONF_POINT_MAP
from custom_components.tecoapi.pyplc.core.registry import source
from tests.fake_source import house_map

TECOAPI: Final = source("tecoapi")


def test_a_source_s_step_id_is_answered_and_no_other() -> None:
    flow = PlcOptionsFlow()

    assert flow.async_step_tecoapi == flow.async_step_settings
    assert flow.async_step_mervis_upload == flow.async_step_upload
    with pytest.raises(AttributeError):
        flow.async_step_nothing  # noqa: B018
    with pytest.raises(AttributeError):
        flow.tecoapi  # noqa: B018


def test_a_failure_is_the_form_error_its_descriptor_maps() -> None:
    placeholders: dict[str, str] = {}

    assert form_errors(TECOAPI, plc.PlcAuthenticationError("401"), placeholders) == {
        "base": "invalid_auth"
    }
    assert form_errors(TECOAPI, plc.InvalidHostError("x y"), placeholders) == {
        CONF_HOST: "invalid_host"
    }
    # A form of one field shows it there.
    assert form_errors(
        TECOAPI, plc.PlcAuthenticationError("401"), placeholders, CONF_POINT_MAP
    ) == {CONF_POINT_MAP: "invalid_auth"}


def test_an_unexpected_failure_is_logged_and_unknown(
    caplog: pytest.LogCaptureFixture,
) -> None:
    errors = form_errors(TECOAPI, plc.PlcError("odd"), {})

    assert errors == {"base": "unknown"}
    assert "answered the check with an error" in caplog.text


async def test_an_entry_s_stored_map_is_read_beside_it(hass: HomeAssistant) -> None:
    map_id = await async_save_point_map(hass, house_map())
    with_map = MockConfigEntry(
        domain=DOMAIN, data={CONF_TRANSPORT: "memory", CONF_POINT_MAP: map_id}
    )
    without = MockConfigEntry(domain=DOMAIN, data={CONF_HOST: "http://10.0.0.7"})

    assert await async_stored_map(hass, with_map) == house_map()
    assert await async_stored_map(hass, without) is None
