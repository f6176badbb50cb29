"""Program files: the shipped programs, the type language, initial values, errors."""

import json
from pathlib import Path
from typing import Any

import pytest
import yaml

from tests.simulator import Program, ProgramError, load_program
from tests.simulator.iec import ArrayOf, Elementary, Struct, leaf_count
from tests.simulator.program import API_OBJECT_ATTR, api_object_type, is_valid_name

PLC = {
    "family": "Fx2",
    "type": "CP-2080",
    "serialNumber": "PP 0004",
    "version": "Fx2 CP2080I v1.1",
    "mac": "F8-DC-7A-11-F4-DC",
}
USER_PROGRAM = {"name": "TEST v1", "compiled": "2018-01-18T16:39:38.000Z"}


def program(variables: dict[str, Any], types: dict[str, Any] | None = None) -> Program:
    source: dict[str, Any] = {
        "plc": PLC,
        "program": USER_PROGRAM,
        "variables": variables,
    }
    if types is not None:
        source["types"] = types
    return Program.from_mapping(source)


def only(variables: dict[str, Any], types: dict[str, Any] | None = None) -> Any:
    """The single declaration of a one-variable program."""
    (declaration,) = program(variables, types).declarations
    return declaration


def test_manual_program() -> None:
    manual = load_program("manual")

    assert [d.name for d in manual.declarations] == [
        "plcName",
        "plcType",
        "plcDesc",
        "plcData",
        "myObject",
        "arr1",
        "arr2",
        "arr3",
        "Main",
    ]
    assert (manual.plc.family, manual.plc.type, manual.plc.mac) == (
        "sim",
        "CP-W32",
        "00-15-AF-CB-4E-7D",
    )
    items = {d.name: leaf_count(d.type) for d in manual.declarations}
    assert (items["myObject"], items["Main"], items["arr3"]) == (13, 24, 24)


def test_demo_program_looks_like_a_house() -> None:
    demo = load_program("demo")
    text = json.dumps(demo.to_mapping(), ensure_ascii=False)

    assert demo.plc.type == "CP-2080"
    for unit in ("°C", "%", "kWh", '"W"'):
        assert unit in text
    for kind in (
        "OF BOOL",
        "OF USINT",
        "OF LREAL",
        "OF DATE",
        "OF TIME",
        "OF DT",
        "OF TOD",
    ):
        assert kind in text
    roots = {d.name: d.type for d in demo.declarations}
    assert isinstance(roots["lights"], ArrayOf)
    assert isinstance(roots["ventilation"], Struct)
    assert isinstance(roots["ventilation"].members["filter"], Struct)
    plain = [name for name, t in roots.items() if isinstance(t, Elementary)]
    assert len(plain) >= 5
    assert all(leaf_count(t) <= 256 for t in roots.values())


def test_load_program_from_files(tmp_path: Path) -> None:
    source = load_program("manual").to_mapping()
    yaml_file = tmp_path / "plc.yml"
    json_file = tmp_path / "plc.json"
    yaml_file.write_text(yaml.safe_dump(source, allow_unicode=True), encoding="utf-8")
    json_file.write_text(json.dumps(source), encoding="utf-8")

    assert load_program(str(yaml_file)).stamp == load_program("manual").stamp
    assert load_program(str(json_file)).stamp == load_program("manual").stamp


@pytest.mark.parametrize(
    ("name", "text", "message"),
    [
        ("missing.yaml", None, "no program"),
        ("plc.txt", "plc: {}", "not a .yaml"),
        ("list.yaml", "- 1", "does not hold a mapping"),
    ],
)
def test_load_program_errors(
    tmp_path: Path, name: str, text: str | None, message: str
) -> None:
    path = tmp_path / name
    if text is not None:
        path.write_text(text, encoding="utf-8")

    with pytest.raises(ProgramError, match=message):
        load_program(str(path))


def test_the_stamp_ignores_the_hardware_and_follows_the_program() -> None:
    base = program({"a": "INT"})
    other_plc = base.to_mapping()
    other_plc["plc"]["serialNumber"] = "XX 0000"
    other_value = base.to_mapping()
    other_value["variables"]["a"] = {"type": "INT", "value": 1}

    assert Program.from_mapping(other_plc).stamp == base.stamp
    assert Program.from_mapping(other_value).stamp != base.stamp


def test_to_mapping_is_a_copy() -> None:
    base = program({"a": "INT"})
    copy = base.to_mapping()
    copy["variables"]["b"] = "INT"

    assert "b" not in base.to_mapping()["variables"]


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("bool", Elementary("BOOL")),
        ("STRING", Elementary("STRING", 80)),
        ("string [ 12 ]", Elementary("STRING", 12)),
        ("T_ApiObject", api_object_type(Elementary("REAL"))),
        ("t_apiobject of udint", api_object_type(Elementary("UDINT"))),
        ("T_ApiObjectAttr", API_OBJECT_ATTR),
    ],
)
def test_type_expressions(text: str, expected: object) -> None:
    assert only({"v": text}).type == expected


def test_multi_dimensional_and_nested_arrays() -> None:
    flat = only({"v": "ARRAY[0..1, 0..2] OF BYTE"})
    nested = only({"v": "ARRAY[0..1] OF ARRAY[0..2] OF BYTE"})

    assert flat.type.type_name == "ARRAY[0..1, 0..2] OF BYTE"
    assert flat.type.element.type_name == "ARRAY[0..2] OF BYTE"
    assert nested.type.type_name == "ARRAY[0..1] OF ARRAY[0..2] OF BYTE"
    assert flat.initial == nested.initial == [[0, 0, 0], [0, 0, 0]]


def test_type_names_in_messages() -> None:
    assert api_object_type(Elementary("BOOL")).type_name == "T_ApiObject OF BOOL"
    assert (
        api_object_type(Elementary("STRING", 20)).type_name
        == "T_ApiObject OF STRING[20]"
    )


@pytest.mark.parametrize(
    ("declaration", "initial"),
    [
        ({"type": "BYTE", "value": "16#11"}, 17),
        ({"type": "WORD", "value": "2#1010_1010"}, 170),
        ({"type": "DINT", "value": "8#777"}, 511),
        ({"type": "REAL", "value": 3}, 3.0),
        ({"type": "DATE", "value": "2015-06-17"}, "2015-06-17"),
        ("DT", "1970-01-01T00:00:00.000Z"),
        ("TOD", "00:00:00.000"),
        ("BOOL", False),
        ({"type": "STRING[16]", "value": "°C"}, "°C"),
        ({"type": "ARRAY[0..2] OF INT", "value": [1]}, [1, 0, 0]),
        ({"type": "ARRAY[0..1, 0..1] OF INT", "value": [1, 2, 3]}, [[1, 2], [3, 0]]),
        (
            {"type": "ARRAY[0..1, 0..1] OF INT", "value": [[1], [2, 3]]},
            [[1, 0], [2, 3]],
        ),
    ],
)
def test_initial_values(declaration: Any, initial: object) -> None:
    assert only({"v": declaration}).initial == initial


def test_yaml_dates_and_timestamps_become_plc_strings() -> None:
    source = yaml.safe_load(
        "v: {type: DATE, value: 2015-06-17}\nw: {type: DT, value: 2018-05-11T11:22:33.456Z}"
    )

    declarations = program(source).declarations

    assert [d.initial for d in declarations] == [
        "2015-06-17",
        "2018-05-11T11:22:33.456Z",
    ]


def test_structs_and_instances() -> None:
    declarations = program(
        {
            "s": {"type": "TOuter", "value": {"INNER": {"x": 5}}},
            "Main": {
                "program": "prgMain",
                "variables": {"t": "INT", "u": {"type": "BOOL", "value": True}},
            },
        },
        types={
            "TInner": {"x": "INT", "y": "INT"},
            "TOuter": {"inner": "TInner", "z": "REAL"},
        },
    ).declarations

    assert declarations[0].initial == {"inner": {"x": 5, "y": 0}, "z": 0.0}
    assert declarations[1].type.type_name == "prgMain"
    assert declarations[1].initial == {"t": 0, "u": True}


@pytest.mark.parametrize(
    ("variables", "types", "message"),
    [
        ({"1bad": "INT"}, None, "not a valid IEC variable name"),
        ({"a__b": "INT"}, None, "not a valid IEC variable name"),
        ({"x" * 65: "INT"}, None, "not a valid IEC variable name"),
        ({"a": "INT", "A": "INT"}, None, "declared twice"),
        ({"a": 5}, None, "expected a type or a mapping"),
        ({"a": {"value": 1}}, None, "needs 'type'"),
        ({"a": "FLOAT"}, None, "unknown type 'FLOAT'"),
        ({"a": "STRING[0]"}, None, "STRING length"),
        ({"a": "STRING[256]"}, None, "STRING length"),
        ({"a": "ARRAY[1..5] OF INT"}, None, "indexed from 0"),
        ({"a": "ARRAY[0..x] OF INT"}, None, "indexed from 0"),
        ({"a": {"type": "INT", "value": 40000}}, None, "not a valid INT"),
        ({"a": {"type": "INT", "value": "16#GG"}}, None, "not a valid INT"),
        (
            {"a": {"type": "STRING[2]", "value": "abc"}},
            None,
            "not a valid STRING\\[2\\]",
        ),
        ({"a": {"type": "STRING", "value": 5}}, None, "not a valid STRING"),
        ({"a": {"type": "DATE", "value": "1969-01-01"}}, None, "not a valid DATE"),
        ({"a": {"type": "ARRAY[0..1] OF INT", "value": 5}}, None, "is a list"),
        (
            {"a": {"type": "ARRAY[0..1] OF INT", "value": [1, 2, 3]}},
            None,
            "more than 2",
        ),
        (
            {"a": {"type": "ARRAY[0..1, 0..1] OF INT", "value": [1, 2, 3, 4, 5]}},
            None,
            "more than 4",
        ),
        ({"a": {"type": "T", "value": 5}}, {"T": {"x": "INT"}}, "is a mapping"),
        ({"a": {"type": "T", "value": {"y": 1}}}, {"T": {"x": "INT"}}, "has no 'y'"),
        ({"a": "T"}, {"T": {}}, "needs members"),
        ({"a": "T"}, {"T": {"t": "T"}}, "contains itself"),
        (
            {"a": "T"},
            {"T": {"u": "ARRAY[0..1] OF U"}, "U": {"t": "T"}},
            "contains itself",
        ),
        ({"a": "INT"}, {"bad name": {"x": "INT"}}, "not a valid IEC type name"),
        ({"a": "INT"}, {"T": {"bad name": "INT"}}, "not a valid IEC member name"),
        ("not a mapping", None, "'variables' must be a mapping"),
    ],
)
def test_program_errors(
    variables: Any, types: dict[str, Any] | None, message: str
) -> None:
    with pytest.raises(ProgramError, match=message):
        program(variables, types)


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"plc": None}, "'plc' must be a mapping"),
        ({"publicFile": "gone"}, "publicFile must be one of"),
        ({"program": {"name": "x"}}, "missing field 'compiled'"),
    ],
)
def test_program_header_errors(change: dict[str, Any], message: str) -> None:
    source: dict[str, Any] = {"plc": PLC, "program": USER_PROGRAM, "variables": {}}
    source |= change

    with pytest.raises(ProgramError, match=message):
        Program.from_mapping(source)


@pytest.mark.parametrize(
    ("name", "valid"),
    [
        ("plcName", True),
        ("_x1", True),
        ("BF_LM", True),
        ("BF__LM", False),
        ("9a", False),
        ("č", False),
    ],
)
def test_iec_names(name: str, valid: bool) -> None:
    assert is_valid_name(name) is valid
