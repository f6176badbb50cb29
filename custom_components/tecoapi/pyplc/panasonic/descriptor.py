"""The FP-I4C as a caller offers it: the gateway's address, a register map, its errors.

The form asks the gateway's address with its REST API's port (the port is set
on the gateway's *REST API / HTTP server* page; no default is documented and
every example uses 2000, which an address without a port gets), optionally
the interface (0 COM1, 1 COM2, 2 USB, 3 the gateway's own memory, 4 COM4 /
Ethernet) and the station (0 … 99) the gateway reaches the PLC by (without
them, those set on its pages), and the map of points (CSV, see
``docs/point-map-csv.md``). The connection is checked by reading DT0 of each
station the map uses.
"""

from collections.abc import Mapping
from typing import Any, Final

from ..core.descriptor import (
    CONF_HOST,
    CONF_POINT_MAP,
    Capability,
    ErrorRule,
    Field,
    FieldKind,
    Form,
    SourceContext,
    SourceDescriptor,
    SourceOptions,
    Words,
)
from ..core.exceptions import (
    InvalidHostError,
    MalformedResponseError,
    NotAPlcError,
    PlcConnectionError,
    PlcError,
    PlcResponseError,
    ResponseTooLargeError,
)
from ..core.host import normalize_host, resolved_identity
from ..core.pointmap import CSV, PointMap
from ..core.source import PlcSource
from ..core.structs import STRUCTS
from .client import (
    FpI4cClient,
    GatewayError,
    PlcNotAnsweringError,
    StationNotAnsweringError,
)
from .mapping import FPI4C_TYPES, MAX_STATION, check_point
from .source import MANUFACTURER, FpI4cSource

NAME: Final = "fpi4c"
CONF_INTERFACE: Final = "interface"
CONF_STATION: Final = "station"
DEFAULT_PORT: Final = 2000
"""The REST API's port an address without one gets (every example of the manual's)."""
MAX_INTERFACE: Final = 4


class InvalidInterfaceError(PlcError, ValueError):
    """The form's interface is none of the gateway's (0 … 4)."""


class InvalidStationError(PlcError, ValueError):
    """The form's station is no station number (0 … 99)."""


def base_url(host: str) -> str:
    """Return the gateway's base URL: an address without a port gets :data:`DEFAULT_PORT`.

    An IPv6 address may come bare (``fe80::1``) or in brackets with a port.
    """
    return normalize_host(host, default_port=DEFAULT_PORT)


def _number(value: Any, highest: int, error: type[PlcError], what: str) -> int | None:
    """Return an optional number of a form (None: empty), 0 … ``highest``."""
    text = "" if value is None else str(value).strip()
    if not text:
        return None
    if not text.isdigit() or int(text) > highest:
        raise error(f"{text!r} is not {what} (0 to {highest})")
    return int(text)


def _interface_station(values: Mapping[str, Any]) -> tuple[int | None, int | None]:
    """Return a form's or an entry's interface and station (None: not given)."""
    interface = _number(
        values.get(CONF_INTERFACE), MAX_INTERFACE, InvalidInterfaceError, "an interface"
    )
    station = _number(
        values.get(CONF_STATION), MAX_STATION, InvalidStationError, "a station"
    )
    return interface, station


def _connection(form: Mapping[str, Any]) -> dict[str, Any]:
    """Return the stored connection: the base URL, the interface and station as text."""
    connection: dict[str, Any] = {CONF_HOST: base_url(str(form[CONF_HOST]))}
    interface, station = _interface_station(form)
    if interface is not None:
        connection[CONF_INTERFACE] = str(interface)
    if station is not None:
        connection[CONF_STATION] = str(station)
    return connection


def _create(
    context: SourceContext, data: Mapping[str, Any], options: SourceOptions
) -> PlcSource:
    """Return the gateway's source; its identity the entry's, else its address's."""
    interface, station = _interface_station(data)
    client = FpI4cClient(
        context.http(True),
        data[CONF_HOST],
        interface=interface,
        timeout=context.timeout,
    )
    return FpI4cSource(
        client,
        options.point_map or PointMap(()),
        identity=options.identity,
        interface=interface,
        station=station,
        metadata_interval=options.metadata_interval,
        clock=context.clock,
    )


_HOST: Final = Field(key=CONF_HOST, kind=FieldKind.URL)
_INTERFACE: Final = Field(key=CONF_INTERFACE, kind=FieldKind.TEXT, required=False)
_STATION: Final = Field(key=CONF_STATION, kind=FieldKind.TEXT, required=False)

FPI4C: Final = SourceDescriptor(
    name=NAME,
    title="Panasonic FP-I4C",
    manufacturer=MANUFACTURER,
    noun="gateway",
    connect=Form(
        step_id=NAME,
        fields=(
            _HOST,
            _INTERFACE,
            _STATION,
            Field(key=CONF_POINT_MAP, kind=FieldKind.POINT_MAP),
        ),
    ),
    reconfigure=Form(
        step_id=f"reconfigure_{NAME}", fields=(_HOST, _INTERFACE, _STATION)
    ),
    prepare=_connection,
    create=_create,
    capabilities=frozenset({Capability.POINT_MAP}),
    errors=(
        ErrorRule(error=InvalidHostError, key="invalid_fpi4c_host", field=CONF_HOST),
        ErrorRule(
            error=InvalidInterfaceError, key="invalid_interface", field=CONF_INTERFACE
        ),
        ErrorRule(error=InvalidStationError, key="invalid_station", field=CONF_STATION),
        ErrorRule(error=PlcConnectionError, key="fpi4c_cannot_connect"),
        ErrorRule(error=NotAPlcError, key="not_fpi4c"),
        ErrorRule(error=MalformedResponseError, key="not_fpi4c"),
        ErrorRule(error=ResponseTooLargeError, key="not_fpi4c"),
        ErrorRule(
            error=StationNotAnsweringError,
            key="station_not_answering",
            placeholders=("station", "code", "message"),
        ),
        ErrorRule(
            error=PlcNotAnsweringError,
            key="plc_not_answering",
            placeholders=("code", "message"),
        ),
        ErrorRule(error=GatewayError, key="gateway_refused", placeholders=("message",)),
        ErrorRule(error=PlcResponseError, key="unknown", logged=True),
    ),
    point_map_loaders=CSV,
    check_address=check_point,
    point_types=FPI4C_TYPES,
    canonical_identity=resolved_identity,
    words=Words.of(NAME, settings=True, points=True),
    # A map's names may follow Tecomat's conventions.
    recognisers=(STRUCTS,),
)

DESCRIPTORS: Final = (FPI4C,)
