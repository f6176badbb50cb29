"""TecoApi with PLCComS push: the best of both ways into a PLC.

Identity, metadata, discovery and writes stay on authenticated TecoApi
(:class:`~..tecoapi.source.TecoApiSession`); the values of the polled points arrive from
PLCComS by ``DIFF:`` within about 100 ms of changing. PLCComS has **no
authentication**: it is used only where the user asked for it, on a trusted
network.

The schedule, while PLCComS is *healthy* (connected, its answer to one
``GET:__PLC_RUN`` per poll arrived, ``__PLC_RUN`` 1):

- every polled point whose ``value_path`` ``LIST:`` names is enabled (``EN:``;
  ``DI:`` when no longer polled) and read once with ``GET:`` when newly enabled
  -- by every poll, and by ``follow(polled)`` at once, without waiting for one
  (Home Assistant calls it as soon as its entities listen);
  its changes are pushed to subscribers, one snapshot per burst, and the next
  poll returns them too;
- a poll reads nothing from TecoApi, except the rare polled points PLCComS does
  not list;
- every ``metadata_interval`` (60 s by default) a poll reads the polled
  T_ApiObjects' attributes over PLCComS (``GET:`` of ``P.attr.*``, which
  ``LIST:`` names like any variable), not over TecoApi;
- TecoApi is read on the *reconciliation* cadence, every
  ``reconcile_interval`` (5 minutes by default): a poll reads GetInfo (the
  program stamp, the PLC's clock) and every polled value from TecoApi, as the
  plain session does. Values DIFF pushed while that poll was under way win over
  what it read (they are newer). Five minutes, not the metadata cadence:
  pushes are exact, the mode and a new program come from ``__PLC_RUN`` at once
  and the attributes from PLCComS, so the reconciliation only guards against a
  push lost without a drop; at one minute the PLC's web server would still see
  a sixth of its polling load (the benchmark's target is a tenth at most).

When PLCComS is not healthy (never connected, dropped, stalled: the probe got no
answer within the client's ``timeout``), every poll is a plain TecoApi poll.
After PLCComS failed, the first poll that finds it healthy again enables, then
reads every polled value from TecoApi, and only then returns to push: nothing
changed in between is lost. PLCComS is connected in the background (a poll
never waits for it); once connected, the client reconnects by itself.

``__PLC_RUN`` changing starts a GetInfo at once: a HALT or ERR (or RUN again) is
pushed as a snapshot with the new mode within one push and one GetInfo, and a
new program stamp makes the next poll discover the new program (so does
PLCComS' own ``ProgramChanged``).

Writes go through TecoApi (validated, SetObject). While the point is pushed, the
acknowledged value is pushed at once and ``write`` returns None: what the PLC
holds then arrives by DIFF, and the poll a caller may ask for costs no TecoApi
request. Otherwise the write reads back through TecoApi, as the plain session.
"""

import asyncio
from collections.abc import Collection, Coroutine, Mapping, Sequence
from dataclasses import replace
from datetime import UTC, datetime, timedelta
import logging
from typing import TYPE_CHECKING, Any, Final, Unpack

from ...core.exceptions import PlcError
from ...core.models import Catalogue, PlcMode, PointAttributes, SourceInfo
from ...core.source import Snapshot, SourceSettings, Write
from ..points import value_path
from ..tecoapi.client import TecoApiClient
from ..tecoapi.source import RunBlocking, TecoApiSession, _in_executor, _program_changed
from ..writes import WireValue
from .catalogue import ATTRIBUTE_KINDS, meta_of
from .client import PlcComsClient
from .events import (
    ConnectionChanged,
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
    point_value,
    read_values,
)

if TYPE_CHECKING:
    from ..tecoapi.plans import ReadPlan

_LOGGER = logging.getLogger(__name__)

DEFAULT_RECONCILE_INTERVAL: Final = timedelta(minutes=5)
"""How often TecoApi is read while PLCComS pushes (see the module)."""
CONNECT_RETRY: Final = timedelta(seconds=60)
"""How long after a failed first connection to PLCComS it is tried again."""
_DAWN: Final = datetime.min.replace(tzinfo=UTC)


class PushedTecoApiSession(TecoApiSession):
    """One PLC over TecoApi, its values pushed by PLCComS (see the module).

    ``coms`` is owned: :meth:`close` closes it. Its ``timeout`` is how long a
    poll waits for PLCComS to answer before it falls back to TecoApi (a few
    seconds suit a server on the local network).
    """

    def __init__(
        self,
        client: TecoApiClient,
        coms: PlcComsClient,
        *,
        run_blocking: RunBlocking = _in_executor,
        check_quiet_polls: bool = True,
        reconcile_interval: timedelta = DEFAULT_RECONCILE_INTERVAL,
        batch_window: float = DEFAULT_BATCH_WINDOW,
        **settings: Unpack[SourceSettings],
    ) -> None:
        """Wrap both clients; nothing is requested until the first call."""
        super().__init__(
            client,
            run_blocking=run_blocking,
            check_quiet_polls=check_quiet_polls,
            **settings,
        )
        self.coms = coms
        self.reconcile_interval = reconcile_interval
        self._reconcile_due = _DAWN
        self._batch = PushBatch(self._push, batch_window)
        # Point keys by the lower-case PLCComS name of their value (enabled ones).
        self._pushed: dict[str, str] = {}
        # Polled points PLCComS cannot push (not listed, or refused).
        self._unpushable: frozenset[str] = frozenset()
        self._unpushable_plan: ReadPlan | None = None
        # Values pushed since the previous poll, each with its arrival number.
        self._pending: dict[str, tuple[int, Any]] = {}
        # Read every polled value from TecoApi before trusting pushes (again).
        self._resync_due = True
        self._exclusive = asyncio.Lock()
        self._tasks: set[asyncio.Task[None]] = set()
        self._coms_started = False
        self._connecting: asyncio.Task[None] | None = None
        self._next_connect = _DAWN
        self._counts = {"pushed": 0, "reconciliations": 0, "fallbacks": 0}
        self._unsubscribe = coms.subscribe(self._on_event)

    # --- what the PlcSource protocol asks --------------------------------------

    async def poll(self, polled: Collection[str]) -> Snapshot:
        """Discover on the first poll; then push, reconcile or fall back (see module)."""
        async with self._exclusive:
            return await super().poll(polled)

    async def read_points(self, keys: Collection[str]) -> Snapshot | None:
        """Read through TecoApi the points PLCComS does not push now (None: all are)."""
        unpushed = [key for key in keys if not self._pushing(key)]
        if not unpushed:
            return None
        async with self._exclusive:
            return await super().read_points(unpushed)

    async def follow(self, polled: Collection[str]) -> None:
        """Enable the polled points on PLCComS now, not at the next poll.

        A connection under way (discovery starts it) is waited for; then the
        points are enabled as a poll enables them, and their values read with
        ``GET:`` are pushed at once (they may have changed since discovery). An
        unreachable or failing PLCComS leaves it to the next poll. The next poll
        still reads every polled value from TecoApi before pushes are trusted,
        as the first poll after discovery always does.
        """
        self._start_coms()
        if (connecting := self._connecting) is not None:
            await asyncio.wait([connecting])
        async with self._exclusive:
            catalogue = self._catalogue
            if catalogue is None:
                return
            fresh = await self._follow(catalogue, frozenset(polled))
        if fresh:
            arrival = self._batch.values
            self._pending.update(
                (key, (arrival, value)) for key, value in fresh.items()
            )
            self._push(fresh)

    async def _read_back(
        self, batch: Sequence[Write[WireValue]], carried: Mapping[str, Any]
    ) -> Snapshot | None:
        """Read back through TecoApi, but not a write of one pushed point.

        What the PLC holds of a pushed point arrives by DIFF (None: the poll a
        caller may ask for costs no TecoApi request). A batch is read back
        through TecoApi, pushed points or not, as the plain session does.
        """
        if len(batch) == 1 and self._pushing(batch[0].key):
            return None
        return await super()._read_back(batch, carried)

    def diagnostics(self) -> dict[str, Any]:
        """TecoApi's figures, and PLCComS': health, enabled points, poll kinds."""
        health = self.coms.health
        return {
            **super().diagnostics(),
            "push": {
                "connected": health.connected,
                "plc_running": health.plc_running,
                "enabled": len(self._pushed),
                "unpushable": len(self._unpushable),
                "polls_without_tecoapi": self._counts["pushed"],
                "reconciliations": self._counts["reconciliations"],
                "reconcile_interval": self.reconcile_interval.total_seconds(),
                "fallback_polls": self._counts["fallbacks"],
                "bursts": self._batch.bursts,
                "values": self._batch.values,
                "reconnects": health.reconnects,
                "stalls": health.stalls,
                "last_error": health.last_error,
            },
        }

    async def close(self) -> None:
        """Close PLCComS (the HTTP session belongs to whoever made it)."""
        self._unsubscribe()
        self._batch.cancel()
        tasks = list(self._tasks)
        for task in tasks:
            task.cancel()
        await asyncio.gather(*tasks, return_exceptions=True)
        await self.coms.close()

    # --- the schedule ----------------------------------------------------------

    async def _discover(
        self, info: SourceInfo | None, info_read_at: datetime | None = None
    ) -> Snapshot:
        """Discover over TecoApi; the points are enabled on PLCComS from the next poll."""
        snapshot = await super()._discover(info, info_read_at)
        self._pushed = {}
        self._unpushable = frozenset()
        self._unpushable_plan = None
        self._pending = {}
        self._batch.cancel()
        self._resync_due = True
        self._start_coms()
        return snapshot

    async def _poll(self, catalogue: Catalogue, polled: frozenset[str]) -> Snapshot:
        """Push when PLCComS is healthy and TecoApi is not due; else TecoApi."""
        self._start_coms()
        fresh = await self._follow(catalogue, polled)
        now = self._clock()
        info = self._info
        assert info is not None  # discovery read it
        if (
            fresh is not None
            and not self._resync_due
            and self.coms.plc_running is True
            and info.mode is PlcMode.RUNNING
            and now < self._reconcile_due
            and now < self._info_due
        ):
            meta: dict[str, PointAttributes] = {}
            if now >= self._metadata_due:
                try:
                    meta = await self._read_attributes(catalogue, polled)
                except PlcError as err:
                    _LOGGER.debug("PLCComS failed reading attributes: %s", err)
                    self._resync_due = True
                    fresh = None
                else:
                    self._metadata_due = now + self._metadata_interval
            if fresh is not None:
                self._counts["pushed"] += 1
                return await self._pushed_poll(catalogue, polled, fresh, meta)
        arrivals = self._batch.values
        if fresh is not None:
            # Reconciliation: GetInfo too (the stamp, the PLC's clock).
            self._info_due = min(self._info_due, now)
        snapshot = await super()._poll(catalogue, polled)
        if fresh is not None:
            self._resync_due = False
            self._reconcile_due = now + self.reconcile_interval
            self._counts["reconciliations"] += 1
        else:
            self._counts["fallbacks"] += 1
        # Values pushed while TecoApi was read are newer than what it read.
        newer = {
            key: value
            for key, (arrival, value) in self._pending.items()
            if arrival > arrivals and key in snapshot.values
        }
        self._pending = {}
        if snapshot.program_changed or not newer:
            return snapshot
        return replace(snapshot, values={**snapshot.values, **newer})

    async def _pushed_poll(
        self,
        catalogue: Catalogue,
        polled: frozenset[str],
        fresh: dict[str, Any],
        meta: dict[str, PointAttributes],
    ) -> Snapshot:
        """Return the values pushed since the last poll (and read the unpushable ones)."""
        values = {key: value for key, (_, value) in self._pending.items()}
        self._pending = {}
        values.update(fresh)
        keys = self._unpushable & polled
        if keys:
            plan = self._unpushable_plan
            if plan is None or plan.point_keys != keys:
                points = [catalogue.points[key] for key in keys]
                plan = await self._run_blocking(
                    lambda: self.client.plan(points, with_attrs=False)
                )
                self._unpushable_plan = plan
            result = await self.client.read(plan, catalogue.points)
            values.update(result.values)
            self._missing = (self._missing - keys) | result.missing
        return self._snapshot(catalogue, values, meta, None)

    async def _read_attributes(
        self, catalogue: Catalogue, polled: frozenset[str]
    ) -> dict[str, PointAttributes]:
        """Read the polled T_ApiObjects' attributes over PLCComS (``P.attr.*``).

        An object whose attributes PLCComS does not list keeps its metadata until
        TecoApi reads it (reconciliation, or a fallback poll on the cadence).
        """
        listed = self.coms.variables
        objects: dict[str, dict[str, str]] = {}
        for key in polled:
            point = catalogue.points.get(key)
            if point is None or point.attributes is None:
                continue
            names: dict[str, str] = {}
            for attribute in ATTRIBUTE_KINDS:
                variable = listed.get(f"{key}.attr.{attribute}")
                if variable is None:
                    break
                names[attribute] = variable.name
            else:
                objects[key] = names
        read, _ = await read_values(
            self.coms,
            [name for names in objects.values() for name in names.values()],
        )
        meta: dict[str, PointAttributes] = {}
        for key, names in objects.items():
            found = meta_of(
                {attribute: read.get(name.lower()) for attribute, name in names.items()}
            )
            if found is not None:
                meta[key] = found
        self._attributes.update(meta)
        return meta

    async def _follow(
        self, catalogue: Catalogue, polled: frozenset[str]
    ) -> dict[str, Any] | None:
        """Enable the polled points on PLCComS and prove it delivers.

        Returns the values of the newly enabled points (read with ``GET:``), or
        None when PLCComS is not healthy (the poll then reads TecoApi).
        """
        coms = self.coms
        if not coms.connected:
            return None
        try:
            fresh = await self._enable(catalogue, polled)
            # The answer comes after every line sent before it: a silent server
            # fails here within the client's timeout (and is reconnected).
            await coms.get([PLC_RUN])
        except PlcError as err:
            _LOGGER.debug("PLCComS is not healthy, polling TecoApi: %s", err)
            self._resync_due = True
            return None
        return fresh

    async def _enable(
        self, catalogue: Catalogue, polled: frozenset[str]
    ) -> dict[str, Any]:
        """``EN:`` newly polled points, ``DI:`` the others; the new ones' values."""
        coms = self.coms
        listed = coms.variables
        wanted: dict[str, str] = {}
        unpushable: set[str] = set()
        for key in polled:
            point = catalogue.points.get(key)
            if point is None:
                continue
            name = value_path(point).lower()
            if name in listed:
                wanted[name] = key
            else:
                unpushable.add(key)
        new, enabled = await enable_points(coms, catalogue, wanted, self._pushed)
        self._pushed = {name: key for name, key in wanted.items() if name in enabled}
        unpushable.update(key for name, key in wanted.items() if name not in enabled)
        self._unpushable = frozenset(unpushable)
        readable = [point for point in new if value_path(point).lower() in enabled]
        if not readable:
            return {}
        read, unread = await read_values(
            coms, [value_path(point) for point in readable]
        )
        if unread:
            # Gone from the PLC since LIST: was read: TecoApi tells.
            self._unpushable |= {
                point.key for point in readable if value_path(point).lower() in unread
            }
        return {
            point.key: point_value(point, read[value_path(point).lower()])
            for point in readable
            if value_path(point).lower() in read
        }

    def _pushing(self, key: str) -> bool:
        """Whether a point's changes arrive by DIFF right now."""
        return (
            self.coms.connected
            and not self._resync_due
            and key in self._pushed.values()
        )

    # --- PLCComS ---------------------------------------------------------------

    def _start_coms(self) -> None:
        """Connect PLCComS in the background the first time (and retry a failure)."""
        if self._coms_started or self._connecting is not None:
            return
        if self._clock() < self._next_connect:
            return
        self._connecting = self._spawn(self._connect())

    async def _connect(self) -> None:
        try:
            await self.coms.connect()
        except PlcError as err:
            _LOGGER.debug("PLCComS could not be reached, polling TecoApi: %s", err)
            self._next_connect = self._clock() + CONNECT_RETRY
        else:
            self._coms_started = True
        finally:
            self._connecting = None

    def _spawn(self, coroutine: Coroutine[Any, Any, None]) -> asyncio.Task[None]:
        task = asyncio.get_running_loop().create_task(coroutine)
        self._tasks.add(task)
        task.add_done_callback(self._tasks.discard)
        return task

    def _on_event(self, event: PlcComsEvent) -> None:
        """Follow PLCComS: pushed values, the run state, a drop, a new program.

        A value goes out in its burst and is kept for the next poll's snapshot. A
        new run state or program reads GetInfo at once; after a drop, the next poll
        reads every value from TecoApi again.
        """
        match event:
            case ValueChanged(key=name, value=value):
                key = self._pushed.get(name)
                catalogue = self._catalogue
                if key is None or catalogue is None:
                    return
                shown = point_value(catalogue.points[key], value)
                self._batch.add(key, shown)
                # Its number, the batch's count of values, tells it newer than a read.
                self._pending[key] = (self._batch.values, shown)
            case RunStateChanged() | ProgramChanged():
                # GetInfo at once: the new mode pushed, a new program found.
                self._info_due = self._clock()
                self._spawn(self._check_mode())
            case ConnectionChanged(connected=False):
                self._resync_due = True

    async def _check_mode(self) -> None:
        """Read GetInfo after ``__PLC_RUN`` changed; push a new mode at once."""
        async with self._exclusive:
            previous = self._info
            if previous is None or self._catalogue is None:
                return
            try:
                info, info_read_at = await self._get_info()
            except PlcError as err:
                self._info_due = self._clock()
                if self.coms.plc_running is False and previous.mode is PlcMode.RUNNING:
                    # TecoApi is silent; PLCComS says the program stopped.
                    self._info = replace(previous, mode=PlcMode.STOPPED)
                    self._push({})
                _LOGGER.debug("GetInfo after __PLC_RUN changed failed: %s", err)
                return
            if _program_changed(previous, info):
                # The next poll discovers the new program.
                self._info_due = self._clock()
                return
            self._info = info
            if info.mode is not previous.mode:
                self._listeners.push(
                    self._snapshot(self._catalogue, {}, {}, info_read_at)
                )
