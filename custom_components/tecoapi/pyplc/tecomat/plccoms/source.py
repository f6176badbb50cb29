"""PLCComS alone as a PLC source: for installations without TecoApi users.

PLCComS has **no authentication**: whoever reaches its port reads and writes the
PLC. Use this source only on a trusted network, and only when the user asked.

What it does with a :class:`~.client.PlcComsClient`:

- ``identify()`` connects, reads ``GETINFO:`` (its keys in any case: the
  manual prints them in upper case) and checks that ``LIST:`` names
  variables; a server that answers but cannot reach its PLC raises
  :class:`~...core.exceptions.PlcUnreachableError`. PLCComS tells no serial number, so the identity is the PLC's EPSNET
  address as the server reaches it: ``serial_number`` is
  ``"EPSNET <ipaddr>:<epsport>"`` from ``GETINFO:`` (the same PLC keeps it when
  PLCComS moves to another host or port; it changes only when the PLC's own
  address does, and then PLCComS must be reconfigured too). Without those keys,
  the server's own ``"PLCComS <host>:<port>"`` stands in. ``type`` is the CPU
  read from ``version_plc`` (``Fx2 CP2080I v1.1`` gives ``CP-2080``),
  ``firmware`` is ``version_plc``, ``program_name`` the public file's name
  (``PUBFILE``, also in the manual's ``2/2 [FIXED_Foxtrot.pub,Program.pub]``
  form, whose ``FIXED_`` file is the server's own), ``api_version`` the
  server's version number (``6.1`` of ``Ver 6.1 Jun  1 2023 13:15:36``),
  ``program_stamp`` the ``__PF_CRC`` variable as eight hex digits when ``LIST:``
  has it. The PLC's clock, MAC and ERR are unknown to PLCComS: ``time`` and
  ``mac`` are None, and a stopped program (``__PLC_RUN`` 0) is HALT.
  ``way_in`` is ``PLCComS``: the same PLC may have an entry through TecoApi
  too, and the entry's title and its devices' names say which is which (not
  the EPSNET address).
- The first ``poll()`` discovers: every ``LIST:`` variable is read with
  ``GET:``; the eight variables of each T_ApiObject (``P.value``,
  ``P.attr.*``) become one point ``P`` with its metadata, as TecoApi discovers
  it (:mod:`.catalogue`), every other variable of a known type a point
  without metadata. Later polls ``EN:`` the polled points' values (``DI:`` those
  no longer polled; ``follow(polled)`` does it at once, between polls) and read
  with ``GET:`` only the newly enabled ones; every
  other value arrives by ``DIFF:``, and the poll returns those pushed since the
  previous one. One ``GET:__PLC_RUN`` per poll proves that the connection still
  delivers (a stalled server fails the poll within the client's ``timeout``).
  Every ``metadata_interval`` a poll reads ``GETINFO:`` again and the polled
  T_ApiObjects' attributes with ``GET:``.
- ``__PLC_RUN`` changes the mode at once: a snapshot with the new mode is pushed.
  A program download (``__PLC_RUN`` 0 -> 1 with another ``LIST:``) is
  discovered again on the next poll, whose snapshot says ``program_changed``.
- ``subscribe()`` hears every burst of ``DIFF:`` lines as one snapshot (see
  :class:`~.push.PushBatch`), and every mode change.
- ``write()`` and ``write_many()`` are the base's template: each value is
  validated like TecoApi's (:func:`~..writes.written_value`: read-only, range,
  kind, ASCII text) and taken typed as the PLC will hold it, every ``SET:``
  line of a batch goes in one exchange, the acknowledged values are pushed and
  what ``GET:`` reads afterwards is returned.
- ``close()`` closes the TCP connection.

Every failure is a neutral exception; an unreachable, dropped or stalled server
is :class:`~...core.exceptions.PlcConnectionError` (the client reconnects by itself
with backoff; polls fail until it has); a server that cannot reach its PLC
(``ERROR:10``) fails polls with :class:`~...core.exceptions.PlcUnreachableError` until
the PLC answers again, and the client has read everything again.
"""

import asyncio
from collections.abc import Collection, Iterable, Mapping, Sequence
from dataclasses import asdict, replace
import logging
import re
from typing import Any, Final, Unpack

from ...core.exceptions import (
    InvalidValueError,
    NoPublicVariablesError,
    NotAPlcError,
    PlcConnectionError,
    PlcError,
    PlcUnreachableError,
)
from ...core.models import (
    Catalogue,
    PlcMode,
    Point,
    PointAttributes,
    PointQuality,
    Quality,
    SourceInfo,
)
from ...core.source import BaseSource, Snapshot, SourceSettings, Write
from ...core.texts import Template
from ..points import MANUFACTURER, point_key, value_path
from ..tecoapi.info import device_name
from ..writes import encode_json_value, written_value
from .catalogue import (
    build_catalogue,
    find_api_objects,
    meta_of,
)
from .client import PlcComsClient
from .events import (
    PlcComsEvent,
    ProgramChanged,
    RunStateChanged,
    ValueChanged,
)
from .protocol import PLC_RUN
from .push import (
    DEFAULT_BATCH_WINDOW,
    PushBatch,
    enable_points,
    json_shaped,
    point_value,
    read_values,
)

_LOGGER = logging.getLogger(__name__)

ONE_ELEMENTARY: Final = Template(
    "write_elementary", "PLCComS writes one elementary variable at a time"
)
"""Why a structure's or an array's value is refused through PLCComS."""

PF_CRC: Final = "__PF_CRC"
WAY_IN: Final = "PLCComS"
"""What a PLC's entry title and its devices' names say of PLCComS alone."""
_CPU: Final = re.compile(r"\bCP-?(\d{4})", re.IGNORECASE)
_VERSION: Final = re.compile(r"(?:Ver\.?\s*)?(\d+(?:\.\d+)+)", re.IGNORECASE)
_FILE_LIST: Final = re.compile(r"\[([^\]]*)\]")
_FIXED_FILE: Final = "fixed_"
UNFIT: Final = PointQuality(
    quality=Quality.BAD,
    reason="the server sent a value its type cannot hold",
    text=Template("plccoms_unfit", "the server sent a value its type cannot hold")(),
)
"""The quality of a point whose last value did not fit its type."""


def plc_info_from_getinfo(
    info: Mapping[str, str],
    *,
    server: str,
    running: bool | None,
    stamp: str | None,
) -> SourceInfo:
    """Return the neutral PLC info of a ``GETINFO:`` answer (see the module).

    ``server`` is the PLCComS server's ``host:port``, the identity's fallback;
    ``running`` is ``__PLC_RUN`` (None until known counts as running: the server
    answered, and the first push corrects it).
    """
    keys = {key.lower(): value.strip() for key, value in info.items()}
    version = keys.get("version")
    if not version:
        raise NotAPlcError("GETINFO: did not describe a PLCComS server")
    address, port = keys.get("ipaddr"), keys.get("epsport")
    identity = f"EPSNET {address}:{port}" if address and port else f"PLCComS {server}"
    firmware = keys.get("version_plc") or None
    cpu = _CPU.search(firmware) if firmware else None
    model = f"CP-{cpu.group(1)}" if cpu else None
    number = _VERSION.match(version)
    return SourceInfo(
        identity=identity,
        name=device_name(model),
        manufacturer=MANUFACTURER,
        family=None,
        model=model,
        serial_number=identity,
        firmware=firmware,
        mac=None,
        mode=PlcMode.STOPPED if running is False else PlcMode.RUNNING,
        program_name=_program_file(keys.get("pubfile")),
        program_compiled=None,
        program_stamp=stamp,
        time=None,
        api_version=f"PLCComS {number.group(1) if number else version}",
        # The same PLC may have a TecoApi entry too: the title and names say which.
        way_in=WAY_IN,
    )


def _meta(
    attributes: Mapping[str, str], read: Mapping[str, Any]
) -> PointAttributes | None:
    """Return a T_ApiObject's metadata from the values read by lower-case name."""
    return meta_of(
        {attribute: read.get(name.lower()) for attribute, name in attributes.items()}
    )


def _program_file(pubfile: str | None) -> str | None:
    """Return the program's public file of a ``PUBFILE`` value, without ``.pub``.

    The value is one file, or (the manual) ``2/2 [FIXED_Foxtrot.pub,Prog.pub]``:
    the files in brackets, the server's own ``FIXED_`` file among them.
    """
    if not pubfile or (files := _FILE_LIST.search(pubfile)) is None:
        return _file_stem(pubfile)
    names = [name.strip() for name in files.group(1).split(",")]
    programs = [name for name in names if not name.lower().startswith(_FIXED_FILE)]
    return _file_stem(programs[-1]) if programs else None


def _file_stem(path: str | None) -> str | None:
    """Return a public file's name without directories and ``.pub`` (None for none)."""
    if not path:
        return None
    name = re.split(r"[\\/]", path)[-1]
    return name.removesuffix(".pub").removesuffix(".PUB") or None


class PlcComsSource(BaseSource):
    """One PLC through PLCComS alone, as a :class:`~...core.source.PlcSource`.

    The client is owned: :meth:`close` closes it. ``batch_window`` is how long a
    burst of pushed values is gathered (see :class:`~.push.PushBatch`);
    ``settings`` are those of every source. The statistics count command lines sent
    as requests; subscribers hear of every burst of pushed values and every mode
    change.
    """

    def __init__(
        self,
        client: PlcComsClient,
        *,
        batch_window: float = DEFAULT_BATCH_WINDOW,
        **settings: Unpack[SourceSettings],
    ) -> None:
        """Wrap a client (connected or not); nothing is sent until the first call."""
        super().__init__(wire=client.wire, **settings)
        self.client = client
        self._batch = PushBatch(self._push, batch_window)
        self._server_info: dict[str, str] = {}
        # Point keys by the lower-case PLCComS name of their value.
        self._keys: dict[str, str] = {}
        # Values pushed since the previous poll, returned by the next one.
        self._pending: dict[str, Any] = {}
        self._program_due = False
        # The attribute variables of each T_ApiObject point, by point key.
        self._attributes: dict[str, Mapping[str, str]] = {}
        # The latest attributes read of T_ApiObject points (writes are checked by them).
        self._latest: dict[str, PointAttributes] = {}
        self._started = False
        # A poll and following the polled points between polls take turns.
        self._exclusive = asyncio.Lock()
        self._unsubscribe = client.subscribe(self._on_event)

    # --- what the PlcSource protocol asks --------------------------------------

    @property
    def configuration_url(self) -> None:
        """None: PLCComS has no web page, and the PLC's own web server is unknown to it."""
        return None

    async def identify(self) -> SourceInfo:
        """Connect, read ``GETINFO:`` and check that ``LIST:`` names variables.

        The connection stays open for the polls; :meth:`close` it when the source
        is not used further.
        """
        await self._connect()
        catalogue = self.client.catalogue
        if catalogue is None or not catalogue.points:
            raise NoPublicVariablesError("PLCComS lists no variable of the PLC")
        return await self._read_info()

    async def poll(self, polled: Collection[str]) -> Snapshot:
        """Discover on the first poll (and after a download); else return the pushes."""
        async with self._exclusive:
            return await super().poll(polled)

    async def follow(self, polled: Collection[str]) -> None:
        """``EN:`` the polled points now, not at the next poll; push their values.

        The values ``GET:`` reads of the newly enabled points are pushed at once
        (they may have changed since discovery) and kept for the next poll. A
        failure is left to the next poll.
        """
        async with self._exclusive:
            catalogue = self._catalogue
            if catalogue is None or not self.client.connected:
                return
            try:
                fresh = await self._follow(catalogue, frozenset(polled))
            except PlcError as err:
                _LOGGER.debug("PLCComS failed enabling the polled points: %s", err)
                return
        if fresh:
            self._pending.update(fresh)
            self._push(fresh)

    async def read_points(self, keys: Collection[str]) -> Snapshot | None:
        """``GET:`` the points PLCComS does not push (None: every one is pushed)."""
        catalogue = self._catalogue
        followed = set(self._keys.values())
        points = [
            catalogue.points[key]
            for key in keys
            if catalogue is not None and key in catalogue.points and key not in followed
        ]
        if catalogue is None or not points:
            return None
        read, _ = await self._read(
            read_values(self.client, [value_path(point) for point in points])
        )
        values = {
            point.key: self._shown(point, read[value_path(point).lower()])
            for point in points
            if value_path(point).lower() in read
        }
        return self._snapshot(catalogue, values, {}, None) if values else None

    # --- writes: the base's template, here SET: lines in one exchange -------------

    def _encode(self, point: Point, value: Any) -> Write[Any]:
        """Validate a value as TecoApi does (the latest attributes); the value held.

        ``SET:`` spells the typed value itself (:func:`~..writes.written_value`).
        """
        held = written_value(point, value)
        return Write(point=point, value=value, wire=held, shown=held)

    async def _send_writes(self, writes: Sequence[Write[Any]]) -> None:
        """``SET:`` every line of the batch in one exchange; one barrier proves them taken.

        (:meth:`PlcComsClient.set_many`: the first refusal raised, naming its
        variable.)
        """
        await self.client.set_many(
            [(value_path(write.point), write.wire) for write in writes]
        )

    async def _read_back(
        self, batch: Sequence[Write[Any]], carried: Mapping[str, Any]
    ) -> Snapshot | None:
        """One ``GET:`` a point: what the PLC holds, pushed or not."""
        points = [write.point for write in batch]
        held = await self.client.get([value_path(point) for point in points])
        assert self._catalogue is not None  # the points are in it
        return self._snapshot(
            self._catalogue,
            {
                point.key: self._shown(point, held[value_path(point)])
                for point in points
            },
            {},
            None,
        )

    def _point(self, key: str) -> Point:
        """Return the catalogue's point with its latest attributes (as TecoApi's)."""
        point = super()._point(key)
        return replace(point, attributes=self._latest.get(key, point.attributes))

    async def write_variable(self, path: str, value: Any) -> Snapshot | None:
        """Write to any variable: a point as :meth:`write`, another one as it is.

        PLCComS writes one elementary variable at a time: a struct or array value
        is refused (InvalidValueError).
        """
        points = self._catalogue.points if self._catalogue is not None else {}
        if (key := point_key(points, path)) is not None:
            return await self.write(key, value)
        if isinstance(value, Mapping | list | tuple):
            raise InvalidValueError(path, value, ONE_ELEMENTARY())
        encode_json_value(path, value)
        await self._send(self.client.set(path, value))
        return None

    async def read_variable(self, path: str) -> Any:
        """Read one elementary variable: its JSON-shaped value."""
        values = await self._read(self.client.get([path]))
        return json_shaped(values[path])

    def diagnostics(self) -> dict[str, Any]:
        """Describe the server's versions, the connection's health and the counters."""
        health = asdict(self.client.health)
        if health["last_line_at"] is not None:
            health["last_line_at"] = health["last_line_at"].isoformat()
        catalogue = self._catalogue
        return {
            "transport": "plccoms",
            "server": {
                key: self._server_info[key]
                for key in ("version", "version_plc")
                if key in self._server_info
            },
            "points": len(catalogue.points) if catalogue else 0,
            "skipped_variables": list(catalogue.skipped_groups) if catalogue else [],
            "enabled": len(self._keys),
            "connection": health,
            "push": {"bursts": self._batch.bursts, "values": self._batch.values},
            "requests": asdict(self._statistics),
        }

    async def close(self) -> None:
        """Close the connection to the server; the source is not used again."""
        self._unsubscribe()
        self._batch.cancel()
        await self.client.close()

    # --- polling ---------------------------------------------------------------

    def _discovery_due(self) -> bool:
        """On the first poll, and after a program download."""
        return self._catalogue is None or self._program_due

    async def _connect(self) -> None:
        """Connect the first time; later, fail while the client reconnects."""
        client = self.client
        if client.connected:
            self._started = True
            return
        if not self._started:
            # Never connected (or the first attempt failed): try now.
            await client.connect()
            self._started = True
            return
        if isinstance(failure := client.failure, PlcUnreachableError):
            raise PlcUnreachableError(str(failure))
        raise PlcConnectionError(
            f"PLCComS at {client.host}:{client.port} is not connected (reconnecting)"
        )

    async def _read_info(self) -> SourceInfo:
        """``GETINFO:`` and ``__PF_CRC``: the PLC info, kept for the snapshots."""
        client = self.client
        self._server_info = {
            key.lower(): value for key, value in (await client.get_info()).items()
        }
        stamp = None
        if PF_CRC.lower() in client.variables:
            crc = (await client.get([PF_CRC]))[PF_CRC]
            if isinstance(crc, int) and not isinstance(crc, bool):
                stamp = f"{crc:08X}"
        self._info = plc_info_from_getinfo(
            self._server_info,
            server=f"{client.host}:{client.port}",
            running=client.plc_running,
            stamp=stamp,
        )
        self._metadata_due = self._clock() + self.metadata_interval
        return self._info

    async def _discover_catalogue(self, polled: frozenset[str]) -> Snapshot:
        """Read ``LIST:`` as a catalogue (T_ApiObjects grouped) and every value."""
        await self._connect()
        client = self.client
        info = await self._read_info()
        info_read_at = self._clock()
        self._program_due = False
        variables = [
            variable
            for variable in client.variables.values()
            if not variable.name.startswith("__") and variable.kind is not None
        ]
        if not variables:
            raise NoPublicVariablesError("PLCComS lists no variable of the PLC")
        objects = find_api_objects(variables)
        read, unread = await read_values(
            self.client, [variable.name for variable in variables]
        )
        metas = {
            key: meta
            for key, names in objects.items()
            if (meta := _meta(names.attributes, read)) is not None
        }
        catalogue = build_catalogue(client.variables.values(), objects, metas)
        self._quality = {}
        values = {
            key: self._shown(point, read[value_path(point).lower()])
            for key, point in catalogue.points.items()
            if value_path(point).lower() in read
        }
        catalogue = replace(catalogue, values=values)
        program_changed = self._catalogue is not None
        self._catalogue = catalogue
        self._attributes = {key: objects[key].attributes for key in metas}
        self._latest = {}
        self._keys = {}
        self._pending = {}
        self._batch.cancel()
        self._missing = frozenset(
            key
            for key, point in catalogue.points.items()
            if value_path(point).lower() in unread
        )
        await self._follow(catalogue, polled, read=False)
        return self._discovered(
            info,
            catalogue,
            values,
            metas,
            info_read_at,
            program_changed=program_changed,
        )

    async def _poll(self, catalogue: Catalogue, polled: frozenset[str]) -> Snapshot:
        """Enable what is newly polled, prove the connection, return the pushes."""
        await self._connect()
        fresh = await self._follow(catalogue, polled)
        # The answer comes after every line the server sent before it: a stalled
        # server fails here, within the client's timeout.
        await self.client.get([PLC_RUN])
        info_read_at = None
        meta: dict[str, PointAttributes] = {}
        if self._clock() >= self._metadata_due:
            # The metadata cadence: GETINFO: and the polled T_ApiObjects' attributes.
            await self._read_info()
            info_read_at = self._clock()
            meta = await self._read_meta(
                key for key in polled if key in self._attributes
            )
            self._latest.update(meta)
        if self._program_due:
            return await self._discover_catalogue(polled)
        values, self._pending = {**self._pending, **fresh}, {}
        return self._snapshot(catalogue, values, meta, info_read_at)

    async def _read_meta(self, keys: Iterable[str]) -> dict[str, PointAttributes]:
        """``GET:`` the attributes of T_ApiObject points: their metadata."""
        objects = {key: self._attributes[key] for key in keys}
        read, _ = await read_values(
            self.client,
            [name for attributes in objects.values() for name in attributes.values()],
        )
        meta: dict[str, PointAttributes] = {}
        for key, attributes in objects.items():
            if (found := _meta(attributes, read)) is not None:
                meta[key] = found
        return meta

    async def _follow(
        self, catalogue: Catalogue, polled: frozenset[str], *, read: bool = True
    ) -> dict[str, Any]:
        """``EN:`` newly polled points, ``DI:`` the others; the new ones' values.

        ``read=False`` when the values were just read (discovery).
        """
        client = self.client
        wanted = {
            value_path(catalogue.points[key]).lower(): key
            for key in polled
            if key in catalogue.points
        }
        new, enabled = await enable_points(client, catalogue, wanted, self._keys)
        self._keys = {name: key for name, key in wanted.items() if name in enabled}
        refused = frozenset(key for name, key in wanted.items() if name not in enabled)
        if not read:
            self._missing |= refused
            return {}
        points = [point for point in new if point.key not in refused]
        got, unread = await read_values(
            self.client, [value_path(point) for point in points]
        )
        fresh = {
            point.key: self._shown(point, got[value_path(point).lower()])
            for point in points
            if value_path(point).lower() in got
        }
        missing = {point.key for point in points if value_path(point).lower() in unread}
        self._missing = (self._missing - {p.key for p in new}) | missing | refused
        return fresh

    def _shown(self, point: Point, value: Any) -> Any:
        """Return a value as the point shows it; one its type cannot hold is bad.

        The server sent a value its type cannot hold (a DT beyond 9999, a TOD
        beyond a day): the point alone is unavailable until a value fits again.
        """
        shown = point_value(point, value)
        if shown is None:
            self._quality[point.key] = UNFIT
        else:
            self._quality.pop(point.key, None)
        return shown

    # --- pushes ----------------------------------------------------------------

    def _on_event(self, event: PlcComsEvent) -> None:
        """Follow the client: values, the run state, a new program."""
        match event:
            case ValueChanged(key=name, value=value):
                key = self._keys.get(name)
                catalogue = self._catalogue
                if key is None and catalogue is not None and name in catalogue.points:
                    # A SET: answers with a DIFF: of its variable, enabled or not.
                    key = name
                if key is None or catalogue is None:
                    return
                shown = self._shown(catalogue.points[key], value)
                self._pending[key] = shown
                self._batch.add(key, shown)
            case RunStateChanged(running=running):
                if self._info is not None:
                    mode = PlcMode.RUNNING if running else PlcMode.STOPPED
                    self._info = replace(self._info, mode=mode)
                    self._batch.flush()
                    self._push({})
            case ProgramChanged():
                self._program_due = True
