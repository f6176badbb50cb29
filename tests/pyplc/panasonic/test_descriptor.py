"""The FP-I4C's descriptor: its form, what it stores, the source it makes, its errors."""

from typing import Any

import aiohttp
import pytest

from custom_components.tecoapi.pyplc import (
    InvalidHostError,
    MalformedResponseError,
    NotAPlcError,
    PlcConnectionError,
    PlcResponseError,
)
from custom_components.tecoapi.pyplc.core import registry
from custom_components.tecoapi.pyplc.core.descriptor import (
    CONF_HOST,
    CONF_POINT_MAP,
    Capability,
    FieldKind,
    SourceContext,
    SourceOptions,
)
from custom_components.tecoapi.pyplc.panasonic import FpI4cSource
from custom_components.tecoapi.pyplc.panasonic.client import (
    GatewayError,
    PlcNotAnsweringError,
    StationNotAnsweringError,
)
from custom_components.tecoapi.pyplc.panasonic.descriptor import (
    CONF_INTERFACE,
    CONF_STATION,
    FPI4C,
    InvalidInterfaceError,
    InvalidStationError,
    base_url,
)
from tests.pyplc.panasonic.conftest import example_map


def test_it_is_a_built_in_source_after_tecomat_s_and_mervis() -> None:
    assert [item.name for item in registry.sources()][:4] == [
        "tecoapi",
        "plccoms",
        "mervis",
        "fpi4c",
    ]
    assert registry.source("fpi4c") is FPI4C
    assert FPI4C.capabilities == {Capability.POINT_MAP}
    assert FPI4C.status_entities == frozenset()
    assert FPI4C.secrets == frozenset()
    assert [
        (field.key, field.kind, field.required) for field in FPI4C.connect.fields
    ] == [
        (CONF_HOST, FieldKind.URL, True),
        (CONF_INTERFACE, FieldKind.TEXT, False),
        (CONF_STATION, FieldKind.TEXT, False),
        (CONF_POINT_MAP, FieldKind.POINT_MAP, True),
    ]
    assert [field.key for field in FPI4C.reconfigure.fields] == [
        CONF_HOST,
        CONF_INTERFACE,
        CONF_STATION,
    ]


@pytest.mark.parametrize(
    ("host", "url"),
    [
        ("192.168.1.155", "http://192.168.1.155:2000"),
        ("192.168.1.155:2001", "http://192.168.1.155:2001"),
        ("http://192.168.1.155:2000/", "http://192.168.1.155:2000"),
        (" gateway.local ", "http://gateway.local:2000"),
        ("http://gateway.local:80", "http://gateway.local"),
        ("fe80::1", "http://[fe80::1]:2000"),
        ("[fe80::1]:2001", "http://[fe80::1]:2001"),
        ("https://gw", "https://gw:2000"),
    ],
)
def test_an_address_without_a_port_gets_2000(host: str, url: str) -> None:
    assert base_url(host) == url


@pytest.mark.parametrize(
    "host", ["", "http://gw/plcpost", "ftp://gw", "gw:99999", "http://[fe80::1"]
)
def test_what_is_no_address_is_refused(host: str) -> None:
    with pytest.raises(InvalidHostError):
        base_url(host)


@pytest.mark.parametrize(
    ("form", "stored"),
    [
        ({CONF_HOST: "gw"}, {CONF_HOST: "http://gw:2000"}),
        (
            {CONF_HOST: "gw", CONF_INTERFACE: "", CONF_STATION: " "},
            {CONF_HOST: "http://gw:2000"},
        ),
        (
            {CONF_HOST: "gw", CONF_INTERFACE: "4", CONF_STATION: "07"},
            {CONF_HOST: "http://gw:2000", CONF_INTERFACE: "4", CONF_STATION: "7"},
        ),
        (
            {CONF_HOST: "gw", CONF_INTERFACE: 0, CONF_STATION: 99},
            {CONF_HOST: "http://gw:2000", CONF_INTERFACE: "0", CONF_STATION: "99"},
        ),
    ],
)
def test_the_stored_connection(form: dict[str, Any], stored: dict[str, Any]) -> None:
    assert FPI4C.prepare(form) == stored


@pytest.mark.parametrize(
    ("form", "error", "field"),
    [
        ({CONF_INTERFACE: "5"}, InvalidInterfaceError, CONF_INTERFACE),
        ({CONF_INTERFACE: "COM1"}, InvalidInterfaceError, CONF_INTERFACE),
        ({CONF_STATION: "100"}, InvalidStationError, CONF_STATION),
        ({CONF_STATION: "-1"}, InvalidStationError, CONF_STATION),
        ({CONF_HOST: "gw/x"}, InvalidHostError, CONF_HOST),
    ],
)
def test_a_bad_form_is_refused_on_its_field(
    form: dict[str, Any], error: type[Exception], field: str
) -> None:
    with pytest.raises(error) as raised:
        FPI4C.prepare({CONF_HOST: "gw", **form})
    assert isinstance(
        raised.value, InvalidHostError | InvalidInterfaceError | InvalidStationError
    )
    rule = FPI4C.error_for(raised.value)
    assert rule is not None
    assert rule.field == field


@pytest.mark.parametrize(
    ("error", "key", "shown"),
    [
        (PlcConnectionError("x"), "fpi4c_cannot_connect", {}),
        (NotAPlcError("x"), "not_fpi4c", {}),
        (MalformedResponseError("x"), "not_fpi4c", {}),
        (
            StationNotAnsweringError("No response", code="28", station=2),
            "station_not_answering",
            {"station": "2", "code": "28", "message": "No response"},
        ),
        (
            PlcNotAnsweringError("No response", code="28"),
            "plc_not_answering",
            {"code": "28", "message": "No response"},
        ),
        (
            GatewayError("Interface 1 is not enabled"),
            "gateway_refused",
            {"message": "Interface 1 is not enabled"},
        ),
        (PlcResponseError("x"), "unknown", {}),
    ],
)
def test_each_failure_has_its_form_error_with_what_it_shows(
    error: PlcResponseError | PlcConnectionError, key: str, shown: dict[str, str]
) -> None:
    rule = FPI4C.error_for(error)
    assert rule is not None
    assert rule.key == key
    assert rule.shown(error) == shown


async def test_the_source_keeps_the_entry_s_identity() -> None:
    async with aiohttp.ClientSession() as http:
        context = SourceContext(http=lambda verify: http, timeout=3)
        data = {CONF_HOST: "http://gw:2000", CONF_INTERFACE: "4", CONF_STATION: "1"}
        added = FPI4C.create(context, data, SourceOptions(point_map=example_map()))
        assert isinstance(added, FpI4cSource)
        assert added.identity == "gw:2000/I4/A1"
        assert (added.client.interface, added.station) == (4, 1)
        moved = FPI4C.create(
            context,
            {CONF_HOST: "http://other:2001"},
            SourceOptions(point_map=example_map(), identity="gw:2000/I4/A1"),
        )
        assert isinstance(moved, FpI4cSource)
        assert moved.identity == "gw:2000/I4/A1"
        assert moved.client.base_url == "http://other:2001"
        bare = FPI4C.create(context, {CONF_HOST: "http://gw:2000"}, SourceOptions())
        assert isinstance(bare, FpI4cSource)
        assert bare.point_map.points == ()
