"""The core's write checks by data type, scale and offset, and the source registry."""

from datetime import UTC, date, datetime, time, timedelta, timezone
from typing import Any

import pytest

from custom_components.tecoapi.pyplc import (
    Access,
    AccessDeniedError,
    DataType,
    DateTooEarlyError,
    DurationOutOfRangeError,
    InvalidHostError,
    InvalidValueError,
    NotAPlcError,
    NotAsciiError,
    NotEncodableError,
    OutOfRangeError,
    PlcConnectionError,
    PlcTlsError,
    Point,
    PointAttributes,
    ReadOnlyError,
    ServiceUnavailableError,
    ValueKind,
)
from custom_components.tecoapi.pyplc.core import registry
from custom_components.tecoapi.pyplc.core.codec import (
    check_value,
    check_write,
    to_raw,
    to_shown,
)
from custom_components.tecoapi.pyplc.core.descriptor import Capability
from custom_components.tecoapi.pyplc.tecomat.descriptor import PLCCOMS, TECOAPI
from custom_components.tecoapi.pyplc.tekon.descriptor import TEKON
from tests.fake_source import MEMORY


def point(
    data_type: DataType,
    *,
    access: Access = Access.READ_WRITE,
    low: float | None = None,
    high: float | None = None,
    scale: float = 1.0,
    offset: float = 0.0,
) -> Point:
    return Point(
        key="p",
        path="P",
        address="DT1",
        type=data_type,
        attributes=PointAttributes(access=access, minimum=low, maximum=high),
        scale=scale,
        offset=offset,
    )


INT16 = DataType(kind=ValueKind.INTEGER, bits=16)
UINT8 = DataType(kind=ValueKind.INTEGER, bits=8, signed=False)
INT64 = DataType(kind=ValueKind.INTEGER, bits=64)


@pytest.mark.parametrize(
    ("data_type", "good", "bad"),
    [
        (INT16, [-32768, 32767, 5.0], [-32769, 32768, 1.5, True, "1"]),
        (UINT8, [0, 255], [-1, 256]),
        (INT64, [-(2**63), 2**63 - 1], [2**63]),
        (DataType(kind=ValueKind.INTEGER), [10**30], ["x"]),
        (DataType(kind=ValueKind.REAL, bits=32), [1.5, 2], [float("nan"), "1.5"]),
        (DataType(kind=ValueKind.BOOL), [True, False], [1, "on"]),
    ],
)
def test_numbers_and_flags_by_their_type(
    data_type: DataType, good: list[Any], bad: list[Any]
) -> None:
    for value in good:
        assert check_value(data_type, "P", value) == value
    for value in bad:
        with pytest.raises(InvalidValueError):
            check_value(data_type, "P", value)


def test_an_integral_float_is_written_as_an_integer() -> None:
    assert type(check_value(INT16, "P", 7.0)) is int


def test_text_by_its_encoding_and_length() -> None:
    ascii_text = DataType(kind=ValueKind.STRING, encoding="ascii", length=5)
    cp1250 = DataType(kind=ValueKind.STRING, encoding="cp1250")
    any_text = DataType(kind=ValueKind.STRING)
    assert check_value(ascii_text, "P", "Hello") == "Hello"
    with pytest.raises(NotAsciiError):
        check_value(ascii_text, "P", "Žluť")
    with pytest.raises(InvalidValueError, match="longer than 5"):
        check_value(ascii_text, "P", "Hello!")
    assert check_value(cp1250, "P", "Žluťoučký kůň") == "Žluťoučký kůň"
    with pytest.raises(NotEncodableError) as raised:
        check_value(cp1250, "P", "Лифт")
    assert raised.value.encoding == "cp1250"
    assert not isinstance(raised.value, NotAsciiError)
    assert check_value(any_text, "P", "Лифт") == "Лифт"


def test_dates_and_times_become_their_python_values() -> None:
    assert check_value(DataType(kind=ValueKind.DATE), "P", "2026-03-14") == date(
        2026, 3, 14
    )
    assert check_value(
        DataType(kind=ValueKind.DATETIME), "P", "2026-03-14T10:00:00.000Z"
    ) == datetime(2026, 3, 14, 10, tzinfo=UTC)
    assert check_value(DataType(kind=ValueKind.TIME), "P", time(6, 30)) == timedelta(
        hours=6, minutes=30
    )
    assert check_value(DataType(kind=ValueKind.DURATION), "P", "01:00:00.000") == (
        timedelta(hours=1)
    )
    with pytest.raises(InvalidValueError):
        check_value(DataType(kind=ValueKind.DURATION), "P", time(6, 30))
    with pytest.raises(InvalidValueError):
        check_value(DataType(kind=ValueKind.DATE), "P", "14.3.2026")
    with pytest.raises(InvalidValueError):
        check_value(DataType(kind=ValueKind.TIME), "P", timedelta(seconds=-1))


EPOCH = datetime(1970, 1, 1, tzinfo=UTC)
LONGEST = timedelta(milliseconds=2**31 - 1)
DATE_1970 = DataType(kind=ValueKind.DATE, earliest=EPOCH)
DT_1970 = DataType(kind=ValueKind.DATETIME, earliest=EPOCH)
TIME_31 = DataType(kind=ValueKind.TIME, longest=LONGEST)


@pytest.mark.parametrize(
    ("data_type", "first", "before"),
    [
        (DATE_1970, "1970-01-01", "1969-12-31"),
        (DATE_1970, date(1970, 1, 1), date(1969, 12, 31)),
        (DT_1970, "1970-01-01T00:00:00.000Z", "1969-12-31T23:59:59.999Z"),
        (DT_1970, EPOCH, EPOCH - timedelta(milliseconds=1)),
        # The same moments in another zone, and naive (UTC).
        (
            DT_1970,
            datetime(1970, 1, 1, 1, tzinfo=timezone(timedelta(hours=1))),
            datetime(
                1970, 1, 1, 0, 59, 59, 999000, tzinfo=timezone(timedelta(hours=1))
            ),
        ),
        (
            DT_1970,
            datetime(1970, 1, 1),  # noqa: DTZ001 - naive on purpose: UTC
            datetime(1969, 12, 31, 23, 59, 59, 999999),  # noqa: DTZ001
        ),
    ],
)
def test_a_date_before_the_type_s_earliest_is_refused(
    data_type: DataType, first: Any, before: Any
) -> None:
    """The first day or millisecond is taken; the one before is not, named so."""
    check_value(data_type, "P", first)
    with pytest.raises(DateTooEarlyError) as raised:
        check_value(data_type, "P", before)
    assert raised.value.earliest == (
        "1970-01-01" if data_type is DATE_1970 else "1970-01-01T00:00:00.000Z"
    )
    assert raised.value.path == "P"
    assert raised.value.value == before


@pytest.mark.parametrize(
    ("good", "bad"),
    [
        ("596:31:23.647", "596:31:23.648"),
        (LONGEST, LONGEST + timedelta(milliseconds=1)),
        (timedelta(0), timedelta(milliseconds=-1)),
        ("00:00:00.000", timedelta(days=-1)),
        ("-00:00:00.000", "-00:00:00.001"),
        # Below the millisecond is not written: it rounds to what is.
        (LONGEST + timedelta(microseconds=499), LONGEST + timedelta(microseconds=500)),
    ],
)
def test_a_duration_outside_the_type_s_range_is_refused(good: Any, bad: Any) -> None:
    """0 to the longest, both ends taken, a millisecond beyond refused, named so."""
    check_value(TIME_31, "P", good)
    with pytest.raises(DurationOutOfRangeError) as raised:
        check_value(TIME_31, "P", bad)
    assert raised.value.longest == "596:31:23.647"
    assert "00:00:00.000 to 596:31:23.647" in str(raised.value)


def test_a_naive_earliest_is_utc() -> None:
    """A type's earliest given without a zone is UTC, as a naive value written is."""
    naive = DataType(kind=ValueKind.DATETIME, earliest=datetime(1970, 1, 1))  # noqa: DTZ001
    check_value(naive, "P", EPOCH)
    with pytest.raises(DateTooEarlyError):
        check_value(naive, "P", EPOCH - timedelta(milliseconds=1))


def test_without_bounds_dates_and_durations_are_as_before() -> None:
    """A type that names no bound: any date, any duration but a negative one."""
    assert check_value(DataType(kind=ValueKind.DATE), "P", "1900-01-01") == date(
        1900, 1, 1
    )
    assert check_value(DataType(kind=ValueKind.DURATION), "P", timedelta(days=900))
    for negative in (timedelta(seconds=-1), "-00:00:01.000"):
        with pytest.raises(InvalidValueError) as raised:
            check_value(DataType(kind=ValueKind.DURATION), "P", negative)
        assert not isinstance(raised.value, DurationOutOfRangeError)


def test_a_write_is_refused_read_only_and_out_of_range() -> None:
    with pytest.raises(ReadOnlyError):
        check_write(point(INT16, access=Access.READ), 1)
    with pytest.raises(OutOfRangeError) as raised:
        check_write(point(INT16, low=0, high=100), 101)
    assert (raised.value.min_value, raised.value.max_value) == (0, 100)
    assert check_write(point(INT16, low=0, high=100), 100) == 100


def test_a_refusal_names_what_the_caller_says() -> None:
    with pytest.raises(ReadOnlyError) as raised:
        check_write(point(INT16, access=Access.READ), 1, name="P.value")
    assert raised.value.path == "P.value"


def test_scale_and_offset_both_ways() -> None:
    tenths = point(INT16, scale=0.1, low=-50, high=150)
    assert tenths.kind is ValueKind.REAL
    assert to_shown(tenths, 215) == pytest.approx(21.5)
    # The shown value is checked against the shown range, the raw one against
    # the register.
    assert to_raw(tenths, check_write(tenths, 22.0)) == 220
    with pytest.raises(OutOfRangeError):
        check_write(tenths, 150.5)
    unranged = point(INT16, scale=0.1)
    with pytest.raises(InvalidValueError, match=r"-32768\.\.32767"):
        to_raw(unranged, check_write(unranged, 4000.0))
    # What is shown leaves out a float's rounding error (498 * 0.1 is
    # 49.800000000000004).
    assert to_shown(tenths, 498) == 49.8
    assert to_shown(tenths, 214) == 21.4
    assert to_shown(point(INT16, scale=0.01), -1) == -0.01
    kelvin = point(INT16, offset=-273.0)
    assert kelvin.kind is ValueKind.INTEGER
    assert to_shown(kelvin, 293) == 20
    assert to_raw(kelvin, 20) == 293
    plain = point(INT16)
    assert to_shown(plain, 7) == 7
    assert to_raw(plain, 7) == 7


def test_the_registry_offers_built_in_and_registered_sources() -> None:
    names = [item.name for item in registry.sources()]
    assert names[:2] == ["tecoapi", "plccoms"]
    assert {"fpi4c", "tekon"} <= set(names)
    assert registry.source("tecoapi") is TECOAPI
    assert registry.find("memory") is None
    with pytest.raises(KeyError):
        registry.source("memory")
    unregister = registry.register(MEMORY)
    try:
        assert registry.find("memory") is MEMORY
        with pytest.raises(ValueError, match="exists"):
            registry.register(MEMORY)
        with pytest.raises(ValueError, match="exists"):
            registry.register(TECOAPI)
    finally:
        unregister()
    assert registry.find("memory") is None
    unregister()  # a second time does nothing


def test_a_descriptor_declares_its_keys_secrets_errors_and_status() -> None:
    assert TECOAPI.connection_keys == {
        "transport",
        "host",
        "username",
        "password",
        "verify_ssl",
    }
    # A map's upload is no connection key: a reconfigured entry keeps its map.
    assert MEMORY.connection_keys == {"transport", "host"}
    assert TECOAPI.secrets == {"password"}
    assert PLCCOMS.secrets == frozenset()
    assert TECOAPI.status_entities == {
        Capability.MODE,
        Capability.PROGRAM,
        Capability.CLOCK,
    }
    assert MEMORY.status_entities == frozenset()
    # The first rule that fits wins: TLS before any connection failure.
    tls = TECOAPI.error_for(PlcTlsError("untrusted"))
    assert tls is not None
    assert tls.key == "tls_not_trusted"
    rule = TECOAPI.error_for(PlcConnectionError("refused"))
    assert rule is not None
    assert rule.key == "cannot_connect"
    host = PLCCOMS.error_for(InvalidHostError("x"))
    assert host is not None
    assert (host.field, host.key) == ("host", "invalid_plccoms_host")


def test_plccoms_takes_a_bare_host_and_a_port() -> None:
    assert PLCCOMS.prepare({"host": " plc.local ", "port": 5011.0}) == {
        "host": "plc.local",
        "port": 5011,
    }
    with pytest.raises(InvalidHostError):
        PLCCOMS.prepare({"host": "http://plc.local", "port": 5010})


def test_a_record_is_read_never_written() -> None:
    record = point(DataType(kind=ValueKind.RECORD))
    with pytest.raises(InvalidValueError, match="record"):
        check_write(record, "up")


def test_the_tekon_gateway_s_descriptor() -> None:
    """A URL, polled every second; each refusal its own form error."""
    assert TEKON.prepare({"host": "10.0.0.5:8081", "verify_ssl": True}) == {
        "host": "http://10.0.0.5:8081",
        "verify_ssl": True,
    }
    with pytest.raises(InvalidHostError):
        TEKON.prepare({"host": "http://gateway/GetUpdates", "verify_ssl": True})
    assert TEKON.scan_interval == timedelta(seconds=1)
    assert TECOAPI.scan_interval is None
    keys = {
        error: rule.key
        for error in (
            AccessDeniedError("403"),
            ServiceUnavailableError("503"),
            PlcConnectionError("refused"),
            NotAPlcError("web page"),
        )
        if (rule := TEKON.error_for(error)) is not None
    }
    assert list(keys.values()) == [
        "tekon_forbidden",
        "tekon_opc_unavailable",
        "tekon_cannot_connect",
        "not_tekon",
    ]
