"""Reading an FP-I4C's points: the planner's POSTs, and the failing addresses isolated.

:class:`GatewayReader` is the reading half of :class:`~.source.FpI4cSource`
(whose module docstring tells the behaviour): it reads points in the POSTs
of the planner, takes their answers, halves the requests that fail until the
failing points are alone, and keeps what a read learned (the points' quality,
the stations' health).
"""

from abc import abstractmethod
from collections import defaultdict
from collections.abc import Collection, Iterable
from dataclasses import dataclass, field
import logging
from typing import Any, Final, Unpack

from ..core.codec import to_shown
from ..core.exceptions import PlcConnectionError
from ..core.models import PointQuality, Quality
from ..core.source import BaseSource, SourceSettings
from ..core.texts import Template, Text
from .client import (
    FpI4cClient,
    GatewayError,
    ItemAnswer,
    ItemError,
    PlcNotAnsweringError,
)
from .mapping import device_key, device_name, station_named
from .planner import (
    MAX_REQUESTS,
    Post,
    ReadPlan,
    ReadRequest,
    Target,
    covering,
    plan_reads,
)

_LOGGER = logging.getLogger(__name__)

UNREADABLE: Final = Template("fpi4c_unreadable", "the gateway answered no value for it")
MALFORMED_ITEM: Final = Template(
    "fpi4c_malformed_item", "the gateway's answer for it cannot be read"
)
_PLANS_KEPT: Final = 8
SEARCH_POSTS: Final = 1
"""POSTs a read spends at most per station on halving failed requests, beyond
its plan's (the planner's bound): a request of 100 values is down to its single
failing value after ``ceil(log2(100))`` = 7 reads."""
REJOIN_READS: Final = 3
"""Good reads in a row after which a point read alone joins its neighbours."""
CUT_POLLS: Final = 30
"""Polls after which a cut no point failed at is tried again (dropped)."""


@dataclass(slots=True)
class Reading:
    """What one read of points (a poll, a read-back) gathered."""

    values: dict[str, Any] = field(default_factory=dict)
    bad: dict[str, PointQuality] = field(default_factory=dict)
    answered: set[int | None] = field(default_factory=set)
    """Stations of which at least one item was answered."""
    failures: dict[int | None, str] = field(default_factory=dict)
    """Each station's first failure, as its reason."""
    errors: dict[str, ItemError] = field(default_factory=dict)
    """Each point's failed item."""
    failed: list[tuple[int | None, ReadRequest]] = field(default_factory=list)
    """The requests that failed (not yet halved), by station."""


class GatewayReader(BaseSource):
    """Reads a gateway's points, isolating failing addresses (see the module)."""

    def __init__(self, client: FpI4cClient, **settings: Unpack[SourceSettings]) -> None:
        """Read nothing yet."""
        super().__init__(wire=client.wire, **settings)
        self.client = client
        self._targets: dict[str, Target] = {}
        self._plans: dict[frozenset[str], ReadPlan] = {}
        # What the reads learned about failing addresses (see _search): the
        # points read alone (each with its good reads in a row), the points
        # that begin a request (each with the poll that cut there), the
        # halvings of each station's search under way; each failing point's
        # item now.
        self._alone: dict[str, int] = {}
        self._cuts: dict[str, int] = {}
        self._retried: set[str] = set()
        self._searching: dict[int | None, set[str]] = {}
        self._polls = 0
        self._errors: dict[str, ItemError] = {}
        self.read_plan: ReadPlan | None = None
        """The plan of the latest poll (for diagnostics and the benchmark)."""
        # Writes acknowledged so far, and the count when each point was last
        # written: a read sent before then shows an older value.
        self._writes_done = 0
        self._written: dict[str, int] = {}

    @property
    @abstractmethod
    def _gateway(self) -> str:
        """The gateway as its log lines name it."""

    # --- reading -------------------------------------------------------------------

    def plan(self, keys: Iterable[str]) -> ReadPlan:
        """Return the plan of some points' reads (kept while they stay the same)."""
        wanted = frozenset(key for key in keys if key in self._targets)
        plan = self._plans.get(wanted)
        if plan is None:
            if len(self._plans) >= _PLANS_KEPT:
                self._plans.clear()
            plan = self._plans[wanted] = plan_reads(
                (self._targets[key] for key in wanted),
                breaks=self._breaks(),
                alone=self._alone.keys(),
            )
        return plan

    def _breaks(self) -> set[str]:
        """Return the points that begin a request: the cuts and the searches' halvings."""
        return set(self._cuts).union(*self._searching.values())

    async def _read_keys(
        self, keys: Collection[str], *, poll: bool = False
    ) -> dict[str, Any]:
        """Read some points; note their quality and their stations' health.

        A POST nothing answered costs its station only while another POST of
        the read was answered; when none was, the read fails. A poll's plan is
        kept as :attr:`read_plan`.
        """
        if poll:
            self._polls += 1
            self._expire_cuts()
        plan = self.plan(keys)
        if poll:
            self.read_plan = plan
        begun = self._writes_done
        reading = Reading()
        unreachable: PlcConnectionError | None = None
        for post in plan.posts:
            try:
                answers = await self.client.post(
                    [request.body() for request in post.requests], post.station
                )
            except PlcConnectionError as err:
                unreachable = unreachable or err
                reading.failures.setdefault(post.station, f"no answer: {err}")
                continue
            except GatewayError as err:
                reading.failures.setdefault(post.station, f"refused: {err}")
                continue
            self._take(post, answers, reading)
        if unreachable is not None and not reading.answered:
            raise unreachable
        await self._search(plan, reading)
        self._account(plan, reading)
        # A point written since this read began shows what the write left.
        return {
            key: value
            for key, value in reading.values.items()
            if self._written.get(key, 0) <= begun
        }

    def _take(self, post: Post, answers: list[ItemAnswer], reading: Reading) -> None:
        """Take one POST's answers: values by point, bad points, station health."""
        catalogue = self._catalogue
        assert catalogue is not None
        for request, answer in zip(post.requests, answers, strict=True):
            if (error := answer.error) is not None:
                reading.failures.setdefault(post.station, reason(error))
                # Only a request of one address tells that the code is its
                # points'; the points of a longer one wait for the search.
                own = len(request.indices) == 1
                bad = PointQuality(
                    quality=Quality.BAD,
                    reason=reason(error),
                    text=reason_text(error),
                    code=error.code if own else None,
                )
                reading.bad.update((key, bad) for key, _ in request.points)
                if own:
                    reading.errors.update((key, error) for key, _ in request.points)
                reading.failed.append((post.station, request))
                _LOGGER.debug("%s failed: %s", request.name, error)
                continue
            reading.answered.add(post.station)
            for key, index in request.points:
                reading.errors.pop(key, None)
                raw = answer.values[index] if index < len(answer.values) else None
                if raw is None:
                    reading.bad[key] = PointQuality(
                        quality=Quality.BAD, reason="unreadable", text=UNREADABLE()
                    )
                    continue
                reading.bad.pop(key, None)
                reading.values[key] = to_shown(catalogue.points[key], raw)

    async def _search(self, plan: ReadPlan, reading: Reading) -> None:
        """Halve the requests that failed, in one more POST a station.

        Only a station that answered other items is searched (one whose every
        item failed is offline: nothing tells a bad address from a PLC that
        does not answer). Its POST halves at most ten failed requests; the
        halves' values count as read. While halves still fail, the halving
        points stay the station's search (:attr:`_searching`: later plans
        begin requests there, and the next read halves what fails again);
        once none does, they go, and what is left apart is what isolates the
        failures: the single failing addresses (:attr:`_alone`) and, where
        both halves of a failed request read, a cut between them
        (:attr:`_cuts`).
        """
        halves: dict[
            int | None, list[tuple[frozenset[str], ReadRequest, ReadRequest]]
        ] = defaultdict(list)
        unfinished: set[int | None] = set()
        for station, request in self._suspects(reading):
            if 2 * len(halves[station]) + 2 <= MAX_REQUESTS:
                halves[station].append(self._halve(station, request))
            else:
                unfinished.add(station)
        self._retried.clear()
        for station, pairs in halves.items():
            requests = [half for _, *two in pairs for half in two]
            try:
                answers = await self.client.post(
                    [request.body() for request in requests], station
                )
            except (PlcConnectionError, GatewayError):
                # The plan's failures stand; the next read halves them again.
                unfinished.add(station)
                continue
            self._take(Post(station, tuple(requests)), answers, reading)
            for (middle, _, _), low, high in zip(
                pairs, answers[::2], answers[1::2], strict=True
            ):
                if low.error is None and high.error is None:
                    self._cut(middle)
        unfinished.update(station for station, _ in self._suspects(reading))
        for station in reading.answered & {post.station for post in plan.posts}:
            if station not in unfinished and station in self._searching:
                del self._searching[station]
                self._plans.clear()

    def _suspects(self, reading: Reading) -> list[tuple[int | None, ReadRequest]]:
        """Take the failed requests of stations that answered: those to halve.

        A failed request of one address is that address's: its points are
        read alone from now on.
        """
        suspects: list[tuple[int | None, ReadRequest]] = []
        for station, request in reading.failed:
            if station not in reading.answered:
                continue
            if len(request.indices) > 1:
                suspects.append((station, request))
                continue
            for key, _ in request.points:
                if key not in self._alone:
                    self._plans.clear()
                self._alone[key] = 0
        reading.failed = []
        return suspects

    def _halve(
        self, station: int | None, request: ReadRequest
    ) -> tuple[frozenset[str], ReadRequest, ReadRequest]:
        """Split a request's points in two at their middle address.

        A cut this poll dropped (:meth:`_expire_cuts`) splits first: when its
        failing address is still there, both halves read in this one POST.
        Returns the middle's points (noted in the station's search) and the
        two halves.
        """
        indices = sorted(request.indices)
        middle = min(
            (
                index
                for key, index in request.points
                if key in self._retried and index > indices[0]
            ),
            default=indices[len(indices) // 2],
        )
        keys = frozenset(key for key, index in request.points if index == middle)
        self._searching.setdefault(station, set()).update(keys)
        self._plans.clear()
        return (
            keys,
            covering(
                self._targets[key] for key, index in request.points if index < middle
            ),
            covering(
                self._targets[key] for key, index in request.points if index >= middle
            ),
        )

    def _cut(self, keys: Iterable[str]) -> None:
        """Begin requests at some points from now on (for :data:`CUT_POLLS` polls)."""
        self._cuts.update(dict.fromkeys(keys, self._polls))
        self._plans.clear()

    def _expire_cuts(self) -> None:
        """Drop the cuts made :data:`CUT_POLLS` polls ago: their neighbours read together.

        This poll's search splits a failed request at such a cut first.
        """
        self._retried = {
            key for key, since in self._cuts.items() if self._polls - since >= CUT_POLLS
        }
        for key in self._retried:
            del self._cuts[key]
        if self._retried:
            self._plans.clear()

    def _rejoin(self, key: str, bad: bool) -> None:
        """Count a lone point's good reads; after :data:`REJOIN_READS` it rejoins."""
        if key not in self._alone:
            return
        if bad:
            self._alone[key] = 0
            return
        self._alone[key] += 1
        if self._alone[key] >= REJOIN_READS:
            del self._alone[key]
            self._plans.clear()

    def _account(self, plan: ReadPlan, reading: Reading) -> None:
        """Keep what a read learned: the points' quality, the stations' health."""
        read = plan.point_keys
        stations = {post.station for post in plan.posts}
        offline = {station for station in stations if station not in reading.answered}
        for key in read:
            if self._targets[key].station in offline:
                # Its station's reason stands for it.
                self._quality.pop(key, None)
                self._errors.pop(key, None)
            elif key in reading.bad:
                self._quality[key] = reading.bad[key]
                if key in reading.errors:
                    self._follow_error(key, reading.errors[key])
                self._rejoin(key, bad=True)
            else:
                self._quality.pop(key, None)
                self._follow_error(key, None)
                self._rejoin(key, bad=False)
        for station in stations:
            device = device_key(station)
            if station in offline:
                reason = reading.failures.get(station, "no answer")
                if device not in self._offline:
                    self._note(
                        "poll",
                        PlcNotAnsweringError(f"{device_name(station)}: {reason}"),
                    )
                    _LOGGER.info(
                        "%s behind the FP-I4C gateway %s does not answer, its "
                        "entities are unavailable: %s",
                        station_named(station),
                        self._gateway,
                        reason,
                    )
                self._offline[device] = reason
            elif self._offline.pop(device, None) is not None:
                _LOGGER.info(
                    "%s behind the FP-I4C gateway %s answers again",
                    station_named(station),
                    self._gateway,
                )

    def _follow_error(self, key: str, error: ItemError | None) -> None:
        """Keep a point's failed item; log when it starts failing, changes, reads again."""
        known = self._errors.pop(key, None)
        if error is None:
            if known is not None:
                _LOGGER.info("%s reads again", key)
            return
        self._errors[key] = error
        if known is None or known.code != error.code:
            _LOGGER.warning(
                "%s cannot be read, its entity is unavailable: %s", key, error
            )


def reason(error: ItemError) -> str:
    """Return a failed item as a reason (a point's, a station's): code and message."""
    return f"err_code {error.code}: {error.message}"


def reason_text(error: ItemError) -> Text | None:
    """Return a failed item's reason in a user's words (None: the gateway's code says it).

    An item without a code is one the gateway's answer got wrong: its message
    is the library's.
    """
    return None if error.code else MALFORMED_ITEM()
