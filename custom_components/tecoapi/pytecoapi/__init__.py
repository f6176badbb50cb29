"""pytecoapi: ways into Tecomat PLCs, with nothing of Home Assistant in it.

The transport-neutral part -- what a caller such as Home Assistant depends on --
is ``source`` (the ``PlcSource`` protocol and its ``Snapshot``), ``models`` and
``exceptions``. TecoApi is its first implementation: ``TecoApiSession`` (the
schedule: what to read on which poll) over ``TecoApiClient`` (HTTP, Digest, the
services, discovery and the read planner). PLCComS is the second, over
``PlcComsClient``: ``PlcComsSource`` (PLCComS alone) and
``PushedTecoApiSession`` (TecoApi, its values pushed by PLCComS). See README.md
next to this file.
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
from .plccoms import PlcComsClient
from .plccoms_source import PlcComsSource
from .pushed_session import PushedTecoApiSession
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
    "PlcComsClient",
    "PlcComsSource",
    "PlcConnectionError",
    "PlcError",
    "PlcInfo",
    "PlcMode",
    "PlcResponseError",
    "PlcSource",
    "PlcTlsError",
    "Point",
    "PointMeta",
    "PushedTecoApiSession",
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
