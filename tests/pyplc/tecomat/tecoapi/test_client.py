"""The client against the simulated PLC over real HTTP: info, discovery, polling."""

from datetime import UTC, date, datetime

import aiohttp
import pytest

from custom_components.tecoapi.pyplc import (
    DiscoveryCost,
    InvalidHostError,
    PlcMode,
    PlcResponseError,
    ValueKind,
    VariableNotFoundError,
)
from custom_components.tecoapi.pyplc.core.scalars import as_duration
from custom_components.tecoapi.pyplc.tecomat import (
    PlannedRequest,
    ReadPlan,
    TecoApiClient,
)
from custom_components.tecoapi.pyplc.tecomat.points import (
    api_object_attributes,
    tecomat_point,
    value_path,
)
from custom_components.tecoapi.pyplc.tecomat.tecoapi.info import item_limit_for_type
from custom_components.tecoapi.pyplc.tecomat.tecoapi.paths import get_object_target
from tests.pyplc.conftest import StartSimulator, make_client
from tests.simulator import Program, Simulator, load_program

MANUAL_OBJECTS = {
    "main.myobject1": api_object_attributes(
        title="outside temperature",
        units="°C",
        read_only=True,
        min_value=0.0,
        max_value=0.0,
        enable=True,
        visibility=True,
    ),
    "main.myobject2": api_object_attributes(
        title="inside temperature",
        units="°C",
        read_only=True,
        min_value=0.0,
        max_value=0.0,
        enable=True,
        visibility=True,
    ),
    "main.myobject3": api_object_attributes(
        title="requested temperature",
        units="°C",
        read_only=False,
        min_value=10.0,
        max_value=30.0,
        enable=True,
        visibility=True,
    ),
}


def _authorized(sim: Simulator) -> list[str]:
    """The services the simulator answered after authentication, in order."""
    return [record.service for record in sim.requests if record.authorized]


async def test_get_info_of_the_manual_plc(
    manual_client: TecoApiClient, manual_simulator: Simulator
) -> None:
    assert manual_client.item_limit == 128
    info = await manual_client.get_info()
    assert info.family == "sim"
    assert info.model == "CP-W32"
    assert info.serial_number == "VN 1957"
    assert info.firmware == "sim CP-W32I v1.1"
    assert info.mac == "00:15:af:cb:4e:7d"
    assert info.mode is PlcMode.RUNNING
    assert info.program_name == "DOC_TECOAPI v1.0"
    assert info.program_compiled == datetime(2018, 1, 18, 16, 36, 46, tzinfo=UTC)
    assert info.program_stamp == manual_simulator.stamp
    assert info.api_version == "TecoApi v1.0.0"
    assert info.time is not None
    assert abs((info.time - datetime.now(UTC)).total_seconds()) < 60
    assert manual_client.item_limit == item_limit_for_type(info.model) == 128


async def test_get_info_learns_the_cp2xxx_limit_and_the_mode(
    client: TecoApiClient, simulator: Simulator
) -> None:
    simulator.mode = "HALT"
    info = await client.get_info()
    assert info.model == "CP-2080"
    assert info.mode is PlcMode.STOPPED
    assert client.item_limit == 256


async def test_base_url_is_normalised(session: aiohttp.ClientSession) -> None:
    assert TecoApiClient(session, "plc.local:8080", "u", "p").base_url == (
        "http://plc.local:8080"
    )
    with pytest.raises(InvalidHostError):
        TecoApiClient(session, "plc.local/TecoApi", "u", "p")


async def test_manual_catalogue_has_the_chapter_5_3_objects(
    manual_client: TecoApiClient, manual_simulator: Simulator
) -> None:
    catalogue = await manual_client.discover()
    assert catalogue.groups == (
        "plcName",
        "plcType",
        "plcDesc",
        "plcData",
        "myObject",
        "arr1",
        "arr2",
        "arr3",
        "Main",
    )
    assert catalogue.skipped_groups == ()
    api_objects = {
        key: point.attributes
        for key, point in catalogue.points.items()
        if point.attributes is not None
    }
    assert api_objects == MANUAL_OBJECTS
    for key in MANUAL_OBJECTS:
        point = catalogue.points[key]
        assert point.kind is ValueKind.REAL
        assert point.path == f"Main.myObject{key[-1]}"
    assert not catalogue.points["main.myobject1"].writable
    assert not catalogue.points["main.myobject2"].writable
    assert catalogue.points["main.myobject3"].writable
    assert catalogue.values["main.myobject1"] == -0.5
    assert catalogue.values["main.myobject2"] == 22.1
    assert catalogue.values["main.myobject3"] == 23.0
    # Every leaf of the chapter 4/5 variables is a plain point of the right kind.
    plain = catalogue.points
    assert plain["plcdata.varreal"].kind is ValueKind.REAL
    assert plain["plcdata.varbyte"].kind is ValueKind.INTEGER
    assert plain["plcdata.vartime"].kind is ValueKind.TIME
    assert plain["plcdata.vardate"].kind is ValueKind.DATE
    assert plain["plcdata.vardt"].kind is ValueKind.DATETIME
    assert plain["plcdata.varbool1"].kind is ValueKind.BOOL
    assert plain["myobject.favorites.color"].kind is ValueKind.STRING
    assert catalogue.values["myobject.favorites.color"] == '"Blue"'
    assert catalogue.values["plcdata.vardate"] == date(2015, 6, 17)
    assert [key for key in plain if key.startswith("arr1")] == [
        f"arr1[{index}]" for index in range(6)
    ]
    assert plain["arr2[2][3]"].path == "arr2[2][3]"
    assert catalogue.values["arr2[2][3]"] == 2.3
    assert catalogue.values["arr3[1][2][3]"] == 123
    assert len(plain) == 84
    # Values match the PLC's, point by point.
    for key, point in plain.items():
        expected = manual_simulator.get_value(value_path(point))
        if point.kind in (ValueKind.DATE, ValueKind.DATETIME):
            assert catalogue.values[key] is not None
        elif point.kind is ValueKind.TIME:
            assert catalogue.values[key] == as_duration(expected), key
        else:
            assert catalogue.values[key] == expected, key


async def test_manual_discovery_and_poll_request_counts(
    manual_client: TecoApiClient, manual_simulator: Simulator
) -> None:
    catalogue = await manual_client.discover()
    # One challenge, GetList, one GetObject of all nine roots.
    assert manual_client.request_count == 3
    assert catalogue.discovery is not None
    assert (catalogue.discovery.requests, catalogue.discovery.lower_bound) == (2, 2)
    assert catalogue.discovery.too_large == 0
    assert len(manual_simulator.requests) == 3
    assert _authorized(manual_simulator) == ["GetList", "GetObject"]

    for with_attrs in (False, True):
        manual_simulator.clear_requests()
        before = manual_client.request_count
        plan = manual_client.plan(catalogue.points.values(), with_attrs=with_attrs)
        result = await manual_client.read(plan, catalogue.points)
        assert len(plan.requests) == plan.lower_bound == 1
        assert manual_client.request_count - before == 1
        assert [record.status for record in manual_simulator.requests] == [200]
        assert result.missing == frozenset()
        assert result.values == catalogue.values
        assert set(result.attributes) == (set(MANUAL_OBJECTS) if with_attrs else set())
    # Without attributes only the three values of Main are read.
    plan = manual_client.plan(catalogue.points.values(), with_attrs=False)
    assert plan.requests[0].names[-3:] == (
        "Main.myObject1.value",
        "Main.myObject2.value",
        "Main.myObject3.value",
    )


async def test_demo_discovery_and_poll_request_counts(
    client: TecoApiClient, simulator: Simulator
) -> None:
    await client.get_info()
    simulator.clear_requests()
    before = client.request_count
    catalogue = await client.discover()
    # GetList; the first roots in one target are too many items for one response
    # (one 413), so they are read alone up to the first holding more than its
    # share (Rooms); the rest go in batches sized by the roots read, the top-level
    # GTSAP1 variables' long names filling 256-character targets.
    assert client.request_count - before == len(simulator.requests) == 14
    assert [record.status for record in simulator.requests] == [200, 413] + [200] * 12
    assert [record.query for record in simulator.requests[2:6]] == [
        "outsideTemp",
        "displayMessage",
        "Rooms",
        "Heating&lights&blinds&Energy",
    ]
    assert catalogue.discovery == DiscoveryCost(
        requests=14,
        lower_bound=7,
        too_large=1,
        overflowing_groups=1,
        oversized_groups=0,
        item_limit=256,
    )
    assert len(catalogue.points) == 143
    assert sum(point.described for point in catalogue.points.values()) == 54

    for with_attrs in (False, True):
        simulator.clear_requests()
        before = client.request_count
        plan = client.plan(catalogue.points.values(), with_attrs=with_attrs)
        result = await client.read(plan, catalogue.points)
        assert len(plan.requests) == plan.lower_bound == 6
        assert client.request_count - before == len(simulator.requests) == 6
        assert all(record.status == 200 for record in simulator.requests)
        assert [record.items for record in simulator.requests] == [
            request.items for request in plan.requests
        ]
        assert result.missing == frozenset()
        assert result.values == catalogue.values


async def test_every_request_after_the_first_challenge_is_one_round_trip(
    manual_client: TecoApiClient, manual_simulator: Simulator
) -> None:
    await manual_client.get_info()
    assert manual_client.request_count == 2
    for count in range(3, 8):
        await manual_client.get_object(["plcName"])
        assert manual_client.request_count == count
    assert [record.authorized for record in manual_simulator.requests] == [
        False,
        *[True] * 6,
    ]


async def test_responses_map_back_ignoring_case(
    manual_client: TecoApiClient,
) -> None:
    shouting = tecomat_point(
        "MAIN.MYOBJECT3", ValueKind.REAL, MANUAL_OBJECTS["main.myobject3"]
    )
    element = tecomat_point("ARR1[4]", ValueKind.STRING)
    points = {point.key: point for point in (shouting, element)}
    plan = manual_client.plan(points.values(), with_attrs=True)
    assert plan.requests[0].names == ("MAIN", "ARR1")
    result = await manual_client.read(plan, points)
    assert result.values == {"main.myobject3": 23.0, "arr1[4]": "four"}
    assert result.attributes == {"main.myobject3": MANUAL_OBJECTS["main.myobject3"]}
    assert result.missing == frozenset()


async def test_a_member_whose_struct_became_a_number_is_missing(
    manual_client: TecoApiClient, manual_simulator: Simulator
) -> None:
    """A new program made ``plcData`` a number: its members are not found in it
    (none takes the number for its value); the rest of the plan reads on."""
    catalogue = await manual_client.discover()
    points = {
        key: point
        for key, point in catalogue.points.items()
        if key.startswith("plcdata.") or key == "plcname"
    }
    plan = manual_client.plan(points.values(), with_attrs=False)
    source = load_program("manual").to_mapping()
    source["variables"]["plcData"] = {"type": "UINT", "value": 7}
    manual_simulator.load_program(Program.from_mapping(source))

    result = await manual_client.read(plan, points)

    assert result.values == {"plcname": "myFoxtrot"}
    assert result.missing == points.keys() - {"plcname"}


async def test_an_attribute_changed_in_the_plc_shows_on_the_next_read(
    manual_client: TecoApiClient, manual_simulator: Simulator
) -> None:
    """Unchanged attributes are not parsed again, but a changed one is never missed."""
    point = tecomat_point(
        "Main.myObject3", ValueKind.REAL, MANUAL_OBJECTS["main.myobject3"]
    )
    points = {point.key: point}
    plan = manual_client.plan(points.values(), with_attrs=True)
    first = await manual_client.read(plan, points)
    assert first.attributes == {point.key: MANUAL_OBJECTS[point.key]}
    assert (await manual_client.read(plan, points)).attributes == first.attributes

    manual_simulator.set_value("Main.myObject3.attr.maxValue", 42.5)
    manual_simulator.set_value("Main.myObject3.attr.title", "Boiler")
    changed = (await manual_client.read(plan, points)).attributes[point.key]
    assert (changed.maximum, changed.name) == (42.5, "Boiler")
    assert changed.minimum == MANUAL_OBJECTS[point.key].minimum


async def test_a_rejected_root_is_isolated_in_discovery(
    manual_client: TecoApiClient, manual_simulator: Simulator
) -> None:
    manual_simulator.faults.rejected_by_object = {"arr2"}
    manual_simulator.faults.hidden_from_list = {"plcDesc"}
    catalogue = await manual_client.discover()
    assert catalogue.skipped_groups == ("arr2",)
    assert "plcDesc" not in catalogue.groups
    assert not any(key.startswith(("arr2", "plcdesc")) for key in catalogue.points)
    assert len(catalogue.points) == 84 - 12 - 1
    # The failing batch named arr2: it is dropped and the rest read again.
    assert [record.status for record in manual_simulator.requests[-2:]] == [400, 200]


async def test_missing_points_are_isolated_and_the_rest_still_polled(
    manual_client: TecoApiClient, manual_simulator: Simulator
) -> None:
    catalogue = await manual_client.discover()
    plan = manual_client.plan(catalogue.points.values(), with_attrs=False)
    manual_simulator.faults.rejected_by_object = {"arr1", "Main"}
    manual_simulator.clear_requests()
    result = await manual_client.read(plan, catalogue.points)
    gone = {key for key in catalogue.points if key.startswith(("arr1[", "main."))}
    assert result.missing == gone
    assert set(result.values) == set(catalogue.points) - gone
    for key in result.values:
        assert result.values[key] == catalogue.values[key]
    # One request failed per missing name found, then the rest was read once.
    statuses = [record.status for record in manual_simulator.requests]
    assert statuses.count(200) == 1
    assert statuses.count(400) == 4


async def test_missing_names_are_isolated_by_halving_when_not_named(
    manual_client: TecoApiClient, manual_simulator: Simulator
) -> None:
    catalogue = await manual_client.discover()
    points = {
        key: point
        for key, point in catalogue.points.items()
        if key in {"plcname", "plctype", "plcdesc", "arr1[0]"}
    }
    ghost = tecomat_point("ghostVariable", ValueKind.BOOL)
    points[ghost.key] = ghost
    plan = manual_client.plan(points.values(), with_attrs=False)
    assert len(plan.requests) == 1
    # The PLC names a different spelling than requested: the client halves.
    manual_simulator.faults.rejected_by_object = {"ghostVariable"}
    result = await manual_client.read(plan, points)
    assert result.missing == {"ghostvariable"}
    assert result.values == {
        "plcname": "myFoxtrot",
        "plctype": 2005,
        "plcdesc": "for testing only",
        "arr1[0]": "zero",
    }


async def test_a_lower_item_limit_is_learned_and_the_request_replanned(
    start_simulator: StartSimulator, session: aiohttp.ClientSession
) -> None:
    sim = await start_simulator("demo")
    client = make_client(session, sim)
    await client.get_info()
    catalogue = await client.discover()
    plan = client.plan(catalogue.points.values(), with_attrs=True)
    assert plan.item_limit == 256
    assert max(request.items for request in plan.requests) > 128
    sim.plc_type = "CP-1000"
    sim.clear_requests()
    result = await client.read(plan, catalogue.points)
    assert client.item_limit == 128
    assert result.missing == frozenset()
    assert result.values == catalogue.values
    assert 413 in [record.status for record in sim.requests]
    assert all(record.items <= 128 for record in sim.requests)
    # The next plan uses the learned limit and never hits 413.
    replanned = client.plan(catalogue.points.values(), with_attrs=True)
    assert replanned.item_limit == 128
    sim.clear_requests()
    await client.read(replanned, catalogue.points)
    assert [record.status for record in sim.requests] == [200] * len(replanned.requests)


async def test_a_too_long_target_is_shortened(
    manual_client: TecoApiClient, manual_simulator: Simulator
) -> None:
    catalogue = await manual_client.discover()
    members = [
        point
        for point in catalogue.points.values()
        if point.path.startswith("plcData.") and "[" not in point.path
    ]
    names = (*(point.path for point in members), "arr3")
    target = get_object_target(names)
    assert len(target) > 256
    keys = frozenset(point.key for point in members) | {
        key for key in catalogue.points if key.startswith("arr3[")
    }
    plan = ReadPlan(
        requests=(
            PlannedRequest(names=names, target=target, items=0, point_keys=keys),
        ),
        lower_bound=1,
        with_attrs=False,
        point_keys=keys,
    )
    manual_simulator.clear_requests()
    result = await manual_client.read(plan, catalogue.points)
    assert result.missing == frozenset()
    assert result.values == {key: catalogue.values[key] for key in keys}
    # 400.007 for the whole target, then the two halves.
    assert [record.status for record in manual_simulator.requests] == [400, 200, 200]


async def test_read_path_reads_elements_through_their_array(
    manual_client: TecoApiClient, manual_simulator: Simulator
) -> None:
    assert await manual_client.read_path("arr1[2]") == "two"
    assert manual_simulator.requests[-1].query == "arr1"
    assert await manual_client.read_path("arr2[1][3]") == 1.3
    assert await manual_client.read_path("PLCDATA.varReal") == 1000.0
    assert await manual_client.read_path("myObject.favorites") == {
        "color": '"Blue"',
        "sport": "Soccer",
        "food": "Spaghetti",
    }
    main = await manual_client.read_path("Main.myObject3")
    assert main["value"] == 23.0
    assert main["attr"]["title"] == "requested temperature"
    with pytest.raises(VariableNotFoundError) as caught:
        await manual_client.read_path("noSuchVariable")
    assert caught.value.code == "400.005"
    assert caught.value.path == "noSuchVariable"
    with pytest.raises(VariableNotFoundError) as missing:
        await manual_client.read_path("arr1[9]")
    assert missing.value.path == "arr1[9]"


async def test_names_cannot_inject_parameters(
    manual_client: TecoApiClient, manual_simulator: Simulator
) -> None:
    with pytest.raises(PlcResponseError) as caught:
        await manual_client.get_object(["plcName&plcType"])
    assert caught.value.code == "400.005"
    assert "plcName&plcType" in caught.value.message
    assert manual_simulator.requests[-1].query == "plcName%26plcType"
    with pytest.raises(PlcResponseError):
        await manual_client.get_object(['plcName#x"y z=1°'])
    assert manual_simulator.requests[-1].query == ("plcName%23x%22y%20z%3D1%C2%B0")


async def test_read_path_of_an_array_too_big_for_a_response_reads_the_element(
    start_simulator: StartSimulator, session: aiohttp.ClientSession
) -> None:
    source = load_program("manual").to_mapping()
    source["variables"]["big"] = {
        "type": "ARRAY[0..199] OF BYTE",
        "value": list(range(200)),
    }
    sim = await start_simulator(Program.from_mapping(source))
    client = make_client(session, sim)
    assert await client.read_path("big[150]") == 150
    assert [record.query for record in sim.requests[-2:]] == ["big", "big[150]"]
    assert [record.status for record in sim.requests[-2:]] == [413, 200]
    # A catalogue cannot hold it (the root alone is too large): it is skipped.
    catalogue = await client.discover()
    assert catalogue.skipped_groups == ("big",)


async def test_read_path_sends_odd_paths_as_they_are(
    manual_client: TecoApiClient, manual_simulator: Simulator
) -> None:
    with pytest.raises(PlcResponseError) as caught:
        await manual_client.read_path("plc..Name")
    assert caught.value.code == "400.005"
    assert manual_simulator.requests[-1].query == "plc..Name"
