"""The Tekon catalogue at its edges, with the limits written out.

Each test pins an edge an off-by-one would move (scripts/mutate found them unpinned).
"""

import math

from custom_components.tecoapi.pyplc.core.models import (
    Access,
    DataType,
    PointQuality,
    Quality,
    Record,
    ValueKind,
)
from custom_components.tecoapi.pyplc.tekon.catalogue import (
    build_address_space,
    parse_record,
    parse_value,
    quality_of,
)
from tests.pyplc.tekon.test_catalogue import item


def test_a_lift_state_of_64_kib_is_read_and_one_character_more_is_not() -> None:
    """64 * 1024 characters of XML: longer is a malformed value, not parsed at all."""
    wrapper = len("<L></L>")
    exact = "<L>" + "x" * (64 * 1024 - wrapper) + "</L>"
    assert len(exact) == 65_536
    record = parse_record(exact)
    assert record is not None
    assert record.text == "x" * 255
    assert parse_record("<L>" + "x" * (64 * 1024 - wrapper + 1) + "</L>") is None


def test_the_first_four_parts_name_a_state_without_one() -> None:
    record = parse_record(
        "<L>" + "".join(f"<P{i}>{i}</P{i}>" for i in range(6)) + "</L>"
    )
    assert record == Record(
        text="P0: 0; P1: 1; P2: 2; P3: 3",
        parts=tuple((f"P{i}", str(i)) for i in range(6)),
    )


# OLE's VARTYPE codes (property 1): what each number is read as; the codes around
# them (VT_DATE 7, VT_BSTR 8, VT_ERROR 10, VT_VARIANT 12, VT_UI2 18, …) are text.
VARTYPES = {
    2: (ValueKind.INTEGER, 16, True),  # VT_I2
    3: (ValueKind.INTEGER, 32, True),  # VT_I4
    4: (ValueKind.REAL, 32, True),  # VT_R4
    5: (ValueKind.REAL, 64, True),  # VT_R8
    6: (ValueKind.REAL, 64, True),  # VT_CY
    11: (ValueKind.BOOL, None, None),  # VT_BOOL
    16: (ValueKind.INTEGER, 8, True),  # VT_I1
    17: (ValueKind.INTEGER, 8, False),  # VT_UI1
    18: (ValueKind.INTEGER, 16, False),  # VT_UI2
    19: (ValueKind.INTEGER, 32, False),  # VT_UI4
    20: (ValueKind.INTEGER, 64, True),  # VT_I8
    21: (ValueKind.INTEGER, 64, False),  # VT_UI8
    22: (ValueKind.INTEGER, 32, True),  # VT_INT
    23: (ValueKind.INTEGER, 32, False),  # VT_UINT
}


def test_each_vartype_is_read_as_its_type() -> None:
    space = build_address_space([item(f"C.V{code}", p1=code) for code in range(26)])
    for code in range(26):
        data_type = space.catalogue.points[f"c.v{code}"].type
        kind, bits, signed = VARTYPES.get(code, (ValueKind.STRING, None, None))
        assert (data_type.kind, code) == (kind, code)
        if bits is not None:
            assert (data_type.bits, data_type.signed, code) == (bits, signed, code)


# OPC DA's quality status (the code without its two limit bits), by name.
QUALITIES = {
    0x00: "unknown",
    0x04: "config_error",
    0x08: "not_connected",
    0x0C: "device_failure",
    0x10: "sensor_failure",
    0x14: "last_known",
    0x18: "comm_failure",
    0x1C: "out_of_service",
    0x20: "waiting_for_initial_data",
    0x40: "uncertain",
    0x44: "last_usable",
    0x50: "sensor_cal",
    0x54: "egu_exceeded",
    0x58: "sub_normal",
}


def test_every_quality_is_named_by_its_status_and_good_is_none() -> None:
    for code in range(0x100):
        if code >= 0xC0:
            assert (quality_of(code), code) == (None, code)
            continue
        expected = PointQuality(
            quality=Quality.UNCERTAIN
            if code & 0xC0 == 0x40
            else Quality.UNKNOWN
            if code & 0xFC == 0
            else Quality.BAD,
            reason=QUALITIES.get(code & 0xFC, f"quality_{code}"),
        )
        assert (quality_of(code), code) == (expected, code)


# Tekon's channel types (property 5001), and what a channel of each is read as with
# a number's VARTYPE (19, VT_UI4) and a text's (8, VT_BSTR); the codes around them are
# no channel type: the VARTYPE says.
CHANNELS = {
    3000: (ValueKind.BOOL, ValueKind.BOOL),  # discrete
    3001: (ValueKind.BOOL, ValueKind.BOOL),  # intercom
    3002: (ValueKind.BOOL, ValueKind.BOOL),  # control
    3005: (ValueKind.INTEGER, ValueKind.INTEGER),  # status
    3060: (ValueKind.INTEGER, ValueKind.REAL),  # number
    3061: (ValueKind.STRING, ValueKind.STRING),  # string
    3070: (ValueKind.RECORD, ValueKind.RECORD),  # lift state
}


def test_each_channel_type_is_read_as_its_kind() -> None:
    codes = [code + step for code in CHANNELS for step in (-1, 0, 1)]
    space = build_address_space(
        [item(f"C.N{code}", p5001=code, p1=19) for code in codes]
        + [item(f"C.T{code}", p5001=code, p1=8) for code in codes]
    )
    points = space.catalogue.points
    for code in codes:
        number, text = CHANNELS.get(code, (ValueKind.INTEGER, ValueKind.STRING))
        found = (points[f"c.n{code}"].type.kind, points[f"c.t{code}"].type.kind)
        assert (found, code) == ((number, text), code)


def test_a_status_is_an_unsigned_32_bit_integer_whatever_its_vartype() -> None:
    """A device's status (and a status channel) is read as a UDINT, read only."""
    space = build_address_space(
        [
            item("A.Status", p1=2),
            item("A.Link", p5001=3005, p1=16),
            item("A.Plain", p1=2),
        ]
    )
    points = space.catalogue.points
    for key in ("a.status", "a.link"):
        assert (key, points[key].type) == (
            key,
            DataType(kind=ValueKind.INTEGER, bits=32, signed=False),
        )
        attributes = points[key].attributes
        assert attributes is not None
        assert attributes.access is Access.READ
    assert points["a.plain"].type == DataType(
        kind=ValueKind.INTEGER, bits=16, signed=True
    )


def test_an_item_named_only_status_is_no_device_s_status() -> None:
    """``.Status`` has no name before its suffix: a channel of the unnamed root, not the
    status of a device; ``X.Status`` is the shortest that is one."""
    space = build_address_space([item(".Status", p1=19), item("X.Status", p1=19)])
    assert space.status_of == {"x": "x.status"}
    assert space.catalogue.points[".status"].diagnostic is False
    assert space.catalogue.points["x.status"].diagnostic is True


def test_access_from_the_seed_s_table_is_read_write_or_both_and_nothing_else() -> None:
    """Property 3 without 5: 1 read, 2 write, 3 both; 0, 4 and a quality (192) read."""
    expected = {
        0: Access.READ,
        1: Access.READ,
        2: Access.WRITE,
        3: Access.READ_WRITE,
        4: Access.READ,
        192: Access.READ,
    }
    space = build_address_space(
        [item(f"C.A{code}", p1=19, p3=code) for code in expected]
    )
    for code, access in expected.items():
        attributes = space.catalogue.points[f"c.a{code}"].attributes
        assert attributes is not None
        assert (code, attributes.access) == (code, access)


def test_a_real_of_minus_zero_is_zero_without_its_sign() -> None:
    """``-0,0`` is 0.0, not -0.0 (a state of "-0.0" would show a sign on zero)."""
    point = build_address_space([item("C.R", p5001=3060, p1=4)]).catalogue.points["c.r"]
    for text in ("-0,0", "-0.0", "-0"):
        value, quality = parse_value(point, text)
        assert (text, value, math.copysign(1.0, value), quality) == (
            text,
            0.0,
            1.0,
            None,
        )
