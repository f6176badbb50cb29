"""An opcconnector gateway as a PLC source: a session, a subscription, one request a poll.

The schedule:

- the first poll (or :meth:`TekonSource.identify`) reads ``ServerInformation``,
  opens a session and reads the address space's hash; the address space itself
  is read only when the hash differs from the one kept beside the entry (the
  ``cache`` of :class:`~..core.descriptor.SourceContext`), and kept there again;
- every poll subscribes by name what is polled and not yet subscribed (and the
  ``.Status`` of the devices it sits on, and of those above them: a device's
  health decides its points'), takes back what is no longer polled, and reads
  the changes with one ``GetUpdatesText`` whose ``rid`` grows after every
  answer. While nothing changes a poll is that one request;
- a gateway sends an item's value only once it changes (the seed's
  ``GetUpdates``: "only data updated since the previous request"; OPC DA's
  initial update is not promised): after every subscription (the first, a new
  session's, a new address space's, points newly polled) one
  ``ReadAllItemsValues`` asks for the current values, which come with the
  ``GetUpdatesText`` right after it. It is asked again at the next poll where
  the gateway failed it, never where it does not know the call (404);
- a session the gateway no longer knows (409: it expired, or the OPC server went
  through configuration mode and every session was closed) is opened again
  within the same poll: a new session, the hash, the subscription again (one
  request per thousand names); a new hash means a new address space, read and
  followed like a PLC's new program (``program_changed``), its points kept where
  their names are;
- an OPC server that is unavailable (503) fails the poll: the points are
  unavailable, and the gateway is asked again after 1, 2, 4 ... up to
  ``max_backoff`` seconds (the polls between fail without a request), with a new
  session and a new subscription;
- a session left idle for ``keepalive`` seconds (the gateway closes one after
  120) is kept with a ``GetSubscribersCount``: polls far apart do not cost a
  new session each.

Values are read as the catalogue says (:mod:`.catalogue`); a value the gateway
writes with a decimal comma makes written reals use one too. The session, the
subscription and the updates are :mod:`.subscription`'s.
"""

import asyncio
from collections.abc import Collection, Mapping, Sequence
import contextlib
from datetime import UTC, datetime, timedelta
import hashlib
import logging
from typing import Any, Final, Unpack

from ..core.backoff import Backoff
from ..core.cache import VersionedCache
from ..core.codec import check_write
from ..core.descriptor import SourceCache
from ..core.exceptions import (
    NotAPlcError,
    PlcError,
    PlcResponseError,
    ServiceUnavailableError,
    VariableNotFoundError,
)
from ..core.models import (
    Catalogue,
    Point,
    Quality,
    Record,
    SourceInfo,
    ValueKind,
)
from ..core.scalars import format_real
from ..core.source import Snapshot, SourceSettings, Write, counted
from ..core.texts import Template
from .catalogue import (
    KEPT_PROPERTIES,
    AddressSpace,
    build_address_space,
    compact,
    from_compact,
    key_of,
    parse_value,
    quality_of,
)
from .client import (
    SERVER_INFORMATION,
    AddressItem,
    ServerInformation,
    SessionLostError,
    TekonClient,
)
from .subscription import SubscribedSource

UNUSABLE: Final = Template(
    "tekon_unusable", "the gateway's value is not usable (its OPC quality: {quality})"
)
_LOGGER = logging.getLogger(__name__)

MANUFACTURER: Final = "Tekon"
MODEL: Final = "ASUD.SCADA OPC-HTTP"
NAME: Final = "ASUD.SCADA OPC gateway"
KEEPALIVE: Final = 60.0
"""Seconds a session may stay idle before it is kept alive (the gateway: 120)."""
FIRST_BACKOFF: Final = 1.0
"""The wait after the OPC server was first found unavailable (then doubled)."""
MAX_BACKOFF: Final = 60.0
"""The longest wait between two attempts while the OPC server is unavailable."""
CACHE_VERSION: Final = 1
ZONE_STEP: Final = timedelta(minutes=15)
"""Time zones are whole quarters of an hour from UTC."""


def identity_of(items: Collection[AddressItem]) -> str:
    """Return the gateway's identity: what its address space's top-level names make.

    The gateway tells no serial number and its address may change; the
    top-level names (its OPC server's subsystems) are what two URLs of the same
    gateway share. The first identity an entry has is kept beside it.
    """
    roots = sorted({item.name.split(".", 1)[0] for item in items})
    digest = hashlib.sha256("\n".join(roots).encode()).hexdigest()
    return f"OPC-{digest[:12].upper()}"


def zone_offset(gateway_time: datetime | None, now: datetime) -> timedelta:
    """Return the gateway's local time minus UTC, to the quarter hour (its zone)."""
    if gateway_time is None:
        return timedelta(0)
    difference = gateway_time - now.astimezone(UTC).replace(tzinfo=None)
    return round(difference / ZONE_STEP) * ZONE_STEP


class TekonSource(SubscribedSource):
    """One opcconnector gateway, as a :class:`~..core.source.PlcSource`.

    ``cache`` keeps the address space (and the identity) between runs;
    ``keepalive`` and ``max_backoff`` are seconds (see the module's docstring).
    """

    def __init__(
        self,
        client: TekonClient,
        *,
        cache: SourceCache | None = None,
        keepalive: float = KEEPALIVE,
        max_backoff: float = MAX_BACKOFF,
        **settings: Unpack[SourceSettings],
    ) -> None:
        """Wrap a client; nothing is requested until the first call."""
        super().__init__(client, keepalive=keepalive, **settings)
        self._cache = VersionedCache(cache, CACHE_VERSION)
        self._identity: str | None = None
        self._hash: str | None = None
        self._backoff = Backoff(FIRST_BACKOFF, max_backoff)
        self._retry_at = datetime.min.replace(tzinfo=UTC)
        self.address_space_reads = 0
        """Address spaces read from the gateway (not from the cache)."""

    # --- what the PlcSource protocol asks --------------------------------------

    @property
    def configuration_url(self) -> str:
        """The gateway's one page a browser opens without a session.

        Its root serves nothing (the seed documents API calls only): its
        ``ServerInformation`` shows the connector's and the API's versions, its
        clock and when it started.
        """
        return f"{self.client.base_url}/{SERVER_INFORMATION}"

    async def identify(self) -> SourceInfo:
        """Who the gateway is: ``ServerInformation``, a session and its address space.

        Raises :class:`~..core.exceptions.NotAPlcError` for what is not an
        opcconnector, :class:`~..core.exceptions.AccessDeniedError` for a
        gateway that refuses this client (403) and
        :class:`~..core.exceptions.ServiceUnavailableError` when its OPC server
        is unavailable (503). A gateway without ``ServerInformation`` (it came
        with API 2.0) is one where it opens a session: its version and its
        clock are then not known.
        """
        server: ServerInformation | None = None
        try:
            server = await self.client.server_information()
        except NotAPlcError as err:
            try:
                await self._open_session()
            except PlcResponseError:
                raise err from None
        else:
            await self._open_session()
        self._zone = zone_offset(
            None if server is None else server.current_time, self._clock()
        )
        self._space = await self._load(await self.client.address_space_hash())
        self._check_hash = False
        assert self._identity is not None
        self._info = SourceInfo(
            identity=self._identity,
            name=NAME,
            manufacturer=MANUFACTURER,
            model=MODEL,
            firmware=None if server is None else server.connector_version or None,
            api_version=None if server is None else server.api_version,
        )
        return self._info

    async def read_points(self, keys: Collection[str]) -> Snapshot | None:
        """Nothing to read between polls: the subscription brings every change."""
        return None

    async def follow(self, polled: Collection[str]) -> None:
        """Subscribe the polled points now and push their values (not a poll later)."""
        catalogue = self._catalogue
        if catalogue is None or self.client.session_id is None:
            return
        try:
            values = await self._read_updates(catalogue, frozenset(polled))
        except PlcError as err:
            _LOGGER.debug("Subscribing the polled points failed: %s", err)
            return
        self._push(values)

    async def write_variable(self, path: str, value: Any) -> Snapshot | None:
        """Write an item by its name: a point's as :meth:`write`."""
        return await self.write(self._key(path), value)

    async def read_variable(self, path: str) -> Any:
        """Read any item's value now by its name (``ReadItemValueSyncText``).

        Any item of the address space, an entity's or not. A value of bad or
        unknown quality (or that cannot be read as its type) is an error that
        says why;
        a lift's state is ``{"text": …, "parts": {…}}``.
        """
        point = self._point(self._key(path))
        found = await self._read(self.client.read(point.address))
        if found is None:
            raise VariableNotFoundError(f"{path!r} has no value", path=path)
        value, malformed = parse_value(point, found.value)
        quality = quality_of(found.quality) or malformed
        if quality is not None and quality.quality in (Quality.BAD, Quality.UNKNOWN):
            raise PlcResponseError(
                f"the gateway's value of {path!r} is not usable: {quality.reason}",
                why=UNUSABLE(quality=quality.reason),
            )
        if isinstance(value, Record):
            return {"text": value.text, "parts": dict(value.parts)}
        return value

    def diagnostics(self) -> dict[str, Any]:
        """Describe the address space, the subscription and the requests.

        The subscription's session ID is the caller's to redact.
        """
        space = self._space
        catalogue = space.catalogue if space is not None else None
        devices = list(catalogue.devices.values()) if catalogue else []
        with_status = space.status_of if space is not None else {}
        return {
            "points": len(catalogue.points) if catalogue else 0,
            "roots": len(catalogue.groups) if catalogue else 0,
            "address_space": {
                "hash": self._hash,
                # A controller's status sits at the top, a device's under it;
                # what has no status of its own is a group of channels.
                "controllers": sum(
                    device.key in with_status and not device.parent
                    for device in devices
                ),
                "devices": sum(
                    device.key in with_status and bool(device.parent)
                    for device in devices
                ),
                "groups": sum(device.key not in with_status for device in devices),
                "read_from_gateway": self.address_space_reads,
            },
            "subscription": {
                "session_id": self.client.session_id,
                "sessions": self.sessions,
                "items": len(self._subscribed),
                "rid": self._rid,
                "reads_all_values": self._reads_all_values,
                "last_update": (
                    self._last_update.isoformat() if self._last_update else None
                ),
                "offline_devices": len(self._offline),
                "every_change": self.client.alldata,
                "collapsed_changes": self.collapsed_changes,
                "skipped_answers": self.skipped_answers,
            },
            "gateway_zone_offset_minutes": self._zone.total_seconds() / 60,
            "decimal_commas": self._commas,
            "text_calls_without_text": sorted(self.client.plain_text_calls),
            "requests": {
                "on_the_wire": self.client.request_count,
                "by_call": dict(sorted(self.client.calls.items())),
                "backoff_seconds": self._backoff.seconds,
                **counted(self._statistics, "address_space_changes"),
            },
        }

    async def close(self) -> None:
        """Stop keeping the session alive and close it."""
        if self._keeper is not None:
            self._keeper.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await self._keeper
            self._keeper = None
        await self.client.close_session()

    # --- polling ---------------------------------------------------------------

    async def _discover_catalogue(self, polled: frozenset[str]) -> Snapshot:
        """Return the catalogue of the address space identify read, and the polled values.

        After a discovery that failed, the address space known is kept unless
        its hash changed.
        """
        if self._space is None:
            await self.identify()
        elif self.client.session_id is None:
            await self._open_session()
            address_hash = await self.client.address_space_hash()
            if address_hash != self._hash:
                self._space = await self._load(address_hash)
            self._confirmed(self._space)
        assert self._space is not None
        assert self._info is not None
        catalogue = self._space.catalogue
        values = await self._read_updates(catalogue, polled)
        self._catalogue = catalogue
        return self._discovered(
            self._info, catalogue, values, {}, None, program_changed=False
        )

    async def _poll(self, catalogue: Catalogue, polled: frozenset[str]) -> Snapshot:
        """One ``GetUpdatesText``; a new session (and maybe a new catalogue) first if due."""
        now = self._clock()
        if now < self._retry_at:
            raise ServiceUnavailableError(
                "The gateway's OPC server was unavailable: asked again in "
                f"{(self._retry_at - now).total_seconds():.0f} s"
            )
        try:
            if self.client.session_id is None:
                await self._open_session()
            if self._check_hash and (changed := await self._follow_hash(polled)):
                return changed
            try:
                values = await self._read_updates(catalogue, polled)
            except SessionLostError:
                await self._open_session()
                if changed := await self._follow_hash(polled):
                    return changed
                values = await self._read_updates(self._require_catalogue(), polled)
        except ServiceUnavailableError:
            self._back_off(now)
            raise
        self._backoff.reset()
        return self._snapshot(self._require_catalogue(), values, {}, None)

    def _back_off(self, now: datetime) -> None:
        """Ask again later: twice as long as last time, up to ``max_backoff``."""
        self.client.forget_session()
        self._retry_at = now + timedelta(seconds=self._backoff.failed())

    def _require_catalogue(self) -> Catalogue:
        assert self._catalogue is not None
        return self._catalogue

    async def _follow_hash(self, polled: frozenset[str]) -> Snapshot | None:
        """Compare the address space's hash; read and follow a new address space."""
        address_hash = await self.client.address_space_hash()
        self._check_hash = False
        if address_hash == self._hash:
            self._confirmed(self._space)
            return None
        previous = self._require_catalogue()
        self._space = await self._load(address_hash)
        catalogue = self._catalogue = self._space.catalogue
        self._quality = {}
        self._missing = frozenset()
        self._offline = {}
        # Told like a PLC's new program (its caller logs it in the gateway's name).
        _LOGGER.debug(
            "The gateway's address space changed: %d points (%d before)",
            len(catalogue.points),
            len(previous.points),
        )
        values = await self._read_updates(catalogue, polled)
        assert self._info is not None
        return self._discovered(
            self._info, catalogue, values, {}, None, program_changed=True
        )

    async def _load(self, address_hash: str) -> AddressSpace:
        """Return the address space of a hash: the one kept, or one read and kept."""
        kept = await self._cache.load()
        items = None
        if kept is not None:
            self._identity = self._identity or kept.get("identity")
            if kept.get("hash") == address_hash:
                items = from_compact(kept.get("items"))
        del kept
        if items is None:
            items = await self.client.address_space(KEPT_PROPERTIES)
            self.address_space_reads += 1
            self._identity = self._identity or identity_of(items)
            await self._cache.save(
                identity=self._identity, hash=address_hash, items=compact(items)
            )
        self._identity = self._identity or identity_of(items)
        self._hash = address_hash
        space = build_address_space(items)
        self._confirmed(space)
        return space

    def _confirmed(self, space: AddressSpace | None) -> None:
        """Take an address space as the session's: its hash was checked, its IDs count."""
        self._check_hash = False
        self.client.item_id = None if space is None else space.item_id

    # --- writes: the base's template, one request for the batch --------------------

    def _encode(self, point: Point, value: Any) -> Write[str]:
        """Check a value by the core's codec; spell it as the gateway takes it."""
        checked = check_write(point, value)
        return Write(
            point=point, value=value, wire=self._spelled(point, checked), shown=checked
        )

    async def _send_writes(self, writes: Sequence[Write[str]]) -> None:
        """Write the batch by name in one ``WriteItemsValues(Text)`` (a list: the seed).

        A lost session is opened again and the write sent again. A gateway
        written without Text (API 2.1 or 2.0: by ``ItemID`` too) has the new
        session's hash compared first: it is written by the IDs of the address
        space known only when it still has that one (else by name alone; the
        next poll follows the new one).
        """
        items = [(write.point.address, write.wire) for write in writes]
        try:
            await self.client.write(items)
        except SessionLostError:
            await self._open_session()
            if (
                "WriteItemsValues" in self.client.plain_text_calls
                and await self.client.address_space_hash() == self._hash
            ):
                self._confirmed(self._space)
            await self.client.write(items)

    async def _read_back(
        self, batch: Sequence[Write[str]], carried: Mapping[str, Any]
    ) -> Snapshot | None:
        """Nothing to read: the value the gateway holds comes with the next updates.

        (None: the caller polls.)
        """
        return None

    def _key(self, path: str) -> str:
        """Return the key of an item name; not a point: :class:`VariableNotFoundError`."""
        key = key_of(path)
        catalogue = self._catalogue
        if catalogue is None or key not in catalogue.points:
            raise VariableNotFoundError(f"{path!r} is not an item", path=path)
        return key

    def _spelled(self, point: Point, value: Any) -> str:
        """Spell a checked value as the gateway takes it: ``1``, ``21,5``, text."""
        match point.type.kind:
            case ValueKind.BOOL:
                return "1" if value else "0"
            case ValueKind.REAL:
                text = format_real(float(value))
                return text.replace(".", ",") if self._commas else text
            case _:
                return str(value)
