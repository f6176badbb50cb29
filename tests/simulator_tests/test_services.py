"""The five TecoApi services over HTTP, against the manual's own examples."""

import datetime as dt
import re
from urllib.parse import unquote

import aiohttp
import pytest

from tests.simulator import Program, Simulator, load_program
from tests.simulator_tests.conftest import Reply, fetch, manual_text

pytestmark = pytest.mark.usefixtures("socket_enabled")


async def get(session: aiohttp.ClientSession, sim: Simulator, target: str) -> Reply:
    return await fetch(session, sim, target)


async def put(
    session: aiohttp.ClientSession, sim: Simulator, body: bytes, target: str = ""
) -> Reply:
    return await fetch(
        session, sim, "/TecoApi/PutObject" + target, method="PUT", data=body
    )


# --- GetInfo -----------------------------------------------------------------------


async def test_get_info_matches_the_manual_layout(
    session: aiohttp.ClientSession, manual_plc: Simulator
) -> None:
    reply = await get(session, manual_plc, "/TecoApi/GetInfo")

    assert reply.status == 200
    plc = reply.json()["plc"]
    assert plc["userProg"]["stamp"] == manual_plc.stamp
    assert re.fullmatch(r"[0-9A-F]{8}", manual_plc.stamp)
    assert re.fullmatch(r"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\.\d{3}Z", plc["time"])
    plc_time = dt.datetime.fromisoformat(plc["time"])
    assert abs(plc_time - dt.datetime.now(dt.UTC)) < dt.timedelta(minutes=5)
    # Chapter 3.2's example, with this run's stamp and clock.
    assert reply.body == manual_text(
        f"""
        {{
          "api":
          {{
            "version": "TecoApi v1.0.0"
          }},
          "plc":
          {{
            "family": "sim",
            "type": "CP-W32",
            "serialNumber": "VN 1957",
            "version": "sim CP-W32I v1.1",
            "mac": "00-15-AF-CB-4E-7D",
            "mode": "RUN ",
            "userProg":
            {{
              "name": "DOC_TECOAPI v1.0",
              "compiled": "2018-01-18T16:36:46.000Z",
              "stamp": "{manual_plc.stamp}"
            }},
            "time": "{plc["time"]}"
          }}
        }}
        """
    )


@pytest.mark.parametrize(("mode", "printed"), [("HALT", "HALT"), ("ERR", "ERR ")])
async def test_get_info_reports_the_mode_padded(
    session: aiohttp.ClientSession, manual_plc: Simulator, mode: str, printed: str
) -> None:
    manual_plc.mode = mode

    reply = await get(session, manual_plc, "/TecoApi/GetInfo")

    assert reply.json()["plc"]["mode"] == printed


async def test_get_info_takes_no_parameter(
    session: aiohttp.ClientSession, manual_plc: Simulator
) -> None:
    reply = await get(session, manual_plc, "/TecoApi/GetInfo?verbose=1")

    assert (reply.status, reply.error_code) == (400, "400.018")
    assert (
        reply.error_message
        == "Unknown parameter (service: 'GetInfo', param: 'verbose')"
    )


# --- GetList -----------------------------------------------------------------------

MANUAL_ROOTS = [
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


@pytest.mark.parametrize("query", ["", "?listType=struct"])
async def test_get_list_as_struct(
    session: aiohttp.ClientSession, manual_plc: Simulator, query: str
) -> None:
    reply = await get(session, manual_plc, "/TecoApi/GetList" + query)

    assert reply.status == 200
    rows = ",\n".join(f'  "{name}": {{}}' for name in MANUAL_ROOTS)
    assert reply.body == manual_text("{\n" + rows + "\n}")


async def test_get_list_as_array(
    session: aiohttp.ClientSession, manual_plc: Simulator
) -> None:
    reply = await get(session, manual_plc, "/TecoApi/GetList?listType=array")

    assert reply.status == 200
    rows = ",\n".join(f'  {{ "{name}": {{}} }}' for name in MANUAL_ROOTS)
    assert reply.body == manual_text("[\n" + rows + "\n]")


async def test_get_list_of_the_manual_chapter_3_3_example(
    session: aiohttp.ClientSession, socket_enabled: None
) -> None:
    source = load_program("manual").to_mapping()
    source["variables"] = {
        name: source["variables"][name] for name in ("plcName", "plcType", "plcDesc")
    }
    async with Simulator(
        Program.from_mapping(source),
        username="admin",
        password="s3cret-Pa55",
        auth="basic",
    ) as sim:
        as_struct = await get(session, sim, "/TecoApi/GetList")
        as_array = await get(session, sim, "/TecoApi/GetList?listType=array")

    assert int(as_struct.headers["Content-Length"]) == 59
    assert int(as_array.headers["Content-Length"]) == 71
    assert as_array.body == manual_text(
        """
        [
          { "plcName": {} },
          { "plcType": {} },
          { "plcDesc": {} }
        ]
        """
    )


@pytest.mark.parametrize(
    ("query", "code", "message"),
    [
        (
            "listType=tree",
            "400.016",
            "Unknown value of parameter (param: 'listType', value: 'tree')",
        ),
        (
            "listtype=array",
            "400.018",
            "Unknown parameter (service: 'GetList', param: 'listtype')",
        ),
        ("=array", "400.017", "Name of parameter is empty"),
        (
            "listType=",
            "400.019",
            "Value of parameter is empty (service: 'GetList', param: 'listType')",
        ),
    ],
)
async def test_get_list_parameter_errors(
    session: aiohttp.ClientSession,
    manual_plc: Simulator,
    query: str,
    code: str,
    message: str,
) -> None:
    reply = await get(session, manual_plc, "/TecoApi/GetList?" + query)

    assert (reply.status, reply.error_code, reply.error_message) == (400, code, message)


# --- GetObject: the manual's examples, byte for byte --------------------------------


async def test_get_object_plc_name_and_three_names(
    session: aiohttp.ClientSession, manual_plc: Simulator
) -> None:
    one = await get(session, manual_plc, "/TecoApi/GetObject?plcName")
    three = await get(session, manual_plc, "/TecoApi/GetObject?plcName&plcType&plcDesc")

    assert one.body == manual_text('{\n  "plcName": "myFoxtrot"\n}')
    assert int(one.headers["Content-Length"]) == 32
    assert three.body == manual_text(
        """
        {
          "plcName": "myFoxtrot",
          "plcType": 2005,
          "plcDesc": "for testing only"
        }
        """
    )
    assert int(three.headers["Content-Length"]) == 86


async def test_get_object_plc_data_chapter_4(
    session: aiohttp.ClientSession, manual_plc: Simulator
) -> None:
    reply = await get(session, manual_plc, "/TecoApi/GetObject?plcData")

    assert reply.status == 200
    assert reply.body == manual_text(
        """
        {
          "plcData":
          {
            "varBool0": false,
            "varBool1": true,
            "varByte": 17,
            "varWord": 8738,
            "varDword": 858993459,
            "varUsint": 11,
            "varUint": 2222,
            "varUdint": 33333333,
            "varSint": -11,
            "varInt": -2222,
            "varDint": -33333333,
            "varReal": 1000.000000,
            "varLreal": 1000000.000000,
            "varTime": "01:02:03.450",
            "varDate": "2015-06-17",
            "varDT": "2018-05-11T11:22:33.456Z",
            "varString": "Hello everybody",
            "varStringArray":
            [
              "zero",
              "one",
              "two",
              "three",
              "four",
              "five"
            ]
          }
        }
        """
    )
    # The manual prints the array on one line but its Content-Length counts one per line.
    assert int(reply.headers["Content-Length"]) == 615


async def test_get_object_struct_parts_chapter_5_1(
    session: aiohttp.ClientSession, manual_plc: Simulator
) -> None:
    favorites = await get(session, manual_plc, "/TecoApi/GetObject?myObject.favorites")
    selected = await get(
        session,
        manual_plc,
        "/TecoApi/GetObject?myObject.first&myObject.favorites.sport",
    )

    assert favorites.body == manual_text(
        r"""
        {
          "myObject":
          {
            "favorites":
            {
              "color": "\"Blue\"",
              "sport": "Soccer",
              "food": "Spaghetti"
            }
          }
        }
        """
    )
    assert int(favorites.headers["Content-Length"]) == 144
    assert selected.body == manual_text(
        """
        {
          "myObject":
          {
            "first": "John",
            "favorites":
            {
              "sport": "Soccer"
            }
          }
        }
        """
    )
    assert int(selected.headers["Content-Length"]) == 110


async def test_get_object_whole_struct_counts_13_items(
    session: aiohttp.ClientSession, manual_plc: Simulator
) -> None:
    reply = await get(session, manual_plc, "/TecoApi/GetObject?myObject")

    assert reply.json() == {
        "myObject": {
            "first": "John",
            "last": "Doe",
            "age": 39,
            "sex": "M",
            "salary": 70000,
            "married": True,
            "registered": False,
            "interests": ["Reading", "Mountain Biking", "Hacking"],
            "favorites": {"color": '"Blue"', "sport": "Soccer", "food": "Spaghetti"},
        }
    }
    assert manual_plc.requests[-1].items == 13


async def test_get_object_arrays_chapter_5_2(
    session: aiohttp.ClientSession, manual_plc: Simulator
) -> None:
    arr1 = await get(session, manual_plc, "/TecoApi/GetObject?arr1")
    arr2 = await get(session, manual_plc, "/TecoApi/GetObject?arr2")
    arr3 = await get(session, manual_plc, "/TecoApi/GetObject?arr3")

    assert arr1.body == manual_text(
        """
        {
          "arr1":
          [
            "zero",
            "one",
            "two",
            "three",
            "four",
            ""
          ]
        }
        """
    )
    assert int(arr1.headers["Content-Length"]) == 99
    assert arr2.body == manual_text(
        """
        {
          "arr2":
          [
            [
              0.000000,
              0.100000,
              0.200000,
              0.300000
            ],
            [
              1.000000,
              1.100000,
              1.200000,
              1.300000
            ],
            [
              2.000000,
              2.100000,
              2.200000,
              2.300000
            ]
          ]
        }
        """
    )
    assert int(arr2.headers["Content-Length"]) == 272
    assert arr3.json()["arr3"][1][2] == [120, 121, 122, 123]
    assert manual_plc.requests[-1].items == 24


async def test_get_object_program_instance_chapter_5_3(
    session: aiohttp.ClientSession, manual_plc: Simulator
) -> None:
    reply = await get(session, manual_plc, "/TecoApi/GetObject?Main")

    def api_object(value: str, read_only: str, title: str, low: str, high: str) -> str:
        return f"""
            {{
              "value": {value},
              "attr":
              {{
                "enable": true,
                "visibility": true,
                "readOnly": {read_only},
                "title": "{title}",
                "minValue": {low},
                "maxValue": {high},
                "units": "°C"
              }}
            }}"""

    objects = [
        api_object("-0.500000", "true", "outside temperature", "0.000000", "0.000000"),
        api_object("22.100000", "true", "inside temperature", "0.000000", "0.000000"),
        api_object(
            "23.000000", "false", "requested temperature", "10.000000", "30.000000"
        ),
    ]
    members = ",".join(
        f'\n    "myObject{number}":' + text.replace("\n            ", "\n    ")
        for number, text in enumerate(objects, start=1)
    )
    assert reply.body == manual_text('{\n  "Main":\n  {' + members + "\n  }\n}")
    assert "°C".encode() in reply.body
    assert manual_plc.requests[-1].items == 24


# --- GetObject: names, nesting, merging ---------------------------------------------


async def test_get_object_names_are_case_insensitive_and_answered_in_plc_spelling(
    session: aiohttp.ClientSession, manual_plc: Simulator
) -> None:
    reply = await get(
        session,
        manual_plc,
        "/TecoApi/GetObject?MYOBJECT.FIRST&myobject.Favorites.SPORT",
    )

    assert reply.json() == {
        "myObject": {"first": "John", "favorites": {"sport": "Soccer"}}
    }


async def test_get_object_percent_decodes_names(
    session: aiohttp.ClientSession, manual_plc: Simulator
) -> None:
    reply = await get(
        session, manual_plc, "/TecoApi/GetObject?my%4Fbject.first&arr1%5B2%5D"
    )
    spaced = await get(session, manual_plc, "/TecoApi/GetObject?%20plcName")

    assert reply.json() == {"myObject": {"first": "John"}, "arr1[2]": "two"}
    assert spaced.error_code == "400.005"


@pytest.mark.parametrize(
    ("query", "expected"),
    [
        ("arr1[2]", {"arr1[2]": "two"}),
        ("arr2[1][3]", {"arr2[1][3]": 1.3}),
        ("arr2[1,3]", {"arr2[1][3]": 1.3}),
        ("arr2[2]", {"arr2[2]": [2.0, 2.1, 2.2, 2.3]}),
        ("arr3[1][2][3]", {"arr3[1][2][3]": 123}),
        ("myObject.interests[1]", {"myObject": {"interests[1]": "Mountain Biking"}}),
        ("Main.myObject3.value", {"Main": {"myObject3": {"value": 23.0}}}),
        (
            "main.MYOBJECT3.attr.minValue&Main.myObject3.attr.maxValue",
            {"Main": {"myObject3": {"attr": {"minValue": 10.0, "maxValue": 30.0}}}},
        ),
        (
            "myObject.favorites.sport&myObject.favorites",
            {
                "myObject": {
                    "favorites": {
                        "sport": "Soccer",
                        "color": '"Blue"',
                        "food": "Spaghetti",
                    }
                }
            },
        ),
        ("plcType&plcType", {"plcType": 2005}),
    ],
)
async def test_get_object_paths_nest_by_segment_and_merge_by_root(
    session: aiohttp.ClientSession,
    manual_plc: Simulator,
    query: str,
    expected: dict[str, object],
) -> None:
    reply = await get(session, manual_plc, "/TecoApi/GetObject?" + query)

    assert reply.status == 200
    assert reply.json() == expected


async def test_get_object_prints_reals_with_six_decimals_and_integers_plain(
    session: aiohttp.ClientSession, manual_plc: Simulator
) -> None:
    reply = await get(session, manual_plc, "/TecoApi/GetObject?arr2[1][3]&plcType")

    assert b'"arr2[1][3]": 1.300000' in reply.body
    assert b'"plcType": 2005\r\n' in reply.body


# --- GetObject: errors ----------------------------------------------------------------


@pytest.mark.parametrize(
    ("query", "code", "message"),
    [
        ("", "400.001", "Bad parameters (any PLC variable is not specified)"),
        ("?", "400.001", "Bad parameters (any PLC variable is not specified)"),
        ("?plcName&&plcType", "400.003", "Name of variable is empty"),
        ("?plcName&", "400.003", "Name of variable is empty"),
        ("?nothing", "400.005", "Variable 'nothing' is not found"),
        ("?myObject.nothing", "400.005", "Variable 'myObject.nothing' is not found"),
        ("?arr1[6]", "400.005", "Variable 'arr1[6]' is not found"),
        ("?arr1[x]", "400.005", "Variable 'arr1[x]' is not found"),
        ("?plcName[0]", "400.005", "Variable 'plcName[0]' is not found"),
        ("?plcName.length", "400.005", "Variable 'plcName.length' is not found"),
        ("?myObject..first", "400.005", "Variable 'myObject..first' is not found"),
        ("?arr2[1]x", "400.005", "Variable 'arr2[1]x' is not found"),
        (
            "?myObject." + "x" * 65,
            "400.008",
            "Name of item '" + "x" * 64 + "...' is too long",
        ),
    ],
)
async def test_get_object_name_errors(
    session: aiohttp.ClientSession,
    manual_plc: Simulator,
    query: str,
    code: str,
    message: str,
) -> None:
    reply = await get(session, manual_plc, "/TecoApi/GetObject" + query)

    assert (reply.status, reply.error_code, reply.error_message) == (400, code, message)


async def test_get_object_variable_name_over_128_characters_on_a_small_plc(
    session: aiohttp.ClientSession, manual_plc: Simulator
) -> None:
    name = "myObject." + "a" * 60 + "." + "b" * 60
    assert len(name) > 128
    assert len("/TecoApi/GetObject?" + name) <= 256

    reply = await get(session, manual_plc, "/TecoApi/GetObject?" + name)

    assert (reply.status, reply.error_code) == (400, "400.007")
    assert reply.error_message == f"Name of variable '{name[:64]}...' is too long"


def escaped(name: str, count: int) -> str:
    """`name` with its first `count` characters percent-encoded (2 more each)."""
    return "".join(f"%{ord(c):02X}" for c in name[:count]) + name[count:]


def target_of_length(length: int) -> str:
    """A GetObject target of exactly `length` characters naming real variables."""
    prefix = "/TecoApi/GetObject?"
    pieces: list[str] = []

    def left() -> int:
        return length - len(prefix + "&".join(pieces)) - (1 if pieces else 0)

    while left() > 24:
        pieces.append("plcName")
    # arr1 (4), plcName (7) and myObject (8) escaped by 0..8 characters cover 4..24.
    last = next(
        escaped(name, (left() - len(name)) // 2)
        for name in ("arr1", "plcName", "myObject")
        if len(name) <= left() <= 3 * len(name) and (left() - len(name)) % 2 == 0
    )
    target = prefix + "&".join([*pieces, last])
    assert len(target) == length
    return target


async def test_get_object_request_target_limit_is_256_characters(
    session: aiohttp.ClientSession, manual_plc: Simulator
) -> None:
    fitting = await get(session, manual_plc, target_of_length(256))
    too_long = await get(session, manual_plc, target_of_length(257))

    assert fitting.status == 200
    assert (too_long.status, too_long.error_code) == (400, "400.007")
    assert too_long.error_message.startswith("Name of variable 'plcName&plcName&")
    assert too_long.error_message.endswith("...' is too long")


async def test_get_object_too_many_names(
    session: aiohttp.ClientSession, manual_plc: Simulator
) -> None:
    reply = await get(
        session, manual_plc, "/TecoApi/GetObject?" + "&".join(["a"] * 129)
    )

    assert (reply.status, reply.error_code) == (413, "413.002")
    assert (
        reply.error_message
        == "Too many variables in one request (requested: 129, allowed: 128)"
    )


async def test_get_object_too_many_items_on_a_cp_1xxx(
    session: aiohttp.ClientSession, manual_plc: Simulator
) -> None:
    # plcData has 23 items: 5 of them are 115, 6 are 138 > 128.
    five = await get(
        session, manual_plc, "/TecoApi/GetObject?" + "&".join(["plcData"] * 5)
    )
    six = await get(
        session, manual_plc, "/TecoApi/GetObject?" + "&".join(["plcData"] * 6)
    )

    assert five.status == 200
    assert manual_plc.requests[-2].items == 115
    assert (six.status, six.error_code) == (413, "413.004")
    assert six.error_message == "Too many variables (maximum is 128)"


async def test_get_object_item_limit_is_256_on_a_cp_2xxx(
    session: aiohttp.ClientSession, manual_plc: Simulator
) -> None:
    manual_plc.plc_type = "CP-2080"
    six = await get(
        session, manual_plc, "/TecoApi/GetObject?" + "&".join(["plcData"] * 6)
    )
    twelve = await get(
        session, manual_plc, "/TecoApi/GetObject?" + "&".join(["plcData"] * 12)
    )

    assert six.status == 200
    assert (twelve.status, twelve.error_code) == (413, "413.004")
    assert twelve.error_message == "Too many variables (maximum is 256)"


# --- SetObject --------------------------------------------------------------------------


async def test_set_object_manual_examples(
    session: aiohttp.ClientSession, manual_plc: Simulator
) -> None:
    registered = await get(
        session, manual_plc, "/TecoApi/SetObject?myObject.registered=true"
    )
    arr1 = await get(session, manual_plc, "/TecoApi/SetObject?arr1[5]=five")
    pair = await get(
        session,
        manual_plc,
        "/TecoApi/SetObject?plcType=1005&plcDesc=%22testing%20is%20funny%22",
    )

    for reply in (registered, arr1, pair):
        assert (reply.status, reply.body) == (200, b"")
        assert reply.headers["Content-Length"] == "0"
        assert reply.headers["Connection"] == "close"
        assert "Content-Type" not in reply.headers
    assert manual_plc.get_value("myObject.registered") is True
    assert manual_plc.get_value("arr1") == [
        "zero",
        "one",
        "two",
        "three",
        "four",
        "five",
    ]
    assert manual_plc.get_value("plcType") == 1005
    assert manual_plc.get_value("plcDesc") == "testing is funny"


async def test_set_object_writes_a_read_only_api_object(
    session: aiohttp.ClientSession, manual_plc: Simulator
) -> None:
    reply = await get(
        session, manual_plc, "/TecoApi/SetObject?main.myobject1.VALUE=-7.25"
    )

    assert reply.status == 200
    assert manual_plc.get_value("Main.myObject1.value") == -7.25
    assert manual_plc.get_value("Main.myObject1.attr.readOnly") is True


@pytest.mark.parametrize(
    ("path", "text", "stored"),
    [
        ("plcData.varBool0", "TRUE", True),
        ("plcData.varBool1", "0", False),
        ("plcData.varByte", "255", 255),
        ("plcData.varWord", "65535", 65535),
        ("plcData.varDword", "4294967295", 4294967295),
        ("plcData.varUsint", "0", 0),
        ("plcData.varUint", "%2B12", 12),
        ("plcData.varUdint", "4294967295", 4294967295),
        ("plcData.varSint", "-128", -128),
        ("plcData.varInt", "-32768", -32768),
        ("plcData.varDint", "2147483647", 2147483647),
        ("plcData.varReal", "-12.5", -12.5),
        ("plcData.varReal", "3", 3.0),
        ("plcData.varLreal", "0.125", 0.125),
        ("plcData.varTime", "120:02:03.45", "120:02:03.450"),
        ("plcData.varDate", "2024-02-29", "2024-02-29"),
        ("plcData.varDT", "2024-01-02T03:04:05.678Z", "2024-01-02T03:04:05.678Z"),
        ("plcData.varDT", "2024-01-02T03:04:05", "2024-01-02T03:04:05.000Z"),
        ("plcData.varString", "%22quoted%22", "quoted"),
        ("plcData.varString", "", ""),
        ("plcName", "0123456789", "0123456789"),
        ("plcData.varStringArray[5]", "eight%20ch", "eight ch"),
    ],
)
async def test_set_object_accepts_values_within_the_type(
    session: aiohttp.ClientSession,
    manual_plc: Simulator,
    path: str,
    text: str,
    stored: object,
) -> None:
    reply = await get(session, manual_plc, f"/TecoApi/SetObject?{path}={text}")

    assert reply.status == 200
    assert manual_plc.get_value(path) == stored


@pytest.mark.parametrize(
    ("path", "text", "type_name"),
    [
        ("plcData.varBool0", "yes", "BOOL"),
        ("plcData.varBool0", "2", "BOOL"),
        ("plcData.varByte", "256", "BYTE"),
        ("plcData.varByte", "-1", "BYTE"),
        ("plcData.varWord", "65536", "WORD"),
        ("plcData.varDword", "4294967296", "DWORD"),
        ("plcData.varUsint", "256", "USINT"),
        ("plcType", "65536", "UINT"),
        ("plcType", "1.5", "UINT"),
        ("plcType", "16%2310", "UINT"),
        ("plcType", "", "UINT"),
        ("plcData.varUdint", "-1", "UDINT"),
        ("plcData.varSint", "128", "SINT"),
        ("plcData.varInt", "32768", "INT"),
        ("plcData.varDint", "-2147483649", "DINT"),
        ("plcData.varReal", "1.5E3", "REAL"),
        ("plcData.varReal", "1e39", "REAL"),
        ("plcData.varReal", "nan", "REAL"),
        ("plcData.varReal", "4" + "0" * 38, "REAL"),
        ("plcData.varLreal", "inf", "LREAL"),
        ("plcData.varTime", "1:02:03", "TIME"),
        ("plcData.varTime", "597:00:00.000", "TIME"),
        ("plcData.varDate", "2023-02-29", "DATE"),
        ("plcData.varDate", "1969-12-31", "DATE"),
        ("plcData.varDate", "17.6.2015", "DATE"),
        ("plcData.varDT", "2024-01-02%2003:04:05", "DT"),
        ("plcData.varDT", "2024-01-02T24:00:00", "DT"),
        ("plcName", "01234567890", "STRING[10]"),
        ("plcName", "%C2%B0C", "STRING[10]"),
        ("plcData.varString", "x" * 81, "STRING"),
        ("myObject", "1", "TmyObject"),
        ("arr1", "zero", "ARRAY[0..5] OF STRING[10]"),
        ("arr2[1]", "1.0", "ARRAY[0..3] OF REAL"),
        ("Main.myObject3", "5", "prgMain"[:0] + "T_ApiObject"),
        ("Main", "5", "prgMain"),
    ],
)
async def test_set_object_rejects_values_outside_the_type(
    session: aiohttp.ClientSession,
    manual_plc: Simulator,
    path: str,
    text: str,
    type_name: str,
) -> None:
    before = manual_plc.get_value(path)

    reply = await get(session, manual_plc, f"/TecoApi/SetObject?{path}={text}")

    assert (reply.status, reply.error_code) == (400, "400.015")
    shown = unquote(text)
    assert reply.error_message == (
        f"Value {shown} was not written to variable '{path}' (type of variable is {type_name})"
    )
    assert manual_plc.get_value(path) == before


async def test_set_object_is_atomic(
    session: aiohttp.ClientSession, manual_plc: Simulator
) -> None:
    reply = await get(
        session,
        manual_plc,
        "/TecoApi/SetObject?plcType=1&myObject.age=40&plcName=far%20too%20long",
    )

    assert reply.error_code == "400.015"
    assert manual_plc.get_value("plcType") == 2005
    assert manual_plc.get_value("myObject.age") == 39


@pytest.mark.parametrize(
    ("query", "status", "code"),
    [
        ("", 400, "400.001"),
        ("?=5", 400, "400.003"),
        ("?plcType=1&&plcName=a", 400, "400.003"),
        ("?plcType", 400, "400.019"),
        ("?nothing=1", 400, "400.005"),
        ("?myObject." + "y" * 65 + "=1", 400, "400.008"),
        ("?" + "&".join(["plcType=1"] * 129), 413, "413.002"),
        ("?plcDesc=" + "x" * 240, 400, "400.007"),
    ],
)
async def test_set_object_errors(
    session: aiohttp.ClientSession,
    manual_plc: Simulator,
    query: str,
    status: int,
    code: str,
) -> None:
    reply = await get(session, manual_plc, "/TecoApi/SetObject" + query)

    assert (reply.status, reply.error_code) == (status, code)
    assert manual_plc.get_value("plcType") == 2005


async def test_set_object_value_missing_names_the_variable(
    session: aiohttp.ClientSession, manual_plc: Simulator
) -> None:
    reply = await get(session, manual_plc, "/TecoApi/SetObject?plcType")

    assert reply.error_message == (
        "Value of parameter is empty (service: 'SetObject', param: 'plcType')"
    )


# --- PutObject ----------------------------------------------------------------------------


MANUAL_MY_OBJECT = b"""{
  "myObject":
  {
    "first": "Mia",
    "last": "Miller",
    "age": 25,
    "sex": "F",
    "salary": 51000,
    "married": false,
    "registered": true,
    "interests":
    [
      "Reading",
      "Cooking",
      "Traveling"
    ],
    "favorites":
    {
      "color": "Red",
      "sport": "Swimming",
      "food": "Salad"
    }
  }
}
"""


async def test_put_object_whole_struct_chapter_5_1(
    session: aiohttp.ClientSession, manual_plc: Simulator
) -> None:
    reply = await put(session, manual_plc, MANUAL_MY_OBJECT, "?myObject")

    assert (reply.status, reply.body) == (204, b"")
    assert reply.headers["Connection"] == "close"
    assert manual_plc.get_value("myObject") == {
        "first": "Mia",
        "last": "Miller",
        "age": 25,
        "sex": "F",
        "salary": 51000,
        "married": False,
        "registered": True,
        "interests": ["Reading", "Cooking", "Traveling"],
        "favorites": {"color": "Red", "sport": "Swimming", "food": "Salad"},
    }


async def test_put_object_whole_array_chapter_5_2(
    session: aiohttp.ClientSession, manual_plc: Simulator
) -> None:
    body = b"""{
  "arr2": [
    [ 0.00, 0.11, 0.22, 0.33 ],
    [ 11.00, 11.11, 11.22, 11.33 ],
    [ 22.00, 22.11, 22.22, 22.33 ]
  ]
}"""
    reply = await put(session, manual_plc, body)

    assert reply.status == 204
    assert manual_plc.get_value("arr2") == [
        [0.0, 0.11, 0.22, 0.33],
        [11.0, 11.11, 11.22, 11.33],
        [22.0, 22.11, 22.22, 22.33],
    ]
    read = await get(session, manual_plc, "/TecoApi/GetObject?arr2[1][1]")
    assert b"11.110000" in read.body


async def test_put_object_scalars_chapter_3_6(
    session: aiohttp.ClientSession, manual_plc: Simulator
) -> None:
    one = await fetch(
        session,
        manual_plc,
        "/TecoApi/PutObject",
        method="PUT",
        data=b'{ "plcType": 1005 }',
        headers={"Content-Type": "application/x-www-form-urlencoded"},
    )
    two = await put(
        session,
        manual_plc,
        b'{\n  "plcType": 1006,\n  "plcDesc": "testing is funny"\n}',
    )

    assert (one.status, two.status) == (204, 204)
    assert manual_plc.get_value("plcType") == 1006
    assert manual_plc.get_value("plcDesc") == "testing is funny"


@pytest.mark.parametrize(
    ("body", "path", "stored"),
    [
        (b'{"myObject": {"AGE": 40}}', "myObject.age", 40),
        (
            b'{"myObject": {"favorites": {"food": "Soup"}}}',
            "myObject.favorites.food",
            "Soup",
        ),
        (b'{"MyObject.Favorites.Sport": "Chess"}', "myObject.favorites.sport", "Chess"),
        (b'{"arr1[5]": "five"}', "arr1[5]", "five"),
        (
            b'{"arr1": ["null", "jedna"]}',
            "arr1",
            ["null", "jedna", "two", "three", "four", ""],
        ),
        (b'{"Main": {"myObject3": {"value": 21}}}', "Main.myObject3.value", 21.0),
        (b'{"plcData": {"varBool0": 1}}', "plcData.varBool0", True),
        (b'{"plcData": {"varTime": "00:00:01.5"}}', "plcData.varTime", "00:00:01.500"),
        (
            b'{"plcData": {"varString": "a \\"quote\\" \\u0041"}}',
            "plcData.varString",
            'a "quote" A',
        ),
        (b'{"plcData": {"varSint": -0}}', "plcData.varSint", 0),
    ],
)
async def test_put_object_partial_structs_prefix_arrays_and_paths(
    session: aiohttp.ClientSession,
    manual_plc: Simulator,
    body: bytes,
    path: str,
    stored: object,
) -> None:
    reply = await put(session, manual_plc, body)

    assert reply.status == 204
    assert manual_plc.get_value(path) == stored
    if path == "myObject.age":
        assert manual_plc.get_value("myObject.first") == "John"


@pytest.mark.parametrize(
    ("body", "code", "message"),
    [
        (b"", "400.009", "JSON syntax error (Expected character '{')"),
        (b'["plcType"]', "400.009", "JSON syntax error (Expected character '{')"),
        (b"{plcType: 1}", "400.009", "JSON syntax error (Expected character '\"')"),
        (b'{"plcType" 1}', "400.009", "JSON syntax error (Expected character ':')"),
        (b'{"plcType": 1}}', "400.009", "JSON syntax error (JSON stack underflow)"),
        (
            b'{"plcType": 1.5E3}',
            "400.009",
            "JSON syntax error (Unexpected character 'E')",
        ),
        (
            b'{"plcType": 1e3}',
            "400.009",
            "JSON syntax error (Unexpected character 'e')",
        ),
        (b'{"plcType": 1', "400.009", "JSON syntax error (Unexpected end of data)"),
        (
            b'{"plcType": tru}',
            "400.009",
            "JSON syntax error (Unexpected character 't')",
        ),
        (b'{"plcType": 1,}', "400.009", "JSON syntax error (Expected character '\"')"),
        (b'{"plcType": .5}', "400.009", "JSON syntax error (Unexpected character '.')"),
        (b'{"plcType": 1.}', "400.009", "JSON syntax error (Unexpected character '}')"),
        (b'{"plcType": -}', "400.009", "JSON syntax error (Unexpected character '}')"),
        (
            b'{"plcType": [1 2]}',
            "400.009",
            "JSON syntax error (Unexpected character '2')",
        ),
        (
            b'{"plcDesc": "\\x"}',
            "400.009",
            "JSON syntax error (Unexpected character 'x')",
        ),
        (
            b'{"plcDesc": "\\u12"}',
            "400.009",
            "JSON syntax error (Unexpected character 'u')",
        ),
        (b'{"plcDesc": "open', "400.009", "JSON syntax error (Unexpected end of data)"),
        (b'{"plcDesc": "', "400.009", "JSON syntax error (Unexpected end of data)"),
        (
            b'{"plcDesc": "x"} x',
            "400.009",
            "JSON syntax error (Unexpected character 'x')",
        ),
        (
            '{"plcDesc": "°C"}'.encode(),
            "400.009",
            "JSON syntax error (Non-ASCII character)",
        ),
        (
            b'{"plcDesc": "\\u00b0C"}',
            "400.009",
            "JSON syntax error (Non-ASCII character)",
        ),
        (
            b'{"plcDesc": "' + b"x" * 256 + b'"}',
            "400.009",
            "JSON syntax error (Value is too long)",
        ),
        (
            b'{"plcType": ' + b"1" * 256 + b"}",
            "400.009",
            "JSON syntax error (Value is too long)",
        ),
        (
            b'{"' + b"n" * 65 + b'": 1}',
            "400.008",
            "Name of item '" + "n" * 64 + "...' is too long",
        ),
        (b"{}", "400.001", "Bad parameters (any PLC variable is not specified)"),
        (b'{"nothing": 1}', "400.005", "Variable 'nothing' is not found"),
        (
            b'{"myObject": {"hobby": 1}}',
            "400.005",
            "Variable 'myObject.hobby' is not found",
        ),
        (
            b'{"plcType": "1005"}',
            "400.015",
            "Value \"1005\" was not written to variable 'plcType' (type of variable is UINT)",
        ),
        (
            b'{"plcType": 1005.0}',
            "400.015",
            "Value 1005.0 was not written to variable 'plcType' (type of variable is UINT)",
        ),
        (
            b'{"plcType": null}',
            "400.015",
            "Value null was not written to variable 'plcType' (type of variable is UINT)",
        ),
        (
            b'{"plcType": true}',
            "400.015",
            "Value true was not written to variable 'plcType' (type of variable is UINT)",
        ),
        (
            b'{"plcData": {"varReal": false}}',
            "400.015",
            (
                "Value false was not written to variable 'plcData.varReal' "
                "(type of variable is REAL)"
            ),
        ),
        (
            b'{"plcDesc": 5}',
            "400.015",
            "Value 5 was not written to variable 'plcDesc' (type of variable is STRING)",
        ),
        (
            b'{"plcData": {"varBool0": 2}}',
            "400.015",
            (
                "Value 2 was not written to variable 'plcData.varBool0' "
                "(type of variable is BOOL)"
            ),
        ),
        (
            b'{"arr1": [1, 2, 3, 4, 5, 6, 7]}',
            "400.015",
            (
                "Value [1, 2, 3, 4, 5, 6, 7] was not written to variable 'arr1' "
                "(type of variable is ARRAY[0..5] OF STRING[10])"
            ),
        ),
        (
            b'{"myObject": 5}',
            "400.015",
            "Value 5 was not written to variable 'myObject' (type of variable is TmyObject)",
        ),
        (
            b'{"arr2": {"a": 1}}',
            "400.015",
            (
                "Value {\"a\": 1} was not written to variable 'arr2' "
                "(type of variable is ARRAY[0..2, 0..3] OF REAL)"
            ),
        ),
    ],
)
async def test_put_object_errors(
    session: aiohttp.ClientSession,
    manual_plc: Simulator,
    body: bytes,
    code: str,
    message: str,
) -> None:
    reply = await put(session, manual_plc, body)

    assert (reply.status, reply.error_code, reply.error_message) == (
        int(code[:3]),
        code,
        message,
    )
    assert manual_plc.get_value("plcType") == 2005
    assert manual_plc.get_value("plcDesc") == "for testing only"


def nested_objects(levels: int) -> bytes:
    return b'{"a":' * (levels - 1) + b"{}" + b"}" * (levels - 1)


def nested_arrays(arrays: int) -> bytes:
    return b'{"a":' + b"[" * arrays + b"]" * arrays + b"}"


@pytest.mark.parametrize(
    ("body", "overflows"),
    [
        (nested_objects(32), False),
        (nested_objects(33), True),
        (nested_arrays(15), False),  # 1 + 15 * 2 = 31 levels
        (nested_arrays(16), True),  # 1 + 16 * 2 = 33 levels
    ],
)
async def test_put_object_nesting_limit_counts_an_array_as_two_levels(
    session: aiohttp.ClientSession, manual_plc: Simulator, body: bytes, overflows: bool
) -> None:
    reply = await put(session, manual_plc, body)

    if overflows:
        assert reply.error_message == "JSON syntax error (JSON stack overflow)"
    else:  # parsed, then the name `a` is looked up
        assert reply.error_code == "400.005"


async def test_put_object_is_atomic(
    session: aiohttp.ClientSession, manual_plc: Simulator
) -> None:
    reply = await put(
        session,
        manual_plc,
        b'{"plcType": 7, "myObject": {"age": 41, "sex": "too long"}, "plcDesc": "x"}',
    )

    assert reply.error_code == "400.015"
    assert manual_plc.get_value("plcType") == 2005
    assert manual_plc.get_value("myObject.age") == 39
    assert manual_plc.get_value("plcDesc") == "for testing only"


async def test_put_object_too_many_names(
    session: aiohttp.ClientSession, manual_plc: Simulator
) -> None:
    body = "{" + ", ".join(f'"n{i}": 1' for i in range(129)) + "}"

    reply = await put(session, manual_plc, body.encode())

    assert (reply.status, reply.error_code) == (413, "413.002")


# --- services, methods, headers -------------------------------------------------------------


@pytest.mark.parametrize(
    ("method", "target", "status", "code", "message"),
    [
        (
            "GET",
            "/TecoApi/GetData",
            501,
            "501.013",
            "Unimplemented service 'HTTP GET | GetData'",
        ),
        (
            "GET",
            "/TecoApi/PutObject",
            501,
            "501.013",
            "Unimplemented service 'HTTP GET | PutObject'",
        ),
        (
            "PUT",
            "/TecoApi/GetObject?plcName",
            501,
            "501.013",
            "Unimplemented service 'HTTP PUT | GetObject'",
        ),
        (
            "POST",
            "/TecoApi/SetObject?plcType=1",
            501,
            "501.013",
            "Unimplemented service 'HTTP POST | SetObject'",
        ),
        ("GET", "/TecoApi/", 400, "400.014", "Service is not specified"),
        ("GET", "/TecoApi", 400, "400.014", "Service is not specified"),
    ],
)
async def test_unknown_services_and_methods(
    session: aiohttp.ClientSession,
    *,
    manual_plc: Simulator,
    method: str,
    target: str,
    status: int,
    code: str,
    message: str,
) -> None:
    reply = await fetch(session, manual_plc, target, method=method)

    assert (reply.status, reply.error_code, reply.error_message) == (
        status,
        code,
        message,
    )
    assert manual_plc.get_value("plcType") == 2005


async def test_error_body_layout_chapter_3_7(
    session: aiohttp.ClientSession, manual_plc: Simulator
) -> None:
    reply = await get(session, manual_plc, "/TecoApi/GetData")

    time = reply.json()["error"]["time"]
    assert re.fullmatch(r"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\.\d{3}Z", time)
    assert reply.body == manual_text(
        f"""
        {{
          "error": {{
            "code": "501.013",
            "message": "Unimplemented service 'HTTP GET | GetData'",
            "time": "{time}"
          }}
        }}
        """
    )
    assert int(reply.headers["Content-Length"]) == 151
    assert reply.headers["Content-Type"] == "application/json"
    assert reply.headers["Connection"] == "close"


@pytest.mark.parametrize(
    ("accept", "status"),
    [
        ("*/*", 200),
        ("application/json", 200),
        ("application/*", 200),
        ("text/html,application/xhtml+xml,*/*;q=0.8", 200),
        ("Application/JSON; charset=utf-8", 200),
        ("text/html", 400),
        ("application/xml, text/plain", 400),
    ],
)
async def test_accept_header_must_allow_json(
    session: aiohttp.ClientSession, manual_plc: Simulator, accept: str, status: int
) -> None:
    reply = await fetch(
        session, manual_plc, "/TecoApi/GetObject?plcName", headers={"Accept": accept}
    )

    assert reply.status == status
    if status == 400:
        assert reply.error_code == "400.016"
        assert reply.error_message == (
            f"Unknown value of parameter (param: 'Accept', value: '{accept}')"
        )


@pytest.mark.parametrize(
    ("public_file", "status", "code", "message"),
    [
        ("missing", 500, "500.010", "Public file 'tecoapi.pub' is not found"),
        ("too_big", 500, "500.011", "Public file 'tecoapi.pub' is too big"),
        ("unreadable", 500, "500.012", "Reading of public file 'tecoapi.pub' failed"),
        ("empty", 400, "400.006", "No variable is found"),
    ],
)
async def test_public_file_problems(
    session: aiohttp.ClientSession,
    *,
    socket_enabled: None,
    public_file: str,
    status: int,
    code: str,
    message: str,
) -> None:
    source = load_program("manual").to_mapping()
    source["publicFile"] = public_file
    async with Simulator(
        Program.from_mapping(source),
        username="admin",
        password="s3cret-Pa55",
        auth="basic",
    ) as sim:
        info = await get(session, sim, "/TecoApi/GetInfo")
        replies = [
            await get(session, sim, "/TecoApi/GetList"),
            await get(session, sim, "/TecoApi/GetObject?plcName"),
            await get(session, sim, "/TecoApi/SetObject?plcType=1"),
            await put(session, sim, b'{"plcType": 1}'),
        ]

    assert info.status == 200
    for reply in replies:
        assert (reply.status, reply.error_code, reply.error_message) == (
            status,
            code,
            message,
        )


async def test_program_without_variables_has_no_public_file(
    session: aiohttp.ClientSession, socket_enabled: None
) -> None:
    source = load_program("manual").to_mapping()
    source["variables"] = {}
    source.pop("types")
    async with Simulator(
        Program.from_mapping(source),
        username="admin",
        password="s3cret-Pa55",
        auth="basic",
    ) as sim:
        listing = await get(session, sim, "/TecoApi/GetList")

    assert (listing.status, listing.error_code) == (500, "500.010")
