"""An opcconnector gateway's session and subscription: one ``GetUpdatesText`` a poll.

:class:`SubscribedSource` is the lower half of :class:`~.source.TekonSource`
(whose module docstring tells the schedule): it opens a session, subscribes by
name what is polled (and the statuses of the devices it sits on), asks for
the current values after a subscription, reads the updates at a growing
``rid``, takes each update's value and quality (and its device's health), and
keeps an idle session alive.

**Every change.** The session is opened with ``alldata=1``: an answer holds
every change since the previous one, each with its ``UpTime``. They are taken
in that order (:mod:`.changes`: at most ``MOST_CHANGES`` of an item, the ones
between its first and its last collapsed beyond that), and every state
between, up to where an item changes again, is pushed to the listeners
before the poll returns the last: a door that opened and closed within one
poll is shown open, then closed, and an intercom's call that came and went is
a call. An answer too large to read (:data:`~.client.MAX_UPDATES_BYTES`) is
skipped, not asked again (the gateway took its changes): the current values
are asked for and read at once.
"""

import asyncio
from datetime import UTC, datetime, timedelta
import logging
import re
import time
from typing import Any, Final, Unpack

from ..core.exceptions import (
    AccessDeniedError,
    PlcConnectionError,
    PlcError,
    PlcResponseError,
    ResponseTooLargeError,
    ServiceUnavailableError,
)
from ..core.models import (
    Catalogue,
    DataExchange,
    Point,
    PointQuality,
    Quality,
    ValueKind,
)
from ..core.source import BaseSource, SourceSettings
from .catalogue import (
    NO_DATA_EXCHANGE,
    AddressSpace,
    key_of,
    parse_value,
    quality_of,
)
from .changes import MOST_CHANGES, in_order, states
from .client import ItemUpdate, TekonClient

_LOGGER = logging.getLogger(__name__)

_COMMA_NUMBER: Final = re.compile(r"\s*[+-]?[0-9]*,[0-9]+\s*")
_DOT_NUMBER: Final = re.compile(r"\s*[+-]?[0-9]*\.[0-9]+\s*")


class SubscribedSource(BaseSource):
    """A gateway's session and its subscription (see the module's docstring).

    ``keepalive`` is the seconds a session may stay idle.
    """

    def __init__(
        self,
        client: TekonClient,
        *,
        keepalive: float,
        **settings: Unpack[SourceSettings],
    ) -> None:
        """Wrap a client; nothing is requested until the first call."""
        super().__init__(wire=client.wire, **settings)
        self.client = client
        self._keepalive = keepalive
        self._space: AddressSpace | None = None
        self._rid = 1
        # The rid of an updates request whose answer did not arrive (None: none).
        self._unanswered: int | None = None
        self._subscribed: set[str] = set()
        # Items were subscribed: ask for their current values (ReadAllItemsValues),
        # unless the gateway does not know the call.
        self._values_due = False
        self._reads_all_values = True
        # Once a session was (re)opened: compare the address space's hash.
        self._check_hash = False
        self._wanted_for: tuple[Catalogue | None, frozenset[str]] = (None, frozenset())
        self._wanted: dict[str, None] = {}
        self._zone = timedelta(0)
        self._commas = False
        self._last_update: datetime | None = None
        self.sessions = 0
        """Sessions opened (the first one and every one after a loss)."""
        self.collapsed_changes = 0
        """Changes left out: beyond ``MOST_CHANGES`` of an item in one answer."""
        self.skipped_answers = 0
        """Updates answers too large to read, skipped (their changes lost)."""
        self._keeper: asyncio.Task[None] | None = None

    async def _open_session(self) -> None:
        """Open a session: nothing is subscribed in it, its hash is to be compared."""
        await self.client.open_session()
        self.sessions += 1
        self._subscribed.clear()
        self._check_hash = True
        if self._keeper is None and self._keepalive > 0:
            self._keeper = asyncio.get_running_loop().create_task(
                self._keep_alive(), name="opcconnector keepalive"
            )

    async def _read_updates(
        self, catalogue: Catalogue, polled: frozenset[str]
    ) -> dict[str, Any]:
        """Subscribe what is wanted now; read the updates; return the polled values."""
        wanted = self._wanted_names(catalogue, polled)
        if new := [name for name in wanted if name not in self._subscribed]:
            await self.client.subscribe(new)
            self._subscribed.update(new)
            self._values_due = self._reads_all_values
        if gone := [name for name in self._subscribed if name not in wanted]:
            await self.client.unsubscribe(gone)
            self._subscribed.difference_update(gone)
            self._forget({key_of(name) for name in gone})
        if self._values_due and self._subscribed:
            await self._ask_current_values()
        updates = await self._updates()
        return self._take(catalogue, updates, polled)

    async def _updates(self) -> list[ItemUpdate]:
        """``GetUpdatesText`` at the next ``rid``; after a lost answer, twice.

        A ``rid`` asked again is answered again (the seed): the gateway may have
        taken the updates of an answer that never arrived, and repeats them; what
        changed since comes with the next ``rid``, asked at once, so the poll
        shows the values of now, not of the lost answer's time. Should that
        second answer be lost too, the first one's updates still count (the
        gateway will not send them again) and the next poll asks twice again.
        """
        again = self._unanswered == self._rid
        updates = await self._updates_at_rid()
        if again:
            try:
                updates += await self._updates_at_rid()
            except PlcConnectionError as err:
                _LOGGER.debug("The updates after a lost answer were lost: %s", err)
        return updates

    async def _updates_at_rid(self, *, skipping: bool = True) -> list[ItemUpdate]:
        """One ``GetUpdatesText`` at the next ``rid``; a lost answer is noted.

        Lost: no answer came (dropped, timed out). An answer that refuses (409,
        503, 403) took nothing. An answer too large to read took its changes:
        its ``rid`` is not asked again (it would be answered the same), the
        current values are asked for (``ReadAllItemsValues``) and the next
        ``rid`` read at once; should that be too large as well, the poll fails
        (``skipping`` False).
        """
        rid = self._rid
        try:
            updates = await self.client.updates(rid)
        except ResponseTooLargeError as err:
            self._unanswered = None
            self._rid = rid + 1
            self.skipped_answers += 1
            if not skipping:
                raise
            (_LOGGER.warning if self.skipped_answers == 1 else _LOGGER.debug)(
                "The gateway's changes since the previous poll were too many to "
                "read (%s): the current values are read instead",
                err,
            )
            if self._reads_all_values:
                self._values_due = True
                await self._ask_current_values()
            return await self._updates_at_rid(skipping=False)
        except PlcConnectionError as err:
            if not isinstance(err, (ServiceUnavailableError, AccessDeniedError)):
                self._unanswered = rid
            raise
        self._unanswered = None
        self._rid = rid + 1
        return updates

    async def _ask_current_values(self) -> None:
        """``ReadAllItemsValues``: the subscribed items' values come with the next updates.

        A gateway that does not know the call (404) is not asked again: its
        values come as they change. Another failed answer (an error, no
        count, a lost answer or a timeout) is asked again at the next poll;
        none costs the poll: the updates that follow decide it (after a lost
        session, 409, they find no session and the poll opens another; a
        gateway gone fails them too).
        """
        try:
            await self.client.read_all()
        except (PlcConnectionError, PlcResponseError) as err:
            if not isinstance(err, PlcResponseError) or err.status != 404:
                _LOGGER.debug("Asking for the current values failed: %s", err)
                return
            self._reads_all_values = False
            _LOGGER.info(
                "The gateway does not know ReadAllItemsValues: a value is shown "
                "once it changes"
            )
        self._values_due = False

    def _wanted_names(
        self, catalogue: Catalogue, polled: frozenset[str]
    ) -> dict[str, None]:
        """Return the names to subscribe: the readable polled points, their devices' statuses."""
        if self._wanted_for == (catalogue, polled):
            return self._wanted
        assert self._space is not None
        space = self._space
        points = catalogue.points
        names: dict[str, None] = {}
        devices: set[str] = set()
        for key in sorted(polled):
            point = points.get(key)
            if point is None or point.attributes is None:
                continue
            if point.attributes.access.readable:
                names[point.address] = None
            devices.update(space.devices_above.get(point.device, ()))
        for device in sorted(devices):
            if (status := space.status_of.get(device)) is not None:
                names[points[status].address] = None
        self._wanted_for, self._wanted = (catalogue, polled), names
        return names

    def _forget(self, keys: set[str]) -> None:
        """Forget the quality and health of points no longer subscribed."""
        readers = self._space.readers if self._space is not None else {}
        for key in keys:
            self._quality.pop(key, None)
            for reader in readers.get(key, ()):
                self._quality.pop(reader, None)
        if self._space is not None:
            for device, status in self._space.status_of.items():
                if status in keys:
                    self._offline.pop(device, None)

    def _take(
        self, catalogue: Catalogue, updates: list[ItemUpdate], polled: frozenset[str]
    ) -> dict[str, Any]:
        """Take an answer's changes in their order; return the polled values at its end.

        Each state but the last (see the module's docstring) is pushed with the
        qualities and the devices' health of its moment.
        """
        ordered = in_order(updates, MOST_CHANGES)
        if ordered.collapsed:
            self.collapsed_changes += ordered.collapsed
            _LOGGER.debug(
                "%d changes of items changing more than %d times since the "
                "previous poll were left out",
                ordered.collapsed,
                MOST_CHANGES,
            )
        values: dict[str, Any] = {}
        pending: dict[str, Any] | None = None
        for state in states(ordered.changes):
            if pending is not None:
                self._push(pending)
            pending = {}
            for update in state:
                self._take_one(catalogue, update, polled, pending)
            values.update(pending)
        times = [update.time for update in ordered.changes if update.time is not None]
        if times:
            self._last_update = (max(times) - self._zone).replace(tzinfo=UTC)
        return values

    def _take_one(
        self,
        catalogue: Catalogue,
        update: ItemUpdate,
        polled: frozenset[str],
        values: dict[str, Any],
    ) -> None:
        """Note an update's quality (and its device's health); add the polled values.

        The item's value is read into its own point and the points read beside
        it (an intercom's call state and calls).
        """
        assert self._space is not None
        key = (
            key_of(update.name)
            if update.name is not None
            else self._space.ids.get(update.item_id or 0, "")
        )
        for reader in (key, *self._space.readers.get(key, ())):
            if (point := catalogue.points.get(reader)) is None:
                continue
            value, malformed = parse_value(point, update.value)
            quality = quality_of(update.quality) or malformed
            if quality is not None and quality.quality is Quality.UNKNOWN:
                value = None
            if quality is None:
                self._quality.pop(reader, None)
            else:
                self._quality[reader] = quality
            if point.diagnostic:
                self._follow_health(point, value, quality)
            if point.kind is ValueKind.REAL:
                self._learn_separator(update.value)
            if reader in polled:
                values[reader] = value

    def _follow_health(
        self, point: Point, value: Any, quality: PointQuality | None
    ) -> None:
        """Follow a device's status: 0 (its minimum) or a value not good is no data exchange."""
        if quality is not None:
            self._offline[point.device] = quality.reason
        elif point.exchange(value) is not DataExchange.EXCHANGING:
            self._offline[point.device] = NO_DATA_EXCHANGE
        else:
            self._offline.pop(point.device, None)

    def _learn_separator(self, text: str) -> None:
        """Write reals as the gateway writes them: with a decimal comma or a point."""
        if _COMMA_NUMBER.fullmatch(text):
            self._commas = True
        elif _DOT_NUMBER.fullmatch(text):
            self._commas = False

    async def _keep_alive(self) -> None:
        """Send a request whenever the session has been idle ``keepalive`` seconds."""
        while True:
            idle = time.monotonic() - self.client.last_request
            if idle < self._keepalive:
                await asyncio.sleep(self._keepalive - idle)
                continue
            if self.client.session_id is None:
                await asyncio.sleep(self._keepalive)
                continue
            try:
                await self.client.subscribers_count()
            except PlcError as err:
                # The next poll opens a new session.
                _LOGGER.debug("Keeping the session alive failed: %s", err)
