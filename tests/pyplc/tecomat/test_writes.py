"""Writes: validation before anything is sent, and both documented write forms."""

from datetime import UTC, date, datetime, time, timedelta, timezone
import json
from typing import Any

import pytest

from custom_components.tecoapi.pyplc import (
    Catalogue,
    InvalidValueError,
    InvalidWriteError,
    OutOfRangeError,
    PlcResponseError,
    Point,
    PointAttributes,
    ReadOnlyError,
    ValueKind,
    ValueRejectedError,
)
from custom_components.tecoapi.pyplc.tecomat import TecoApiClient
from custom_components.tecoapi.pyplc.tecomat.points import (
    api_object_attributes,
    tecomat_point,
)
from custom_components.tecoapi.pyplc.tecomat.tecoapi.values import parse_value
from custom_components.tecoapi.pyplc.tecomat.writes import (
    WireValue,
    encode_json_value,
    validate_write,
    written_value,
)
from tests.simulator import Simulator


def _meta(
    read_only: bool = False, low: float = 0.0, high: float = 0.0
) -> PointAttributes:
    return api_object_attributes(
        title="t",
        units="",
        read_only=read_only,
        min_value=low,
        max_value=high,
        enable=True,
        visibility=True,
    )


def _point(
    kind: ValueKind, meta: PointAttributes | None = None, path: str = "x.y"
) -> Point:
    return tecomat_point(path, kind, meta)


@pytest.fixture
async def catalogue(manual_client: TecoApiClient) -> Catalogue:
    return await manual_client.discover()


# --- validation (no PLC needed) ---------------------------------------------


@pytest.mark.parametrize(
    ("kind", "value", "wire"),
    [
        (ValueKind.BOOL, True, WireValue("true", "true")),
        (ValueKind.BOOL, False, WireValue("false", "false")),
        (ValueKind.INTEGER, 1005, WireValue("1005", "1005")),
        (ValueKind.INTEGER, 21.0, WireValue("21", "21")),
        (ValueKind.INTEGER, -2147483648, WireValue("-2147483648", "-2147483648")),
        (ValueKind.INTEGER, 4294967295, WireValue("4294967295", "4294967295")),
        (ValueKind.REAL, 21.5, WireValue("21.5", "21.5")),
        (ValueKind.REAL, 1.5e3, WireValue("1500.0", "1500.0")),
        (ValueKind.REAL, 7, WireValue("7.0", "7.0")),
        (ValueKind.STRING, "five", WireValue('"five"', '"five"')),
        (ValueKind.STRING, '"Blue"', WireValue('""Blue""', '"\\"Blue\\""')),
        (ValueKind.STRING, "", WireValue('""', '""')),
        (ValueKind.DATE, date(2020, 1, 2), WireValue("2020-01-02", '"2020-01-02"')),
        (ValueKind.DATE, "2020-01-02", WireValue("2020-01-02", '"2020-01-02"')),
        (
            ValueKind.DATETIME,
            datetime(2020, 1, 2, 3, 4, 5, 678000, tzinfo=UTC),
            WireValue("2020-01-02T03:04:05.678Z", '"2020-01-02T03:04:05.678Z"'),
        ),
        (
            ValueKind.TIME,
            time(1, 2, 3, 450000),
            WireValue("01:02:03.450", '"01:02:03.450"'),
        ),
        (
            ValueKind.TIME,
            timedelta(hours=120, seconds=3.45),
            WireValue("120:00:03.450", '"120:00:03.450"'),
        ),
        (ValueKind.TIME, "01:02:03.450", WireValue("01:02:03.450", '"01:02:03.450"')),
    ],
)
def test_valid_values_and_their_wire_forms(
    kind: ValueKind, value: Any, wire: WireValue
) -> None:
    assert validate_write(_point(kind), value) == wire


@pytest.mark.parametrize(
    ("kind", "value"),
    [
        (ValueKind.BOOL, 1),
        (ValueKind.BOOL, "true"),
        (ValueKind.INTEGER, True),
        (ValueKind.INTEGER, 1.5),
        (ValueKind.INTEGER, "5"),
        (ValueKind.INTEGER, 4294967296),
        (ValueKind.INTEGER, -2147483649),
        (ValueKind.REAL, float("nan")),
        (ValueKind.REAL, float("inf")),
        (ValueKind.REAL, "21.5"),
        (ValueKind.REAL, False),
        (ValueKind.STRING, 5),
        (ValueKind.STRING, "°C"),
        (ValueKind.STRING, "x" * 256),
        (ValueKind.DATE, "2020-13-01"),
        (ValueKind.DATE, datetime(2020, 1, 2, tzinfo=UTC)),
        (ValueKind.DATETIME, "2020-01-02"),
        (ValueKind.DATETIME, date(2020, 1, 2)),
        (ValueKind.TIME, "1 hour"),
        (ValueKind.TIME, timedelta(seconds=-1)),
    ],
)
def test_invalid_values_are_refused(kind: ValueKind, value: Any) -> None:
    with pytest.raises(InvalidValueError) as caught:
        validate_write(_point(kind, path="Main.thing"), value)
    assert caught.value.path == "Main.thing"
    assert caught.value.value is value or caught.value.value == value


def test_a_string_of_255_ascii_characters_is_fine() -> None:
    assert validate_write(_point(ValueKind.STRING), "x" * 255).query == (
        '"' + "x" * 255 + '"'
    )


def test_read_only_points_are_refused() -> None:
    point = _point(ValueKind.REAL, _meta(read_only=True), path="Main.myObject1")
    with pytest.raises(ReadOnlyError) as caught:
        validate_write(point, 1.0)
    assert caught.value.path == "Main.myObject1.value"
    assert isinstance(caught.value, InvalidWriteError)


@pytest.mark.parametrize("value", [9.99, 30.01, -5, 31])
def test_values_outside_the_range_are_refused(value: float) -> None:
    point = _point(ValueKind.REAL, _meta(low=10.0, high=30.0), path="Main.myObject3")
    with pytest.raises(OutOfRangeError) as caught:
        validate_write(point, value)
    assert (caught.value.min_value, caught.value.max_value) == (10.0, 30.0)
    assert "10..30" in str(caught.value)


@pytest.mark.parametrize("value", [10.0, 30.0, 21.5])
def test_values_inside_the_range_pass(value: float) -> None:
    point = _point(ValueKind.REAL, _meta(low=10.0, high=30.0))
    assert validate_write(point, value).query == format(value, ".1f")


def test_without_a_range_any_value_of_the_kind_passes() -> None:
    point = _point(ValueKind.INTEGER, _meta())
    assert validate_write(point, 123456).query == "123456"


@pytest.mark.parametrize(
    ("kind", "value", "held"),
    [
        (ValueKind.BOOL, True, True),
        (ValueKind.INTEGER, 21.0, 21),
        (ValueKind.REAL, 7, 7.0),
        (ValueKind.REAL, 0.1234567, 0.123457),
        (ValueKind.REAL, -0.0000001, 0.0),
        (ValueKind.STRING, '"Blue"', '"Blue"'),
        (ValueKind.DATE, "2020-01-02", date(2020, 1, 2)),
        (
            ValueKind.DATETIME,
            datetime(2020, 1, 2, 4, 4, 5, 678912, tzinfo=timezone(timedelta(hours=1))),
            datetime(2020, 1, 2, 3, 4, 5, 678000, tzinfo=UTC),
        ),
        (
            ValueKind.DATETIME,
            "2020-01-02T03:04:05.678Z",
            datetime(2020, 1, 2, 3, 4, 5, 678000, tzinfo=UTC),
        ),
        (
            ValueKind.TIME,
            time(1, 2, 3, 450600),
            timedelta(hours=1, minutes=2, seconds=3, milliseconds=451),
        ),
        (ValueKind.TIME, "120:00:03.450", timedelta(hours=120, seconds=3.45)),
    ],
)
def test_a_written_value_is_typed_as_the_plc_holds_it(
    kind: ValueKind, value: Any, held: Any
) -> None:
    """What PLCComS sends: TecoApi's form, typed at once (no JSON spelled and read)."""
    point = _point(kind)
    written = written_value(point, value)
    assert written == held
    assert type(written) is type(held)
    assert written == parse_value(kind, json.loads(validate_write(point, value).json))


def test_a_written_value_is_refused_as_validate_write_refuses_it() -> None:
    point = _point(ValueKind.REAL, _meta(read_only=True), path="Main.myObject1")
    with pytest.raises(ReadOnlyError) as caught:
        written_value(point, 1.0)
    assert caught.value.path == "Main.myObject1.value"
    with pytest.raises(OutOfRangeError):
        written_value(_point(ValueKind.REAL, _meta(low=10.0, high=30.0)), 31)
    with pytest.raises(InvalidValueError):
        written_value(_point(ValueKind.STRING), "°C")


def test_raw_values_are_typed_by_what_they_are() -> None:
    assert encode_json_value("a", True) == WireValue("true", "true")
    assert encode_json_value("a", 3) == WireValue("3", "3")
    assert encode_json_value("a", 2.5e-7).json == "0.0"
    assert encode_json_value("a", "x y") == WireValue('"x y"', '"x y"')
    assert encode_json_value("a", {"b": [1.5e10, True], "c": "d"}) == WireValue(
        None, '{"b": [15000000000.0, true], "c": "d"}'
    )
    for bad in (None, {"b": None}, {"b": "°"}, {1: 2}, object()):
        with pytest.raises(InvalidValueError):
            encode_json_value("a", bad)
    # What no variable holds is refused in a text a user reads translated.
    with pytest.raises(InvalidValueError) as caught:
        encode_json_value("a", object())
    assert caught.value.text().key == "write_not_a_value"
    with pytest.raises(InvalidValueError) as caught:
        encode_json_value("a", {1: 2})
    assert caught.value.text().key == "write_member_name"


# --- over HTTP ----------------------------------------------------------------


async def test_a_t_api_object_is_written_with_set_object(
    manual_client: TecoApiClient,
    manual_simulator: Simulator,
    catalogue: Catalogue,
) -> None:
    manual_simulator.clear_requests()
    await manual_client.write(catalogue.points["main.myobject3"], 21.5)
    assert manual_simulator.get_value("Main.myObject3.value") == 21.5
    (record,) = manual_simulator.requests
    assert (record.method, record.service, record.status) == ("GET", "SetObject", 200)
    assert record.query == "Main.myObject3.value=21.5"


async def test_a_top_level_variable_is_written_with_put_object(
    manual_client: TecoApiClient,
    manual_simulator: Simulator,
    catalogue: Catalogue,
) -> None:
    manual_simulator.clear_requests()
    await manual_client.write(catalogue.points["plctype"], 1005)
    assert manual_simulator.get_value("plcType") == 1005
    (record,) = manual_simulator.requests
    assert (record.method, record.service, record.status) == ("PUT", "PutObject", 204)
    text = 'testing is "funny" & more = 100% #1'
    await manual_client.write(catalogue.points["plcdesc"], text)
    assert manual_simulator.get_value("plcDesc") == text


async def test_member_and_element_paths_use_set_object_safely(
    manual_client: TecoApiClient,
    manual_simulator: Simulator,
    catalogue: Catalogue,
) -> None:
    manual_simulator.clear_requests()
    await manual_client.write(catalogue.points["arr1[5]"], "five")
    assert manual_simulator.get_value("arr1[5]") == "five"
    assert manual_simulator.requests[-1].query == "arr1[5]=%22five%22"
    tricky = '"R" & b=1 #2'
    await manual_client.write(catalogue.points["myobject.favorites.color"], tricky)
    assert manual_simulator.get_value("myObject.favorites.color") == tricky
    assert manual_simulator.get_value("myObject.favorites.sport") == "Soccer"
    await manual_client.write(catalogue.points["myobject.registered"], True)
    assert manual_simulator.get_value("myObject.registered") is True
    await manual_client.write(catalogue.points["plcdata.vardate"], date(2020, 1, 2))
    assert manual_simulator.get_value("plcData.varDate") == "2020-01-02"
    moment = datetime(2021, 3, 4, 5, 6, 7, 890000, tzinfo=UTC)
    await manual_client.write(catalogue.points["plcdata.vardt"], moment)
    assert manual_simulator.get_value("plcData.varDT") == "2021-03-04T05:06:07.890Z"
    await manual_client.write(
        catalogue.points["plcdata.vartime"], time(0, 0, 1, 500000)
    )
    assert manual_simulator.get_value("plcData.varTime") == "00:00:01.500"
    await manual_client.write(catalogue.points["plcdata.varlreal"], 0.125)
    assert manual_simulator.get_value("plcData.varLreal") == 0.125
    assert all(record.service == "SetObject" for record in manual_simulator.requests)
    assert all(record.status == 200 for record in manual_simulator.requests)


async def test_a_long_string_member_goes_as_a_nested_put_object(
    manual_client: TecoApiClient,
    manual_simulator: Simulator,
    catalogue: Catalogue,
) -> None:
    text = "= " * 40
    manual_simulator.clear_requests()
    await manual_client.write(catalogue.points["plcdata.varstring"], text)
    assert manual_simulator.get_value("plcData.varString") == text
    assert manual_simulator.get_value("plcData.varInt") == -2222
    (record,) = manual_simulator.requests
    assert (record.method, record.service) == ("PUT", "PutObject")


async def test_validation_refusals_send_nothing(
    manual_client: TecoApiClient,
    manual_simulator: Simulator,
    catalogue: Catalogue,
) -> None:
    manual_simulator.clear_requests()
    points = catalogue.points
    with pytest.raises(ReadOnlyError):
        await manual_client.write(points["main.myobject1"], 5.0)
    with pytest.raises(OutOfRangeError):
        await manual_client.write(points["main.myobject3"], 30.5)
    with pytest.raises(InvalidValueError):
        await manual_client.write(points["main.myobject3"], "warm")
    with pytest.raises(InvalidValueError):
        await manual_client.write(points["plcdesc"], "°C")
    with pytest.raises(InvalidValueError):
        await manual_client.write(points["plcdesc"], "x" * 256)
    with pytest.raises(InvalidValueError):
        await manual_client.write(points["plcdata.varbool0"], 1)
    with pytest.raises(InvalidValueError):
        await manual_client.write(points["plcdata.vardate"], "tomorrow")
    with pytest.raises(InvalidValueError):
        await manual_client.write(points["plctype"], 2**40)
    assert manual_simulator.requests == []
    assert manual_simulator.get_value("Main.myObject3.value") == 23.0


async def test_a_value_the_plc_refuses_names_variable_and_value(
    manual_client: TecoApiClient,
    manual_simulator: Simulator,
    catalogue: Catalogue,
) -> None:
    # A plain integer's IEC type is unknown: 300 passes validation, USINT refuses.
    with pytest.raises(ValueRejectedError) as caught:
        await manual_client.write(catalogue.points["plcdata.varusint"], 300)
    assert caught.value.code == "400.015"
    assert caught.value.path == "plcData.varUsint"
    assert caught.value.value == 300
    # The value and the variable are told once: the PLC's message adds the type.
    assert caught.value.message == "it does not fit the variable's type, USINT"
    assert str(caught.value).count("300") == 1
    assert str(caught.value).count("plcData.varUsint") == 1
    assert isinstance(caught.value, PlcResponseError)
    assert manual_simulator.get_value("plcData.varUsint") == 11
    with pytest.raises(ValueRejectedError):
        await manual_client.write_path("plcType", 70000)
    assert manual_simulator.get_value("plcType") == 2005


async def test_write_path_writes_raw_json_values(
    manual_client: TecoApiClient,
    manual_simulator: Simulator,
    catalogue: Catalogue,
) -> None:
    await manual_client.write_path("plcName", "Foxy")
    assert manual_simulator.get_value("plcName") == "Foxy"
    await manual_client.write_path(
        "arr2", [[0.0, 0.11, 0.22, 0.33], [11.0, 11.11, 11.22, 11.33]]
    )
    assert manual_simulator.get_value("arr2[1][1]") == 11.11
    assert manual_simulator.get_value("arr2[2][0]") == 2.0
    await manual_client.write_path("myObject.age", 40)
    assert manual_simulator.get_value("myObject.age") == 40
    # A structure below the root goes as a nested PutObject (not into arrays).
    await manual_client.write_path("myObject.favorites", {"food": "Salad"})
    assert manual_simulator.get_value("myObject.favorites.food") == "Salad"
    assert manual_simulator.get_value("myObject.favorites.sport") == "Soccer"
    assert manual_simulator.requests[-1].service == "PutObject"
    with pytest.raises(InvalidValueError) as caught:
        await manual_client.write_path("arr2[1]", [1.0, 2.0])
    assert caught.value.text().key == "tecoapi_array_element"
    assert caught.value.text().params == {"length": "256"}
    with pytest.raises(InvalidValueError, match="not a variable path") as caught:
        await manual_client.write_path("myObject..favorites", {"food": "Soup"})
    assert caught.value.text().key == "write_not_a_path"


async def test_writes_to_a_variable_the_plc_rejects(
    manual_client: TecoApiClient,
    manual_simulator: Simulator,
    catalogue: Catalogue,
) -> None:
    manual_simulator.faults.rejected_by_object = {"Main"}
    with pytest.raises(PlcResponseError) as caught:
        await manual_client.write(catalogue.points["main.myobject3"], 20.0)
    assert caught.value.code == "400.005"
    assert not isinstance(caught.value, ValueRejectedError)
