"""Point maps: the CSV loader, its errors, the loaders' plug-in point, the stored form.

The Mervis .vlist loader, a system's own, is tested in tests/pyplc/mervis/test_vlist.py.
"""

from collections.abc import Iterable
from pathlib import Path
import types
from typing import Any, Final

from hypothesis import given, settings, strategies as st
import pytest

from custom_components.tecoapi.pyplc import Access, ValueKind
from custom_components.tecoapi.pyplc.core.models import NUMERIC_KINDS
from custom_components.tecoapi.pyplc.core.pointmap import (
    CSV,
    CSV_COLUMNS,
    TYPE_NAMES,
    AddressCheck,
    MapPoint,
    PointMap,
    PointMapError,
    cells_of,
    data_type,
    dump_csv,
    load,
    load_csv,
    map_catalogue,
    point_of,
)

HEADER = ",".join(CSV_COLUMNS)


# --- CSV ---------------------------------------------------------------------


def test_a_csv_row_becomes_a_point() -> None:
    point_map = load_csv(
        f"{HEADER}\n"
        "boiler,Boiler water,DT100,INT,,°C,0.1,-5,yes,0,90,0.5,Plant,,temperature,"
        "measurement,,hot\n"
    )
    (point,) = point_map.points
    assert point == MapPoint(
        id="boiler",
        name="Boiler water",
        address="DT100",
        type=data_type("int"),  # type: ignore[arg-type]
        access=Access.READ_WRITE,
        unit="°C",
        scale=0.1,
        offset=-5.0,
        minimum=0.0,
        maximum=90.0,
        step=0.5,
        device="Plant",
        device_class="temperature",
        state_class="measurement",
        description="hot",
    )
    assert point.type.bits == 16
    assert point.type.signed


def test_semicolons_decimal_commas_aliases_comments_and_blank_rows() -> None:
    """What a Czech spreadsheet writes: ';', decimal commas, its own column names."""
    text = (
        "\ufeff# registers of the plant\n"
        "Name;Address;Type;Unit;Scale;Access;Station\n"
        "\n"
        "Teplota kotle;DT10;int;°C;0,1;no;1\n"
        "# a comment row\n"
        "Čerpadlo;Y1A;bool;;;ano?;1\n"
    )
    with pytest.raises(PointMapError) as raised:
        load_csv(text)
    assert (raised.value.row, raised.value.column) == (6, "writable")
    point_map = load_csv(text.replace("ano?", "yes"))
    first, second = point_map.points
    assert (first.id, first.scale, first.device) == ("Teplota kotle", 0.1, "1")
    assert (second.name, second.access) == ("Čerpadlo", Access.READ_WRITE)


@pytest.mark.parametrize(
    ("row", "column", "message"),
    [
        ("a,,INT", "address", "is empty"),
        ("a,x,QWORD", "type", "unknown type 'QWORD'"),
        ("a,x,INT,zero", "length", "not a positive whole number"),
        ("a,x,INT,,,0", "scale", "must not be 0"),
        ("a,x,INT,,,abc", "scale", "'abc' is not a number"),
        ("a,x,INT,,,,,,,10,5", "min", "10 is above max 5"),
        ("a,x,INT,,,,,,,inf", "min", "'inf' is not a number"),
    ],
)
def test_a_bad_cell_names_its_row_and_column(
    row: str, column: str, message: str
) -> None:
    header = "name,address,type,length,unit,scale,offset,writable,x,min,max"
    header = header.replace(",x,", ",step,")
    with pytest.raises(PointMapError) as raised:
        load_csv(f"{header}\nok,y,BOOL\n{row}\n")
    assert (raised.value.row, raised.value.column) == (3, column)
    assert message in str(raised.value)


def test_a_flag_may_be_inverted_and_shown_with_the_class_its_map_gives() -> None:
    """A limit switch on when the door is closed, shown as a garage door."""
    point_map = load_csv(
        "id,name,address,type,device_class,invert\n"
        "closed,Garage door closed,X0,BOOL,garage_door,yes\n"
        "light,Garage light,Y0,BOOL,,\n"
    )
    closed, light = point_map.points
    assert (closed.device_class, closed.invert, light.invert) == (
        "garage_door",
        True,
        False,
    )
    catalogue = map_catalogue(point_map)
    assert catalogue.points["closed"].invert
    assert catalogue.points["closed"].flag(True) is False
    assert catalogue.points["light"].flag(True) is True
    assert PointMap.from_json(point_map.as_json()) == point_map
    assert "invert" not in point_map.as_json()["points"][1]
    for row, message in (
        ("x,X1,BOOL,,maybe", "'maybe' is neither yes nor no"),
        ("x,DT1,INT,,yes", "only a BOOL can be inverted, not INT"),
    ):
        with pytest.raises(PointMapError) as raised:
            load_csv(f"name,address,type,device_class,invert\n{row}\n")
        assert (raised.value.row, raised.value.column) == (2, "invert")
        assert message in str(raised.value)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("", "the file has no header"),
        ("name,type\n", "no 'address' column"),
        ("name,address,type,colour\n", "unknown column 'colour'"),
        ("name,address,type\n", "the file holds no point"),
        ("name,address,type\na,b,INT,1\n", "4 cells, the header has 3"),
        ("name,address,type\na,b,INT\nA,c,INT\n", "the ID 'A' is taken by row 2"),
    ],
)
def test_a_bad_file_imports_nothing(text: str, message: str) -> None:
    with pytest.raises(PointMapError, match=message):
        load_csv(text)


def test_an_area_column_is_written_before_the_address() -> None:
    """Register lists that keep the area apart: DT and 100 are DT100."""
    point_map = load_csv("name;area;address;type\nBoiler;DT;100;INT\nPump;;Y1A;BOOL\n")
    assert [point.address for point in point_map.points] == ["DT100", "Y1A"]
    # Written back, the address is whole (and reads the same).
    assert load_csv(dump_csv(point_map)).points == point_map.points
    with pytest.raises(PointMapError) as raised:
        load_csv("name,area,address,type\nBoiler,DT,,INT\n")
    assert raised.value.column == "address"


def test_the_source_checks_each_address() -> None:
    def registers_only(point: MapPoint) -> str | None:
        return None if point.address.startswith("DT") else "not a register"

    with pytest.raises(PointMapError) as raised:
        load_csv("name,address,type\na,DT1,INT\nb,X1,BOOL\n", registers_only)
    assert (raised.value.row, raised.value.column) == (3, "address")


def test_a_check_may_name_another_column() -> None:
    """A source's check that finds the type at fault says so; the loader adds the row."""

    def words_only(point: MapPoint) -> str | None:
        if point.type.kind is ValueKind.BOOL:
            raise PointMapError("a register holds no BOOL", column="type")
        if point.address == "anything":
            raise PointMapError("the whole point is wrong")
        return None

    with pytest.raises(PointMapError) as raised:
        load_csv("name,address,type\na,DT1,INT\nb,DT2,BOOL\n", words_only)
    assert (raised.value.row, raised.value.column) == (3, "type")
    assert str(raised.value) == "row 3, column type: a register holds no BOOL"
    with pytest.raises(PointMapError) as raised:
        point_of({"name": "b", "address": "DT2", "type": "BOOL"}, words_only)
    assert (raised.value.row, raised.value.column) == (0, "type")
    # A problem that names no column is the check's own column's.
    with pytest.raises(PointMapError) as raised:
        load_csv("name,address,type\na,anything,INT\n", words_only)
    assert (raised.value.row, raised.value.column) == (2, "address")


_ident = (
    st.text(
        alphabet=st.characters(codec="utf-8", exclude_categories=("C", "Zl", "Zp")),
        min_size=1,
        max_size=12,
    )
    .map(str.strip)
    .filter(bool)
)
_number = st.one_of(
    st.none(), st.floats(-1e6, 1e6, allow_nan=False).map(lambda x: round(x, 3))
)


@st.composite
def map_points(draw: st.DrawFn) -> MapPoint:
    type_name = draw(st.sampled_from(sorted(TYPE_NAMES)))
    found = data_type(type_name, draw(st.none() | st.integers(1, 1000)))
    assert found is not None
    low, high = draw(_number), draw(_number)
    if low is not None and high is not None and low > high:
        low, high = high, low
    return MapPoint(
        # A first cell starting with # is a comment row (not a point) in a CSV.
        id=draw(_ident.filter(lambda text: not text.startswith("#"))),
        name=draw(_ident),
        address=draw(_ident),
        type=found,
        access=draw(st.sampled_from([Access.READ, Access.READ_WRITE])),
        unit=draw(st.sampled_from(["", "°C", "%", "kWh"])),
        scale=draw(st.sampled_from([1.0, 0.1, 0.01, 10.0, -2.5])),
        offset=draw(st.sampled_from([0.0, -40.0, 273.15])),
        minimum=low,
        maximum=high,
        step=draw(st.none() | st.sampled_from([0.5, 1.0, 0.1])),
        device=draw(st.sampled_from(["", "Plant", "Garáž"])),
        platform=draw(st.sampled_from(["", "sensor"])),
        device_class=draw(st.sampled_from(["", "temperature"])),
        state_class=draw(st.sampled_from(["", "measurement", "total_increasing"]))
        if found.kind in NUMERIC_KINDS
        else "",
        invert=found.kind is ValueKind.BOOL and draw(st.booleans()),
        description=draw(st.sampled_from(["", 'a, b; "c"'])),
    )


def _unique(points: list[MapPoint]) -> tuple[MapPoint, ...]:
    seen: set[str] = set()
    kept = []
    for point in points:
        if point.key not in seen:
            seen.add(point.key)
            kept.append(point)
    return tuple(kept)


@settings(max_examples=60, deadline=None)
@given(st.lists(map_points(), min_size=1, max_size=8).map(_unique))
def test_csv_round_trip(points: tuple[MapPoint, ...]) -> None:
    """A map written as CSV reads back to the same points, every type and column."""
    point_map = PointMap(points)
    assert load_csv(dump_csv(point_map)).points == points


@settings(max_examples=60, deadline=None)
@given(st.lists(map_points(), min_size=1, max_size=8).map(_unique))
def test_stored_round_trip(points: tuple[MapPoint, ...]) -> None:
    """A map stored as JSON reads back to the same points (a 0 range end too)."""
    point_map = PointMap(points, "csv")
    assert PointMap.from_json(point_map.as_json()) == point_map


@settings(max_examples=40, deadline=None)
@given(map_points())
def test_one_point_round_trips_through_its_form(point: MapPoint) -> None:
    assert point_of(cells_of(point)) == point


def test_an_id_that_starts_with_a_hash_is_no_comment() -> None:
    """Written back, an ID such as #1 is quoted: unquoted, its row would be a comment."""
    points = tuple(
        MapPoint(id=ident, name="x", address="a", type=TYPE_NAMES["int"])
        for ident in ("#", "#1", 'a,"b"', "c")
    )
    text = dump_csv(PointMap(points))
    assert '\n"#1",x,' in text
    assert load_csv(text).points == points
    assert load_csv("name,address,type\n#1,a,INT\n" + '"#2",a,INT\n').points == (
        MapPoint(id="#2", name="#2", address="a", type=TYPE_NAMES["int"]),
    )


def test_a_map_refuses_two_points_of_one_id() -> None:
    point = load_csv("name,address,type\na,b,INT\n").points[0]
    with pytest.raises(PointMapError, match="two points have the ID"):
        PointMap((point, point))
    with pytest.raises(PointMapError, match="is taken"):
        PointMap((point,)).with_new_point(point)


def test_points_are_replaced_added_and_removed_by_key() -> None:
    point_map = load_csv("name,address,type\nA,x,INT\nB,y,INT\n")
    renamed = MapPoint(
        id="A", name="Renamed", address="x", type=point_map.points[0].type
    )
    assert point_map.with_point(renamed).points[0].name == "Renamed"
    assert [point.id for point in point_map.without("a").points] == ["B"]


def test_the_catalogue_of_a_map() -> None:
    point_map = load_csv(
        "id,name,address,type,unit,scale,writable,device\n"
        "T1,Boiler,DT1,INT,°C,0.1,yes,Plant room\n"
        "p,Pump,Y1,BOOL,,,no,\n"
    )
    catalogue = map_catalogue(point_map)
    boiler = catalogue.points["t1"]
    assert (boiler.path, boiler.address, boiler.device) == ("T1", "DT1", "plant room")
    assert boiler.kind is ValueKind.REAL  # an INT register in tenths shows reals
    assert boiler.attributes is not None
    assert boiler.attributes.writable
    assert catalogue.devices["plant room"].name == "Plant room"
    assert catalogue.points["p"].device == ""


def test_load_picks_the_format_by_the_file_name() -> None:
    csv_map = load(b"name,address,type\na,b,INT\n", "points.CSV")
    assert csv_map.format == "csv"
    with pytest.raises(PointMapError, match=r"not a \.csv file"):
        load(b"x", "points.xlsx", CSV)
    with pytest.raises(PointMapError, match="larger than"):
        load(b" " * (9 * 1024 * 1024), "big.csv")


def test_load_reads_the_formats_of_the_loaders_it_is_given() -> None:
    """The plug-in point: a format is the loader a caller passes, none built in but CSV."""
    seen: list[tuple[str, object, tuple[str, ...], str]] = []

    def lines(
        text: str,
        check: AddressCheck | None = None,
        types: Iterable[str] = (),
        *,
        file_name: str = "",
    ) -> PointMap:
        seen.append((text, check, tuple(types), file_name))
        return load_csv("name,address,type\n" + text, None)

    with pytest.raises(PointMapError, match=r"not a \.csv file"):
        load(b"a,b,INT\n", "points.lines")
    point_map = load(b"a,b,INT\n", "points.lines", {"lines": lines}, None, ("INT",))
    assert [point.id for point in point_map.points] == ["a"]
    # The file's name too: a format's names may say something of the map.
    assert seen == [("a,b,INT\n", None, ("INT",), "points.lines")]
    with pytest.raises(PointMapError, match=r"of these formats: \.lines, \.csv"):
        load(b"", "points.xlsx", {"lines": lines, **CSV})


# --- state classes (a number's history) ------------------------------------------------


def test_a_state_class_is_a_number_s_and_one_home_assistant_keeps() -> None:
    """An energy counter kept as a total; a word no one knows, or a flag's, refused."""
    point_map = load_csv(
        "name,address,type,unit,state_class\n"
        "Energy,DT0,UDINT,kWh,TOTAL_INCREASING\n"
        "Temperature,DT2,REAL,°C,\n"
    )
    energy, temperature = point_map.points
    assert (energy.state_class, temperature.state_class) == ("total_increasing", "")
    catalogue = map_catalogue(point_map)
    assert catalogue.points["energy"].state_class == "total_increasing"
    for row, key, params in (
        (
            "E,DT0,UDINT,kWh,increasing",
            "map_unknown_state_class",
            {
                "value": "'increasing'",
                "known": "measurement, measurement_angle, total, total_increasing",
            },
        ),
        ("Door,X0,BOOL,,total", "map_no_state_class", {"type": "BOOL"}),
    ):
        with pytest.raises(PointMapError) as raised:
            load_csv(f"name,address,type,unit,state_class\n{row}\n")
        assert (raised.value.row, raised.value.column) == (2, "state_class")
        assert (raised.value.key, dict(raised.value.params)) == (key, params)


FIXTURES: Final = Path(__file__).parent / "fixtures"
STORED_0_3_0: Final = FIXTURES / "pointmap_0_3_0.py.txt"
"""The point map module of 0.3.0 (commit 5b5de6a), the release before this one."""


def previous_release() -> Any:
    """The module 0.3.0 read its stored maps with, on this library's models."""
    package = PointMap.__module__.rsplit(".", 2)[0]  # ….pyplc.core
    module = types.ModuleType(f"{package}.pointmap_0_3_0")
    module.__package__ = package
    code = compile(STORED_0_3_0.read_text(encoding="utf-8"), str(STORED_0_3_0), "exec")
    exec(code, module.__dict__)  # noqa: S102 (the previous release's own code)
    return module


def test_a_map_stored_with_state_classes_is_one_0_3_0_reads() -> None:
    """0.3.0 reads the fields it knows and leaves the others: the map loads there.

    (A previous release keeps working on what this one stores: its
    ``PointMap.from_json`` takes each known field with ``get`` and ignores
    the rest, as the stored JSON's ``version`` stays 1.)
    """
    point_map = load_csv(
        "name,address,type,unit,state_class,device_class\n"
        "Energy,DT0,UDINT,kWh,total_increasing,energy\n"
        "Pump,Y0,BOOL,,,running\n"
    )
    stored = point_map.as_json()
    assert stored["points"][0]["state_class"] == "total_increasing"
    assert "state_class" not in stored["points"][1]  # none: left out
    assert stored["version"] == 1

    old = previous_release().PointMap.from_json(stored)
    assert [(point.id, point.unit, point.device_class) for point in old.points] == [
        ("Energy", "kWh", "energy"),
        ("Pump", "", "running"),
    ]
    # And a map 0.3.0 stored (no state class) is one this release reads.
    again = PointMap.from_json(previous_release().PointMap.as_json(old))
    assert [point.state_class for point in again.points] == ["", ""]
    assert again.points[0].device_class == "energy"
