"""The Mervis .vlist loader on the format's corner cases (mervis/vlist.py).

Names become readable, devices are function block instances or top-level
segments, containers are not points, enumerations are 32-bit integers, a row
whose length is not its type's is reported, and the project's name is kept.
"""

from dataclasses import replace

import pytest

from custom_components.tecoapi.pyplc import ValueKind
from custom_components.tecoapi.pyplc.core import registry
from custom_components.tecoapi.pyplc.core.models import DataType
from custom_components.tecoapi.pyplc.core.pointmap import (
    MapPoint,
    PointMap,
    PointMapError,
    load,
    map_catalogue,
)
from custom_components.tecoapi.pyplc.mervis.vlist import (
    PROJECT,
    adopt_vlist,
    load_vlist,
    projects_of,
    readable_name,
    with_project,
)
from tests.simulator.mervis.project import (
    LIBRARIES,
    SHARED_NAME,
    SOLUTION_NAME,
    solution,
)

HEADER = (
    "#ver:1.0\nProject;Name;Type;CommUid;Offset;Length;ParentTypeFamily;HistoryId\n"
)


def vlist(*rows: str) -> str:
    return HEADER + "".join(f"{row}\n" for row in rows)


def test_names_are_spelled_in_words_and_ids_keep_the_dots() -> None:
    point_map = load_vlist(
        vlist(
            "House;$hw$.$neuron_s103_di_1.04$;$bool$;17249;0;1;none;",
            "House;$obyvak$.$teplotaZadana$;$real$;7001;0;4;fb;",
        )
    )
    di, setpoint = point_map.points
    assert (di.id, di.name) == ("hw.neuron_s103_di_1.04", "Hw neuron S103 DI 1.04")
    assert (setpoint.id, setpoint.name) == (
        "obyvak.teplotaZadana",
        "Obyvak teplota zadana",
    )
    assert setpoint.key == "obyvak.teplotazadana"


@pytest.mark.parametrize(
    ("parts", "name"),
    [
        (("hw", "neuron_s103_ro_2.01"), "Hw neuron s103 ro 2.01"),
        (("kotel", "do_1.01"), "Kotel do 1.01"),
        (("Kuchyň", "světloStrop"), "Kuchyň světlo strop"),
        (("ŽaluzieObývák",), "Žaluzie obývák"),
        (("a__b",), "A b"),
    ],
)
def test_readable_names(parts: tuple[str, ...], name: str) -> None:
    assert readable_name(parts) == name


@pytest.mark.parametrize(
    ("name", "spelled"),
    [
        ("$hw$.$neuron_l203_di_1.01$", "Hw neuron L203 DI 1.01"),
        ("$hw$.$neuron_l203_ro_2.08$", "Hw neuron L203 RO 2.08"),
        ("$hw$.$NEURON_S103_AI_1.01$", "Hw neuron S103 AI 1.01"),
        ("$hw$.$neuron_l203_ao_1.01$", "Hw neuron L203 AO 1.01"),
        ("$hw$.$neuron_l203_do_1.04$", "Hw neuron L203 DO 1.04"),
        ("$hw$.$neuron_l203_uart_1_baudrate$", "Hw neuron L203 UART 1 baudrate"),
        ("$hw$.$neuron_l203_led_1.02$", "Hw neuron L203 LED 1.02"),
        ("$hw$.$neuron_l203_ro_2.01_pwm_duty$", "Hw neuron L203 RO 2.01 PWM duty"),
        # Outside the boards' namespace the words are the program's: "do" is
        # Czech for "into", and no board is named.
        ("$cas_do_zapnuti$", "Cas do zapnuti"),
        ("$kotel$.$di_1.01$", "Kotel di 1.01"),
    ],
)
def test_unipi_s_io_names_keep_their_capitals(name: str, spelled: str) -> None:
    """Unipi writes DI, DO, RO, AI, AO, UART: its boards' names keep them."""
    (point,) = load_vlist(vlist(f"House;{name};$bool$;1;0;1;none;")).points
    assert point.name == spelled


def test_devices_are_function_blocks_or_top_level_segments() -> None:
    """A member of a block is on the block, however deep; anything else on its top."""
    point_map = load_vlist(
        vlist(
            # A top-level variable: the controller's own device.
            "House;$clock$;$dt$;10;0;8;none;",
            # A namespace.
            "House;$hw$.$neuron_s103_ro_2.01$;$bool$;11;0;1;none;",
            # A function block instance, its own row first.
            "House;$kotel_1$;$T_BOILER$;12;0;16;none;",
            "House;$kotel_1$.$teplota$;$real$;12;0;4;fb;",
            # A struct of blocks: each block is a device.
            "House;$rooms$.$living$.$temperature$;$real$;13;4;4;fb;",
            "House;$rooms$.$living$.$setpoint$;$real$;13;8;4;fb;",
            "House;$rooms$.$living$.$limits$.$high$;$real$;13;12;4;struct;",
            "House;$rooms$.$count$;$int$;13;0;2;struct;",
            # An array of numbers.
            "House;$hours$[3];$udint$;14;12;4;array;",
        )
    )
    devices = {point.id: point.device for point in point_map.points}
    assert devices == {
        "clock": "",
        "hw.neuron_s103_ro_2.01": "Hw",
        "kotel_1.teplota": "Kotel 1",
        "rooms.living.temperature": "Rooms living",
        "rooms.living.setpoint": "Rooms living",
        "rooms.living.limits.high": "Rooms living",
        "rooms.count": "Rooms",
        "hours[3]": "Hours",
    }
    catalogue = map_catalogue(point_map)
    assert catalogue.devices["rooms living"].name == "Rooms living"
    assert catalogue.points["rooms.living.setpoint"].device == "rooms living"


def test_an_array_element_is_named_by_its_index() -> None:
    (point,) = load_vlist(vlist("House;$valves$[2,1];$bool$;20;5;1;array;")).points
    assert (point.id, point.name, point.address) == (
        "valves[2,1]",
        "Valves 2 1",
        "20[5,1]",
    )


def test_containers_are_no_points_and_are_not_reported() -> None:
    point_map = load_vlist(
        vlist(
            "House;$heating$;$T_HEATING$;7001;0;64;none;",
            "House;$heating$.$setpoint$;$real$;7001;4;4;fb;",
            "House;$heating$.$mode$;$T_MODE$;7001;8;4;fb;",
        )
    )
    assert [point.id for point in point_map.points] == [
        "heating.setpoint",
        "heating.mode",
    ]
    assert point_map.skipped == ()


def test_an_enumeration_is_a_32_bit_integer() -> None:
    """A 4-byte type a map does not know, with nothing in it: the panel's int32."""
    point_map = load_vlist(
        vlist(
            "House;$mode$;$T_MODE$;30;0;4;none;",
            "House;$pair$;$T_PAIR$;31;0;4;none;",
            "House;$pair$.$a$;$int$;31;0;2;struct;",
            "House;$pair$.$b$;$int$;31;2;2;struct;",
        )
    )
    points = point_map.by_key()
    mode = points["mode"]
    assert mode.type == DataType(kind=ValueKind.INTEGER, bits=32)
    assert mode.details["enum"] == "T_MODE"
    # A 4-byte struct is a container: its members are the points.
    assert "pair" not in points
    assert "enum" not in points["pair.a"].details


@pytest.mark.parametrize(
    ("row", "reason"),
    [
        ("House;$x$;$int$;1;0;4;none;", "type 'int' takes 2 bytes, the row says 4"),
        ("House;$x$;$bool$;1;0;2;none;", "type 'bool' takes 1 bytes, the row says 2"),
        ("House;$x$;$dt$;1;0;4;none;", "type 'dt' takes 8 bytes, the row says 4"),
        ("House;$x$;$time$;1;0;2;none;", "type 'time' takes 4 or 8 bytes"),
        ("House;$x$;$T_RECIPE$;1;0;64;none;", "type 'T_RECIPE' is not one"),
    ],
)
def test_a_row_that_does_not_fit_its_type_is_reported(row: str, reason: str) -> None:
    point_map = load_vlist(vlist("House;$ok$;$bool$;2;0;1;none;", row))
    assert [point.id for point in point_map.points] == ["ok"]
    ((line, said),) = point_map.skipped
    assert line == 4
    assert said.startswith(reason)


@pytest.mark.parametrize(
    ("type_name", "length", "kind"),
    [
        ("time", 8, ValueKind.DURATION),
        ("time", 4, ValueKind.DURATION),
        ("tod", 8, ValueKind.TIME),
        ("date", 8, ValueKind.DATE),
        ("dt", 8, ValueKind.DATETIME),
        ("lword", 8, ValueKind.INTEGER),
        ("usint", 1, ValueKind.INTEGER),
        ("byte", 1, ValueKind.INTEGER),
        ("lreal", 8, ValueKind.REAL),
    ],
)
def test_the_types_of_ticks_and_widths(
    type_name: str, length: int, kind: ValueKind
) -> None:
    (point,) = load_vlist(vlist(f"House;$x$;${type_name}$;1;0;{length};none;")).points
    assert point.type.kind is kind


def test_a_string_holds_its_bytes() -> None:
    (point,) = load_vlist(vlist("House;$note$;$string$;1;0;32;none;")).points
    assert (point.type.kind, point.type.length, point.type.encoding) == (
        ValueKind.STRING,
        32,
        "utf-8",
    )


@pytest.mark.parametrize(
    ("row", "column", "message"),
    [
        ("House;$a$$b$;$bool$;1;0;1;none;", "Name", "is not a name"),
        ("House;$a$.b;$bool$;1;0;1;none;", "Name", "is not a name"),
        ("House;$ $;$bool$;1;0;1;none;", "Name", "is not a name"),
        ("House;[1];$bool$;1;0;1;none;", "Name", "is not a name"),
        ("House;$a$;$bool$;1;0;0;none;", "Length", "must not be 0"),
        ("House;$a$;$bool$;1;x;1;none;", "Offset", "'x' is not a number"),
        ("House;$a$;$bool$;1", "", "4 cells, the header has 8"),
    ],
)
def test_a_bad_row_names_its_column(row: str, column: str, message: str) -> None:
    with pytest.raises(PointMapError, match=message) as raised:
        load_vlist(vlist(row))
    assert (raised.value.row, raised.value.column) == (3, column)


def test_the_project_is_kept_and_stored() -> None:
    point_map = load_vlist(vlist("Podlužany;$a$;$bool$;1;0;1;none;"))
    assert point_map.properties == {"project": "Podlužany"}
    stored = PointMap.from_json(point_map.as_json())
    assert stored.properties == {"project": "Podlužany"}
    assert stored == point_map
    assert point_map.without("a").properties == point_map.properties
    added = MapPoint(id="b", name="B", address="2[0,1]", type=point_map.points[0].type)
    assert point_map.with_new_point(added).properties == point_map.properties
    assert load_vlist(vlist(";$a$;$bool$;1;0;1;none;")).properties == {}


def test_a_map_of_no_project_stores_none() -> None:
    point_map = load_vlist(vlist(";$a$;$bool$;1;0;1;none;"))
    assert "properties" not in point_map.as_json()


@pytest.mark.parametrize("encoding", ["utf-8", "utf-8-sig", "cp1250"])
def test_diacritics_in_either_encoding_with_crlf(encoding: str) -> None:
    text = vlist("Dům;$kuchyň$.$světlo$;$bool$;1;0;1;struct;").replace("\n", "\r\n")
    point_map = load(text.encode(encoding), "dum.VLIST", {"vlist": load_vlist})
    (point,) = point_map.points
    assert (point.id, point.name, point.device) == (
        "kuchyň.světlo",
        "Kuchyň světlo",
        "Kuchyň",
    )
    assert point_map.properties["project"] == "Dům"


def test_a_file_of_containers_only_holds_no_point() -> None:
    with pytest.raises(PointMapError, match="holds no variable a map knows"):
        load_vlist(vlist("House;$recipe$;$T_RECIPE$;1;0;64;none;"))


def test_the_address_check_names_the_row() -> None:
    def refuse(point: MapPoint) -> str | None:
        return "too far" if point.address.startswith("9") else None

    with pytest.raises(PointMapError, match="too far") as raised:
        load_vlist(
            vlist("House;$a$;$bool$;1;0;1;none;", "House;$b$;$bool$;9;0;1;none;"),
            refuse,
        )
    assert (raised.value.row, raised.value.column) == (4, "CommUid")


OWN_HEADER = (
    "#ver:1.0\nProject;Name;Type;CommUid;Offset;Length;ParentTypeFamily;HistoryId;"
    "Unit;Writable;Min;Max;Invert\n"
)


def test_a_map_s_own_columns_after_the_ide_s_set_what_the_options_would() -> None:
    """A unit, writable, a range, an inverted flag: read as a CSV map's cells are.

    Rows without them (cut after the IDE's columns, or empty cells) keep the
    defaults; the point's ID, address and device stay the .vlist's.
    """
    point_map = load_vlist(
        OWN_HEADER
        + "House;$room$.$setpoint$;$real$;7001;4;4;fb;;°C;yes;15;28;\n"
        + "House;$energy$;$lreal$;7002;0;8;none;;kWh\n"
        + "House;$closed$;$bool$;7003;0;1;none;;;;;;yes\n"
        + "House;$other$;$int$;7004;0;2;none;\n"
    )
    setpoint, energy, closed, other = point_map.points
    assert (setpoint.id, setpoint.address, setpoint.device) == (
        "room.setpoint",
        "7001[4,4]",
        "Room",
    )
    assert (setpoint.unit, setpoint.access.writable) == ("°C", True)
    assert (setpoint.minimum, setpoint.maximum) == (15.0, 28.0)
    assert (energy.unit, energy.access.writable) == ("kWh", False)
    assert closed.invert
    assert other == load_vlist(vlist("House;$other$;$int$;7004;0;2;none;")).points[0]


def test_a_vlist_s_own_state_class_keeps_a_counter_s_history_as_a_total() -> None:
    """The CSV map's state_class column, after the IDE's: a number's only."""
    header = OWN_HEADER.replace("Invert\n", "Invert;State_class\n")
    point_map = load_vlist(
        header + "House;$energy$;$lreal$;7002;0;8;none;;kWh;;;;;total_increasing\n"
    )
    assert point_map.points[0].state_class == "total_increasing"
    with pytest.raises(PointMapError) as caught:
        load_vlist(header + "House;$closed$;$bool$;7003;0;1;none;;;;;;;total\n")
    assert (caught.value.row, caught.value.column) == (3, "state_class")
    assert caught.value.key == "map_no_state_class"


@pytest.mark.parametrize(
    ("cells", "column", "message"),
    [
        (";maybe;;;", "writable", "'maybe' is neither yes nor no"),
        (";;x;;", "min", "'x' is not a number"),
        (";;;;yes", "invert", "only a BOOL can be inverted, not REAL"),
    ],
)
def test_a_bad_cell_of_a_map_s_own_column_names_its_row_and_column(
    cells: str, column: str, message: str
) -> None:
    with pytest.raises(PointMapError) as caught:
        load_vlist(OWN_HEADER + f"House;$a$;$real$;7001;0;4;none;;°C{cells}\n")
    assert (caught.value.row, caught.value.column) == (3, column)
    assert message in str(caught.value)


# --- Moved from tests/pyplc/core/test_pointmap.py with the loader -------------------

VLIST = (
    "#ver:1.0\r\n"
    "Project;Name;Type;CommUid;Offset;Length;ParentTypeFamily;HistoryId\r\n"
    "House;$hw$.$neuron_s103_di_1.04$;$bool$;17249;0;1;none;\r\n"
    "House;$lreal1$;$lreal$;6690;0;8;none;\r\n"
    "House;$heating$.$setpoint$;$real$;7001;4;4;fb;\r\n"
    "House;$heating$.$active$;$bool$;7001;8;1;fb;\r\n"
    "House;$rooms$.$obývák$;$int$;7100;2;2;struct;\r\n"
    "House;$arr$.$3$;$dint$;7200;12;4;array;\r\n"
    "House;$clock$;$dt$;7300;0;8;none;\r\n"
    "House;$note$;$string$;7400;0;32;none;\r\n"
    "House;$recipe$;$T_RECIPE$;7500;0;64;none;\r\n"
)


def test_a_vlist_becomes_points_members_on_their_parent_s_device() -> None:
    point_map = load_vlist(VLIST)
    points = point_map.by_key()
    di = points["hw.neuron_s103_di_1.04"]
    assert (di.address, di.type.kind, di.device) == (
        "17249[0,1]",
        ValueKind.BOOL,
        "Hw",
    )
    setpoint = points["heating.setpoint"]
    assert (setpoint.address, setpoint.device) == ("7001[4,4]", "Heating")
    assert setpoint.details["family"] == "fb"
    assert points["rooms.obývák"].device == "Rooms"
    assert points["arr.3"].type.bits == 32
    assert points["clock"].type.kind is ValueKind.DATETIME
    assert points["note"].type.length == 32
    assert point_map.format == "vlist"


def test_an_unknown_vlist_type_is_reported_not_crashed() -> None:
    point_map = load_vlist(VLIST)
    assert "recipe" not in point_map.by_key()
    assert point_map.skipped == ((11, "type 'T_RECIPE' is not one a map knows"),)


@pytest.mark.parametrize("encoding", ["utf-8", "cp1250"])
def test_a_vlist_in_utf8_or_windows_1250(encoding: str) -> None:
    data = VLIST.replace("\r\n", "\n").encode(encoding)
    point_map = load(data, "house.vlist", registry.source("mervis").point_map_loaders)
    assert "rooms.obývák" in point_map.by_key()


@pytest.mark.parametrize(
    ("text", "row", "message"),
    [
        ("Project;Name\n", 1, "no #ver: line"),
        ("#ver:2.0\nProject;Name\n", 1, "version 2.0 is not 1.x"),
        ("#ver:1.0\n", 1, "the file has no header"),
        ("#ver:1.0\nProject;Name;Type\n", 2, "no 'commuid' column"),
        (VLIST + "House;$x$;$bool$;abc;0;1;none;\r\n", 12, "'abc' is not a number"),
        (VLIST + "House;x;$bool$;1;0;1;none;\r\n", 12, "is not a name"),
        (VLIST + "House;$clock$;$dt$;7301;0;8;none;\r\n", 12, "is taken by row 9"),
    ],
)
def test_a_bad_vlist_imports_nothing(text: str, row: int, message: str) -> None:
    with pytest.raises(PointMapError, match=message) as raised:
        load_vlist(text)
    assert raised.value.row == row


def test_a_check_may_name_another_column() -> None:
    """A source's check that finds the type at fault says so; the loader adds the row."""

    def words_only(point: MapPoint) -> str | None:
        if point.type.kind is ValueKind.BOOL:
            raise PointMapError("a register holds no BOOL", column="type")
        return None

    with pytest.raises(PointMapError) as raised:
        load_vlist(
            "#ver:1.0\nProject;Name;Type;CommUid;Offset;Length\nP;$a$;$BOOL$;1;0;1\n",
            words_only,
        )
    assert (raised.value.row, raised.value.column) == (3, "type")


def test_the_mervis_descriptor_declares_the_loader() -> None:
    """The core reads no .vlist of its own: Mervis's descriptor brings the loader."""
    data = vlist("House;$clock$;$dt$;7300;0;8;none;").encode()
    with pytest.raises(PointMapError, match=r"not a \.csv file"):
        load(data, "house.vlist")
    mervis = registry.source("mervis")
    assert mervis.point_map_formats == ("vlist",)
    assert mervis.point_map_loaders["vlist"] is load_vlist
    assert load(data, "House.VLIST", mervis.point_map_loaders).format == "vlist"


# --- real exports: several projects, libraries, arrays as segments ----------------------

GUID = "0b9d3c1e-7a44-4f2a-9c6e-5d8f1a2b3c4d"


def test_a_real_export_is_read_whole() -> None:
    """Libraries first, a shared project, names with dots, arrays as segments, a BOM.

    The shape MERVIS.md describes (the simulator's ``solution()``, served in the
    integration's tests): every row of a variable is a point, each where it
    belongs, with the installation's project from the file's name.
    """
    project = solution()
    data = project.vlist(bom=True).encode("utf-8")
    point_map = load(
        data, project.export_name, registry.source("mervis").point_map_loaders
    )
    assert point_map.properties == {
        "project": SOLUTION_NAME,
        "exported_as": SOLUTION_NAME,
        "projects": ";".join((*LIBRARIES, SHARED_NAME, SOLUTION_NAME)),
    }
    assert point_map.skipped == ()
    points = point_map.by_key()
    containers = {"in", "meteo", "kotelna.ekviterm", "kotel"}
    assert set(points) == {row.key.lower() for row in project.rows} - containers
    element = points["in[3]"]
    assert (element.id, element.name, element.address, element.device) == (
        "in[3]",
        "In 3",
        "3014[2,1]",
        "In",
    )
    dotted = points["hw_hidden.markcom3.mxio.ai08.transformation"]
    assert (dotted.name, dotted.device) == (
        "Hw hidden markcom3.mxio.ai08.transformation",
        "Hw hidden",
    )
    # A library block's instance is no point: its members are, on its device.
    assert "kotelna.ekviterm" not in points
    assert points["kotelna.ekviterm.y"].device == "Kotelna ekviterm"
    assert points["kotelna.ekviterm.en"].type.kind is ValueKind.BOOL
    assert points["hvac.season"].details["enum"] == "T_SEASON"
    assert points["hvac.season"].details["project"] == "Lib.Hvac"


@pytest.mark.parametrize(
    ("rows", "file_name", "project"),
    [
        # The file's name, when its project has rows: though another has more.
        (
            ("Lib.Core", "Shared", "Shared", "Shared", "Own"),
            f"Own_{GUID}.vlist",
            "Own",
        ),
        # The name's case may differ; the rows' spelling is kept.
        (("Shared", "Own"), f"own_{GUID.upper()}.vlist", "Own"),
        # A path before it.
        (("Shared", "Shared", "Own"), f"C:\\exports\\Own_{GUID}.vlist", "Own"),
        # A name of no project of the rows, or of another form: the most rows.
        (("Lib.Core", "Shared", "Shared", "Own"), f"Other_{GUID}.vlist", "Shared"),
        (("Lib.Core", "Shared", "Shared", "Own"), "Own.vlist", "Shared"),
        (("Lib.Core", "Shared", "Shared", "Own"), "Own_1234.vlist", "Shared"),
        (("Lib.Core", "Shared", "Shared", "Own"), "", "Shared"),
        # Never a library, however many rows it has, whatever the file says.
        (("Lib.Core", "Lib.Core", "Lib.Iec", "base", "Own"), "", "Own"),
        (("lib.hvac", "BASE", "Own"), f"Lib.Hvac_{GUID}.vlist", "Own"),
        (("Lib.Core", "base"), "", None),
        # A tie: the first.
        (("A", "B", "B", "A"), "", "A"),
    ],
)
def test_the_installation_s_project(
    rows: tuple[str, ...], file_name: str, project: str | None
) -> None:
    text = vlist(
        *(
            f"{name};$v{index}$;$bool$;{index};0;1;none;"
            for index, name in enumerate(rows, start=1)
        )
    )
    point_map = load_vlist(text, file_name=file_name)
    assert point_map.properties.get("project") == project
    assert projects_of(point_map) == list(dict.fromkeys(rows))


def test_a_map_stored_before_the_projects_were_kept_has_its_own() -> None:
    stored = PointMap.from_json(
        {
            "version": 1,
            "format": "vlist",
            "points": [{"id": "a", "name": "A", "address": "1[0,1]", "type": "bool"}],
            "properties": {"project": "Cervajs"},
        }
    )
    assert projects_of(stored) == ["Cervajs"]
    assert projects_of(PointMap(stored.points, "vlist")) == []


@pytest.mark.parametrize(
    ("typed", "project"),
    [("Own", "Own"), (" own ", "Own"), ("Shared", "Shared")],
)
def test_the_user_names_the_installation_s_project(typed: str, project: str) -> None:
    point_map = load_vlist(
        vlist(
            "Lib.Core;$a$;$bool$;1;0;1;none;",
            "Shared;$b$;$bool$;2;0;1;none;",
            "Shared;$c$;$bool$;3;0;1;none;",
            "Own;$d$;$bool$;4;0;1;none;",
        )
    )
    named = with_project(point_map, typed)
    assert named.properties["project"] == project
    assert named.points == point_map.points
    assert projects_of(named) == projects_of(point_map)


@pytest.mark.parametrize("typed", ["Lib.Core", "Other", ""])
def test_a_project_the_file_has_not_or_a_library_is_refused(typed: str) -> None:
    point_map = load_vlist(
        vlist("Lib.Core;$a$;$bool$;1;0;1;none;", "Own;$d$;$bool$;4;0;1;none;")
    )
    with pytest.raises(PointMapError, match=r"its projects: Own\)") as raised:
        with_project(point_map, typed)
    assert raised.value.column == "project"


@pytest.mark.parametrize(
    ("name", "ident", "parts"),
    [
        ("$in$.$[1]$", "in[1]", "In 1"),
        ("$in$.$[ 2, 3 ]$", "in[2,3]", "In 2 3"),
        ("$rooms$.$[2]$.$temperature$", "rooms[2].temperature", "Rooms 2 temperature"),
        ("$in$[1]", "in[1]", "In 1"),
        ("$matrix$.$[1]$.$[2]$", "matrix[1][2]", "Matrix 1 2"),
    ],
)
def test_an_array_element_s_segment_is_its_index(
    name: str, ident: str, parts: str
) -> None:
    """Real exports write an element as a segment of its own: ``$in$.$[1]$`` is ``in[1]``."""
    (point,) = load_vlist(vlist(f"House;{name};$bool$;1;0;1;array;")).points
    assert (point.id, point.name) == (ident, parts)


def test_a_name_cannot_start_with_an_index() -> None:
    with pytest.raises(PointMapError, match="is not a name"):
        load_vlist(vlist("House;$[1]$;$bool$;1;0;1;none;"))


def test_a_newer_file_keeps_the_stored_element_ids_and_project() -> None:
    """An entry's map spelled an element ``in.[1]`` once: a newer file keeps that ID.

    The installation's project: the one typed, else the file name's, else the
    stored one (when the file has it and it is no library), else the rows'.
    """
    rows = (
        "Lib.Core;$a$;$bool$;1;0;1;none;",
        "Shared;$in$.$[1]$;$bool$;2;0;1;array;",
        "Shared;$in$.$[2]$;$bool$;2;1;1;array;",
        "Own;$b$;$bool$;3;0;1;none;",
    )
    newer = load_vlist(vlist(*rows), file_name="renamed.vlist")
    assert newer.properties["project"] == "Shared"
    stored = PointMap(
        tuple(
            replace(point, id=point.id.replace("[", ".["))
            if point.id.startswith("IN")
            else point
            for point in (replace(point, id=point.id.upper()) for point in newer.points)
        ),
        "vlist",
        properties={"project": "Own"},
    )
    adopted = adopt_vlist(newer, {}, stored)
    assert [point.id for point in adopted.points] == ["a", "IN.[1]", "IN.[2]", "b"]
    assert adopted.properties["project"] == "Own"
    assert adopt_vlist(newer, {PROJECT: "shared"}, stored).properties["project"] == (
        "Shared"
    )
    named = load_vlist(vlist(*rows), file_name=f"Shared_{GUID}.vlist")
    assert named.properties["exported_as"] == "Shared"
    assert adopt_vlist(named, {}, stored).properties["project"] == "Shared"
    # A stored library's name, or one the file has not, is not kept.
    for kept in ("Lib.Core", "Gone"):
        library = PointMap(stored.points, "vlist", properties={"project": kept})
        assert adopt_vlist(newer, {}, library).properties["project"] == "Shared"
    # Nothing stored: the file as it is.
    assert adopt_vlist(newer, {PROJECT: ""}, None) == newer
