"""A Mervis controller as a PLC source: the points of its ``.vlist``, read at the lower bound.

The web panel API lists no variables: the points are the user's map (the IDE's
``.vlist`` export, :func:`~.vlist.load_vlist`). The schedule:

- ``identify()`` signs in and reads a few of the map's variables (spread over
  it) to prove the map is this controller's: when more than half of them are
  unknown, in either ID spelling, the map is refused
  (:class:`~..core.exceptions.VariableNotFoundError`);
- the first poll makes the catalogue of the map and reads every point once;
- every poll reads the polled points with the plan of :mod:`.planner` (one
  range per CommUid, requests packed under the limits), made again only when
  the polled points or the limits change; a refused request is read in halves
  under lower limits (:meth:`MervisClient.learn_refusal`);
- one item's error, or a quality other than good, makes that item's points
  bad (their entities unavailable, with the reason) and costs nothing else.

A write is the base's template: checked by the core's codec (read-only,
range, the data type's bits), sent to ``command.cgi`` one variable at a time,
pushed to the subscribers at once and read back.

**Limits kept.** What the controller told or a refusal taught of its limits is
kept in the entry's store (``cache``): a restart reads at the bound from its
first request, refused nothing.

**Identity.** The web panel API tells nothing of the device: no serial number,
MAC or host name (MERVIS.md), and installers deploy one project to several
units. A controller being added is ``Mervis <project> @ <host[:port]>``, its
project and the address it is added at (a map without a project: ``Mervis
<base URL>``); an entry's identity stays wherever its controller moves, as
long as the map is of the project it names. A unit added where an entry was
added before (that entry moved since) is another: the config flow numbers its
identity (``Mervis <project> @ <host> (2)``, still of the project). Entries
added before this kept ``Mervis <project>`` (:func:`of_project`).
"""

from collections.abc import Collection, Iterable, Mapping, Sequence
from dataclasses import dataclass, field, replace
import itertools
import logging
import re
from typing import Any, Final, Unpack

from ..core.cache import VersionedCache
from ..core.codec import to_shown
from ..core.descriptor import SourceCache
from ..core.exceptions import NoPublicVariablesError, VariableNotFoundError
from ..core.models import Catalogue, Point, PointQuality, Quality, SourceInfo
from ..core.pointmap import MapPoint, PointMap, map_catalogue
from ..core.source import (
    NOT_FOUND,
    BaseSource,
    Snapshot,
    SourceSettings,
    Write,
    counted,
)
from ..core.texts import Template, Text
from .client import Item, MervisClient, RequestRefusedError
from .codec import UndecodableError, decode
from .ids import Address, IdStyle
from .planner import RangeRead, ReadPlan, pack, plan_reads, spanning
from .vlist import projects_of

_LOGGER = logging.getLogger(__name__)

MANUFACTURER: Final = "Unipi Technology"
MODEL: Final = "Mervis"
SAMPLE_SIZE: Final = 8
"""How many of a map's variables ``identify()`` reads."""
SEARCH_REQUESTS: Final = 1
"""Requests a read spends at most on cutting refused ranges, beyond its plan's."""
REJOIN_READS: Final = 3
"""Good reads in a row after which a point read apart joins its neighbours."""
CUT_POLLS: Final = 30
"""Polls after which a cut no point was refused at is tried again (dropped)."""
CACHE_VERSION: Final = 1
"""The shape of what the entry's store keeps (the limits)."""
_BOARD: Final = re.compile(r"hw\.([a-z0-9_]+?)_[a-z]+_[0-9]+\.", re.IGNORECASE)
"""A Unipi board's input or output in the ``hw`` namespace: ``hw.neuron_l203_di_1.01``."""


# Why a variable's value cannot be shown, in a user's words.
NO_ADDRESS: Final = Template(
    "mervis_no_address", "it has no address the controller reads"
)
NOT_ANSWERED: Final = Template(
    "mervis_not_answered", "the controller did not answer it"
)
WRONG_LENGTH: Final = Template(
    "mervis_wrong_length", "the controller answered another length than its own"
)
MARKED: Final = Template("mervis_quality", "the controller marks its value {quality}")
UNDECODABLE: Final = Template(
    "mervis_undecodable", "its bytes cannot be read as its type"
)


def bad(reason: str, text: Text | None = None) -> PointQuality:
    """Return the quality of a point whose value cannot be shown.

    ``text`` says the reason in a user's words (None: it is the controller's).
    """
    return PointQuality(quality=Quality.BAD, reason=reason, text=text)


class MervisSource(BaseSource):
    """One Mervis controller over its web panel API, as a :class:`~..core.source.PlcSource`."""

    def __init__(
        self,
        client: MervisClient,
        point_map: PointMap,
        *,
        identity: str | None = None,
        cache: SourceCache | None = None,
        **settings: Unpack[SourceSettings],
    ) -> None:
        """Wrap a client and a map; nothing is requested until the first call.

        ``identity`` is the entry's (None: a controller being added); ``cache``
        the entry's store, where the limits are kept.
        """
        super().__init__(wire=client.wire, **settings)
        self.client = client
        self.point_map = point_map
        self._entry_identity = identity
        self._cache = VersionedCache(cache, CACHE_VERSION)
        self._kept: dict[str, Any] | None = None
        self._plan: ReadPlan | None = None
        # What the reads learned of the points the controller refuses (see
        # _search): the points read apart (each with its good reads in a row),
        # the points a search under way begins ranges at, the cuts kept (each
        # with the poll that made it); each refused point's refusal (logged).
        self._alone: dict[str, int] = {}
        self._searching: set[str] = set()
        self._cuts: dict[str, int] = {}
        self._polls = 0
        self._refused: dict[str, str] = {}

    # --- who the controller is ------------------------------------------------------

    @property
    def configuration_url(self) -> str:
        """The controller's web panel."""
        return self.client.base_url

    @property
    def identity(self) -> str:
        """What makes two entries the same controller (see the module's docstring)."""
        project = self.point_map.properties.get("project", "").strip()
        kept = self._entry_identity
        if kept is not None and any(
            of_project(kept, name.strip())
            for name in projects_of(self.point_map) or [""]
        ):
            return kept
        if not project:
            return f"{MODEL} {self.client.base_url}"
        return f"{MODEL} {project} @ {self._host}"

    @property
    def _host(self) -> str:
        """Where the controller is reached: its host (and port), as a title says it."""
        return self.client.base_url.partition("://")[2]

    async def identify(self) -> SourceInfo:
        """Sign in, and prove the map is this controller's by reading some of it."""
        await self._restore_limits()
        await self.client.login()
        sample = _sample(self.point_map.points)
        if not sample:
            raise NoPublicVariablesError("The map has no variable to read")
        known = await self._known(sample)
        if known * 2 < len(sample):
            other = (
                IdStyle.SEED
                if self.client.id_style is IdStyle.RELEASED
                else IdStyle.RELEASED
            )
            current = self.client.id_style
            self.client.id_style = other
            if (known_other := await self._known(sample)) > known:
                _LOGGER.debug("%s spells IDs %s", self.client.base_url, other.value)
                known = known_other
            else:
                self.client.id_style = current
        if known * 2 < len(sample):
            raise VariableNotFoundError(
                f"The controller knows {known} of {len(sample)} variables of the file"
            )
        project = self.point_map.properties.get("project", "").strip()
        model = f"{MODEL} {self.client.platform}" if self.client.platform else MODEL
        return SourceInfo(
            identity=self.identity,
            name=project or MODEL,
            manufacturer=MANUFACTURER,
            model=model,
            program_name=project or None,
            location=self._host,
        )

    async def _known(self, sample: list[MapPoint]) -> int:
        """How many of some points the controller answers, each its own ID.

        Read in requests packed under the limits in use; a refused one is
        packed again under the lower limits it teaches (a smaller request, or
        the refusal stands).
        """
        pending = [RangeRead(Address.parse(point.address), ()) for point in sample]
        known = 0
        while pending:
            batch = self._first_request(pending)
            try:
                items = await self.client.values(batch)
            except RequestRefusedError as err:
                if (
                    len(batch) > 1
                    and self.client.learn_refusal(err)
                    and len(self._first_request(pending)) < len(batch)
                ):
                    continue
                raise
            known += sum(
                1
                for address in batch
                if (item := items.get(address)) is not None
                and item.error is None
                and item.value is not None
                and len(item.value) == address.length
            )
            del pending[: len(batch)]
        return known

    async def check_points(self, keys: Collection[str]) -> dict[str, PointQuality]:
        """Sign in and read some of the map's points once: those the controller refuses.

        One request reads them (the planner's: a range per CommUid). The points
        refused are read once more in the other ID spelling (what ``identify()``
        settles on a sample, settled here on the points themselves): the
        spelling the controller knows more of stays, with its reasons.
        """
        await self._restore_limits()
        await self.client.login()
        catalogue = self._catalogue = map_catalogue(self.point_map)
        wanted = [key for key in keys if key in catalogue.points]
        refused = await self._not_read(catalogue, wanted)
        if refused:
            current = self.client.id_style
            self.client.id_style = (
                IdStyle.SEED if current is IdStyle.RELEASED else IdStyle.RELEASED
            )
            again = await self._not_read(catalogue, list(refused))
            if len(again) < len(refused):
                refused = again
            else:
                self.client.id_style = current
        unknown = {key: NOT_FOUND for key in keys if key not in catalogue.points}
        return unknown | refused

    async def _not_read(
        self, catalogue: Catalogue, keys: list[str]
    ) -> dict[str, PointQuality]:
        """Read some points; return those not read, each with its reason."""
        values = await self._read_points(catalogue, keys)
        return {
            key: self._quality.get(key, NOT_FOUND) for key in keys if key not in values
        }

    def _first_request(self, reads: list[RangeRead]) -> list[Address]:
        """Return the IDs of the first request some ranges are packed into."""
        return [read.address for read in self._packed(reads).requests[0].reads]

    # --- the limits kept ---------------------------------------------------------------

    async def _restore_limits(self) -> None:
        """Take the limits the entry's store kept (once a run)."""
        if self._kept is not None or not self._cache.enabled:
            return
        if (kept := await self._cache.load()) is not None:
            self.client.restore_limits(kept.get("limits"))
        self._kept = self.client.limits_state()

    async def _keep_limits(self) -> None:
        """Keep the limits in the entry's store when they changed."""
        if self._kept is None:
            return
        state = self.client.limits_state()
        if state != self._kept:
            await self._cache.save(limits=state)
            self._kept = state

    # --- polling -------------------------------------------------------------------

    async def _discover_catalogue(self, polled: frozenset[str]) -> Snapshot:
        """Identify, make the catalogue of the map, and read every point once."""
        self._info = await self.identify()
        catalogue = map_catalogue(self.point_map)
        self._catalogue = catalogue
        self._replan()
        values = await self._read_points(catalogue, catalogue.points.keys(), poll=True)
        await self._keep_limits()
        catalogue = replace(catalogue, values=values)
        self._catalogue = catalogue
        return self._discovered_map(self._info, catalogue, values)

    async def _poll(self, catalogue: Catalogue, polled: frozenset[str]) -> Snapshot:
        """Read the polled points with the kept plan."""
        self._polls += 1
        self._expire_cuts()
        keys = polled & catalogue.points.keys()
        plan = self._plan
        if plan is None or not self._fits(plan, keys):
            plan = self._plan = self._planned(catalogue, keys)
        values = await self._read_plan(catalogue, plan, poll=True)
        await self._keep_limits()
        return self._snapshot(catalogue, values, {}, None)

    async def read_points(self, keys: Collection[str]) -> Snapshot | None:
        """Read some points now (planned at once), the schedule as it is."""
        catalogue = self._catalogue
        if catalogue is None or self._info is None:
            return None
        wanted = [key for key in keys if key in catalogue.points]
        if not wanted:
            return None
        values = await self._read(self._read_points(catalogue, wanted))
        return self._snapshot(catalogue, values, {}, None)

    @property
    def read_plan(self) -> ReadPlan | None:
        """The plan of the polls (None before the first poll after discovery)."""
        return self._plan

    def _fits(self, plan: ReadPlan, keys: frozenset[str]) -> bool:
        """Whether a plan still reads these points under the limits in use."""
        return (
            plan.point_keys == keys
            and plan.style is self.client.id_style
            and (plan.max_variables, plan.max_bytes) == self._limits()
        )

    def _replan(self) -> None:
        """Make the polls' plan again (the ranges changed: a cut, a point apart)."""
        self._plan = None

    def _planned(self, catalogue: Catalogue, keys: Collection[str]) -> ReadPlan:
        """Plan reading some points under the limits in use, the cuts and lone points kept."""
        return plan_reads(
            (catalogue.points[key] for key in keys),
            max_variables=self.client.max_variables,
            max_bytes=self.client.max_request_size,
            style=self.client.id_style,
            credentials=self._body_credentials(),
            breaks=self._searching | self._cuts.keys(),
            alone=self._alone.keys(),
        )

    def _packed(self, reads: list[RangeRead]) -> ReadPlan:
        """Pack some ranges into requests under the limits in use."""
        return pack(
            reads,
            point_keys=frozenset(),
            max_variables=self.client.max_variables,
            max_bytes=self.client.max_request_size,
            style=self.client.id_style,
            credentials=self._body_credentials(),
        )

    def _body_credentials(self) -> Mapping[str, Any] | None:
        """Return what a request's body carries as ``c`` (its size counts)."""
        client = self.client
        if not client.signs_in:
            return None
        current = client.session_credentials
        return current if current is not None else {"u": "", "p": ""}

    async def _read_points(
        self, catalogue: Catalogue, keys: Collection[str], *, poll: bool = False
    ) -> dict[str, Any]:
        """Read some points with a plan of their own (not kept)."""
        return await self._read_plan(
            catalogue, self._planned(catalogue, keys), poll=poll
        )

    async def _read_plan(
        self, catalogue: Catalogue, plan: ReadPlan, *, poll: bool = False
    ) -> dict[str, Any]:
        """Execute a plan: the shown values; the qualities of the others noted.

        Once a refusal lowered the limits, the requests left are packed again
        under them (none of them is refused for the same reason). Ranges the
        controller refused are searched for the points at fault
        (:meth:`_search`); a poll (which reads every polled point) also ends a
        search that found them all.
        """
        values: dict[str, Any] = {}
        for key in plan.unreadable:
            self._quality[key] = bad("no address", NO_ADDRESS())
        reading = _Reading()
        limits = (plan.max_variables, plan.max_bytes)
        requests = list(plan.requests)
        while requests:
            request = requests.pop(0)
            await self._read_ranges(catalogue, list(request.reads), values, reading)
            if requests and self._limits() != limits:
                limits = self._limits()
                left = [read for request in requests for read in request.reads]
                requests = list(self._packed(left).requests)
        if not reading.answered:
            # Nothing read: nothing tells a point at fault from a controller
            # that refuses everything (a project downloaded anew).
            for key in reading.refused:
                self._quality[key] = replace(self._quality[key], code=None)
            reading.refused.clear()
        await self._search(catalogue, reading, values)
        if poll and not reading.unfinished and self._searching:
            self._searching.clear()
            self._replan()
        self._account(plan.point_keys, values)
        return values

    def _limits(self) -> tuple[int, int]:
        """Return the limits in use: IDs and body bytes per request."""
        return (self.client.max_variables, self.client.max_request_size)

    async def _read_ranges(
        self,
        catalogue: Catalogue,
        reads: list[RangeRead],
        values: dict[str, Any],
        reading: "_Reading",
    ) -> None:
        """Read some ranges in one request; a refused one in parts, under new limits."""
        try:
            items = await self.client.values([read.address for read in reads])
        except RequestRefusedError as err:
            if len(reads) == 1:
                # The controller refuses this variable alone: its points only.
                for key, _ in reads[0].members:
                    self._quality[key] = bad(f"refused: {err.message}")
                return
            self.client.learn_refusal(err)
            for part in _parts(reads, self.client.max_variables):
                await self._read_ranges(catalogue, part, values, reading)
            return
        for read in reads:
            self._take(catalogue, read, items.get(read.address), values, reading)

    def _take(
        self,
        catalogue: Catalogue,
        read: RangeRead,
        item: Item | None,
        values: dict[str, Any],
        reading: "_Reading",
    ) -> None:
        """Slice a range's answer into its points' values, or note why not.

        A range the controller refuses (an item error, no answer, or bytes of
        another length) is a search's suspect while it holds more than one
        point; a point refused alone is the controller's refusal of that
        point: its quality has a code, and it is read apart from now on.
        """
        refusal: str | None = None
        reason: str | None = None
        text: Text | None = None  # the reason in a user's words (else the controller's)
        if item is None:
            refusal, reason, text = "not answered", "not answered", NOT_ANSWERED()
        elif item.error is not None:
            refusal, reason = item.error, f"error: {item.error}"
        elif not item.good:
            reason = f"quality: {item.quality or 'none'}"
            text = MARKED(quality=item.quality or "—")
        elif item.value is None or len(item.value) != read.address.length:
            refusal, reason, text = "wrong length", "wrong length", WRONG_LENGTH()
        else:
            reading.answered = True
        if refusal is not None and len(read.members) > 1:
            reading.failed.append(read)
        for key, member in read.members:
            if reason is not None:
                own = refusal is not None and len(read.members) == 1
                self._quality[key] = PointQuality(
                    quality=Quality.BAD,
                    reason=reason,
                    code=refusal if own else None,
                    text=text,
                )
                if own:
                    reading.refused.add(key)
                continue
            assert item is not None
            assert item.value is not None
            point = catalogue.points[key]
            try:
                raw = decode(point.type, read.slice(item.value, member))
            except UndecodableError as err:
                self._quality[key] = bad(f"undecodable: {err}", UNDECODABLE())
                continue
            values[key] = to_shown(point, raw)
            self._quality.pop(key, None)

    # --- finding the points a refused range holds ----------------------------------------

    async def _search(
        self, catalogue: Catalogue, reading: "_Reading", values: dict[str, Any]
    ) -> None:
        """Read the ranges the controller refused in parts, in one more request.

        Only when the controller answered some other item of the read (a
        controller that refuses everything, a project downloaded anew, is not
        searched: nothing tells a point at fault from a project it no longer
        runs). Each refused range of several points is cut into parts (as many
        as one request holds, shared among them, at least two each); the parts
        are read in :data:`SEARCH_REQUESTS` request, their values count as
        read. The cuts stay (later plans begin ranges there) while a part of
        several points still fails, or a part was not sent: the next reads cut
        those again. A point that fails alone is read apart from now on; a
        range whose every part read is cut there for :data:`CUT_POLLS` polls
        (what the controller refused lies between its points).
        """
        suspects, reading.failed = reading.failed, []
        if not suspects or not reading.answered:
            reading.unfinished = bool(suspects)
            return
        room = max(2, self.client.max_variables // len(suspects))
        splits = [_split(read, room) for read in suspects]
        for split in splits:
            self._searching.update(part.members[0][0] for part in split[1:])
        self._replan()
        parts = [part for split in splits for part in split]
        sent: list[RangeRead] = []
        for request in self._packed(parts).requests[:SEARCH_REQUESTS]:
            sent.extend(request.reads)
            await self._read_ranges(catalogue, list(request.reads), values, reading)
        failed, reading.failed = set(reading.failed), []
        reading.unfinished = bool(failed) or len(sent) < len(parts)
        for split in splits:
            if all(
                part in sent
                and part not in failed
                and reading.refused.isdisjoint(key for key, _ in part.members)
                for part in split
            ):
                # Each part read: what the controller refused lies between them.
                self._cut(part.members[0][0] for part in split[1:])

    def _cut(self, keys: Iterable[str]) -> None:
        """Begin ranges at some points for :data:`CUT_POLLS` polls."""
        self._cuts.update(dict.fromkeys(keys, self._polls))
        self._replan()

    def _expire_cuts(self) -> None:
        """Drop the cuts made :data:`CUT_POLLS` polls ago: their neighbours read together."""
        expired = [
            key for key, since in self._cuts.items() if self._polls - since >= CUT_POLLS
        ]
        for key in expired:
            del self._cuts[key]
        if expired:
            self._replan()

    def _account(self, read: Collection[str], values: Mapping[str, Any]) -> None:
        """Follow the points read apart: log when one starts failing, rejoin good ones.

        A point the controller refuses is read apart, its refusal logged once
        (and once when it reads again); one that reads :data:`REJOIN_READS`
        times in a row joins its neighbours again.
        """
        for key in read:
            quality = self._quality.get(key)
            refused = quality is not None and quality.code is not None
            if refused:
                assert quality is not None
                # Read alone already (the plan's range or the search's part).
                self._alone[key] = 0
                if self._refused.get(key) != quality.code:
                    _LOGGER.warning(
                        "%s of the controller %s cannot be read, its entity is "
                        "unavailable: %s",
                        key,
                        self.client.base_url,
                        quality.reason,
                    )
                self._refused[key] = quality.code or ""
                continue
            if key in values and self._refused.pop(key, None) is not None:
                _LOGGER.info("%s reads again", key)
            if key in values and key in self._alone:
                self._alone[key] += 1
                if self._alone[key] >= REJOIN_READS:
                    del self._alone[key]
                    self._replan()

    # --- writes --------------------------------------------------------------------
    # The base's template: ``command.cgi`` uses only a command's first item on
    # uPLC (MERVIS.md), so each value is a request of its own (the base's sends);
    # the read-backs are one read of all (the base's, :meth:`read_points`).

    def _encode(self, point: Point, value: Any) -> Write[tuple[Address, Any]]:
        """Check a value by the core's codec and the wire's forms; its raw value."""
        write = super()._encode(point, value)
        address = Address.parse(point.address)
        self.client.write_forms(address, point.type, point.path, write.wire)
        return Write(
            point=point, value=value, wire=(address, write.wire), shown=write.shown
        )

    def _sends(
        self, batch: Sequence[Write[tuple[Address, Any]]]
    ) -> Iterable[Sequence[Write[tuple[Address, Any]]]]:
        """Each value alone: a request of its own, pushed once the controller took it."""
        return ([write] for write in batch)

    async def _send_writes(self, writes: Sequence[Write[tuple[Address, Any]]]) -> None:
        """Write each value with ``command.cgi``."""
        for write in writes:
            address, raw = write.wire
            point = write.point
            await self.client.write(address, point.type, point.path, raw)

    async def write_variable(self, path: str, value: Any) -> Snapshot | None:
        """Write a point by its ID (the web panel has no paths beyond the map's)."""
        return await self.write(self._map_key(path), value)

    async def read_variable(self, path: str) -> Any:
        """Read a point by its ID."""
        key = self._map_key(path)
        assert self._catalogue is not None
        values = await self._read(self._read_points(self._catalogue, [key]))
        if key not in values:
            raise VariableNotFoundError(
                f"{path!r} cannot be read: {self._quality[key].reason}", path=path
            )
        return values[key]

    # --- the rest ------------------------------------------------------------------

    def diagnostics(self) -> dict[str, Any]:
        """Describe the map, the plan, the limits and the requests (no credentials).

        ``points``, ``read_plans`` and ``requests`` are the keys a diagnostics
        download shows of every source.
        """
        plan = self._plan
        client = self.client
        point_map = self.point_map
        return {
            "points": len(point_map.points),
            "project": {
                "name": point_map.properties.get("project", "").strip() or None,
                "projects": projects_of(point_map),
                "format": point_map.format,
                "skipped_rows": len(point_map.skipped),
                "boards": boards(point_map),
            },
            "read_plans": {
                "values": None
                if plan is None
                else {
                    "requests": len(plan.requests),
                    "lower_bound": plan.lower_bound,
                    "ids": plan.ids,
                    "points": len(plan.point_keys),
                    "unreadable": sorted(plan.unreadable),
                },
                "limits": {
                    "max_variables": client.max_variables,
                    "max_request_size": client.max_request_size,
                    "told": client.limits_told,
                },
                "platform": client.platform,
                "id_style": client.id_style.value,
                "write_format": client.write_format,
                "signs_in": client.signs_in,
                "bad_points": {
                    key: quality.reason
                    for key, quality in sorted(self._quality.items())
                },
                "read_apart": sorted(self._alone),
                "cuts": sorted(self._searching | self._cuts.keys()),
            },
            "requests": {
                "on_the_wire": client.request_count,
                "logins": client.logins,
                **counted(self._statistics, None),
            },
        }

    async def close(self) -> None:
        """Nothing to release: the HTTP session belongs to whoever made it."""


def boards(point_map: PointMap) -> list[str]:
    """Return the Unipi boards a map's ``hw`` variables name: ``neuron_l203``.

    Each input's and output's ID says its board before its kind and its group
    (``hw.neuron_l203_di_1.01``: the board ``neuron_l203``, digital input 1.01).
    """
    return sorted(
        {
            found[1].lower()
            for point in point_map.points
            if (found := _BOARD.match(point.id)) is not None
        }
    )


def of_project(identity: str, project: str) -> bool:
    """Whether an entry's identity is of a map of this project, wherever it is.

    ``Mervis <project>`` (entries added before two units of one project could
    be), ``Mervis <project> @ <address>``; without a project ``Mervis <base URL>``;
    either numbered by the config flow (``... (2)``).
    """
    if not project:
        return identity.startswith((f"{MODEL} http://", f"{MODEL} https://"))
    head, at, _ = identity.rpartition(" @ ")
    return identity == f"{MODEL} {project}" or (
        bool(at) and head == f"{MODEL} {project}"
    )


def _sample(points: Iterable[MapPoint]) -> list[MapPoint]:
    """Up to :data:`SAMPLE_SIZE` points spread evenly over a map, one per variable."""
    by_variable: dict[tuple[str, int], MapPoint] = {}
    for point in points:
        try:
            address = Address.parse(point.address)
        except ValueError:
            continue
        by_variable.setdefault(address.variable, point)
    chosen = list(by_variable.values())
    if len(chosen) <= SAMPLE_SIZE:
        return chosen
    step = len(chosen) / SAMPLE_SIZE
    return [chosen[int(index * step)] for index in range(SAMPLE_SIZE)]


def _split(read: RangeRead, count: int) -> list[RangeRead]:
    """Cut a range's points (in order) into ``count`` ranges as even as can be (at most one a point)."""
    members = read.members
    count = min(count, len(members))
    bounds = [len(members) * index // count for index in range(count + 1)]
    return [spanning(members[low:high]) for low, high in itertools.pairwise(bounds)]


@dataclass(slots=True)
class _Reading:
    """What one read of points (a poll, a read-back) learned of the ranges refused."""

    answered: bool = False
    """Whether the controller answered some item with a good value."""
    failed: list[RangeRead] = field(default_factory=list)
    """Ranges of several points it refused, not yet searched."""
    refused: set[str] = field(default_factory=set)
    """Points it refused alone."""
    unfinished: bool = False
    """Whether a search is left for later reads (a part failed, or was not sent)."""


def _parts(reads: list[RangeRead], size: int) -> list[list[RangeRead]]:
    """Cut ranges into parts of ``size`` (at most half of them, at least one)."""
    size = max(1, min(size, len(reads) // 2))
    return [reads[start : start + size] for start in range(0, len(reads), size)]
