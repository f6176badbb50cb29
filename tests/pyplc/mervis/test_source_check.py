"""A point a user typed, checked on the controller before it is taken.

``check_points`` signs in and reads the typed points once (the planner's
request); a point the controller refuses comes back with its reason, after one
more read in the other ID spelling (a controller may know only the seed's).
"""

import aiohttp

from custom_components.tecoapi.pyplc import PointQuality, Quality
from custom_components.tecoapi.pyplc.core.pointmap import PointMap, point_of
from custom_components.tecoapi.pyplc.mervis.descriptor import check_address
from custom_components.tecoapi.pyplc.mervis.ids import IdStyle
from tests.pyplc.mervis.conftest import StartMervis, source_of
from tests.simulator.mervis import HOUSE_NAME, MervisSimulator


def typed(*rows: tuple[str, str, str]) -> PointMap:
    """A map of points typed in a form (ID, address, type) of the house's project."""
    points = tuple(
        point_of(
            {"id": ident, "name": ident, "address": address, "type": type_name},
            check_address,
        )
        for ident, address, type_name in rows
    )
    return PointMap(points, "vlist", properties={"project": HOUSE_NAME})


async def test_a_typed_point_is_read_once(
    http: aiohttp.ClientSession, mervis: MervisSimulator
) -> None:
    """``6003[9,4]``: the boiler's starts, 4 bytes from byte 9 of CommUid 6003."""
    source = source_of(http, mervis, typed(("kotel.test", "6003[9,4]", "UDINT")))
    assert await source.check_points({"kotel.test"}) == {}
    assert [record.service for record in mervis.requests] == ["login", "values"]
    assert mervis.requests[1].variables == 1


async def test_a_typed_point_past_its_block_is_refused_with_the_reason(
    http: aiohttp.ClientSession, mervis: MervisSimulator
) -> None:
    """The boiler's block is 21 bytes: ``6003[60,1]`` is no variable of it."""
    source = source_of(
        http,
        mervis,
        typed(("kotel.test", "6003[60,1]", "BOOL"), ("di", "17000[0,1]", "BOOL")),
    )
    refused = await source.check_points({"kotel.test", "di", "nothing"})
    assert refused == {
        "kotel.test": PointQuality(
            quality=Quality.BAD,
            reason="error: unknown variable",
            code="unknown variable",
        ),
        "nothing": PointQuality(quality=Quality.BAD, reason="not_found"),
    }
    # Read, then the refused one again in the other spelling, which knows no more.
    assert [record.service for record in mervis.requests] == [
        "login",
        "values",
        "values",
    ]
    assert [record.variables for record in mervis.requests[1:]] == [2, 1]
    assert source.client.id_style is IdStyle.RELEASED


async def test_a_controller_of_the_seed_s_spelling_reads_a_typed_point(
    http: aiohttp.ClientSession, start_mervis: StartMervis
) -> None:
    sim = await start_mervis(spelling="seed")
    source = source_of(http, sim, typed(("kotel.test", "6003[9,4]", "UDINT")))
    assert await source.check_points({"kotel.test"}) == {}
    assert source.client.id_style is IdStyle.SEED
    assert len(sim.requests) == 3  # login, the released spelling, the seed's
