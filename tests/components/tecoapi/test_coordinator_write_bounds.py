"""Dates and durations a Tecomat PLC cannot hold are refused before anything is sent.

The manual's table of types (seed 000, chapter 4): DATE and DT hold the moments
from 1.1.1970 00:00:00.0 on, TIME (and TOD) <0, 24d 20:31:23.647>: 2**31 - 1
milliseconds, ``T#24d20h31m23s647ms``, never negative (TecoApi's ``hh:mm:ss.zzz``
and PLCComS's unsigned milliseconds carry no sign either). Through TecoApi and
through PLCComS alike, a value beyond a bound is refused with a translated
error: nothing reaches the simulated PLC (its request log), Home Assistant shows
what it showed; the bound itself is written.
"""

from collections.abc import AsyncIterator, Awaitable, Callable
from dataclasses import dataclass
from datetime import UTC, date, datetime
from typing import Any

from homeassistant.const import (
    ATTR_CONFIG_ENTRY_ID,
    ATTR_ENTITY_ID,
    CONF_HOST,
    CONF_PORT,
)
from homeassistant.core import HomeAssistant
from homeassistant.exceptions import ServiceValidationError
from homeassistant.helpers import entity_registry as er
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.tecoapi.const import CONF_TRANSPORT, DOMAIN
from tests.components.tecoapi.conftest import make_entry, setup_entry
from tests.simulator import Program, Simulator
from tests.simulator.plccoms import PlcComsServer


def _api_object(kind: str, value: str, title: str) -> dict[str, Any]:
    """A writable T_ApiObject of a kind, as a program file declares it."""
    attr = {"enable": True, "visibility": True, "readOnly": False, "title": title}
    return {"type": f"T_ApiObject OF {kind}", "value": {"value": value, "attr": attr}}


@dataclass
class Plc:
    """The demo PLC with a writable DATE and DT, through one transport."""

    simulator: Simulator
    coms: PlcComsServer | None
    entry: MockConfigEntry

    def sent(self) -> int:
        """How many requests (TecoApi) or command lines (PLCComS) the PLC received."""
        if self.coms is not None:
            return len(self.coms.commands)
        return len(self.simulator.requests)

    def entity_id(self, hass: HomeAssistant, platform: str, key: str) -> str:
        """The entity ID of a point's entity, by its unique ID."""
        identity = self.entry.runtime_data.data.info.identity
        found = er.async_get(hass).async_get_entity_id(
            platform, DOMAIN, f"{identity}_{key}"
        )
        assert found is not None, key
        return found


@pytest.fixture(params=["tecoapi", "plccoms"])
async def plc(
    request: pytest.FixtureRequest,
    hass: HomeAssistant,
    simulator: Simulator,
    entity_registry_enabled_by_default: None,
) -> AsyncIterator[Plc]:
    """The PLC set up as a TecoApi entry, or as a PLCComS-only one."""
    source = simulator.program.to_mapping()
    source["variables"]["holidayFrom"] = _api_object(
        "DATE", "2026-12-20", "Holiday from"
    )
    source["variables"]["lastService"] = _api_object(
        "DT", "2026-03-01T08:00:00.000Z", "Last service"
    )
    simulator.load_program(Program.from_mapping(source))
    if request.param == "tecoapi":
        yield Plc(simulator, None, await setup_entry(hass, make_entry(simulator)))
        return
    async with PlcComsServer(simulator, scan_interval=None) as coms:
        entry = MockConfigEntry(
            domain=DOMAIN,
            title="CP-2080 · FAMILY_HOUSE v1.3 · PLCComS",
            unique_id="EPSNET 127.0.0.1:61682",
            data={
                CONF_TRANSPORT: "plccoms",
                CONF_HOST: "127.0.0.1",
                CONF_PORT: coms.port,
            },
        )
        yield Plc(simulator, coms, await setup_entry(hass, entry))


type Write = Callable[[HomeAssistant, Plc, Any], Awaitable[None]]


def entity_write(platform: str, key: str, field: str) -> Write:
    """Set a point's entity's value, as a user in its card."""

    async def write(hass: HomeAssistant, plc: Plc, value: Any) -> None:
        await hass.services.async_call(
            platform,
            "set_value",
            {ATTR_ENTITY_ID: plc.entity_id(hass, platform, key), field: value},
            blocking=True,
        )

    return write


def action_write(path: str) -> Write:
    """Write a variable with the tecoapi.write_variable action (its value is JSON)."""

    async def write(hass: HomeAssistant, plc: Plc, value: Any) -> None:
        await hass.services.async_call(
            DOMAIN,
            "write_variable",
            {ATTR_CONFIG_ENTRY_ID: plc.entry.entry_id, "path": path, "value": value},
            blocking=True,
        )

    return write


@dataclass(frozen=True)
class Bound:
    """A bound of a type: the value beyond it, the value at it, what is said."""

    write: Write
    shown: tuple[str, str]
    """The platform and the point key whose entity shows the value."""
    path: str
    beyond: Any
    at: Any
    held: str
    """What the PLC holds once the bound itself is written."""
    key: str
    placeholder: tuple[str, str]


BOUNDS = {
    "a DATE before 1970": Bound(
        entity_write("date", "holidayfrom", "date"),
        ("date", "holidayfrom"),
        "holidayFrom.value",
        date(1969, 12, 31),
        date(1970, 1, 1),
        "1970-01-01",
        "date_too_early",
        ("earliest", "1970-01-01"),
    ),
    "a DT before 1970": Bound(
        entity_write("datetime", "lastservice", "datetime"),
        ("datetime", "lastservice"),
        "lastService.value",
        datetime(1969, 12, 31, 23, 59, 59, 999000, tzinfo=UTC),
        datetime(1970, 1, 1, tzinfo=UTC),
        "1970-01-01T00:00:00.000Z",
        "date_too_early",
        ("earliest", "1970-01-01T00:00:00.000Z"),
    ),
    "a TIME beyond T#24d20h31m23s647ms": Bound(
        action_write("pumpRuntime"),
        ("sensor", "pumpruntime"),
        "pumpRuntime",
        '"596:31:23.648"',
        '"596:31:23.647"',
        "596:31:23.647",
        "duration_out_of_range",
        ("longest", "596:31:23.647"),
    ),
    "a TIME below zero": Bound(
        action_write("pumpRuntime"),
        ("sensor", "pumpruntime"),
        "pumpRuntime",
        '"-00:00:00.001"',
        '"00:00:00.000"',
        "00:00:00.000",
        "duration_out_of_range",
        ("longest", "596:31:23.647"),
    ),
}


@pytest.mark.parametrize("bound", BOUNDS.values(), ids=BOUNDS.keys())
async def test_beyond_a_bound_nothing_is_sent_at_it_the_value_is_written(
    hass: HomeAssistant, plc: Plc, bound: Bound
) -> None:
    """Refused with the translated reason, the PLC and the state as they were."""
    entity_id = plc.entity_id(hass, *bound.shown)
    before = hass.states.get(entity_id)
    assert before is not None
    held = plc.simulator.get_value(bound.path)
    sent = plc.sent()

    with pytest.raises(ServiceValidationError) as raised:
        await bound.write(hass, plc, bound.beyond)

    assert raised.value.translation_key == bound.key
    name, text = bound.placeholder
    assert raised.value.translation_placeholders[name] == text
    assert text in str(raised.value)  # the translated message says the bound
    assert plc.sent() == sent
    assert plc.simulator.get_value(bound.path) == held
    await hass.async_block_till_done()
    after = hass.states.get(entity_id)
    assert after is not None
    assert after.state == before.state

    await bound.write(hass, plc, bound.at)

    assert plc.sent() > sent
    assert plc.simulator.get_value(bound.path) == bound.held
