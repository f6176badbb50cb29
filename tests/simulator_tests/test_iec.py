"""IEC types: defaults, item counts and the values each type takes."""

import pytest

from tests.simulator.iec import (
    ArrayOf,
    Elementary,
    RejectedValueError,
    Struct,
    default_value,
    from_json,
    from_program,
    from_query_text,
    leaf_count,
)

POINT = Struct(
    "TPoint", {"x": Elementary("REAL"), "tags": ArrayOf(2, Elementary("STRING", 8), "")}
)


def test_defaults_and_leaf_counts() -> None:
    grid = ArrayOf(2, ArrayOf(3, POINT, ""), "")

    assert default_value(POINT) == {"x": 0.0, "tags": ["", ""]}
    assert default_value(Elementary("TIME")) == "00:00:00.000"
    assert default_value(Elementary("DATE")) == "1970-01-01"
    assert default_value(Elementary("UDINT")) == 0
    assert leaf_count(POINT) == 3
    assert leaf_count(grid) == 18


def test_struct_members_are_found_case_insensitively() -> None:
    assert POINT.member("TAGS") == "tags"
    assert POINT.member("nothing") is None


@pytest.mark.parametrize(
    ("name", "text", "value"),
    [
        ("TIME", "596:31:23.647", "596:31:23.647"),
        ("TIME", "00:00:00", "00:00:00.000"),
        ("TOD", "23:59:59.999", "23:59:59.999"),
        ("DT", "2024-02-29T23:59:59.9Z", "2024-02-29T23:59:59.900Z"),
        ("LREAL", "-0.000001", -0.000001),
    ],
)
def test_time_and_real_texts(name: str, text: str, value: object) -> None:
    assert from_query_text(Elementary(name), text) == value


@pytest.mark.parametrize(
    ("name", "text"),
    [
        ("TIME", "596:31:23.648"),
        ("TOD", "24:00:00.000"),
        ("TOD", "12:60:00"),
        ("DT", "2024-13-01T00:00:00Z"),
        ("DATE", "2024-1-1"),
    ],
)
def test_time_texts_out_of_range(name: str, text: str) -> None:
    with pytest.raises(RejectedValueError):
        from_query_text(Elementary(name), text)


@pytest.mark.parametrize(
    ("iec_type", "value"),
    [
        (Elementary("INT"), 1.0),
        (Elementary("INT"), False),
        (Elementary("REAL"), "1.0"),
        (Elementary("REAL"), True),
        (Elementary("BOOL"), "true"),
        (Elementary("STRING", 4), "abcde"),
        (Elementary("STRING", 4), "°C"),
        (Elementary("DATE"), 20240101),
    ],
)
def test_json_values_of_the_wrong_kind(iec_type: Elementary, value: object) -> None:
    with pytest.raises(RejectedValueError):
        from_json(iec_type, value)


def test_program_values_take_radix_integers_only_for_integers() -> None:
    assert from_program(Elementary("DWORD"), "16#FFFF_FFFF") == 0xFFFFFFFF
    with pytest.raises(RejectedValueError):
        from_program(Elementary("DWORD"), "16#1_0000_0000")
    with pytest.raises(RejectedValueError):
        from_program(Elementary("INT"), "12")


def test_string_type_names() -> None:
    assert Elementary("STRING", 80).type_name == "STRING"
    assert Elementary("STRING", 10).type_name == "STRING[10]"
    assert Elementary("TOD").type_name == "TOD"
