"""The Mervis source over real HTTP: identify, poll at the lower bound, qualities, writes."""

from dataclasses import replace
from datetime import UTC, datetime, timedelta
import math

import aiohttp
from aiohttp import web
import pytest

from custom_components.tecoapi.pyplc import (
    Access,
    InvalidValueError,
    NoPublicVariablesError,
    OutOfRangeError,
    PlcConnectionError,
    Quality,
    ReadOnlyError,
    Snapshot,
    VariableNotFoundError,
)
from custom_components.tecoapi.pyplc.core.pointmap import (
    MapPoint,
    PointMap,
    data_type,
)
from custom_components.tecoapi.pyplc.mervis import (
    IdStyle,
    MervisClient,
    MervisSource,
    RequestRefusedError,
)
from custom_components.tecoapi.pyplc.mervis.source import CUT_POLLS, boards
from custom_components.tecoapi.pyplc.mervis.vlist import load_vlist
from tests.pyplc.tekon.test_source import MemoryCache
from tests.simulator.mervis import MervisSimulator, generated, house

from .conftest import PASSWORD, Serve, StartMervis, source_of

HOUSE_POINTS = 64


def writable(
    point_map: PointMap,
    ident: str,
    minimum: float | None = None,
    maximum: float | None = None,
    **changes: object,
) -> PointMap:
    """The map with one point marked writable (what the options' point form does)."""
    point = point_map.by_key()[ident]
    changed = replace(
        point,
        access=Access.READ_WRITE,
        minimum=minimum,
        maximum=maximum,
        **changes,  # type: ignore[arg-type]
    )
    return point_map.with_point(changed)


async def test_identify_signs_in_and_proves_the_map_is_this_controller_s(
    http: aiohttp.ClientSession, mervis: MervisSimulator
) -> None:
    source = source_of(http, mervis)
    info = await source.identify()
    assert info.identity == f"Mervis Chata Lipno @ {mervis.host}"
    assert (info.name, info.program_name) == ("Chata Lipno", "Chata Lipno")
    assert (info.manufacturer, info.model) == ("Unipi Technology", "Mervis")
    assert info.running
    assert [record.service for record in mervis.requests] == ["login", "values"]
    assert mervis.requests[1].variables == 8
    assert source.configuration_url == mervis.url


async def test_the_platform_told_is_the_model(
    http: aiohttp.ClientSession, start_mervis: StartMervis
) -> None:
    sim = await start_mervis(tell_limits=True)
    assert (await source_of(http, sim).identify()).model == "Mervis uPLC"


async def test_another_project_s_file_is_refused(
    http: aiohttp.ClientSession, mervis: MervisSimulator
) -> None:
    foreign = load_vlist(generated(40, seed=3).vlist())
    with pytest.raises(VariableNotFoundError, match="knows 0 of 6 variables"):
        await source_of(http, mervis, foreign).identify()


async def test_a_controller_of_the_seed_s_spelling_is_spoken_to_in_it(
    http: aiohttp.ClientSession, start_mervis: StartMervis
) -> None:
    sim = await start_mervis(spelling="seed")
    source = source_of(http, sim)
    await source.identify()
    assert source.client.id_style is IdStyle.SEED
    snapshot = await source.poll(())
    assert snapshot.quality == {}


async def test_a_map_without_a_project_is_known_by_the_address(
    http: aiohttp.ClientSession, mervis: MervisSimulator
) -> None:
    text = mervis.project.vlist().replace("Chata Lipno;", ";")
    source = source_of(http, mervis, load_vlist(text))
    info = await source.identify()
    assert info.identity == f"Mervis {mervis.url}"
    assert (info.name, info.program_name) == ("Mervis", None)


async def test_discovery_reads_every_point_decoded_exactly(
    http: aiohttp.ClientSession, start_mervis: StartMervis
) -> None:
    clock = datetime(2026, 3, 14, 10, 0, 0, 250000, tzinfo=UTC)
    sim = await start_mervis(house(clock=lambda: clock))
    snapshot = await source_of(http, sim).poll(())
    assert len(snapshot.catalogue.points) == HOUSE_POINTS
    values = snapshot.values
    assert len(values) == HOUSE_POINTS
    assert values["koupelna.temperature"] == 21.5
    assert values["koupelna.heating"] is True
    assert values["koupelna.mode"] == 1
    assert values["kotel.starts"] == 1234
    assert values["kotel.runtime"] == timedelta(hours=813, minutes=20)
    assert values["energie.total"] == 15234.25
    assert values["clock"] == clock
    assert values["hw.neuron_l203_ro_2.02"] is True
    assert snapshot.catalogue.points["koupelna.setpoint"].device == "koupelna"
    assert snapshot.catalogue.devices["koupelna"].name == "Koupelna"
    assert snapshot.quality == {}


async def test_a_poll_reads_the_polled_points_at_the_lower_bound(
    http: aiohttp.ClientSession, start_mervis: StartMervis
) -> None:
    """Each function block once, sliced; IDs packed under the controller's limits."""
    sim = await start_mervis(max_variables=5, max_request_size=1500, tell_limits=True)
    source = source_of(http, sim)
    first = await source.poll(())
    polled = frozenset(
        key for key in first.catalogue.points if not key.startswith("hw")
    )
    sim.clear_requests()
    snapshot = await source.poll(polled)
    assert set(snapshot.values) == polled
    # 23 points in four function blocks, a struct and four top-level variables.
    assert [record.variables for record in sim.requests] == [5, 4]
    plan = source.read_plan
    assert plan is not None
    assert (plan.ids, len(plan.requests), plan.lower_bound) == (9, 2, 2)
    assert source.statistics.last_poll_requests == 2
    sim.project.set("jidelna.temperature", 23.25)
    assert (await source.poll(polled)).values["jidelna.temperature"] == 23.25


@pytest.mark.parametrize("count", [50, 300])
async def test_generated_projects_are_read_at_the_lower_bound(
    http: aiohttp.ClientSession, start_mervis: StartMervis, count: int
) -> None:
    sim = await start_mervis(
        generated(count, seed=1), tell_limits=True, max_variables=64
    )
    source = source_of(http, sim)
    polled = frozenset((await source.poll(())).catalogue.points)
    sim.clear_requests()
    snapshot = await source.poll(polled)
    assert len(snapshot.values) == count
    plan = source.read_plan
    assert plan is not None
    assert len(sim.requests) == len(plan.requests) == plan.lower_bound
    assert len(sim.requests) == math.ceil(plan.ids / 64)
    assert plan.ids < count


async def test_a_refused_poll_is_read_in_parts_and_planned_again(
    http: aiohttp.ClientSession, start_mervis: StartMervis
) -> None:
    sim = await start_mervis(max_variables=3)
    source = source_of(http, sim)
    first = await source.poll(())
    polled = frozenset(
        key for key in first.catalogue.points if not key.startswith("hw")
    )
    snapshot = await source.poll(polled)
    assert set(snapshot.values) == polled
    assert snapshot.quality == {}
    assert source.client.max_variables == 3
    sim.clear_requests()
    await source.poll(polled)
    assert [record.variables for record in sim.requests] == [3, 3, 3]
    assert {record.code for record in sim.requests} == {"ok"}


async def test_one_bad_item_costs_its_points_only(
    http: aiohttp.ClientSession, mervis: MervisSimulator
) -> None:
    source = source_of(http, mervis)
    polled = frozenset((await source.poll(())).catalogue.points)
    kotel = mervis.project.row("kotel.burner").commuid
    away = mervis.project.row("away").commuid
    mervis.switches.item_errors.add(kotel)
    mervis.switches.qualities[away] = "B"
    snapshot = await source.poll(polled)
    assert snapshot.quality["kotel.burner"].quality is Quality.BAD
    assert snapshot.quality["kotel.burner"].reason == "error: unknown variable"
    assert snapshot.quality["away"].reason == "quality: B"
    assert "kotel.starts" in snapshot.missing
    assert "away" not in snapshot.values
    assert snapshot.values["koupelna.temperature"] == 21.5
    assert len(snapshot.missing) == 6
    mervis.switches.item_errors.clear()
    mervis.switches.qualities.clear()
    again = await source.poll(polled)
    assert again.quality == {}
    assert again.values["kotel.burner"] is True


async def test_a_variable_refused_alone_costs_its_points_only(
    http: aiohttp.ClientSession, mervis: MervisSimulator
) -> None:
    point_map = load_vlist(mervis.project.vlist())
    wide = replace(
        point_map.by_key()["note"]
        if "note" in point_map.by_key()
        else point_map.points[0],
        id="wide",
        address="7001[0,4]",
    )
    source = source_of(http, mervis, point_map.with_new_point(wide))
    await source.poll(())
    mervis.switches.max_request_size = 10
    snapshot = await source.poll(frozenset({"wide"}))
    assert snapshot.quality["wide"].reason.startswith("refused: ")


async def test_a_value_of_the_wrong_width_is_bad(
    http: aiohttp.ClientSession, mervis: MervisSimulator
) -> None:
    point_map = load_vlist(mervis.project.vlist())
    row = mervis.project.row("outside_temp")
    wrong = MapPoint(
        id="too_long",
        name="Too long",
        address=f"{row.commuid}[0,8]",
        type=point_map.by_key()["energie.total"].type,
    )
    source = source_of(http, mervis, point_map.with_new_point(wrong))
    snapshot = await source.poll(())
    assert snapshot.quality["too_long"].reason == "error: unknown variable"
    dt_row = mervis.project.row("clock")
    mervis.project.write(dt_row.commuid, 0, b"\xff" * 8)
    snapshot = await source.poll(frozenset({"clock"}))
    assert snapshot.quality["clock"].reason.startswith("undecodable: ")


async def test_a_write_is_checked_sent_pushed_and_read_back(
    http: aiohttp.ClientSession, mervis: MervisSimulator
) -> None:
    point_map = writable(
        load_vlist(mervis.project.vlist()), "koupelna.setpoint", 15.0, 28.0
    )
    source = source_of(http, mervis, point_map)
    await source.poll(())
    told: list[Snapshot] = []
    source.subscribe(told.append)
    mervis.clear_requests()
    confirmed = await source.write("koupelna.setpoint", 23.5)
    assert [record.service for record in mervis.requests] == ["command", "values"]
    assert mervis.requests[0].variables == 1
    assert told[0].values == {"koupelna.setpoint": 23.5}
    assert confirmed is not None
    assert confirmed.values["koupelna.setpoint"] == 23.5
    assert mervis.project.get("koupelna.setpoint") == 23.5
    assert source.statistics.writes == 1


@pytest.mark.parametrize(
    ("key", "value", "error"),
    [
        ("koupelna.setpoint", 40.0, OutOfRangeError),
        ("koupelna.setpoint", "warm", InvalidValueError),
        ("kotel.starts", -1, InvalidValueError),
        ("kotel.starts", 2**32, InvalidValueError),
        ("outside_temp", 1e39, InvalidValueError),
        ("koupelna.temperature", 20.0, ReadOnlyError),
        ("boost", timedelta(seconds=-1), InvalidValueError),
    ],
)
async def test_a_value_that_does_not_fit_is_refused_and_nothing_is_sent(
    http: aiohttp.ClientSession,
    mervis: MervisSimulator,
    key: str,
    value: object,
    error: type[Exception],
) -> None:
    point_map = load_vlist(mervis.project.vlist())
    point_map = writable(point_map, "koupelna.setpoint", 15.0, 28.0)
    for ident in ("kotel.starts", "outside_temp", "boost"):
        point_map = writable(point_map, ident)
    source = source_of(http, mervis, point_map)
    await source.poll(())
    mervis.clear_requests()
    with pytest.raises(error):
        await source.write(key, value)
    assert mervis.requests == []
    assert mervis.writes == []


async def test_a_scaled_point_is_written_raw(
    http: aiohttp.ClientSession, mervis: MervisSimulator
) -> None:
    point_map = writable(
        load_vlist(mervis.project.vlist()), "kotel.starts", scale=0.5, offset=10.0
    )
    source = source_of(http, mervis, point_map)
    snapshot = await source.poll(())
    assert snapshot.values["kotel.starts"] == 1234 * 0.5 + 10
    await source.write("kotel.starts", 110.0)
    assert mervis.project.get("kotel.starts") == 200


async def test_writes_of_every_kind(
    http: aiohttp.ClientSession, mervis: MervisSimulator
) -> None:
    point_map = load_vlist(mervis.project.vlist())
    for ident in ("away", "boost", "clock", "koupelna.mode", "energie.total"):
        point_map = writable(point_map, ident)
    source = source_of(http, mervis, point_map)
    await source.poll(())
    moment = datetime(2026, 12, 24, 18, 0, tzinfo=UTC)
    for key, value in (
        ("away", True),
        ("boost", timedelta(hours=2)),
        ("clock", moment),
        ("koupelna.mode", 3),
        ("energie.total", 1.5),
    ):
        await source.write(key, value)
        assert mervis.project.get(key) == value


async def test_a_write_the_controller_refuses_is_not_a_failure_of_the_source(
    http: aiohttp.ClientSession, mervis: MervisSimulator
) -> None:
    point_map = writable(load_vlist(mervis.project.vlist()), "away")
    source = source_of(http, mervis, point_map)
    await source.poll(())
    mervis.switches.write_encoding = "both"
    mervis.project.rows.remove(mervis.project.row("away"))
    with pytest.raises(Exception, match="unknown variable"):
        await source.write("away", True)
    assert source.statistics.failed_writes == 0
    assert source.recent_errors == ()


async def test_a_read_back_that_fails_leaves_it_to_the_next_poll(
    http: aiohttp.ClientSession, mervis: MervisSimulator
) -> None:
    point_map = writable(load_vlist(mervis.project.vlist()), "away")
    source = source_of(http, mervis, point_map)
    await source.poll(())
    mervis.switches.max_variables = 0
    assert await source.write("away", True) is not None
    assert mervis.project.get("away") is True


async def test_points_by_path_and_some_points_now(
    http: aiohttp.ClientSession, mervis: MervisSimulator
) -> None:
    point_map = writable(load_vlist(mervis.project.vlist()), "away")
    source = source_of(http, mervis, point_map)
    assert await source.read_points(["away"]) is None
    await source.poll(())
    assert await source.read_variable("Away") is False
    await source.write_variable("away", True)
    assert mervis.project.get("away") is True
    snapshot = await source.read_points(["away", "nothing"])
    assert snapshot is not None
    assert snapshot.values == {"away": True}
    assert await source.read_points(["nothing"]) is None
    with pytest.raises(VariableNotFoundError):
        await source.read_variable("nothing.here")
    with pytest.raises(VariableNotFoundError):
        await source.write_variable("nothing.here", 1)
    mervis.switches.item_errors.add(mervis.project.row("away").commuid)
    with pytest.raises(VariableNotFoundError, match="unknown variable"):
        await source.read_variable("away")


async def test_nothing_answering_fails_the_poll_and_the_next_good_one_recovers(
    http: aiohttp.ClientSession, mervis: MervisSimulator
) -> None:
    source = source_of(http, mervis, timeout=2)
    first = await source.poll(())
    polled = frozenset(first.catalogue.points)
    port = mervis.port
    await mervis.stop()
    with pytest.raises(PlcConnectionError):
        await source.poll(polled)
    assert source.statistics.failed_polls == 1
    await mervis.start(port=port)
    assert len((await source.poll(polled)).values) == HOUSE_POINTS


async def test_diagnostics_tell_the_plan_and_never_the_credentials(
    http: aiohttp.ClientSession, mervis: MervisSimulator
) -> None:
    source = source_of(http, mervis)
    polled = frozenset((await source.poll(())).catalogue.points)
    mervis.switches.item_errors.add(mervis.project.row("away").commuid)
    await source.poll(polled)
    diagnostics = source.diagnostics()
    assert diagnostics["points"] == HOUSE_POINTS
    plans = diagnostics["read_plans"]
    assert plans["values"]["requests"] == 1
    assert plans["bad_points"] == {"away": "error: unknown variable"}
    assert plans["id_style"] == "svc://DefaultConnection/"
    assert diagnostics["requests"]["logins"] == 1
    text = repr(diagnostics)
    assert PASSWORD not in text
    assert str(source.client.session_credentials["p"]) not in text
    await source.close()


async def test_a_point_without_an_address_is_bad(
    http: aiohttp.ClientSession, mervis: MervisSimulator
) -> None:
    point_map = load_vlist(mervis.project.vlist())
    away = point_map.by_key()["away"]
    source = source_of(
        http, mervis, point_map.with_point(replace(away, address="nowhere"))
    )
    discovered = await source.poll(())
    assert "away" not in discovered.values
    polled = await source.poll(frozenset(discovered.catalogue.points))
    assert "away" not in polled.values
    assert len(polled.values) == HOUSE_POINTS - 1
    quality = polled.quality["away"]
    assert (quality.quality, quality.reason) == (Quality.BAD, "no address")
    assert source.diagnostics()["read_plans"]["bad_points"] == {"away": "no address"}


def test_a_source_is_made_with_no_request(http: aiohttp.ClientSession) -> None:
    source = MervisSource(
        MervisClient(http, "unipi.local"), load_vlist(house().vlist())
    )
    assert source.read_plan is None
    assert source.client.request_count == 0


async def test_limits_lowered_later_split_a_poll_and_are_learned(
    http: aiohttp.ClientSession, mervis: MervisSimulator
) -> None:
    source = source_of(http, mervis)
    first = await source.poll(())
    polled = frozenset(
        key for key in first.catalogue.points if not key.startswith("hw")
    )
    await source.poll(polled)
    mervis.switches.max_variables = 2
    # Each poll reads every point; a few refusals find the new limit.
    for _ in range(3):
        snapshot = await source.poll(polled)
        assert set(snapshot.values) == polled
        assert snapshot.quality == {}
    assert source.client.max_variables == 2
    mervis.clear_requests()
    await source.poll(polled)
    assert {record.code for record in mervis.requests} == {"ok"}
    assert len(mervis.requests) == 5


async def test_a_project_without_credentials(
    http: aiohttp.ClientSession, start_mervis: StartMervis
) -> None:
    sim = await start_mervis(username=None)
    source = source_of(http, sim, username="")
    snapshot = await source.poll(())
    assert len(snapshot.values) == HOUSE_POINTS
    assert {record.service for record in sim.requests} == {"values"}


async def test_a_controller_refusing_one_variable_fails_identify(
    http: aiohttp.ClientSession, start_mervis: StartMervis
) -> None:
    sim = await start_mervis(max_request_size=60)
    with pytest.raises(RequestRefusedError, match="request too large"):
        await source_of(http, sim).identify()


async def test_a_map_of_nothing_readable_is_refused(
    http: aiohttp.ClientSession, mervis: MervisSimulator
) -> None:
    point_map = load_vlist(mervis.project.vlist())
    nowhere = PointMap(
        tuple(replace(point, address="nowhere") for point in point_map.points[:3])
    )
    with pytest.raises(NoPublicVariablesError):
        await source_of(http, mervis, nowhere).identify()


async def test_answers_that_miss_a_variable_or_its_bytes(
    http: aiohttp.ClientSession, serve: Serve
) -> None:
    """A controller answering one item short, another of the wrong length."""
    item = {"q": "G", "t": 0}

    async def panel(request: web.Request) -> web.Response:
        asked = (await request.json())["v"]
        if "set" in str(asked):
            return web.json_response({"ver": 1, "code": "ok"})
        if len(asked) == 1 and "[0,1]" not in asked[0]:
            return web.Response(status=500, text="busy")
        answered = [
            {"i": ident, "v": "00" if "[0,1]" in ident else "0102", **item}
            for ident in asked
            if not ident.endswith("/2[0,1]")
        ]
        return web.json_response({"ver": 1, "code": "ok", "v": answered})

    text = (
        "#ver:1.0\nProject;Name;Type;CommUid;Offset;Length;ParentTypeFamily;HistoryId\n"
        "P;$a$;$bool$;1;0;1;none;\nP;$b$;$bool$;2;0;1;none;\nP;$c$;$real$;3;0;4;none;\n"
        "P;$d$;$bool$;4;0;1;none;\nP;$e$;$bool$;5;0;1;none;\n"
    )
    point_map = writable(load_vlist(text), "c")
    source = MervisSource(MervisClient(http, await serve(panel)), point_map)
    snapshot = await source.poll(())
    assert snapshot.values == {"a": False, "d": False, "e": False}
    assert snapshot.quality["b"].reason == "not answered"
    assert snapshot.quality["c"].reason == "wrong length"
    # The write is taken; its read-back fails: the next poll tells.
    assert await source.write("c", 1.5) is None


# --- identity: two units of one project -------------------------------------------------


async def test_two_units_of_one_project_are_two_controllers(
    http: aiohttp.ClientSession, start_mervis: StartMervis
) -> None:
    """The web panel tells nothing of the device: the address it is added at tells them apart."""
    first, second = await start_mervis(), await start_mervis()
    one = await source_of(http, first).identify()
    other = await source_of(http, second).identify()
    assert one.identity == f"Mervis Chata Lipno @ {first.host}"
    assert other.identity == f"Mervis Chata Lipno @ {second.host}"


@pytest.mark.parametrize(
    ("kept", "project", "identity"),
    [
        # An entry's own, wherever its controller is now.
        ("Mervis Chata Lipno", "Chata Lipno", "Mervis Chata Lipno"),
        (
            "Mervis Chata Lipno @ 10.0.0.7",
            "Chata Lipno",
            "Mervis Chata Lipno @ 10.0.0.7",
        ),
        ("Mervis http://10.0.0.7", "", "Mervis http://10.0.0.7"),
        ("Mervis A @ B @ 10.0.0.7", "A @ B", "Mervis A @ B @ 10.0.0.7"),
        # Numbered by the config flow (an entry added at that address moved away).
        (
            "Mervis Chata Lipno @ 10.0.0.7 (2)",
            "Chata Lipno",
            "Mervis Chata Lipno @ 10.0.0.7 (2)",
        ),
        ("Mervis http://10.0.0.7 (2)", "", "Mervis http://10.0.0.7 (2)"),
        # A map of another project is not the entry's controller.
        ("Mervis Chata", "Chata Lipno", "Mervis Chata Lipno @ {host}"),
        ("Mervis Chata @ 10.0.0.7", "Chata Lipno", "Mervis Chata Lipno @ {host}"),
        ("Mervis A @ 10.0.0.7", "A @ B", "Mervis A @ B @ {host}"),
        ("Mervis Chata Lipno", "", "Mervis {url}"),
        ("Mervis http://10.0.0.7", "http", "Mervis http @ {host}"),
    ],
)
async def test_an_entry_s_identity_stays_as_long_as_the_map_is_its_project_s(
    http: aiohttp.ClientSession,
    mervis: MervisSimulator,
    kept: str,
    project: str,
    identity: str,
) -> None:
    point_map = load_vlist(mervis.project.vlist())
    point_map = replace(point_map, properties={"project": project})
    source = MervisSource(source_of(http, mervis).client, point_map, identity=kept)
    assert source.identity == identity.format(host=mervis.host, url=mervis.url)


# --- limits: refused, learned, kept ----------------------------------------------------


def refusals(sim: MervisSimulator) -> int:
    return sum(1 for record in sim.requests if record.code not in ("ok", ""))


async def test_a_limit_refusal_costs_no_sign_in(
    http: aiohttp.ClientSession, start_mervis: StartMervis
) -> None:
    """The seed's uPLC (5 IDs, 1,500 bytes), told nothing: two refusals, one sign-in.

    Each refusal was met by signing in again (47 requests, 18 refused, 10
    sign-ins before): ``too many variables`` speaks of a limit, not a session.
    """
    sim = await start_mervis(max_variables=5, max_request_size=1500)
    source = source_of(http, sim)
    await source.poll(())
    assert (len(sim.requests), refusals(sim), sim.count("login")) == (16, 2, 1)
    assert (source.client.max_variables, source.client.logins) == (5, 1)
    sim.clear_requests()
    await source.poll(source.point_map.by_key())
    assert (len(sim.requests), refusals(sim)) == (10, 0)


async def test_the_limits_kept_let_a_restart_refuse_nothing(
    http: aiohttp.ClientSession, start_mervis: StartMervis
) -> None:
    sim = await start_mervis(max_variables=5, max_request_size=1500)
    cache = MemoryCache()
    first = MervisSource(
        source_of(http, sim).client, load_vlist(sim.project.vlist()), cache=cache
    )
    await first.poll(())
    await first.poll(())
    assert cache.saves >= 1
    saves = cache.saves
    await first.poll(())
    assert cache.saves == saves  # nothing new learned: nothing written
    sim.clear_requests()
    again = MervisSource(
        source_of(http, sim).client, load_vlist(sim.project.vlist()), cache=cache
    )
    await again.poll(())
    assert refusals(sim) == 0
    assert (again.client.max_variables, again.client.logins) == (5, 1)
    assert len(sim.requests) == 1 + 2 + 10  # sign-in, the sample, every point


KEPT = {
    "max_variables": 5,
    "max_request_size": 1500,
    "told": False,
    "taken": [5, 257],
    "refused": [6, None],
    "platform": None,
}
"""Limits as a store keeps them."""


async def test_limits_kept_as_told_that_the_controller_lowered_are_learned_again(
    http: aiohttp.ClientSession, start_mervis: StartMervis
) -> None:
    """The store holds 10 IDs the controller told; it takes 5 now, telling nothing.

    A refusal within told limits taught nothing: every poll was refused and
    read in parts again, and the store kept the 10.
    """
    sim = await start_mervis(max_variables=5, max_request_size=1500)
    cache = MemoryCache()
    told = {**KEPT, "max_variables": 10, "told": True, "taken": [10, 500]}
    cache.data = {"version": 1, "limits": {**told, "refused": [None, None]}}
    source = MervisSource(
        source_of(http, sim).client, load_vlist(sim.project.vlist()), cache=cache
    )
    await source.poll(())
    assert source.client.max_variables == 5
    assert (cache.data["limits"]["max_variables"], cache.data["limits"]["told"]) == (
        5,
        False,
    )
    sim.clear_requests()
    await source.poll(source.point_map.by_key())
    assert (len(sim.requests), refusals(sim)) == (10, 0)


@pytest.mark.parametrize(
    "kept",
    [
        None,
        "limits",
        {"version": 2, "limits": KEPT},
        {"version": 1, "limits": []},
        {"version": 1, "limits": {**KEPT, "max_variables": 0}},
        {"version": 1, "limits": {**KEPT, "told": "no"}},
        {"version": 1, "limits": {**KEPT, "taken": [5, None]}},
        {"version": 1, "limits": {**KEPT, "refused": [6, -1]}},
        {"version": 1, "limits": {**KEPT, "platform": 3}},
    ],
)
async def test_a_store_of_another_shape_is_learned_again(
    http: aiohttp.ClientSession, mervis: MervisSimulator, kept: object
) -> None:
    cache = MemoryCache()
    cache.data = kept
    source = MervisSource(
        source_of(http, mervis).client,
        load_vlist(mervis.project.vlist()),
        cache=cache,
    )
    await source.identify()
    assert source.client.limits_state() == {
        "max_variables": 64,
        "max_request_size": 4096,
        "told": False,
        "taken": [8, mervis.requests[-1].body_bytes],
        "refused": [None, None],
        "platform": None,
    }


async def test_a_refusal_that_teaches_nothing_smaller_stands(
    http: aiohttp.ClientSession, start_mervis: StartMervis
) -> None:
    """identify() never sends the same refused request again (it would, forever)."""

    class Stubborn(MervisClient):
        def learn_refusal(self, err: RequestRefusedError) -> bool:
            return True  # "a smaller one may pass", the limits unchanged

    sim = await start_mervis(max_variables=2)
    client = Stubborn(http, sim.url, "admin", PASSWORD)
    source = MervisSource(client, load_vlist(sim.project.vlist()))
    with pytest.raises(RequestRefusedError, match="too many variables"):
        await source.identify()
    assert sim.count("values") == 1


def test_the_boards_are_those_the_hw_inputs_and_outputs_name() -> None:
    """A board's name comes before its I/O's kind and group; other names name none."""
    flag = data_type("bool")
    assert flag is not None
    point_map = PointMap(
        tuple(
            MapPoint(id=path, name=path, address="1[0,1]", type=flag)
            for path in (
                "hw.neuron_l203_di_1.01",
                "hw.NEURON_L203_ro_2.04",
                "hw.neuron_s103_ai_1.01",
                "hw.neuron_s103_di_1.04_counter",
                "hw.neuron_l203_reg_1000",
                "kotel.hw_di_1.01",
                "hw_di_1.01",
            )
        ),
        format="vlist",
    )
    assert boards(point_map) == ["neuron_l203", "neuron_s103"]


# --- one bad member of a block: found, read apart, the rest read --------------------------


def with_bad_member(sim: MervisSimulator, address: str = "6003[60,1]") -> PointMap:
    """The house's map with a point past the end of the Kotel block (a typo's)."""
    point_map = load_vlist(sim.project.vlist())
    flag = point_map.by_key()["kotel.burner"]
    return point_map.with_new_point(
        replace(flag, id="kotel.test", name="Kotel test", address=address)
    )


KOTEL = ("kotel.water_temp", "kotel.return_temp", "kotel.burner", "kotel.starts")


async def test_a_bad_member_of_a_block_costs_itself_only(
    http: aiohttp.ClientSession, mervis: MervisSimulator
) -> None:
    """The block's range is refused: its parts are read in one more request.

    Every other member of the block was unavailable, for good, with the
    controller's error as if it were theirs, and nothing said which point was
    at fault.
    """
    source = source_of(http, mervis, with_bad_member(mervis))
    snapshot = await source.poll(())
    # Sign in, the sample, every point (50 IDs), the block's six members apart.
    assert [(r.service, r.variables) for r in mervis.requests] == [
        ("login", 0),
        ("values", 8),
        ("values", 50),
        ("values", 6),
    ]
    assert set(snapshot.values) == set(snapshot.catalogue.points) - {"kotel.test"}
    refused = snapshot.quality["kotel.test"]
    assert (refused.quality, refused.reason, refused.code) == (
        Quality.BAD,
        "error: unknown variable",
        "unknown variable",
    )
    assert set(snapshot.quality) == {"kotel.test"}
    # From now on the block is one range without it, and it one of its own.
    polled = frozenset(snapshot.catalogue.points)
    mervis.clear_requests()
    for _ in range(3):
        snapshot = await source.poll(polled)
        assert set(snapshot.quality) == {"kotel.test"}
        assert snapshot.values["kotel.burner"] is True
    assert [r.variables for r in mervis.requests] == [51, 51, 51]
    plan = source.read_plan
    assert plan is not None
    kotel = [
        str(read.address)
        for request in plan.requests
        for read in request.reads
        if read.address.commuid == 6003
    ]
    assert kotel == ["6003[0,21]", "6003[60,1]"]
    diagnostics = source.diagnostics()["read_plans"]
    assert diagnostics["bad_points"] == {"kotel.test": "error: unknown variable"}
    assert diagnostics["read_apart"] == ["kotel.test"]
    assert diagnostics["cuts"] == []


async def test_the_search_under_the_controller_s_limits_takes_a_read_more(
    http: aiohttp.ClientSession, start_mervis: StartMervis
) -> None:
    """The seed's uPLC (5 IDs a request, told): one request more a read, twice.

    The block's six members in five parts: the last (runtime and the bad one)
    is refused again, its points wait for the next read, whose one more
    request parts those two.
    """
    sim = await start_mervis(max_variables=5, max_request_size=1500, tell_limits=True)
    source = source_of(http, sim, with_bad_member(sim))
    first = await source.poll(())
    polled = frozenset(
        key for key in first.catalogue.points if not key.startswith("hw")
    )
    assert set(first.quality) == {"kotel.runtime", "kotel.test"}
    assert first.quality["kotel.runtime"].code is None
    assert {key: first.values[key] for key in KOTEL} == {
        "kotel.water_temp": 58.5,
        "kotel.return_temp": 44.0,
        "kotel.burner": True,
        "kotel.starts": 1234,
    }
    sim.clear_requests()
    second = await source.poll(polled)
    # 9 IDs, the block in five of them: 13 in three requests; the search's two.
    assert [r.variables for r in sim.requests] == [5, 5, 3, 2]
    assert set(second.quality) == {"kotel.test"}
    assert second.values["kotel.runtime"] == timedelta(hours=813, minutes=20)
    sim.clear_requests()
    third = await source.poll(polled)
    assert [r.variables for r in sim.requests] == [5, 5]
    assert set(third.quality) == {"kotel.test"}
    assert set(third.values) == polled - {"kotel.test"}


async def test_a_point_read_apart_that_reads_again_rejoins_its_block(
    http: aiohttp.ClientSession, mervis: MervisSimulator
) -> None:
    source = source_of(http, mervis, with_bad_member(mervis))
    polled = frozenset((await source.poll(())).catalogue.points)
    # The program grows the block: the point is there now.
    mervis.project.memory[6003].extend(b"\x01" * 40)
    for _ in range(3):
        snapshot = await source.poll(polled)
        assert snapshot.quality == {}
        assert snapshot.values["kotel.test"] is True
    mervis.clear_requests()
    await source.poll(polled)
    assert [r.variables for r in mervis.requests] == [50]
    assert source.diagnostics()["read_plans"]["read_apart"] == []


async def test_a_controller_refusing_everything_is_not_searched(
    http: aiohttp.ClientSession, mervis: MervisSimulator
) -> None:
    """A project downloaded anew: nothing tells a point at fault, nothing is cut."""
    source = source_of(http, mervis)
    polled = frozenset((await source.poll(())).catalogue.points)
    mervis.switches.item_errors.update(row.commuid for row in mervis.project.rows)
    mervis.clear_requests()
    snapshot = await source.poll(polled)
    assert [r.variables for r in mervis.requests] == [50]
    assert snapshot.values == {}
    assert len(snapshot.quality) == HOUSE_POINTS
    assert {quality.code for quality in snapshot.quality.values()} == {None}
    assert source.diagnostics()["read_plans"]["read_apart"] == []
    mervis.switches.item_errors.clear()
    mervis.clear_requests()
    assert (await source.poll(polled)).quality == {}
    assert [r.variables for r in mervis.requests] == [50]


async def test_a_range_refused_whose_parts_all_read_is_cut_for_a_while(
    http: aiohttp.ClientSession, serve: Serve
) -> None:
    """A controller refusing reads of more than 8 bytes: the 12-byte block is cut.

    Both parts read, so no point is at fault: the cut stays for CUT_POLLS
    polls, then the block is read whole again, refused, and cut again.
    """

    async def panel(request: web.Request) -> web.Response:
        asked = (await request.json())["v"]
        answered = []
        for ident in asked:
            length = int(ident.rsplit(",", 1)[1].rstrip("]"))
            if length > 8:
                answered.append({"i": ident, "e": "too long"})
            else:
                answered.append({"i": ident, "v": "00" * length, "q": "G", "t": 0})
        return web.json_response({"ver": 1, "code": "ok", "v": answered})

    text = (
        "#ver:1.0\nProject;Name;Type;CommUid;Offset;Length;ParentTypeFamily;HistoryId\n"
        "P;$b$.$x$;$real$;1;0;4;fb;\nP;$b$.$y$;$real$;1;4;4;fb;\n"
        "P;$b$.$z$;$real$;1;8;4;fb;\nP;$c$;$bool$;2;0;1;none;\n"
    )
    source = MervisSource(MervisClient(http, await serve(panel)), load_vlist(text))
    polled = frozenset((await source.poll(())).catalogue.points)
    counts = []
    for _ in range(CUT_POLLS + 1):
        before = source.client.request_count
        snapshot = await source.poll(polled)
        assert snapshot.quality == {}
        counts.append(source.client.request_count - before)
    # The cut's 29 polls of one request; the whole block again: refused, cut.
    assert counts == [1] * (CUT_POLLS - 1) + [2, 1]
    assert source.diagnostics()["read_plans"]["cuts"] == ["b.y", "b.z"]


async def test_a_variable_of_another_connection_is_read_through_it(
    http: aiohttp.ClientSession, start_mervis: StartMervis
) -> None:
    """The seed's data request names ``svc:otherConnection/…``: a map may address one."""
    sim = await start_mervis(spelling="seed")
    other = generated(20, seed=4)
    sim.connections["plc2"] = other
    row = next(row for row in other.rows if row.type == "real" and row.family == "none")
    point_map = load_vlist(sim.project.vlist())
    remote = replace(
        point_map.by_key()["outside_temp"],
        id="plc2.temperature",
        address=f"svc:PLC2/{row.commuid}[0,4]",
    )
    source = source_of(http, sim, point_map.with_new_point(remote))
    snapshot = await source.poll(())
    assert snapshot.values["plc2.temperature"] == pytest.approx(other.get(row.key))
    assert snapshot.quality == {}
    assert any(record.variables and record.code == "ok" for record in sim.requests)
