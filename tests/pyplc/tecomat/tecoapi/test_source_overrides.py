"""TecoApiSession with the user's overrides: any public variable written, as its type allows.

Seed 000 §3.5 and §3.6: SetObject and PutObject set any variable marked
``{PUBLIC_API}``, a plain one (not a T_ApiObject) as well. Against the
simulated PLC on 127.0.0.1.
"""

from collections.abc import Callable
from datetime import date
from typing import Any

import aiohttp
import pytest

from custom_components.tecoapi.pyplc import (
    InvalidValueError,
    OutOfRangeError,
    ReadOnlyError,
)
from custom_components.tecoapi.pyplc.core.models import PointOverride
from custom_components.tecoapi.pyplc.tecomat import TecoApiSession
from tests.pyplc.conftest import Clock, make_client
from tests.simulator import Program, Simulator

OVERRIDES = {
    "doorbellcount": PointOverride(writable=True),
    "ventilation.filter.lastchange": PointOverride(writable=True),
    "outsidetemp": PointOverride(writable=True, minimum=-40.0, maximum=40.0),
    "heating.livingsetpoint": PointOverride(writable=False),
}


async def _at_once(job: Callable[[], Any]) -> Any:
    return job()


@pytest.fixture
def changed(session: aiohttp.ClientSession, simulator: Simulator) -> TecoApiSession:
    """A session of the demo PLC with the user's overrides."""
    return TecoApiSession(
        make_client(session, simulator),
        clock=Clock(),
        run_blocking=_at_once,
        overrides=OVERRIDES,
    )


def services(simulator: Simulator) -> list[str]:
    return [request.service for request in simulator.requests if request.authorized]


async def test_the_catalogue_discovered_is_the_one_the_user_changed(
    changed: TecoApiSession,
) -> None:
    snapshot = await changed.poll(())
    points = snapshot.catalogue.points

    assert points["doorbellcount"].writable
    assert not points["doorbellcount"].described
    assert points["outsidetemp"].writable
    assert not points["heating.livingsetpoint"].writable
    assert points["alarmarmed"].override is None
    # What the device says is kept beside it.
    assert changed.discovered_point("doorbellcount") is not None
    assert not changed.discovered_point("doorbellcount").writable  # type: ignore[union-attr]
    assert changed.discovered_point("nothing") is None


async def test_a_plain_variable_made_writable_is_written_by_putobject_and_setobject(
    changed: TecoApiSession, simulator: Simulator
) -> None:
    """A top-level variable by PutObject, a struct's member by SetObject."""
    await changed.poll(())
    simulator.clear_requests()

    await changed.write("doorbellcount", 1300)
    await changed.write("ventilation.filter.lastchange", date(2026, 4, 1))

    assert services(simulator) == ["PutObject", "GetObject", "SetObject", "GetObject"]
    assert simulator.get_value("doorbellCount") == 1300
    assert simulator.get_value("ventilation.filter.lastChange") == "2026-04-01"


async def test_a_value_outside_the_type_is_refused_before_anything_is_sent(
    changed: TecoApiSession, simulator: Simulator
) -> None:
    """TecoApi's JSON tells no IEC type: an integer is bound by DINT..UDINT."""
    await changed.poll(())
    simulator.clear_requests()

    with pytest.raises(InvalidValueError):
        await changed.write("doorbellcount", 2**32)
    with pytest.raises(InvalidValueError):
        changed.check_write("doorbellcount", 1.5)

    assert simulator.requests == []
    assert simulator.get_value("doorbellCount") == 1287


async def test_a_read_only_t_apiobject_made_writable_is_written_in_its_range(
    changed: TecoApiSession, simulator: Simulator
) -> None:
    """``attr.readOnly`` is the program's word to its clients; the PLC stores a write."""
    await changed.poll(())
    simulator.clear_requests()

    await changed.write("outsidetemp", 12.5)
    with pytest.raises(OutOfRangeError):
        await changed.write("outsidetemp", 41.0)

    assert services(simulator) == ["SetObject", "GetObject"]
    assert simulator.get_value("outsideTemp.value") == 12.5


async def test_a_point_made_read_only_is_not_written(
    changed: TecoApiSession, simulator: Simulator
) -> None:
    await changed.poll(())
    simulator.clear_requests()

    with pytest.raises(ReadOnlyError):
        await changed.write_variable("Heating.livingSetpoint", 22.0)

    assert simulator.requests == []


async def test_the_overrides_apply_to_a_new_program_s_catalogue(
    changed: TecoApiSession, simulator: Simulator
) -> None:
    """A Mosaic download: the same variables keep what the user changed of them."""
    first = await changed.poll(())
    source = simulator.program.to_mapping()
    source["variables"]["garageDoor"] = {"type": "BOOL", "value": True}
    simulator.load_program(Program.from_mapping(source))

    snapshot = await changed.poll(())

    assert snapshot.program_changed
    assert snapshot.catalogue is not first.catalogue
    assert snapshot.catalogue.points["doorbellcount"].writable
    assert snapshot.catalogue.points["garagedoor"].override is None
    await changed.write("doorbellcount", 7)
    assert simulator.get_value("doorbellCount") == 7
