"""pytecoapi: an async client for Tecomat PLCs speaking TecoApi.

It imports nothing from Home Assistant and is the only code that speaks TecoApi.

Client (``TecoApiClient(session, host, username, password, *, verify_ssl=True,
timeout=10.0)``; the aiohttp session is injected and never closed here):

- ``base_url`` -- the normalised host (``normalize_host``); ``request_count`` --
  HTTP requests sent on the wire, Digest challenges included; ``item_limit`` --
  the learned per-response item limit (128, then the CPU's from ``get_info``,
  lowered on 413); ``auth_scheme`` -- ``"digest"``/``"basic"`` once known;
  ``catalogue`` -- the last discovered catalogue.
- ``get_info() -> PlcInfo``, ``get_list() -> tuple[str, ...]``,
  ``get_object(names) -> dict`` (the raw JSON of one request).
- ``discover() -> Catalogue``: GetList, then the roots read in batches sized
  by what the answers so far told (``roots``); what it cost, against a lower
  bound, in ``Catalogue.discovery`` (``DiscoveryStats``).
- ``plan(points, *, with_attrs) -> ReadPlan`` and ``read(plan, points) ->
  PollResult``; ``plan_reads(points, *, item_limit, with_attrs, catalogue=None)``
  is the pure planner behind ``plan``.
- ``read_path(path)`` -- any variable, JSON-shaped; ``write(point, value)`` --
  validated; ``write_path(path, value, point=None)`` -- raw, validated with a point.

Authentication: Digest through aiohttp's ``DigestAuthMiddleware`` (pre-emptive,
one round trip per request after the first challenge, stale nonces answered
transparently); Basic only when the PLC offers nothing else.

Models: ``PlcInfo`` (``item_limit``), ``PlcMode`` (RUN/HALT/ERR; anything else
the PLC reports is ERR), ``Point``/``PointMeta``/``ValueKind``, ``Catalogue``,
``PlannedRequest``/``ReadPlan`` (with ``item_limit`` and ``unreadable``),
``PollResult`` (a value is None when it no longer fits its point's kind).

Answers are read capped and decoded as UTF-8, else string by string as
Windows-1250 (``body``). Values: bool, int, float (negative zero read as zero),
str, ``datetime.date``, UTC ``datetime.datetime``;
TIME/TOD stay ``"hh:mm:ss.zzz"`` strings. Writes take the same types (and
``datetime.time``/``timedelta`` for TIME, an integral float for an integer).

Errors: ``PlcError`` and below it ``PlcConnectionError``
(``PlcTlsError`` for an untrusted certificate), ``PlcAuthenticationError``,
``PlcResponseError`` (``code``/``status``/``message``;
``ValueRejectedError`` for 400.015 with ``path``/``value``;
``ResponseTooLargeError`` for an answer past ``body.MAX_BODY_BYTES``, with
``limit``/``received``),
``NotAPlcError``, ``InvalidHostError`` and ``InvalidWriteError``
(``path``/``value``) with ``ReadOnlyError``, ``OutOfRangeError``
(``min_value``/``max_value``) and ``InvalidValueError``.
"""

from .catalogue import build_catalogue, parse_root_list
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
    PlannedRequest,
    PlcInfo,
    PlcMode,
    Point,
    PointMeta,
    PollResult,
    ReadPlan,
    ValueKind,
    item_limit_for_type,
)
from .planner import plan_reads

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
    "PlcTlsError",
    "Point",
    "PointMeta",
    "PollResult",
    "ReadOnlyError",
    "ReadPlan",
    "ResponseTooLargeError",
    "TecoApiClient",
    "TooManyItemsError",
    "ValueKind",
    "ValueRejectedError",
    "VariableNotFoundError",
    "build_catalogue",
    "item_limit_for_type",
    "normalize_host",
    "parse_root_list",
    "plan_reads",
]
