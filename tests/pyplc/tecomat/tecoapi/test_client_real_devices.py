"""The client against PLCs that behave as real installations do, not as the manual reads.

Each test runs against the simulator over HTTP on 127.0.0.1 with one of its
real-device switches on; each failed on the client before it tolerated that.
"""

import math
import tracemalloc
from typing import Any

import aiohttp
import pytest

from custom_components.tecoapi.pyplc import (
    DiscoveryCost,
    ResponseTooLargeError,
    ValueKind,
    VariableNotFoundError,
)
from tests.pyplc.conftest import StartSimulator, make_client
from tests.simulator import Program, generate_program, load_program


def czech_manual() -> Program:
    """The manual's program with Czech text in a T_ApiObject and a STRING."""
    source: dict[str, Any] = load_program("manual").to_mapping()
    main = source["variables"]["Main"]["variables"]
    main["myObject2"]["value"]["attr"].update(title="Teplota obývák", units="°C")
    source["variables"]["plcDesc"]["value"] = "Řídicí systém"
    return Program.from_mapping(source)


# --- Windows-1250 text -----------------------------------------------------------------


async def test_windows_1250_titles_units_and_strings_read_correctly(
    start_simulator: StartSimulator, session: aiohttp.ClientSession
) -> None:
    sim = await start_simulator(czech_manual())
    sim.faults.text_encoding = "windows-1250"
    client = make_client(session, sim)

    catalogue = await client.discover()
    meta = catalogue.points["main.myobject2"].attributes
    assert meta is not None
    assert (meta.name, meta.unit) == ("Teplota obývák", "°C")
    assert catalogue.values["plcdesc"] == "Řídicí systém"

    plan = client.plan(catalogue.points.values(), with_attrs=True)
    result = await client.read(plan, catalogue.points)
    assert result.missing == frozenset()
    assert result.attributes["main.myobject2"].unit == "°C"
    assert result.attributes["main.myobject1"].unit == "°C"
    assert result.values["plcdesc"] == "Řídicí systém"


async def test_a_windows_1250_error_body_is_still_understood(
    start_simulator: StartSimulator, session: aiohttp.ClientSession
) -> None:
    sim = await start_simulator("manual")
    sim.faults.text_encoding = "windows-1250"
    client = make_client(session, sim)

    with pytest.raises(VariableNotFoundError) as caught:
        await client.get_object(["teplotaObývák"])
    assert caught.value.code == "400.005"
    assert caught.value.path == "teplotaObývák"


# --- oversized answers -------------------------------------------------------------------


async def test_a_declared_64_mib_answer_fails_before_its_body_is_read(
    start_simulator: StartSimulator, session: aiohttp.ClientSession
) -> None:
    sim = await start_simulator("manual")
    client = make_client(session, sim)
    await client.get_info()
    sim.faults.huge_body = True

    with pytest.raises(ResponseTooLargeError) as caught:
        await client.get_info()
    assert caught.value.status == 200
    assert caught.value.received == 0

    # The next answer is read as usual.
    sim.faults.huge_body = False
    assert (await client.get_info()).model == "CP-W32"


async def test_an_endless_answer_is_cut_at_the_cap_with_flat_memory(
    start_simulator: StartSimulator, session: aiohttp.ClientSession
) -> None:
    """Cut at the cap, not at the timeout; the bytes taken and memory stay at the cap."""
    sim = await start_simulator("manual")
    # Long enough that only the cap can end the read (the body never ends).
    client = make_client(session, sim, timeout=30.0)
    await client.get_info()
    sim.faults.endless_body = True

    tracemalloc.start()
    try:
        with pytest.raises(ResponseTooLargeError) as caught:
            await client.get_object(["plcName"])
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()

    # Read to the first byte past the cap (body.MAX_BODY_BYTES), no further.
    limit = caught.value.limit
    assert caught.value.received == limit + 1
    # The answer so far plus the connection's buffers; not growing with the body.
    assert peak < limit + 2 * 1024 * 1024
    sim.faults.endless_body = False
    assert await client.get_object(["plcName"]) == {"plcName": "myFoxtrot"}


# --- REALs as real devices print them -------------------------------------------------


@pytest.mark.parametrize("short_reals", [True, False], ids=["29.0", "29.000000"])
async def test_reals_short_or_long_and_negative_zero_read_as_zero(
    start_simulator: StartSimulator, session: aiohttp.ClientSession, short_reals: bool
) -> None:
    sim = await start_simulator("manual")
    sim.faults.short_reals = short_reals
    sim.set_value("Main.myObject1.value", -0.0)
    sim.set_value("Main.myObject3.attr.minValue", -0.0)
    sim.set_value("Main.myObject3.value", 29.0)
    client = make_client(session, sim)

    catalogue = await client.discover()
    plan = client.plan(catalogue.points.values(), with_attrs=True)
    result = await client.read(plan, catalogue.points)

    for values in (catalogue.values, result.values):
        assert values["main.myobject3"] == 29.0
        assert values["plcdata.varreal"] == 1000.0
        # -0.0 == 0.0: only the sign tells that it leaked (a state "-0.0").
        assert math.copysign(1.0, values["main.myobject1"]) == 1.0
    assert catalogue.points["main.myobject3"].kind is ValueKind.REAL
    assert catalogue.points["plcdata.varreal"].kind is ValueKind.REAL
    for meta in (
        catalogue.points["main.myobject3"].attributes,
        result.attributes["main.myobject3"],
    ):
        assert meta is not None
        assert (meta.minimum, meta.maximum) == (0.0, 30.0)
        assert meta.minimum is not None
        assert math.copysign(1.0, meta.minimum) == 1.0


# --- discovery and polling on a CP-1xxx with many full roots ---------------------------


async def test_discovery_costs_one_413_per_root_too_big_to_share_a_request(
    start_simulator: StartSimulator, session: aiohttp.ClientSession
) -> None:
    """400 T_ApiObjects in 27 roots of up to 128 items on a CP-1000 (128 per answer)."""
    sim = await start_simulator(generate_program(400, plc_type="CP-1000", roots=27))
    client = make_client(session, sim)
    await client.get_info()
    sim.clear_requests()

    catalogue = await client.discover()

    statuses = [record.status for record in sim.requests]
    # Halving the first batch drew 25 answers 413 (53 requests).
    assert statuses.count(413) == 1
    assert len(statuses) == 29
    assert catalogue.discovery == DiscoveryCost(
        requests=29,
        lower_bound=27,
        too_large=1,
        overflowing_groups=1,
        oversized_groups=0,
        item_limit=128,
    )
    assert sum(point.described for point in catalogue.points.values()) == 400
    assert catalogue.skipped_groups == ()

    # A poll of every value (attributes not wanted), against the planner's bound.
    plan = client.plan(catalogue.points.values(), with_attrs=False)
    assert (len(plan.requests), plan.lower_bound) == (23, 21)
    sim.clear_requests()
    result = await client.read(plan, catalogue.points)
    assert [record.status for record in sim.requests] == [200] * 23
    assert result.missing == frozenset()
    assert result.values == catalogue.values


async def test_a_root_too_big_for_any_answer_costs_one_413_more(
    start_simulator: StartSimulator, session: aiohttp.ClientSession
) -> None:
    source = load_program("manual").to_mapping()
    source["variables"]["big"] = {"type": "ARRAY[0..199] OF BYTE", "value": [1] * 200}
    sim = await start_simulator(Program.from_mapping(source))
    sim.faults.rejected_by_object = {"arr1"}
    client = make_client(session, sim)

    catalogue = await client.discover()

    assert catalogue.skipped_groups == ("arr1", "big")
    stats = catalogue.discovery
    assert stats is not None
    # The first batch overflows (plcData is the first root above its share), then
    # the rest (big is): big, read alone to be sure, answers 413 once more.
    assert (stats.too_large, stats.overflowing_groups, stats.oversized_groups) == (
        3,
        2,
        1,
    )
    assert stats.too_large <= stats.overflowing_groups + stats.oversized_groups
    assert [record.status for record in sim.requests].count(413) == 3
    assert sim.requests[-1].query == "big"
