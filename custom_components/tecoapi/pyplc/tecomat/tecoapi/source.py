"""TecoApi as a PLC source: what to read on which poll, one snapshot per poll.

The schedule:

- the first poll discovers the catalogue (GetInfo, GetList, the roots): its
  snapshot holds every point's value and metadata;
- every poll reads the polled points' values with the fewest GetObject requests
  the planner finds (plans are made in the executor and kept while the polled
  points and the learned item limit stay the same);
- every ``metadata_interval`` a poll reads the T_ApiObject attributes too, and
  GetInfo (the PLC's mode, its program stamp and its clock);
- GetInfo is also read on the poll after a failed one, after a write to a
  variable the PLC no longer has, on every poll while the program is not running
  (its values are then not read), and at once when a poll finds variables newly
  missing (a Mosaic download may have removed them);
- and on a *quiet* poll, one whose values all equal the previous poll's: a
  stopped program (HALT, ERR) changes nothing, so HALT/ERR is seen on the first
  poll after it instead of up to ``metadata_interval`` later. TecoApi answers a
  stopped PLC's GetObject as a running one's (the manual says nothing else, the
  web server keeps serving the frozen memory), so there is no signal in the
  values' answer itself; the quiet poll is the cheapest one there is. It costs
  one GetInfo on a quiet poll and nothing on a poll that saw a change
  (``check_quiet_polls=False`` reads GetInfo on the cadence only);
- a new program stamp means a new program: the catalogue is discovered again
  within the same poll and the snapshot says ``program_changed``.

Between polls, ``read_points(keys)`` reads a few points alone (a blind on its
way: one GetObject), and the schedule stays as it is.
"""

import asyncio
from collections.abc import Awaitable, Callable, Collection, Mapping, Sequence
from dataclasses import asdict, replace
from datetime import datetime
from typing import Any, Final, Unpack

from ...core.exceptions import NoPublicVariablesError, VariableNotFoundError
from ...core.models import Catalogue, PlcMode, Point, PointAttributes, SourceInfo
from ...core.source import NEVER, BaseSource, Snapshot, SourceSettings, Write
from ..points import point_key, value_path
from ..writes import WireValue, validate_write
from .client import TecoApiClient
from .plans import ReadPlan
from .values import parse_value

_ABSENT: Final = object()

type RunBlocking = Callable[[Callable[[], ReadPlan]], Awaitable[ReadPlan]]


async def _in_executor(job: Callable[[], ReadPlan]) -> ReadPlan:
    """Run CPU-bound planning in the event loop's default executor."""
    return await asyncio.get_running_loop().run_in_executor(None, job)


class TecoApiSession(BaseSource):
    """One PLC over TecoApi, as a :class:`~...core.source.PlcSource`.

    ``run_blocking`` runs a planning job off the event loop (Home Assistant passes
    its executor); ``settings`` are those of every source (the schedule's clock).
    ``check_quiet_polls`` reads GetInfo on every poll whose values did not change
    (see the module: HALT/ERR within one poll). Subscribers hear of acknowledged
    writes between polls.
    """

    def __init__(
        self,
        client: TecoApiClient,
        *,
        run_blocking: RunBlocking = _in_executor,
        check_quiet_polls: bool = True,
        **settings: Unpack[SourceSettings],
    ) -> None:
        """Wrap a client; nothing is requested until the first call."""
        super().__init__(wire=client.wire, **settings)
        self.client = client
        self.check_quiet_polls = check_quiet_polls
        self._run_blocking = run_blocking
        self._attributes: dict[str, PointAttributes] = {}
        # The values the latest poll read: a poll that reads the same is quiet.
        self._last_values: Mapping[str, Any] = {}
        self._plans: dict[bool, ReadPlan] = {}
        # The plan of the latest read of some points between polls.
        self._points_plan: ReadPlan | None = None
        self._info_due = NEVER

    # --- what the PlcSource protocol asks --------------------------------------

    @property
    def configuration_url(self) -> str:
        """The PLC's web server."""
        return self.client.base_url

    async def identify(self) -> SourceInfo:
        """GetInfo, and GetList to check that the program publishes variables."""
        info = await self.client.get_info()
        if not await self.client.get_list():
            raise NoPublicVariablesError("The PLC's program publishes no variable")
        return info

    async def write_variable(self, path: str, value: Any) -> Snapshot | None:
        """Write to any path: a known point as :meth:`write`, else as it is.

        A T_ApiObject is its own path or its ``.value`` member. What the PLC holds
        after a write to another path is left to the next poll (None).
        """
        if (key := self._point_key(path)) is not None:
            return await self.write(key, value)
        await self._send(self.client.write_path(path, value))
        return None

    async def read_variable(self, path: str) -> Any:
        """Read any public variable path: its JSON-shaped value."""
        return await self._read(self.client.read_path(path))

    async def read_points(self, keys: Collection[str]) -> Snapshot | None:
        """Read the points' values alone: one GetObject for a few points, no GetInfo.

        The schedule stays as it is. A point gone missing makes GetInfo due and
        the answer None: the next poll tells what happened.
        """
        catalogue = self._catalogue
        if catalogue is None or self._info is None:
            return None
        points = [catalogue.points[key] for key in keys if key in catalogue.points]
        if not points:
            return None
        wanted = frozenset(point.key for point in points)
        plan = self._points_plan
        if (
            plan is None
            or plan.point_keys != wanted
            or plan.item_limit > self.client.item_limit
        ):
            # A few points: planned at once, as a write's read-back is.
            plan = self._points_plan = self.client.plan(points, with_attrs=False)
        result = await self._read(self.client.read(plan, catalogue.points))
        if result.missing:
            self._info_due = self._clock()
            return None
        self._missing = self._missing - wanted
        return self._snapshot(catalogue, result.values, {}, None)

    def diagnostics(self) -> dict[str, Any]:
        """Describe the catalogue's roots, the read plans and the request figures."""
        catalogue = self._catalogue
        return {
            "roots": len(catalogue.groups) if catalogue else 0,
            "skipped_roots": list(catalogue.skipped_groups) if catalogue else [],
            "points": len(catalogue.points) if catalogue else 0,
            "read_plans": {
                "values": _plan(self.read_plan),
                "with_attributes": _plan(self.attribute_plan),
            },
            "requests": {
                "on_the_wire": self.client.request_count,
                "authentication": self.client.auth_scheme,
                "item_limit": self.client.item_limit,
                **asdict(self._statistics),
            },
        }

    async def close(self) -> None:
        """Nothing to release: the HTTP session belongs to whoever made it."""

    # --- TecoApi specifics, for diagnostics and the benchmark --------------------

    @property
    def read_plan(self) -> ReadPlan | None:
        """The plan of value polls (None before the first poll after discovery)."""
        return self._plans.get(False)

    @property
    def attribute_plan(self) -> ReadPlan | None:
        """The plan of polls with attributes (None before the first one)."""
        return self._plans.get(True)

    # --- polling ---------------------------------------------------------------

    async def _discover_catalogue(self, polled: frozenset[str]) -> Snapshot:
        """Discover with GetInfo first (every point is read, polled or not)."""
        return await self._discover(None)

    def _poll_failed(self) -> None:
        """Whatever failed, the PLC may have changed meanwhile: GetInfo is due."""
        self._info_due = self._clock()

    async def _poll(self, catalogue: Catalogue, polled: frozenset[str]) -> Snapshot:
        """One poll after discovery."""
        now = self._clock()
        info = self._info
        assert info is not None  # discovery read it
        with_attrs = now >= self._metadata_due
        info_read_at = None
        if with_attrs or now >= self._info_due or info.mode is not PlcMode.RUNNING:
            info, info_read_at = await self._get_info()
            if _program_changed(self._info, info):
                return await self._discover(info, info_read_at)
            self._info = info
        if info.mode is not PlcMode.RUNNING:
            # A stopped program's values are not read (its attributes neither:
            # they are read when it runs again).
            return self._snapshot(catalogue, {}, {}, info_read_at)
        plan = await self._plan(catalogue, polled, with_attrs=with_attrs)
        result = await self.client.read(plan, catalogue.points)
        if with_attrs:
            self._metadata_due = now + self._metadata_interval
        quiet = self._quiet(result.values)
        self._last_values = result.values
        if info_read_at is None and (
            result.missing - self._missing or (self.check_quiet_polls and quiet)
        ):
            # Variables went missing: a new program may have been downloaded; or
            # nothing changed: the program may have stopped.
            info, info_read_at = await self._get_info()
            if _program_changed(self._info, info):
                return await self._discover(info, info_read_at)
            self._info = info
        self._missing = result.missing
        self._attributes.update(result.attributes)
        return self._snapshot(catalogue, result.values, result.attributes, info_read_at)

    def _quiet(self, values: Mapping[str, Any]) -> bool:
        """Whether a poll read exactly what the previous one read (None counts too)."""
        previous = self._last_values
        for key, value in values.items():
            old = previous.get(key, _ABSENT)
            if old != value or type(old) is not type(value):
                return False
        return True

    async def _get_info(self) -> tuple[SourceInfo, datetime]:
        """GetInfo, and when it answered (the PLC's clock is measured against it)."""
        info = await self.client.get_info()
        self._info_due = NEVER
        return info, self._clock()

    async def _discover(
        self, info: SourceInfo | None, info_read_at: datetime | None = None
    ) -> Snapshot:
        """Discover the program's catalogue: every point's value and metadata."""
        if info is None:
            info, info_read_at = await self._get_info()
        catalogue = await self.client.discover()
        program_changed = self._catalogue is not None
        self._info = info
        self._catalogue = catalogue
        self._plans = {}
        self._points_plan = None
        self._attributes = {
            key: point.attributes
            for key, point in catalogue.points.items()
            if point.attributes is not None
        }
        self._missing = frozenset()
        self._last_values = catalogue.values
        self._metadata_due = self._clock() + self._metadata_interval
        return self._discovered(
            info,
            catalogue,
            catalogue.values,
            dict(self._attributes),
            info_read_at,
            program_changed=program_changed,
        )

    async def _plan(
        self, catalogue: Catalogue, polled: frozenset[str], *, with_attrs: bool
    ) -> ReadPlan:
        """Return the read plan for the polled points.

        Planning is pure CPU work (about 0.1 s for 1000 points): it runs off the
        event loop, and only when the polled points or the item limit changed.
        """
        keys = polled & catalogue.points.keys()
        plan = self._plans.get(with_attrs)
        if (
            plan is None
            or plan.point_keys != keys
            or plan.item_limit > self.client.item_limit
        ):
            points = [catalogue.points[key] for key in keys]
            plan = await self._run_blocking(
                lambda: self.client.plan(points, with_attrs=with_attrs)
            )
            self._plans[with_attrs] = plan
        return plan

    # --- writes ----------------------------------------------------------------
    # The base's template (check all, send, push, read back); here the wire forms,
    # one send for the batch and a read-back of the written points alone.

    def _encode(self, point: Point, value: Any) -> Write[WireValue]:
        """Validate a value with the point's latest attributes; its wire forms."""
        return Write(
            point=point,
            value=value,
            wire=validate_write(point, value),
            shown=_shown(point, value),
        )

    async def _send_writes(self, writes: Sequence[Write[WireValue]]) -> None:
        """Send the batch in SetObjects and PutObjects, each of several variables.

        Consecutive members go in one SetObject (its target within 256
        characters), consecutive top-level variables in one PutObject
        (:meth:`TecoApiClient.write_many`).
        """
        await self.client.write_many(
            [(value_path(write.point), write.value, write.wire) for write in writes]
        )

    def _point(self, key: str) -> Point:
        """Return the catalogue's point with its latest attributes."""
        point = super()._point(key)
        return replace(point, attributes=self._attributes.get(key, point.attributes))

    def _point_key(self, path: str) -> str | None:
        """Return the key of the point at a variable path, if it is one."""
        return point_key(self._catalogue.points if self._catalogue else {}, path)

    async def _send[T](self, write: Awaitable[T], *, values: int = 1) -> T:
        """Await a write, counting it (see the base); a gone variable makes GetInfo due."""
        try:
            return await super()._send(write, values=values)
        except VariableNotFoundError:
            # The variable went away: check the program on the next poll.
            self._info_due = self._clock()
            raise

    async def _read_back(
        self, batch: Sequence[Write[WireValue]], carried: Mapping[str, Any]
    ) -> Snapshot | None:
        """Read back the written points alone: one plan, not a whole poll.

        The PLC program may have changed or clamped a value right away; what the
        PLC holds is what is shown. None when the read-back says nothing (a poll
        will): a variable is gone (GetInfo is then due).
        """
        points = [write.point for write in batch]
        result = await self.client.read(
            self.client.plan(points, with_attrs=False),
            {point.key: point for point in points},
        )
        if result.missing or self._catalogue is None:
            self._info_due = self._clock()
            return None
        self._missing = self._missing - {write.key for write in batch}
        return self._snapshot(self._catalogue, result.values, result.attributes, None)


def _shown(point: Point, value: Any) -> Any:
    """Return a written value as a poll shows it (a text of a date parsed)."""
    shown = parse_value(point.kind, value)
    return value if shown is None else shown


def _program_changed(previous: SourceInfo | None, info: SourceInfo) -> bool:
    """Whether GetInfo reports another user program than before."""
    return (
        previous is not None
        and info.program_stamp is not None
        and info.program_stamp != previous.program_stamp
    )


def _plan(plan: ReadPlan | None) -> dict[str, Any] | None:
    """Describe a read plan: its requests against the lower bound."""
    if plan is None:
        return None
    return {
        "requests": len(plan.requests),
        "lower_bound": plan.lower_bound,
        "item_limit": plan.item_limit,
        "points": len(plan.point_keys),
        "unreadable": sorted(plan.unreadable),
        "targets": [
            {"target": request.target, "items": request.items}
            for request in plan.requests
        ],
    }
