"""TecoApi's JSON: kinds, typed values and the PLC's spelling of dates and times."""

from datetime import UTC, date, datetime, time, timedelta
import json
from typing import Any

import pytest

from custom_components.tecoapi.pyplc import ValueKind
from custom_components.tecoapi.pyplc.tecomat.tecoapi.values import (
    TEXT_KINDS,
    RememberedParser,
    format_time,
    infer_kind,
    parse_timestamp,
    parse_value,
    value_parser,
)

# Manual chapter 4: the JSON of plcData, as the PLC prints it.
PLC_DATA = json.loads("""{
    "varBool0": false, "varByte": 17, "varSint": -11, "varDword": 858993459,
    "varReal": 1000.000000, "varLreal": 1000000.000000, "varZero": 0.000000,
    "varTime": "01:02:03.450", "varLongTime": "120:02:03.450",
    "varDate": "2015-06-17", "varDT": "2018-05-11T11:22:33.456Z",
    "varString": "Hello everybody", "varNotADate": "2015-13-45",
    "varDateLike": "2015-06-17 ", "varClock": "12:30"
}""")


@pytest.mark.parametrize(
    ("name", "kind", "value"),
    [
        ("varBool0", ValueKind.BOOL, False),
        ("varByte", ValueKind.INTEGER, 17),
        ("varSint", ValueKind.INTEGER, -11),
        ("varDword", ValueKind.INTEGER, 858993459),
        ("varReal", ValueKind.REAL, 1000.0),
        ("varLreal", ValueKind.REAL, 1000000.0),
        ("varZero", ValueKind.REAL, 0.0),
        (
            "varTime",
            ValueKind.TIME,
            timedelta(hours=1, minutes=2, seconds=3, milliseconds=450),
        ),
        (
            "varLongTime",
            ValueKind.TIME,
            timedelta(hours=120, minutes=2, seconds=3, milliseconds=450),
        ),
        ("varDate", ValueKind.DATE, date(2015, 6, 17)),
        (
            "varDT",
            ValueKind.DATETIME,
            datetime(2018, 5, 11, 11, 22, 33, 456000, tzinfo=UTC),
        ),
        ("varString", ValueKind.STRING, "Hello everybody"),
        ("varNotADate", ValueKind.STRING, "2015-13-45"),
        ("varDateLike", ValueKind.STRING, "2015-06-17 "),
        ("varClock", ValueKind.STRING, "12:30"),
    ],
)
def test_kind_and_value_from_the_plc_json(
    name: str, kind: ValueKind, value: Any
) -> None:
    raw = PLC_DATA[name]
    assert infer_kind(raw) is kind
    parsed = parse_value(kind, raw)
    assert parsed == value
    assert type(parsed) is type(value)


def test_reals_stay_reals_even_when_integral() -> None:
    assert isinstance(PLC_DATA["varReal"], float)
    assert isinstance(PLC_DATA["varByte"], int)


@pytest.mark.parametrize("raw", [None, [], {}, [1], {"a": 1}])
def test_non_scalars_have_no_kind(raw: Any) -> None:
    assert infer_kind(raw) is None


@pytest.mark.parametrize(
    ("kind", "raw"),
    [
        (ValueKind.BOOL, 1),
        (ValueKind.INTEGER, True),
        (ValueKind.INTEGER, 1.5),
        (ValueKind.REAL, "1.5"),
        (ValueKind.REAL, False),
        (ValueKind.STRING, 3),
        (ValueKind.DATE, "yesterday"),
        (ValueKind.DATE, 20150617),
        (ValueKind.DATETIME, "2018-05-11"),
        (ValueKind.TIME, "1 hour"),
        (ValueKind.TIME, 3600),
    ],
)
def test_values_that_no_longer_fit_their_kind_are_none(
    kind: ValueKind, raw: Any
) -> None:
    assert parse_value(kind, raw) is None


@pytest.mark.parametrize("kind", list(ValueKind))
def test_each_kind_s_parser_reads_what_parse_value_reads(kind: ValueKind) -> None:
    """Chosen once per point, a kind's parser reads every raw value alike."""
    raws = [*PLC_DATA.values(), None, 1, True, 1.5, "16#11", [1], {"a": 1}]
    for raw in raws:
        assert repr(value_parser(kind)(raw)) == repr(parse_value(kind, raw))


@pytest.mark.parametrize("kind", sorted(TEXT_KINDS))
def test_a_remembered_text_is_read_again_only_when_it_changed(
    kind: ValueKind,
) -> None:
    """A point's text of a date or a time is parsed once while the PLC sends it
    unchanged; a new text (or the same spelling of another type) is read anew."""
    parse = RememberedParser(kind)
    texts = [
        PLC_DATA["varDate"],
        PLC_DATA["varDate"],
        PLC_DATA["varTime"],
        PLC_DATA["varDT"],
        "nonsense",
        PLC_DATA["varTime"],
        1,
        True,
        1,
    ]
    for raw in texts:
        assert repr(parse(raw)) == repr(parse_value(kind, raw))
    first = parse(PLC_DATA["varDT"])
    assert parse(PLC_DATA["varDT"]) is first


def test_an_integer_read_for_a_real_point_is_a_float() -> None:
    value = parse_value(ValueKind.REAL, 21)
    assert value == 21.0
    assert isinstance(value, float)


def test_times_are_written_the_manual_way() -> None:
    assert format_time(time(1, 2, 3, 450000)) == "01:02:03.450"
    assert format_time(timedelta(hours=120, minutes=2, seconds=3.45)) == "120:02:03.450"
    with pytest.raises(ValueError, match="negative"):
        format_time(timedelta(seconds=-1))


def test_get_info_timestamps() -> None:
    assert parse_timestamp("2018-01-18T16:39:38.000Z") == datetime(
        2018, 1, 18, 16, 39, 38, tzinfo=UTC
    )
    assert parse_timestamp("2018-01-18T16:39:38") == datetime(
        2018, 1, 18, 16, 39, 38, tzinfo=UTC
    )
    assert parse_timestamp("") is None
    assert parse_timestamp(None) is None
    assert parse_timestamp("2018-99-99") is None
