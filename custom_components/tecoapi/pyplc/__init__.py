"""pyplc: ways into PLCs and their gateways, with nothing of Home Assistant in it.

``core`` is what a caller such as Home Assistant depends on: the ``PlcSource``
protocol and its ``Snapshot`` (``core.source``), the neutral models
(``core.models``), the exceptions (``core.exceptions``) and typed devices
(``core.devices``); this module re-exports them. Each system is a subpackage of
its own: ``tecomat`` (TecoApi and PLCComS), ``mervis`` (the Mervis web panel),
``panasonic`` (the FP-I4C gateway), ``tekon`` (Tekon's OPC-HTTP gateway).
See README.md next to this file.
"""

from .core.exceptions import (
    AccessDeniedError,
    DateTooEarlyError,
    DurationOutOfRangeError,
    InvalidHostError,
    InvalidPathError,
    InvalidValueError,
    InvalidWriteError,
    MalformedResponseError,
    MissingPointError,
    NoPublicVariablesError,
    NotAPlcError,
    NotAsciiError,
    NotEncodableError,
    OutOfRangeError,
    PlcAuthenticationError,
    PlcConnectionError,
    PlcError,
    PlcResponseError,
    PlcTlsError,
    PlcUnreachableError,
    ReadOnlyError,
    ResponseTooLargeError,
    ServiceUnavailableError,
    TooManyItemsError,
    ValueRejectedError,
    VariableListTooLargeError,
    VariableListUnreadableError,
    VariableNotFoundError,
    WritesDisabledError,
)
from .core.host import normalize_host
from .core.models import (
    Access,
    Catalogue,
    DataType,
    DeviceNode,
    DiscoveryCost,
    PlcMode,
    Point,
    PointAttributes,
    PointQuality,
    Quality,
    Record,
    SourceInfo,
    ValueKind,
)
from .core.source import PlcSource, RecentError, Snapshot, SourceStatistics

__version__ = "0.1.0"
"""The library's own version (pyproject.toml beside this file says the same)."""

__all__ = [
    "Access",
    "AccessDeniedError",
    "Catalogue",
    "DataType",
    "DateTooEarlyError",
    "DeviceNode",
    "DiscoveryCost",
    "DurationOutOfRangeError",
    "InvalidHostError",
    "InvalidPathError",
    "InvalidValueError",
    "InvalidWriteError",
    "MalformedResponseError",
    "MissingPointError",
    "NoPublicVariablesError",
    "NotAPlcError",
    "NotAsciiError",
    "NotEncodableError",
    "OutOfRangeError",
    "PlcAuthenticationError",
    "PlcConnectionError",
    "PlcError",
    "PlcMode",
    "PlcResponseError",
    "PlcSource",
    "PlcTlsError",
    "PlcUnreachableError",
    "Point",
    "PointAttributes",
    "PointQuality",
    "Quality",
    "ReadOnlyError",
    "RecentError",
    "Record",
    "ResponseTooLargeError",
    "ServiceUnavailableError",
    "Snapshot",
    "SourceInfo",
    "SourceStatistics",
    "TooManyItemsError",
    "ValueKind",
    "ValueRejectedError",
    "VariableListTooLargeError",
    "VariableListUnreadableError",
    "VariableNotFoundError",
    "WritesDisabledError",
    "normalize_host",
]
