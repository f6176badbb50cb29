"""The FP-I4C source against the simulated gateway over HTTP.

Stations are devices with their own health; a failed item costs its points
only; polls take the planner's POSTs; writes are checked before anything is
sent, go with their read-back in one POST, and are never undone by the poll
they overtook.
"""

import asyncio
import logging
import socket
from typing import Any

import aiohttp
import pytest

from custom_components.tecoapi.pyplc import (
    InvalidValueError,
    MalformedResponseError,
    NotAsciiError,
    OutOfRangeError,
    PlcConnectionError,
    PlcError,
    PointQuality,
    Quality,
    ReadOnlyError,
    Snapshot,
    ValueKind,
    ValueRejectedError,
    VariableNotFoundError,
)
from custom_components.tecoapi.pyplc.core.host import resolved_identity
from custom_components.tecoapi.pyplc.core.pointmap import (
    TYPE_NAMES,
    MapPoint,
    PointMap,
    load_csv,
)
from custom_components.tecoapi.pyplc.panasonic import (
    FpI4cClient,
    FpI4cSource,
    check_point,
)
from custom_components.tecoapi.pyplc.panasonic.client import (
    GatewayError,
    PlcNotAnsweringError,
    StationNotAnsweringError,
)
from custom_components.tecoapi.pyplc.panasonic.mapping import address_identity
from tests.pyplc.panasonic.conftest import MakeSource, Scripted, example_map
from tests.simulator.fpi4c import FpI4cSimulator

HEATING = frozenset(
    {
        "boiler_temp",
        "flow_setpoint",
        "pressure",
        "status",
        "heating_pump",
        "burner_starts",
    }
)
GARAGE = frozenset({"door_position", "door_target", "garage_light"})


async def test_discovery_reads_every_point_station_by_station(
    make_source: MakeSource,
) -> None:
    source = make_source()
    snapshot = await source.poll(())
    catalogue = snapshot.catalogue
    assert len(catalogue.points) == 24
    assert snapshot.values["boiler_temp"] == 65.2
    assert snapshot.values["outdoor_temp"] == -3.5
    assert snapshot.values["dhw_temp"] == 49.8
    assert snapshot.values["pressure"] == 1.8
    assert snapshot.values["status"] == "Heating"
    assert snapshot.values["burner_starts"] == 12_345
    assert snapshot.values["heating_on"] is True
    assert snapshot.values["car_present"] is True
    assert snapshot.offline == {}
    assert snapshot.quality == {}
    # One device per station, under the gateway, named by the map.
    heating, garage = catalogue.devices["station_1"], catalogue.devices["station_2"]
    assert (heating.name, heating.parent, heating.manufacturer) == (
        "Heating plant",
        "",
        "Panasonic",
    )
    assert heating.properties == {"station": "1"}
    assert garage.name == "Door controller"
    assert catalogue.points["door_target"].device == "station_2"
    assert catalogue.points["heating_on"].address == "R10"
    boiler = catalogue.points["boiler_temp"]
    assert boiler.kind is ValueKind.REAL
    assert boiler.type.bits == 16
    status = catalogue.points["status"]
    assert (status.type.length, status.type.encoding) == (24, "ascii")
    # The two stations' points in two POSTs: the bound.
    assert source.statistics.last_poll_requests == 2
    assert source.read_plan is not None
    assert source.read_plan.lower_bound == 2
    assert source.statistics.discoveries == 1


async def test_a_poll_reads_the_polled_points_at_the_bound(
    make_source: MakeSource, gateway: FpI4cSimulator
) -> None:
    source = make_source()
    await source.poll(())
    gateway.set(1, "DT0", "INT", 700)
    gateway.set(2, "Y0", "BOOL", True)
    snapshot = await source.poll(HEATING | GARAGE)
    assert set(snapshot.values) == HEATING | GARAGE
    assert snapshot.values["boiler_temp"] == 70.0
    assert snapshot.values["garage_light"] is True
    assert source.statistics.last_poll_requests == 2
    snapshot = await source.poll(HEATING)
    assert set(snapshot.values) == HEATING
    assert source.statistics.last_poll_requests == 1
    assert source.statistics.polls == 2
    # The same points keep their plan.
    plan = source.read_plan
    await source.poll(HEATING)
    assert source.read_plan is plan


async def test_a_silent_station_is_offline_and_costs_only_its_points(
    make_source: MakeSource, gateway: FpI4cSimulator
) -> None:
    source = make_source()
    await source.poll(())
    gateway.silent.add(2)
    snapshot = await source.poll(HEATING | GARAGE)
    assert snapshot.offline == {"station_2": "err_code 28: No response from the PLC"}
    assert set(snapshot.values) == HEATING
    assert snapshot.quality == {}
    assert source.recent_errors[-1].error == "PlcNotAnsweringError"
    assert "Station 2" in source.recent_errors[-1].message
    errors = len(source.recent_errors)
    await source.poll(HEATING | GARAGE)
    assert len(source.recent_errors) == errors, "an outage is noted once"
    gateway.silent.clear()
    snapshot = await source.poll(HEATING | GARAGE)
    assert snapshot.offline == {}
    assert set(snapshot.values) == HEATING | GARAGE


async def test_a_silent_station_is_logged_once_and_once_when_it_answers(
    gateway: FpI4cSimulator,
    http: aiohttp.ClientSession,
    caplog: pytest.LogCaptureFixture,
) -> None:
    """In the gateway's words, naming its interface; at info, not per poll."""
    client = FpI4cClient(http, gateway.url, interface=4, timeout=5)
    source = FpI4cSource(client, example_map(), identity="gateway", interface=4)
    await source.poll(())
    caplog.set_level(logging.DEBUG)
    gateway.silent.add(2)
    for _ in range(3):
        await source.poll(HEATING | GARAGE)
    reason = "err_code 28: No response from the PLC"
    assert source.diagnostics()["stations"]["station_2"] == {
        "points": 6,
        "offline": reason,
    }
    gateway.silent.clear()
    for _ in range(2):
        await source.poll(HEATING | GARAGE)
    behind = (
        f"Station 2 behind the FP-I4C gateway 127.0.0.1:{gateway.port} (interface 4)"
    )
    assert [
        (record.levelno, record.getMessage())
        for record in caplog.records
        if record.levelno >= logging.INFO
    ] == [
        (
            logging.INFO,
            f"{behind} does not answer, its entities are unavailable: {reason}",
        ),
        (logging.INFO, f"{behind} answers again"),
    ]
    assert source.diagnostics()["stations"]["station_2"]["offline"] is None


async def test_a_failed_item_costs_its_points_only_with_the_code(
    make_source: MakeSource, gateway: FpI4cSimulator
) -> None:
    source = make_source()
    await source.poll(())
    gateway.item_errors[1, "DT210"] = (61, "Data error")
    snapshot = await source.poll(HEATING)
    assert snapshot.missing == {"pressure"}
    assert snapshot.quality["pressure"] == PointQuality(
        quality=Quality.BAD, reason="err_code 61: Data error", code="61"
    )
    assert snapshot.offline == {}
    assert set(snapshot.values) == HEATING - {"pressure"}
    gateway.item_errors.clear()
    snapshot = await source.poll(HEATING)
    assert snapshot.quality == {}
    assert snapshot.values["pressure"] == 1.8


async def test_every_item_of_a_station_failing_is_the_station_offline(
    make_source: MakeSource, gateway: FpI4cSimulator
) -> None:
    source = make_source()
    await source.poll(())
    gateway.item_errors[2, "DT10"] = (66, "Address error")
    gateway.item_errors[2, "Y0"] = (66, "Address error")
    snapshot = await source.poll(GARAGE)
    assert snapshot.offline == {"station_2": "err_code 66: Address error"}
    # Offline says it for its points: they are not each bad too.
    assert snapshot.quality == {}


async def test_a_dropped_post_costs_its_station_while_another_answers(
    make_source: MakeSource, gateway: FpI4cSimulator
) -> None:
    source = make_source()
    await source.poll(())
    gateway.dropped.add(2)
    snapshot = await source.poll(HEATING | GARAGE)
    assert snapshot.offline["station_2"].startswith("no answer: Cannot talk to")
    assert set(snapshot.values) == HEATING
    gateway.dropped.add(1)
    with pytest.raises(PlcConnectionError):
        await source.poll(HEATING | GARAGE)
    assert source.statistics.failed_polls == 1
    gateway.dropped.clear()
    snapshot = await source.poll(HEATING | GARAGE)
    assert snapshot.offline == {}


async def test_a_post_the_gateway_refuses_is_its_station_offline(
    gateway: FpI4cSimulator, http: aiohttp.ClientSession
) -> None:
    # Interface 1 is not the gateway's: each POST is refused as a whole.
    source = FpI4cSource(
        FpI4cClient(http, gateway.url, interface=1), example_map(), identity="g"
    )
    snapshot = await source.poll(())
    assert snapshot.offline == {
        "station_1": "refused: Interface 1 is not enabled",
        "station_2": "refused: Interface 1 is not enabled",
    }
    assert snapshot.values == {}


async def test_a_broken_answer_fails_the_poll_and_the_next_good_one_recovers(
    make_source: MakeSource, gateway: FpI4cSimulator
) -> None:
    source = make_source()
    await source.poll(())
    gateway.broken = True
    with pytest.raises(MalformedResponseError):
        await source.poll(HEATING)
    gateway.broken = False
    snapshot = await source.poll(HEATING)
    assert set(snapshot.values) == HEATING
    assert source.recent_errors[-1].error == "MalformedResponseError"


async def test_lenient_answers_read_the_same(
    make_source: MakeSource, gateway: FpI4cSimulator
) -> None:
    strict = (await make_source().poll(())).values
    gateway.lenient = True
    source = make_source()
    assert (await source.poll(())).values == strict
    assert source.client.statistics.lenient_answers == 2


async def test_the_gateway_s_own_station_is_the_plc_device(
    gateway: FpI4cSimulator, http: aiohttp.ClientSession
) -> None:
    point_map = load_csv("name,address,type\nBoiler,DT0,INT\n", check_point)
    source = FpI4cSource(FpI4cClient(http, gateway.url), point_map, identity="g")
    snapshot = await source.poll(())
    assert snapshot.catalogue.points["boiler"].device == "plc"
    assert snapshot.catalogue.devices["plc"].name == "PLC"
    assert snapshot.catalogue.devices["plc"].properties == {}
    assert "station" not in gateway.posts[-1]
    assert snapshot.values == {"boiler": 652}
    # The form's station is the points' that name none.
    source = FpI4cSource(
        FpI4cClient(http, gateway.url), point_map, identity="g", station=2
    )
    snapshot = await source.poll(())
    assert snapshot.catalogue.points["boiler"].device == "station_2"
    assert gateway.posts[-1]["station"] == 2


async def test_a_stored_point_the_gateway_cannot_read_is_bad_alone(
    make_source: MakeSource,
) -> None:
    point_map = example_map()
    broken = MapPoint(id="old", name="Old", address="Q1", type=point_map.points[0].type)
    source = make_source(point_map.with_new_point(broken))
    snapshot = await source.poll(())
    assert snapshot.missing == {"old"}
    assert snapshot.quality["old"].reason == "invalid_address"
    assert snapshot.quality["old"].code is None
    assert snapshot.values["boiler_temp"] == 65.2
    with pytest.raises(VariableNotFoundError):
        await source.write("old", 1)


# --- writes ---------------------------------------------------------------------


async def test_a_write_is_scaled_sent_with_its_read_back_pushed_and_shown(
    make_source: MakeSource, gateway: FpI4cSimulator
) -> None:
    source = make_source()
    await source.poll(())
    told: list[Snapshot] = []
    source.subscribe(told.append)
    posts = source.client.statistics.posts
    confirmed = await source.write("room_setpoint", 22.0)
    assert gateway.get(1, "DT101", "INT") == 220
    assert source.client.statistics.posts == posts + 1
    written, read_back, probe = gateway.posts[-1]["req"]
    assert written == {
        "area": "DT",
        "type": "INT",
        "start": 101,
        "count": 1,
        "value": 220,
    }
    assert read_back == {"area": "DT", "type": "INT", "start": 101, "count": 1}
    assert probe == {"area": "DT", "type": "INT", "start": 0, "count": 1}
    assert [snapshot.values for snapshot in told] == [{"room_setpoint": 22.0}]
    assert confirmed is not None
    assert confirmed.values == {"room_setpoint": 22.0}
    assert source.statistics.writes == 1


@pytest.mark.parametrize(
    ("key", "value", "held"),
    [
        ("heating_pump", False, (1, "Y0", "BOOL", False)),
        ("heating_on", False, (1, "R10", "BOOL", False)),
        ("door_target", 55, (2, "DT11", "INT", 55)),
        ("dhw_setpoint", 60, (1, "DT102", "INT", 600)),
    ],
)
async def test_writes_of_every_kind(
    make_source: MakeSource,
    gateway: FpI4cSimulator,
    key: str,
    value: object,
    held: tuple[int, str, str, object],
) -> None:
    source = make_source()
    await source.poll(())
    await source.write(key, value)
    station, address, type_, raw = held
    assert gateway.get(station, address, type_) == raw


async def test_strings_reals_and_double_words_are_written(
    gateway: FpI4cSimulator, http: aiohttp.ClientSession
) -> None:
    point_map = load_csv(
        "name,address,type,length,writable\n"
        "Text,DT300,STRING,,yes\n"
        "Ratio,DT210,REAL,,yes\n"
        "Counter,DT200,DINT,,yes\n"
        "Word,DT100,UINT,,yes\n",
        check_point,
    )
    source = FpI4cSource(
        FpI4cClient(http, gateway.url), point_map, identity="g", station=1
    )
    snapshot = await source.poll(())
    assert snapshot.catalogue.points["text"].type.length == 1000
    await source.write("text", "x" * 1000)
    assert gateway.get(1, "DT300", "STRING") == "x" * 1000
    assert "count" not in gateway.posts[-1]["req"][0]
    await source.write("ratio", 22.88)
    assert gateway.get(1, "DT210", "REAL") == pytest.approx(22.88)
    confirmed = await source.write("counter", -100_000)
    assert confirmed is not None
    assert confirmed.values == {"counter": -100_000}
    await source.write("word", 65535)
    assert gateway.get(1, "DT100", "UINT") == 65535


@pytest.mark.parametrize(
    ("write", "error", "message", "text_key"),
    [
        (("room_setpoint", 30.0), OutOfRangeError, "15..28", "error_out_of_range"),
        (("boiler_temp", 50.0), ReadOnlyError, "read-only", "error_read_only"),
        (("heating_pump", 1), InvalidValueError, "true or false", "write_flag"),
        (
            ("counter", 2**31),
            InvalidValueError,
            "-2147483648..2147483647",
            "write_integers",
        ),
        (("int", 32768), InvalidValueError, "-32768..32767", "write_integers"),
        (("int", -32769), InvalidValueError, "-32768..32767", "write_integers"),
        (("tenths", 3276.8), InvalidValueError, "-32768..32767", "write_integers"),
        (("word", -1), InvalidValueError, "0..65535", "write_integers"),
        (
            ("ratio", 1e39),
            InvalidValueError,
            "outside the range of a 32-bit real",
            "write_real",
        ),
        (("ratio", float("nan")), InvalidValueError, "finite", "write_number"),
        (("text", "x" * 1001), InvalidValueError, "longer than 1000", "write_too_long"),
        (("short", "abcdef"), InvalidValueError, "longer than 5", "write_too_long"),
        (("text", "Žluťoučký"), NotAsciiError, "ASCII", "error_not_ascii"),
    ],
)
async def test_a_refused_write_sends_nothing(
    gateway: FpI4cSimulator,
    http: aiohttp.ClientSession,
    *,
    write: tuple[str, object],
    error: type[Exception],
    message: str,
    text_key: str,
) -> None:
    """Refused before any POST, with its reason as a text a user reads translated."""
    key, value = write
    point_map = example_map()
    extra = load_csv(
        "name,address,type,length,scale,writable,device\n"
        "Text,DT400,STRING,,,yes,1\n"
        "Short,DT500,STRING,5,,yes,1\n"
        "Ratio,DT410,REAL,,,yes,1\n"
        "Counter,DT420,DINT,,,yes,1\n"
        "Int,DT430,INT,,,yes,1\n"
        "Tenths,DT431,INT,,0.1,yes,1\n"
        "Word,DT432,UINT,,,yes,1\n",
        check_point,
    )
    for point in extra.points:
        point_map = point_map.with_new_point(point)
    source = FpI4cSource(FpI4cClient(http, gateway.url), point_map, identity="g")
    await source.poll(())
    posts = len(gateway.posts)
    with pytest.raises(error, match=message) as caught:
        await source.write(key, value)
    assert len(gateway.posts) == posts
    assert isinstance(caught.value, PlcError)
    assert caught.value.text().key == text_key


async def test_a_value_the_plc_refuses_is_rejected_with_its_code(
    make_source: MakeSource, gateway: FpI4cSimulator
) -> None:
    source = make_source()
    await source.poll(())
    gateway.write_errors[1, "DT101"] = (65, "Protect error")
    with pytest.raises(ValueRejectedError) as raised:
        await source.write("room_setpoint", 22.0)
    assert (raised.value.code, raised.value.path) == ("65", "room_setpoint")
    # The seed's write item has no message: the code is the reason.
    assert str(raised.value).endswith("for 'room_setpoint' (err_code 65)")
    gateway.write_messages = True
    with pytest.raises(ValueRejectedError) as raised:
        await source.write("room_setpoint", 22.0)
    assert "Protect error (err_code 65)" in str(raised.value)
    assert gateway.get(1, "DT101", "INT") == 215
    # The register is past the PLC's memory: its read-back fails too, DT0 not.
    gateway.stations[1].sizes = {**gateway.stations[1].sizes, "DT": 102}
    with pytest.raises(ValueRejectedError, match="err_code 61"):
        await source.write("dhw_setpoint", 60)
    # A refused value is no failure of the gateway's.
    assert source.statistics.failed_writes == 0
    assert source.statistics.writes == 3


async def test_a_write_to_a_silent_station_says_the_plc_does_not_answer(
    make_source: MakeSource, gateway: FpI4cSimulator
) -> None:
    source = make_source()
    await source.poll(())
    gateway.silent.add(2)
    with pytest.raises(PlcNotAnsweringError, match="err_code 28"):
        await source.write("door_target", 50)
    assert gateway.get(2, "DT11", "INT") == 0
    assert source.statistics.failed_writes == 1
    assert source.recent_errors[-1].operation == "write"


def _answer(body: dict[str, Any], *items: dict[str, Any]) -> dict[str, Any]:
    """An answer of these items, then DT0's for the rest of the requests."""
    rest = [{"err": False, "int": 0}] * (len(body["req"]) - len(items))
    return {"err": False, "err_msg": "", "data": [*items, *rest]}


async def test_what_a_gateway_sends_wrongly_costs_its_point_only(
    scripted: Scripted, http: aiohttp.ClientSession
) -> None:
    point_map = load_csv(
        "name,address,type,writable\nA,DT0,INT,yes\nB,DT1,INT,no\nC,DT5,UINT,no\n",
        check_point,
    )
    source = FpI4cSource(FpI4cClient(http, scripted.url), point_map, identity="g")

    def values(body: dict[str, Any]) -> dict[str, Any]:
        requests = body["req"]
        if requests[0]["type"] == "UINT":
            return _answer(
                body, {"err": False, "uint": 7}, {"err": False, "int": [1, "two"]}
            )
        return _answer(
            body, {"err": False, "int": [1, "two"]}, {"err": False, "uint": 7}
        )

    scripted.answer = values
    snapshot = await source.poll(())
    assert snapshot.values == {"a": 1, "c": 7}
    assert snapshot.quality["b"].reason == "unreadable"
    assert snapshot.quality["b"].code is None
    assert snapshot.offline == {}
    # A write taken whose read-back says nothing: the next poll tells.
    scripted.answer = lambda body: _answer(
        body, {"err": False}, {"err": True, "err_code": 61, "err_msg": "?"}
    )
    assert await source.write("a", 5) is None
    scripted.answer = lambda body: _answer(
        body, {"err": False}, {"err": False, "int": [None]}
    )
    assert await source.write("a", 5) is None
    scripted.answer = lambda body: _answer(
        body, {"err": False}, {"err": False, "int": 5}
    )
    confirmed = await source.write("a", 5)
    assert confirmed is not None
    assert confirmed.values == {"a": 5}


async def test_a_write_is_never_undone_by_the_poll_it_overtook(
    make_source: MakeSource, gateway: FpI4cSimulator
) -> None:
    """A poll's POST reads the setpoint, the write goes before its next POST.

    The poll's older setpoint is not shown; the other values are.
    """
    source = make_source()
    await source.poll(())
    first = len(gateway.posts)
    async with gateway.hold() as hold:
        poll = asyncio.create_task(source.poll(HEATING | GARAGE | {"room_setpoint"}))
        await hold.reached()
        # Scheduled before the release: the write runs first and waits for the
        # held POST (one POST at a time on the wire), ahead of the poll's next.
        write = asyncio.create_task(source.write("room_setpoint", 25.0))
        hold.release()
        await write
        snapshot = await poll
    assert gateway.posts[first + 1]["req"][0].get("value") == 250, "it went second"
    assert "room_setpoint" not in snapshot.values
    assert snapshot.values["boiler_temp"] == 65.2
    assert snapshot.values["door_target"] == 0
    # The next poll shows it, as the write did.
    assert (await source.poll({"room_setpoint"})).values == {"room_setpoint": 25.0}


# --- who it is, and the rest ----------------------------------------------------


async def test_identify_reads_dt0_of_each_station(
    make_source: MakeSource, gateway: FpI4cSimulator
) -> None:
    source = make_source()
    info = await source.identify()
    assert (info.identity, info.name, info.manufacturer, info.model) == (
        "gateway",
        "FP-I4C",
        "Panasonic",
        "FP-I4C",
    )
    assert info.mode is None
    probes = [(post["station"], post["req"]) for post in gateway.posts]
    assert probes == [
        (station, [{"area": "DT", "type": "INT", "start": 0, "count": 1}])
        for station in (1, 2)
    ]
    gateway.silent.add(2)
    with pytest.raises(StationNotAnsweringError) as raised:
        await source.identify()
    assert (raised.value.station, raised.value.code, raised.value.message) == (
        "2",
        "28",
        "No response from the PLC",
    )


async def test_identify_of_the_gateway_s_own_station(
    gateway: FpI4cSimulator, http: aiohttp.ClientSession
) -> None:
    source = FpI4cSource(FpI4cClient(http, gateway.url), PointMap(()), identity="g")
    await source.identify()
    assert "station" not in gateway.posts[-1]
    gateway.silent.add(1)
    with pytest.raises(PlcNotAnsweringError) as raised:
        await source.identify()
    assert not isinstance(raised.value, StationNotAnsweringError)
    assert raised.value.code == "28"
    with pytest.raises(GatewayError, match="Interface 0 is not enabled"):
        await FpI4cSource(
            FpI4cClient(http, gateway.url, interface=0), PointMap(()), identity="g"
        ).identify()


async def test_some_points_are_read_between_polls(
    make_source: MakeSource, gateway: FpI4cSimulator
) -> None:
    source = make_source()
    assert await source.read_points({"door_position"}) is None
    await source.poll(())
    gateway.set(2, "DT10", "INT", 40)
    polled = source.read_plan
    snapshot = await source.read_points({"door_position", "gone"})
    assert source.read_plan is polled, "the poll's plan stays the one shown"
    assert snapshot is not None
    assert snapshot.values == {"door_position": 40}
    assert gateway.posts[-1]["station"] == 2
    assert await source.read_points({"gone"}) is None


async def test_a_point_is_read_and_written_by_its_id(
    make_source: MakeSource, gateway: FpI4cSimulator
) -> None:
    source = make_source()
    await source.poll(())
    assert await source.read_variable("Boiler_Temp") == 65.2
    await source.write_variable("door_target", 30)
    assert gateway.get(2, "DT11", "INT") == 30
    with pytest.raises(VariableNotFoundError):
        await source.read_variable("DT0")
    with pytest.raises(VariableNotFoundError):
        await source.write_variable("nothing", 1)


async def test_diagnostics_tell_the_plan_against_its_bound_and_no_address(
    make_source: MakeSource, gateway: FpI4cSimulator
) -> None:
    source = make_source()
    assert source.diagnostics()["read_plans"] == {"values": None}
    await source.poll(())
    diagnostics = source.diagnostics()
    plan = diagnostics["read_plans"]["values"]
    assert plan["posts"] == plan["lower_bound"] == 2
    assert plan["by_post"][1] == {
        "station": 2,
        "requests": ["INT DT10 x2", "BOOL R0 x1", "BOOL X0 x2", "BOOL Y0 x1"],
    }
    assert diagnostics["stations"] == {
        "station_1": {"points": 18, "offline": None},
        "station_2": {"points": 6, "offline": None},
    }
    assert diagnostics["map"] == {
        "format": "csv",
        "readable_points": 24,
        "skipped_rows": 0,
    }
    assert diagnostics["requests"]["posts"] == 2
    assert diagnostics["requests"]["discoveries"] == 1
    assert "127.0.0.1" not in str(diagnostics)
    await source.close()


async def test_the_device_page_links_the_port_the_rest_api_answers_on(
    make_source: MakeSource, gateway: FpI4cSimulator, http: aiohttp.ClientSession
) -> None:
    """The REST API's port is the HTTP server's (issue 39): not port 80."""
    source = make_source()
    assert source.configuration_url == gateway.url
    assert gateway.port != 80
    async with http.post(
        f"{source.configuration_url}/plcpost",
        json={"req": [{"area": "DT", "type": "INT", "start": 0, "count": 1}]},
    ) as response:
        assert response.status == 200


def test_an_identity_is_the_address_it_was_added_at() -> None:
    assert address_identity("http://192.168.1.5:2000", None, None) == "192.168.1.5:2000"
    assert address_identity("http://gw.local:2001", 0, 3) == "gw.local:2001/I0/A3"
    assert address_identity("http://[fe80::1]:2000", None, 7) == "[fe80::1]:2000/A7"
    assert address_identity("http://gw:80", 4, None) == "gw:80/I4"


async def test_a_gateway_added_by_name_is_known_by_its_address(
    gateway: FpI4cSimulator, http: aiohttp.ClientSession
) -> None:
    """localhost and 127.0.0.1 are one gateway: one identity; the title says it as typed."""
    client = FpI4cClient(http, f"http://localhost:{gateway.port}", timeout=5)
    source = FpI4cSource(client, example_map(), station=1)
    assert source.identity == f"localhost:{gateway.port}/A1"
    info = await source.identify()
    assert info.identity == f"127.0.0.1:{gateway.port}/A1"
    assert info.location == f"localhost:{gateway.port}, station 1"
    assert FpI4cSource(client, example_map(), interface=0).location == (
        f"localhost:{gateway.port}, interface 0"
    )
    # An entry's identity stays as it was stored.
    kept = FpI4cSource(client, example_map(), identity=f"localhost:{gateway.port}")
    assert (await kept.identify()).identity == f"localhost:{gateway.port}"
    await source.close()


async def test_an_address_identity_resolves_its_name_only(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    assert await resolved_identity("localhost:2000/I0/A3") == "127.0.0.1:2000/I0/A3"
    assert await resolved_identity("192.0.2.7:2000") == "192.0.2.7:2000"
    assert await resolved_identity("[fe80::1]:2000/A7") == "[fe80::1]:2000/A7"
    answers: dict[str, Any] = {
        "gw6.example": [(socket.AF_INET6, socket.SOCK_STREAM, 6, "", ("fe80::2", 1))],
        "gw.example": [
            (socket.AF_INET6, socket.SOCK_STREAM, 6, "", ("fe80::3", 1)),
            (socket.AF_INET, socket.SOCK_STREAM, 6, "", ("192.0.2.9", 1)),
        ],
        "empty.example": [],
        "gone.example": socket.gaierror(-2, "Name or service not known"),
    }

    async def getaddrinfo(host: str, *args: Any, **kwargs: Any) -> Any:
        answer = answers[host]
        if isinstance(answer, OSError):
            raise answer
        return answer

    monkeypatch.setattr(asyncio.get_running_loop(), "getaddrinfo", getaddrinfo)
    assert await resolved_identity("gw6.example:2000") == "[fe80::2]:2000"
    assert await resolved_identity("gw.example:2000/A1") == "192.0.2.9:2000/A1"
    for name in ("empty.example", "gone.example"):
        assert await resolved_identity(f"{name}:2000") == f"{name}:2000"


# --- a point a user typed, checked before it is taken -----------------------------


def _typed(*rows: str) -> PointMap:
    """A map of points as a user types them (the CSV's columns, a row each)."""
    return load_csv("id,name,address,type,device\n" + "".join(rows), check_point)


async def test_a_typed_point_is_read_once_with_its_station_s_dt0(
    make_source: MakeSource, gateway: FpI4cSimulator
) -> None:
    gateway.set(2, "DT20", "INT", 123)
    source = make_source(_typed("cycles,Door cycles,DT20,INT,2\n"))
    assert await source.check_points({"cycles"}) == {}
    # One POST: DT0 (the station answers), then the point.
    assert [(post["station"], post["req"]) for post in gateway.posts] == [
        (
            2,
            [
                {"area": "DT", "type": "INT", "start": 0, "count": 1},
                {"area": "DT", "type": "INT", "start": 20, "count": 1},
            ],
        )
    ]


async def test_a_typed_address_the_plc_lacks_is_refused_with_its_code(
    make_source: MakeSource, gateway: FpI4cSimulator
) -> None:
    """R9999F is an FP address; the garage's PLC has no WR9999 (data error 61)."""
    source = make_source(
        _typed("far,Far relay,R9999F,BOOL,2\n", "door,Door open,X3,BOOL,2\n")
    )
    refused = await source.check_points({"far", "door", "nothing"})
    assert refused.keys() == {"far", "nothing"}
    assert refused["far"].quality is Quality.BAD
    assert refused["far"].code == "61"
    assert refused["far"].reason.startswith("err_code 61: ")
    assert "WR9999" in refused["far"].reason
    assert refused["nothing"].reason == "not_found"
    assert len(gateway.posts) == 1
    # The station not answering is the station's failure, not the point's.
    gateway.silent.add(2)
    with pytest.raises(StationNotAnsweringError):
        await make_source(_typed("far,Far relay,R9999F,BOOL,2\n")).check_points({"far"})


async def test_a_typed_point_the_gateway_cannot_read_is_refused_unsent(
    make_source: MakeSource, gateway: FpI4cSimulator
) -> None:
    """A stored point an older check let through: refused as a poll has it."""
    odd = MapPoint(id="odd", name="Odd", address="Q0", type=TYPE_NAMES["int"])
    refused = await make_source(PointMap((odd,))).check_points({"odd"})
    assert refused == {
        "odd": PointQuality(quality=Quality.BAD, reason="invalid_address")
    }
    assert gateway.posts == []


async def test_many_typed_points_of_a_station_keep_to_the_request_limit(
    make_source: MakeSource, gateway: FpI4cSimulator
) -> None:
    """25 registers far apart: 25 requests, DT0 in each POST, 20 requests at most."""
    rows = [f"p{index},P {index},DT{index * 200},INT,1\n" for index in range(25)]
    source = make_source(_typed(*rows))
    assert await source.check_points({f"p{index}" for index in range(25)}) == {}
    assert [len(post["req"]) for post in gateway.posts] == [20, 7]
    assert all(post["req"][0]["start"] == 0 for post in gateway.posts)
