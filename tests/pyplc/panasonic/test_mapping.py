"""An FP-I4C register map: Panasonic addresses, the types they hold, stations.

The core's CSV loader reads the file; the FP-I4C's check (``check_point``,
the descriptor's ``check_address``) refuses what the gateway cannot read,
naming the row and the column, and nothing is imported.
"""

from hypothesis import given, settings, strategies as st
import pytest

from custom_components.tecoapi.pyplc import Access
from custom_components.tecoapi.pyplc.core.pointmap import (
    MapPoint,
    PointMap,
    PointMapError,
    cells_of,
    data_type,
    dump_csv,
    load as load_map,
    load_csv,
    point_of,
)
from custom_components.tecoapi.pyplc.panasonic import check_point
from custom_components.tecoapi.pyplc.panasonic.address import (
    MAX_WORD,
    Address,
    Area,
)
from custom_components.tecoapi.pyplc.panasonic.descriptor import FPI4C
from custom_components.tecoapi.pyplc.panasonic.mapping import parse_station
from tests.pyplc.panasonic.conftest import example_map


def load(rows: str) -> PointMap:
    return load_csv(f"name,address,type,length,device\n{rows}", check_point)


def test_the_example_map_reads() -> None:
    point_map = example_map()
    assert len(point_map.points) == 24
    by_key = point_map.by_key()
    assert by_key["boiler_temp"].address == "DT0"
    assert by_key["boiler_temp"].scale == 0.1
    assert by_key["heating_on"].address == "R10"
    assert by_key["door_target"].device == "2 Door controller"
    assert by_key["status"].type.length == 24
    assert FPI4C.check_address is check_point
    assert FPI4C.point_map_formats == ("csv",)


def test_registers_bits_and_their_types() -> None:
    point_map = load(
        "a,DT100,INT,,\n"
        "b,ld5,UINT,,1\n"
        "c,WR3,WORD,,2 Boiler room\n"
        "d,R1A,BOOL,,\n"
        "e,Y18,BOOL,,\n"
        "f,X0,BOOL,,\n"
        "g,DT200,DINT,,\n"
        "h,FL10,REAL,,\n"
        "i,DT300,STRING,1000,\n"
        "j,WX2,UDINT,,\n"
    )
    assert [point.address for point in point_map.points][:3] == ["DT100", "ld5", "WR3"]


@pytest.mark.parametrize(
    ("row", "column", "message"),
    [
        ("a,DT,INT,,", "address", "not an FP address"),
        ("a,D100,INT,,", "address", "not an FP address"),
        ("a,R1G,BOOL,,", "address", "not an FP address"),
        ("a,DT1000000,INT,,", "address", "not an FP address"),
        ("a,LD16384,INT,,", "address", "no word above"),
        ("a,DT999999,DINT,,", "address", "past the area's end"),
        ("a,FL32767,REAL,,", "address", "FL32768"),
        ("a,R1A,INT,,", "type", "is a bit: its type is BOOL"),
        ("a,DT1,BOOL,,", "type", "R10 is bit 0 of WR1"),
        ("a,DT1,LREAL,,", "type", "reads INT, UINT, DINT, UDINT, REAL, STRING"),
        ("a,DT1,DATE,,", "type", "reads INT"),
        ("a,DT1,INT,4,", "length", "only a STRING has a length"),
        ("a,DT1,STRING,1001,", "length", "at most 1000 characters"),
        ("a,DT1,INT,,100", "device", "not a station"),
        ("a,DT1,INT,,Boiler", "device", "not a station"),
        ("a,DT1,INT,,-1", "device", "not a station"),
    ],
)
def test_what_the_gateway_cannot_read_is_refused_by_row_and_column(
    row: str, column: str, message: str
) -> None:
    with pytest.raises(PointMapError) as raised:
        load(f"ok,DT0,INT,,\n{row}\n")
    assert (raised.value.row, raised.value.column) == (3, column)
    assert message in raised.value.message


def test_an_unknown_type_lists_only_the_types_the_gateway_reads() -> None:
    """Not LREAL, LINT, DATE, TOD or DT: a map that names them is refused anyway."""
    assert FPI4C.point_types == (
        "bool",
        "word",
        "uint",
        "int",
        "dword",
        "udint",
        "dint",
        "real",
        "string",
    )
    text = "name,address,type\na,DT1,QWORD\n"
    with pytest.raises(PointMapError) as raised:
        load_map(
            text.encode(),
            "map.csv",
            FPI4C.point_map_loaders,
            check_point,
            FPI4C.point_types,
        )
    assert raised.value.message == (
        "unknown type 'QWORD' (known: BOOL, WORD, UINT, INT, DWORD, UDINT, DINT, "
        "REAL, STRING)"
    )
    with pytest.raises(PointMapError) as raised:
        point_of(
            {"name": "a", "address": "DT1", "type": "QWORD"},
            check_point,
            FPI4C.point_types,
        )
    assert "LREAL" not in raised.value.message
    assert "DATE" not in raised.value.message


def test_a_register_list_with_the_area_apart() -> None:
    point_map = load_csv(
        "name,area,address,type,count,station\n"
        "Boiler,DT,100,INT,,1\n"
        "Pump,Y,1A,BOOL,,1\n"
        "Text,DT,300,STRING,20,2\n",
        check_point,
    )
    assert [(point.address, point.device) for point in point_map.points] == [
        ("DT100", "1"),
        ("Y1A", "1"),
        ("DT300", "2"),
    ]
    assert point_map.points[2].type.length == 20
    with pytest.raises(PointMapError) as raised:
        load_csv("name,area,address,type\nA,DT,1A,INT\n", check_point)
    assert (raised.value.row, raised.value.column) == (2, "address")


def test_a_form_s_point_is_checked_as_a_row() -> None:
    with pytest.raises(PointMapError) as raised:
        point_of({"name": "a", "address": "Y1", "type": "INT"}, check_point)
    assert raised.value.column == "type"
    with pytest.raises(PointMapError) as raised:
        point_of({"name": "a", "address": "Y1X", "type": "BOOL"}, check_point)
    assert raised.value.column == "address"
    point = point_of(
        {"name": "a", "address": "Y1", "type": "BOOL", "device": "3"}, check_point
    )
    assert point.device == "3"


@pytest.mark.parametrize(
    ("text", "station", "name"),
    [
        ("", None, ""),
        ("0", 0, ""),
        ("2", 2, ""),
        ("99", 99, ""),
        (" 2  Garage door ", 2, "Garage door"),
        ("1 Heating plant", 1, "Heating plant"),
    ],
)
def test_a_station_is_its_number_and_maybe_a_name(
    text: str, station: int | None, name: str
) -> None:
    assert parse_station(text) == (station, name)


@st.composite
def fp_points(draw: st.DrawFn) -> MapPoint:
    """A point of any area the gateway reads, with a type its area holds."""
    area = draw(st.sampled_from(list(Area)))
    if area.bits:
        address = Address(
            area, draw(st.integers(0, MAX_WORD[area.words])), draw(st.integers(0, 15))
        )
        type_name, length = "bool", None
    else:
        type_name = draw(
            st.sampled_from(["int", "uint", "dint", "udint", "real", "string"])
        )
        last = MAX_WORD[area] - (1 if type_name in ("dint", "udint", "real") else 0)
        address = Address(area, draw(st.integers(0, last)))
        length = draw(st.integers(1, 1000)) if type_name == "string" else None
    found = data_type(type_name, length)
    assert found is not None
    return MapPoint(
        id=f"p_{address}",
        name=f"Point {address}",
        address=str(address),
        type=found,
        access=draw(st.sampled_from([Access.READ, Access.READ_WRITE])),
        unit=draw(st.sampled_from(["", "°C", "%"])),
        scale=draw(st.sampled_from([1.0, 0.1, 0.01])),
        offset=draw(st.sampled_from([0.0, -40.0])),
        device=draw(st.sampled_from(["", "0", "7", "99 Kotelna"])),
    )


def _unique(points: list[MapPoint]) -> tuple[MapPoint, ...]:
    return tuple({point.key: point for point in points}.values())


@settings(max_examples=80, deadline=None)
@given(st.lists(fp_points(), min_size=1, max_size=10).map(_unique))
def test_every_area_round_trips_through_a_csv_file(
    points: tuple[MapPoint, ...],
) -> None:
    """A map of any area, bits and words alike, written as CSV reads back the same."""
    text = dump_csv(PointMap(points))
    assert load_csv(text, check_point).points == points
    # And with a semicolon, as a Czech spreadsheet writes it.
    assert load_csv(text.replace(",", ";"), check_point).points == points


@settings(max_examples=40, deadline=None)
@given(fp_points())
def test_every_point_round_trips_through_its_form(point: MapPoint) -> None:
    assert point_of(cells_of(point), check_point) == point
