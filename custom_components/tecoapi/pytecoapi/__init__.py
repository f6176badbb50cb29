"""pytecoapi: ways into Tecomat PLCs, with nothing of Home Assistant in it.

The transport-neutral part -- what a caller such as Home Assistant depends on --
is ``source`` (the ``PlcSource`` protocol and its ``Snapshot``), ``models`` and
``exceptions``. TecoApi is its first implementation: ``TecoApiSession`` (the
schedule: what to read on which poll) over ``TecoApiClient`` (HTTP, Digest, the
services, discovery and the read planner). See README.md next to this file.
"""

from .client import TecoApiClient
from .exceptions import (
    InvalidHostError,
    InvalidPathError,
    InvalidValueError,
    InvalidWriteError,
    MalformedResponseError,
    NoPublicVariablesError,
    NotAPlcError,
    NotAsciiError,
    OutOfRangeError,
    PlcAuthenticationError,
    PlcConnectionError,
    PlcError,
    PlcResponseError,
    PlcTlsError,
    ReadOnlyError,
    ResponseTooLargeError,
    TooManyItemsError,
    ValueRejectedError,
    VariableNotFoundError,
)
from .host import normalize_host
from .models import (
    Catalogue,
    DiscoveryStats,
    PlcInfo,
    PlcMode,
    Point,
    PointMeta,
    ValueKind,
)
from .planner import plan_reads
from .plans import PlannedRequest, ReadPlan
from .session import TecoApiSession
from .source import PlcSource, RecentError, Snapshot, SourceStatistics

__all__ = [
    "Catalogue",
    "DiscoveryStats",
    "InvalidHostError",
    "InvalidPathError",
    "InvalidValueError",
    "InvalidWriteError",
    "MalformedResponseError",
    "NoPublicVariablesError",
    "NotAPlcError",
    "NotAsciiError",
    "OutOfRangeError",
    "PlannedRequest",
    "PlcAuthenticationError",
    "PlcConnectionError",
    "PlcError",
    "PlcInfo",
    "PlcMode",
    "PlcResponseError",
    "PlcSource",
    "PlcTlsError",
    "Point",
    "PointMeta",
    "ReadOnlyError",
    "ReadPlan",
    "RecentError",
    "ResponseTooLargeError",
    "Snapshot",
    "SourceStatistics",
    "TecoApiClient",
    "TecoApiSession",
    "TooManyItemsError",
    "ValueKind",
    "ValueRejectedError",
    "VariableNotFoundError",
    "normalize_host",
    "plan_reads",
]
