"""An OPC address space as the neutral model: devices, points, values, qualities."""

from typing import Any

import pytest

from custom_components.tecoapi.pyplc import (
    Access,
    PointQuality,
    Quality,
    Record,
    ValueKind,
)
from custom_components.tecoapi.pyplc.core.models import DataExchange
from custom_components.tecoapi.pyplc.tekon.catalogue import (
    MALFORMED,
    build_address_space,
    compact,
    from_compact,
    parse_number,
    parse_record,
    parse_value,
    quality_of,
)
from custom_components.tecoapi.pyplc.tekon.client import AddressItem, address_item

ids = iter(range(10_000))


def item(name: str, **properties: Any) -> AddressItem:
    """An item with properties by ID (``p5001=3000``)."""
    return AddressItem(
        name=name,
        item_id=next(ids),
        properties={int(key[1:]): str(value) for key, value in properties.items()},
    )


def test_devices_from_statuses_each_under_the_nearest_above() -> None:
    items = [
        item("A.Status", p5001=3005, p6000="10.0.0.1", p6001="Street 1", p9002="R-1"),
        item("A.B.Status", p5001=3005),
        item("A.B.C.D.Status", p5001=3005),
        item("A.B.C.D.Door", p5001=3000),
        item("A.B.X.Temp", p5001=3060, p1=4),
        item("Top", p1=19),
        item("DBMonitoring.ConnectFailDevices", p1=19),
    ]
    space = build_address_space(items)
    catalogue = space.catalogue
    devices = catalogue.devices
    assert {key: node.parent for key, node in devices.items()} == {
        "a": "",
        "a.b": "a",
        "a.b.c.d": "a.b",
        "dbmonitoring": "",
    }
    assert devices["a"].properties == {
        "install_address": "Street 1",
        "ip_address": "10.0.0.1",
        "registration_number": "R-1",
    }
    assert devices["a"].serial_number == "R-1"
    assert devices["a.b.c.d"].name == "D"
    assert devices["dbmonitoring"].name == "DBMonitoring"
    points = catalogue.points
    # A channel sits on the nearest device above it; a status on its own device.
    assert points["a.b.x.temp"].device == "a.b"
    assert points["a.b.c.d.door"].device == "a.b.c.d"
    assert points["a.b.c.d.status"].device == "a.b.c.d"
    assert points["top"].device == ""
    assert points["dbmonitoring.connectfaildevices"].device == "dbmonitoring"
    assert space.status_of == {
        "a": "a.status",
        "a.b": "a.b.status",
        "a.b.c.d": "a.b.c.d.status",
    }
    assert space.devices_above["a.b.c.d"] == ("a.b.c.d", "a.b", "a")
    assert catalogue.groups == ("A", "Top", "DBMonitoring")
    assert space.ids == {i.item_id: i.name.lower() for i in items}


def test_devices_of_the_same_name_say_their_parent() -> None:
    catalogue = build_address_space(
        [
            item("House.Entrance 1.Status"),
            item("House.Entrance 1.Lift.Status"),
            item("House.Entrance 2.Status"),
            item("House.Entrance 2.Lift.Status"),
        ]
    ).catalogue
    names = {node.name for node in catalogue.devices.values()}
    assert names == {"Entrance 1", "Entrance 2", "Entrance 1 Lift", "Entrance 2 Lift"}


def test_a_name_given_twice_counts_once_and_keys_are_names_in_lower_case() -> None:
    first = item("Дом.Дверь", p5001=3000)
    catalogue = build_address_space([first, item("ДОМ.ДВЕРЬ", p1=8)]).catalogue
    assert list(catalogue.points) == ["дом.дверь"]
    point = catalogue.points["дом.дверь"]
    assert (point.path, point.address) == ("Дом.Дверь", "Дом.Дверь")


@pytest.mark.parametrize(
    ("properties", "kind", "access", "extra"),
    [
        ({"p5001": 3000, "p5": 3}, ValueKind.BOOL, Access.READ, {}),
        ({"p5001": 3001, "p5": 3}, ValueKind.BOOL, Access.WRITE, {}),
        ({"p5001": 3001, "p5": 1}, ValueKind.BOOL, Access.READ, {}),
        ({"p5001": 3002, "p5": 3}, ValueKind.BOOL, Access.READ_WRITE, {}),
        ({"p5001": 3002}, ValueKind.BOOL, Access.READ, {}),
        (
            {"p5001": 3005, "p5": 3, "p6004": 10},
            ValueKind.INTEGER,
            Access.READ,
            {"diagnostic": True},
        ),
        ({"p5001": 3060, "p1": 4, "p5": 3}, ValueKind.REAL, Access.READ_WRITE, {}),
        (
            {"p5001": 3060, "p1": 19},
            ValueKind.INTEGER,
            Access.READ,
            {"bits": 32, "signed": False},
        ),
        (
            {"p5001": 3060, "p1": 2},
            ValueKind.INTEGER,
            Access.READ,
            {"bits": 16, "signed": True},
        ),
        ({"p5001": 3060, "p1": 8}, ValueKind.REAL, Access.READ, {}),
        ({"p5001": 3061, "p1": 8, "p5": 2}, ValueKind.STRING, Access.WRITE, {}),
        ({"p5001": 3070, "p1": 8, "p5": 3}, ValueKind.RECORD, Access.READ, {}),
        # No channel type: the value type says (11: VT_BOOL, 5: VT_R8, 8192|3: an array).
        ({"p1": 11, "p5": 3}, ValueKind.BOOL, Access.READ_WRITE, {}),
        ({"p1": 5}, ValueKind.REAL, Access.READ, {"bits": 64}),
        ({"p1": 8195}, ValueKind.STRING, Access.READ, {}),
        ({}, ValueKind.STRING, Access.READ, {}),
        # Access from property 3 (the seed's table) only where 5 is absent, and
        # only as 1, 2 or 3 (OPC DA's 3 is a quality: 192).
        ({"p1": 19, "p3": 3}, ValueKind.INTEGER, Access.READ_WRITE, {}),
        ({"p1": 19, "p3": 192}, ValueKind.INTEGER, Access.READ, {}),
        ({"p1": 19, "p3": 3, "p5": 1}, ValueKind.INTEGER, Access.READ, {}),
        ({"p1": 19, "p5": "x"}, ValueKind.INTEGER, Access.READ, {}),
    ],
)
def test_a_channel_becomes_a_point_by_its_properties(
    properties: dict[str, Any], kind: ValueKind, access: Access, extra: dict[str, Any]
) -> None:
    point = build_address_space([item("C.Channel", **properties)]).catalogue.points[
        "c.channel"
    ]
    assert point.type.kind is kind
    assert point.attributes is not None
    assert point.attributes.access is access
    assert point.diagnostic is extra.get("diagnostic", False)
    for name in ("bits", "signed"):
        if name in extra:
            assert getattr(point.type, name) == extra[name]


def test_names_units_ranges_and_details() -> None:
    points = build_address_space(
        [
            item("C.Status", p5001=3005, p6003=2, p6004=10, p7000="Связь"),
            item(
                "C.A",
                p5001=3060,
                p1=4,
                p5=3,
                p7001="Fault text",
                p5003="Comment",
                p100="°C",
                p102=30,
                p103=10,
                p6001="Here",
            ),
            item("C.B", p5001=3060, p1=4, p5003="  Comment  ", p100="kWh", p102=30),
            item("C.C", p5001=3061, p1=8, p100="x"),
        ]
    ).catalogue.points
    status = points["c.status"].attributes
    assert status is not None
    assert (status.minimum, status.maximum, status.name) == (2.0, 10.0, "Status")
    assert points["c.status"].details == {"fault_category": "Связь"}
    a = points["c.a"]
    assert a.attributes is not None
    assert (a.attributes.name, a.attributes.unit) == ("Fault text", "°C")
    assert (a.attributes.minimum, a.attributes.maximum) == (10.0, 30.0)
    assert a.description == "Fault text"
    assert a.details == {"install_address": "Here"}
    b = points["c.b"].attributes
    assert b is not None
    # A range needs both ends.
    assert (b.name, b.unit, b.minimum, b.maximum) == ("Comment", "kWh", None, None)
    c = points["c.c"].attributes
    assert c is not None
    # Text has no unit.
    assert (c.name, c.unit) == ("C", "")


@pytest.mark.parametrize(
    ("text", "number"),
    [
        ("0,05", 0.05),
        ("12", 12),
        ("-3", -3),
        ("1 234,5", 1234.5),
        ("1\u00a0234", 1234),
        (".5", 0.5),
        ("1e3", 1000.0),
        ("abc", None),
        ("", None),
        ("1,2,3", None),
    ],
)
def test_numbers_as_the_gateway_writes_them(text: str, number: float | None) -> None:
    assert parse_number(text) == number


def _point(**properties: Any) -> Any:
    return build_address_space([item("C.X", **properties)]).catalogue.points["c.x"]


@pytest.mark.parametrize(
    ("properties", "text", "value"),
    [
        ({"p5001": 3000}, "0", False),
        ({"p5001": 3000}, "3", True),
        ({"p5001": 3000}, "2", False),
        ({"p1": 11}, "-1", True),
        ({"p1": 11}, "True", True),
        ({"p1": 11}, "false", False),
        ({"p5001": 3060, "p1": 19}, "7", 7),
        ({"p5001": 3060, "p1": 19}, "7,0", 7),
        ({"p5001": 3060, "p1": 4}, "21,5", 21.5),
        ({"p5001": 3060, "p1": 4}, "-0", 0.0),
        ({"p5001": 3061, "p1": 8}, "Привет", "Привет"),
    ],
)
def test_values_of_their_text(
    properties: dict[str, Any], text: str, value: Any
) -> None:
    parsed, quality = parse_value(_point(**properties), text)
    assert (parsed, type(parsed), quality) == (value, type(value), None)


@pytest.mark.parametrize(
    ("properties", "text"),
    [
        ({"p5001": 3000}, "on"),
        ({"p5001": 3060, "p1": 19}, "7,5"),
        ({"p5001": 3060, "p1": 4}, "warm"),
        ({"p5001": 3070, "p1": 8}, "<Lift><State>"),
    ],
)
def test_a_malformed_value_is_bad_for_its_point_alone(
    properties: dict[str, Any], text: str
) -> None:
    assert parse_value(_point(**properties), text) == (None, MALFORMED)


def test_a_lift_state_is_a_record_of_its_xml() -> None:
    record = parse_record(
        '<Lift mode="auto"><State>Движение</State><Floor>3</Floor>'
        '<Door side="A">закрыта</Door><Cabin><Load>40</Load><Light>1</Light></Cabin></Lift>'
    )
    assert record == Record(
        text="Движение",
        parts=(
            ("mode", "auto"),
            ("State", "Движение"),
            ("Floor", "3"),
            ("Door_side", "A"),
            ("Door", "закрыта"),
            ("Cabin_Load", "40"),
            ("Cabin_Light", "1"),
        ),
    )
    assert parse_record("<Lift>stopped</Lift>") == Record(text="stopped", parts=())
    assert parse_record("<L><Floor>2</Floor><Door>open</Door></L>") == Record(
        text="Floor: 2; Door: open", parts=(("Floor", "2"), ("Door", "open"))
    )
    assert parse_record("not xml") is None
    assert parse_record("<L>" + "x" * 70_000 + "</L>") is None
    long = parse_record(f"<L><State>{'x' * 300}</State></L>")
    assert long is not None
    assert len(long.text) == 255
    many = parse_record(
        "<L>" + "".join(f"<P{i}>{i}</P{i}>" for i in range(100)) + "</L>"
    )
    assert many is not None
    assert len(many.parts) == 64


@pytest.mark.parametrize(
    ("code", "quality"),
    [
        (192, None),
        (0xD8, None),
        (0xC1, None),
        (0x40, PointQuality(quality=Quality.UNCERTAIN, reason="uncertain")),
        (0x44, PointQuality(quality=Quality.UNCERTAIN, reason="last_usable")),
        (0x57, PointQuality(quality=Quality.UNCERTAIN, reason="egu_exceeded")),
        # The seed's DA_QUALITY_UNCKNOWN: not known, not bad.
        (0x00, PointQuality(quality=Quality.UNKNOWN, reason="unknown")),
        (0x03, PointQuality(quality=Quality.UNKNOWN, reason="unknown")),
        (0x18, PointQuality(quality=Quality.BAD, reason="comm_failure")),
        (0x20, PointQuality(quality=Quality.BAD, reason="waiting_for_initial_data")),
        (0x4C, PointQuality(quality=Quality.UNCERTAIN, reason="quality_76")),
        (0x80, PointQuality(quality=Quality.BAD, reason="quality_128")),
    ],
)
def test_opc_qualities(code: int, quality: PointQuality | None) -> None:
    assert quality_of(code) == quality


def test_items_are_kept_compact_and_read_back() -> None:
    items = [
        AddressItem(name="A.B", item_id=4, properties={1: "4", 5001: "3060", 42: "x"}),
        AddressItem(name="A.Status", item_id=5, properties={5001: "3005"}),
    ]
    kept = compact(items)
    assert kept == [
        ["A.B", 4, {"1": "4", "5001": "3060"}],
        ["A.Status", 5, {"5001": "3005"}],
    ]
    assert from_compact(kept) == [
        AddressItem(name="A.B", item_id=4, properties={1: "4", 5001: "3060"}),
        AddressItem(name="A.Status", item_id=5, properties={5001: "3005"}),
    ]
    assert from_compact({"A": 1}) is None
    assert from_compact([["A", "not an id", {}]]) is None


def test_an_address_space_item_of_the_gateway() -> None:
    raw = {
        "ItemProps": [
            {"Datatype": 18, "ID": 1, "Value": "19", "Error": 0, "Desc": "Тип"},
            {"Datatype": 19, "ID": 5, "Value": 3, "Error": 0, "Desc": "Права"},
            {"Datatype": 8, "ID": 7001, "Value": None, "Error": 0, "Desc": ""},
            {"Datatype": 8, "ID": 6000, "Value": "x", "Error": 5, "Desc": "failed"},
            {"ID": True, "Value": "1"},
            "not a property",
        ],
        "ItemID": 7,
        "ItemName": "DBMonitoring.KIR_BatteryFail",
    }
    assert address_item(raw) == AddressItem(
        name="DBMonitoring.KIR_BatteryFail",
        item_id=7,
        properties={1: "19", 5: "3", 7001: ""},
    )
    assert address_item(raw, keep={5}) == AddressItem(
        name="DBMonitoring.KIR_BatteryFail", item_id=7, properties={5: "3"}
    )
    assert address_item({**raw, "ItemName": " "}) is None
    assert address_item({**raw, "ItemID": True}) is None
    assert address_item("item") is None
    assert address_item({**raw, "ItemProps": None}) == AddressItem(
        name="DBMonitoring.KIR_BatteryFail", item_id=7, properties={}
    )


@pytest.mark.parametrize(
    ("value", "exchange"),
    [
        (10, DataExchange.EXCHANGING),
        (3, DataExchange.EXCHANGING),
        (2, DataExchange.NO_DATA_EXCHANGE),
        (0, DataExchange.NO_DATA_EXCHANGE),
        (None, None),
        ("10", None),
        (True, None),
    ],
)
def test_a_status_tells_whether_its_device_exchanges_data(
    value: object, exchange: DataExchange | None
) -> None:
    """The seed's .Status: above its minimum (6003, else 0) the device exchanges data."""
    points = build_address_space(
        [item("C.Status", p5001=3005, p6003=2, p6004=10), item("C.A", p5001=3060)]
    ).catalogue.points
    assert points["c.status"].data_exchange
    assert not points["c.a"].data_exchange
    assert points["c.status"].exchange(value) is exchange
