"""The typed models and GetInfo parsing."""

from datetime import UTC, datetime

import pytest

from custom_components.tecoapi.pyplc import (
    NotAPlcError,
    PlcMode,
    PointAttributes,
    ValueKind,
)
from custom_components.tecoapi.pyplc.tecomat.points import (
    api_object_attributes,
    tecomat_point,
    value_path,
)
from custom_components.tecoapi.pyplc.tecomat.tecoapi.info import (
    item_limit_for_type,
    normalize_mac,
    parse_mode,
    parse_plc_info,
)

MANUAL_INFO = {
    "api": {"version": "TecoApi v1.0.0"},
    "plc": {
        "family": "Fx2",
        "type": "CP2080",
        "serialNumber": "PP 0004",
        "version": "Fx2 CP2080I v1.1",
        "mac": "F8-DC-7A-11-F4-DC",
        "mode": "RUN ",
        "userProg": {
            "name": "DOC_TECOAPI v1.0",
            "compiled": "2018-01-18T16:39:38.000Z",
            "stamp": "E28AE29B",
        },
        "time": "2018-01-31T16:50:39.949Z",
    },
}


def _meta(**changes: object) -> PointAttributes:
    fields: dict[str, object] = {
        "title": "t",
        "units": "",
        "read_only": False,
        "min_value": 0.0,
        "max_value": 0.0,
        "enable": True,
        "visibility": True,
    } | changes
    return api_object_attributes(**fields)  # type: ignore[arg-type]


def test_manual_get_info_is_parsed() -> None:
    info = parse_plc_info(MANUAL_INFO)
    assert info.family == "Fx2"
    assert info.model == "CP2080"
    assert info.serial_number == "PP 0004"
    assert info.firmware == "Fx2 CP2080I v1.1"
    assert info.mac == "f8:dc:7a:11:f4:dc"
    assert info.mode is PlcMode.RUNNING
    assert info.program_name == "DOC_TECOAPI v1.0"
    assert info.program_compiled == datetime(2018, 1, 18, 16, 39, 38, tzinfo=UTC)
    assert info.program_stamp == "E28AE29B"
    assert info.time == datetime(2018, 1, 31, 16, 50, 39, 949000, tzinfo=UTC)
    assert info.api_version == "TecoApi v1.0.0"
    assert item_limit_for_type(info.model) == 256


def test_get_info_tolerates_missing_optional_fields() -> None:
    info = parse_plc_info({"plc": {"serialNumber": "VN 1957", "time": "garbage"}})
    assert info.serial_number == "VN 1957"
    assert info.family is None
    assert info.model is None
    assert info.mac is None
    assert info.program_name is None
    assert info.program_compiled is None
    assert info.time is None
    assert info.api_version is None
    assert info.mode is PlcMode.FAULT
    assert item_limit_for_type(info.model) == 128


@pytest.mark.parametrize(
    "body",
    [None, [], {}, {"plc": "x"}, {"plc": {}}, {"plc": {"serialNumber": "  "}}],
)
def test_get_info_without_a_plc_is_not_tecoapi(body: object) -> None:
    with pytest.raises(NotAPlcError):
        parse_plc_info(body)


@pytest.mark.parametrize(
    ("raw", "mode"),
    [
        ("RUN ", PlcMode.RUNNING),
        ("run", PlcMode.RUNNING),
        ("HALT", PlcMode.STOPPED),
        (" ERR", PlcMode.FAULT),
        ("BOOT", PlcMode.FAULT),
        (None, PlcMode.FAULT),
        (3, PlcMode.FAULT),
    ],
)
def test_mode_is_normalised(raw: object, mode: PlcMode) -> None:
    assert parse_mode(raw) is mode


def test_the_modes_keep_the_values_users_see() -> None:
    """The members' names are neutral; their values are what states and issues show.

    The mode sensor's options and states, and the repair issue's text, are the
    values (lower case in the sensor): they stay what they were.
    """
    assert {mode.name: mode.value for mode in PlcMode} == {
        "RUNNING": "RUN",
        "STOPPED": "HALT",
        "FAULT": "ERR",
    }


@pytest.mark.parametrize(
    ("raw", "mac"),
    [
        ("00-15-AF-CB-4E-7D", "00:15:af:cb:4e:7d"),
        ("00:0A:14:01:02:03", "00:0a:14:01:02:03"),
        ("000a14010203", "00:0a:14:01:02:03"),
        ("not a mac", "not a mac"),
        (None, None),
    ],
)
def test_mac_is_normalised(raw: str | None, mac: str | None) -> None:
    assert normalize_mac(raw) == mac


@pytest.mark.parametrize(
    ("plc_type", "limit"),
    [
        ("CP2080", 256),
        ("CP-2080", 256),
        ("cp-2000", 256),
        ("CP-1000", 128),
        ("CP1008", 128),
        ("CP-W32", 128),
        ("CP-7004", 128),
        ("", 128),
        (None, 128),
    ],
)
def test_item_limit_follows_the_cpu_series(plc_type: str | None, limit: int) -> None:
    assert item_limit_for_type(plc_type) == limit


def test_range_exists_unless_both_bounds_are_zero() -> None:
    assert not _meta().has_range
    assert _meta(min_value=10.0, max_value=30.0).has_range
    assert _meta(min_value=-5.0).has_range
    assert _meta(max_value=1.0).has_range


def test_point_properties() -> None:
    api = tecomat_point("Main.myObject3", ValueKind.REAL, _meta(read_only=False))
    read_only = tecomat_point("Main.myObject1", ValueKind.REAL, _meta(read_only=True))
    plain = tecomat_point("plcData.varReal", ValueKind.REAL)
    assert api.described
    assert api.writable
    assert value_path(api) == "Main.myObject3.value"
    assert read_only.described
    assert not read_only.writable
    assert not plain.described
    assert not plain.writable
    assert value_path(plain) == "plcData.varReal"
