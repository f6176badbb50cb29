"""A simulated opcconnector: Tekon's WEB OPC HTTP API (2.2) over aiohttp.

It speaks the API as the seed writes it (see ``tests/simulator/README.md``,
*Tekon gateway*): sessions, the address space and its hash, subscriptions by ID
and by name, updates with a ``rid`` (with ``alldata=1`` every change since the
previous request, each with its ``UpTime``), reads, writes,
``ServerInformation`` and ``Zabbix``; errors as the seed's table. Its switches
are what real gateways may do: an older API (2.1: no Text reads and writes;
2.0: no Text calls at all), a version told wrong, the changes of an answer
grouped by item, decimal commas, the Text calls at their own URLs or without
``Text``,
OPC DA's initial update of a newly subscribed item (the seed's gateway sends a
value only once it changed, or once ``ReadAllItemsValues`` asked for it), a
gateway without ``ReadAllItemsValues`` (404), sessions that expire, an OPC server that restarts (503) or goes through
configuration mode (every session closed, maybe a new address space), writes
disabled (-1), an allow-list (403), a slow address space, answers lost on the way.
"""

import asyncio
from collections import Counter
from collections.abc import Awaitable, Callable, Iterable
from dataclasses import dataclass, field, replace
from datetime import UTC, datetime, timedelta
import json
import re
from typing import Any, Final, Literal
import uuid

from aiohttp import web

from tests.simulator.base import ConnectionDroppedError, HttpSimulator

from .building import (
    GOOD,
    STATUS,
    VT_BOOL,
    VT_R4,
    VT_R8,
    Building,
    Item,
    small_building,
)

type TextUrls = Literal["both", "text", "plain"]
type UpdatesOrder = Literal["changes", "items"]
LOST: Final = 0
"""A ``failing`` status: the answer is lost (the connection closed without a byte)."""
TEXT_URLS: Final = ("both", "text", "plain")
UPDATES_ORDERS: Final = ("changes", "items")
API_VERSIONS: Final = ("2.2", "2.1", "2.0")
SESSION_TIMEOUT: Final = 120.0
WAIT: Final = 5.0
API_VERSION: Final = "2.2"
CONNECTOR_VERSION: Final = "2.2.0.41"
TEXT_SINCE: Final = {
    "Subscriber": (2, 1),
    "UnSubscriber": (2, 1),
    "GetUpdates": (2, 1),
    "GetSubscribersTextList": (2, 1),
    "ReadItemValueSync": (2, 2),
    "WriteItemsValues": (2, 2),
}
"""The API version each call's Text form (its items by name) came with (seed: history)."""
TIME_FORMAT: Final = "%Y-%m-%d %H:%M:%S"
_INTEGER: Final = re.compile(r"-?[0-9]+")
_REAL_DOT: Final = re.compile(r"-?[0-9]+(?:\.[0-9]+)?")
_REAL_COMMA: Final = re.compile(r"-?[0-9]+(?:,[0-9]+)?")


@dataclass(slots=True)
class _Session:
    alldata: bool
    seen: float
    subscribed: set[str] = field(default_factory=set)
    # Every change since the previous updates, oldest first (copies of the items).
    changes: list[Item] = field(default_factory=list)
    last_rid: int = 0
    last_answer: list[dict[str, Any]] = field(default_factory=list)


class _HttpError(Exception):
    def __init__(self, status: int) -> None:
        super().__init__(status)
        self.status = status


class TekonGateway(HttpSimulator[str]):
    """An opcconnector gateway serving a :class:`Building` (see the module's docstring).

    Every switch may change while it runs: ``api_version`` (``"2.2"``, the
    seed's; ``"2.1"``: the Text reads and writes answer 404 and the plain ones
    take IDs only; ``"2.0"``: no Text call at all), ``reported_version`` (what
    ``ServerInformation`` tells; None: ``api_version``), ``updates_order``
    (``"changes"``: an answer lists the changes as they came; ``"items"``: each
    item's changes together, items in the order of their first change),
    ``decimal_commas``, ``text_urls``
    (``both``; ``text``: the plain URLs take IDs only; ``plain``: the Text URLs
    answer 404 and the plain ones take names, as the seed's examples write them),
    ``initial_data`` (True: a newly subscribed item's value comes with the next
    updates, as OPC DA's initial update; False, the seed: only once it changed or
    ``ReadAllItemsValues`` asked), ``read_all`` (False: ``ReadAllItemsValues``
    answers 404, a gateway without it), ``session_timeout`` (seconds idle),
    ``opc_available`` (False: 503),
    ``writes_enabled`` (False: -1), ``allowed`` (client addresses; None: any),
    ``address_space_delay`` (seconds before the address space is answered),
    ``failing`` (a call's URL, ``ReadAllItemsValues``, answering an HTTP status:
    a gateway's passing failure; 0, the answer lost: the connection is closed
    without a byte),
    ``lost_answers`` (the next N requests are carried out, their connection
    closed before the answer),
    ``zone`` (the gateway's local time minus UTC).
    """

    def __init__(
        self,
        building: Building | None = None,
        *,
        decimal_commas: bool = False,
        text_urls: TextUrls = "both",
        initial_data: bool = False,
        session_timeout: float = SESSION_TIMEOUT,
        zone: timedelta = timedelta(hours=3),
        api_version: str = API_VERSION,
    ) -> None:
        """Serve a building (the small one by default); nothing listens yet."""
        super().__init__()
        self.building = building or small_building()
        self.api_version = api_version
        self.reported_version: str | None = None
        self.updates_order: UpdatesOrder = "changes"
        self.decimal_commas = decimal_commas
        self.text_urls: TextUrls = text_urls
        self.initial_data = initial_data
        self.read_all = True
        self.failing: dict[str, int] = {}
        self.session_timeout = session_timeout
        self.zone = zone
        self.opc_available = True
        self.writes_enabled = True
        self.allowed: frozenset[str] | None = None
        self.address_space_delay = 0.0
        self.lost_answers = 0
        self.sessions: dict[str, _Session] = {}
        self.calls: Counter[str] = Counter()
        self.writes: list[tuple[str, str]] = []
        self.started = self.now()

    # --- running ------------------------------------------------------------------

    client_max_size = 64 * 1024 * 1024

    def _routes(self, app: web.Application) -> None:
        app.router.add_route("*", "/{call}", self._handle)

    # --- what a test or the console changes -----------------------------------------

    def now(self) -> datetime:
        """The gateway's local time (no zone, as it writes it)."""
        return (datetime.now(UTC) + self.zone).replace(tzinfo=None, microsecond=0)

    def set_value(
        self,
        name: str,
        value: str | None = None,
        quality: int = GOOD,
        *,
        at: datetime | None = None,
    ) -> None:
        """Change an item's value (as text, a point for decimals) or quality.

        ``at`` is the change's ``UpTime`` (the gateway's local time; None: now).
        """
        item = self.building.by_name[name]
        if value is not None:
            item.value = value
        item.quality = quality
        item.time = self.now() if at is None else at.replace(microsecond=0)
        self._changed(item)

    def value(self, name: str) -> str:
        """An item's value as stored (a point for decimals)."""
        return self.building.by_name[name].value

    def expire_sessions(self) -> None:
        """Every session is forgotten (as after 120 s idle): the next call is 409."""
        self.sessions.clear()

    def configuration_mode(
        self,
        *,
        add: Iterable[Item] = (),
        remove: Iterable[str] = (),
        first: bool = False,
    ) -> None:
        """The OPC server went through configuration mode: every session is closed.

        Items may come (``first``: before the others, so every ID moves) and go,
        and properties may have changed meanwhile: the address space is
        described again (its hash changes with it).
        """
        self.sessions.clear()
        added = list(add)
        self.building.remove(remove)
        self.building.add(added, first=first)

    def clear_requests(self) -> None:
        """Forget the requests counted so far."""
        self.calls.clear()
        super().clear_requests()

    async def wait_for_call(self, call: str, count: int = 1) -> None:
        """Wait until ``call`` has arrived ``count`` times (counted since the last clear).

        A safety net of ``WAIT`` seconds: a client that never calls fails the
        test (TimeoutError) instead of hanging it.
        """
        async with asyncio.timeout(WAIT):
            await self._progress.wait_until(lambda: self.calls[call] >= count)

    # --- HTTP -----------------------------------------------------------------------

    async def _handle(self, request: web.Request) -> web.StreamResponse:
        call = request.match_info["call"]
        self.calls[call] += 1
        self._record(call)
        if self.failing.get(call) == LOST:
            raise ConnectionDroppedError
        try:
            self._check_allowed(request)
            handler = self._handler(call)
            answer = await handler(request)
        except _HttpError as err:
            return web.Response(status=err.status, text=f"HTTP {err.status}")
        if self.lost_answers > 0:
            # Carried out, but the answer never reaches the client.
            self.lost_answers -= 1
            raise ConnectionDroppedError(reset=False)
        return web.Response(
            body=json.dumps(answer, ensure_ascii=False).encode(),
            content_type="application/json",
        )

    def _handler(self, call: str) -> Callable[[web.Request], Awaitable[Any]]:
        """The handler of a call's URL (404 for none, or a Text URL switched off).

        A call made to fail answers its status instead.
        """
        if (status := self.failing.get(call)) is not None:
            raise _HttpError(status)
        text = call.endswith("Text")
        base = call.removesuffix("Text")
        if text and (self.text_urls == "plain" or not self._has_text_form(base)):
            raise _HttpError(404)
        handlers: dict[str, Callable[[web.Request], Awaitable[Any]]] = {
            "ServerInformation": self._server_information,
            "Zabbix": self._zabbix,
            "NewSession": self._new_session,
            "CloseSession": self._close_session,
            "GetAddressSpaceHash": self._hash,
            "GetAddressSpace": self._address_space,
            "Subscriber": self._subscriber,
            "SubscriberAll": self._subscriber_all,
            "UnSubscriber": self._unsubscriber,
            "GetUpdates": self._updates,
            "ReadAllItemsValues": self._read_all,
            "ReadItemValueSync": self._read_sync,
            "WriteItemsValues": self._write,
            "GetSubscribersCount": self._subscribers_count,
            "GetSubscribersTextList": self._subscribers_text_list,
        }
        texts = {
            "Subscriber",
            "UnSubscriber",
            "GetUpdates",
            "ReadItemValueSync",
            "WriteItemsValues",
        }
        if (
            base not in handlers
            or (text and base not in texts)
            or (base == "ReadAllItemsValues" and not self.read_all)
            or (base == "GetSubscribersTextList" and not self._has_text_form(base))
        ):
            raise _HttpError(404)
        handler = handlers[base]

        async def handle(request: web.Request) -> Any:
            request["text"] = text
            request["base"] = base
            return await handler(request)

        return handle

    def _check_allowed(self, request: web.Request) -> None:
        """Refuse a client whose address is not on the allow-list (403)."""
        if self.allowed is not None and request.remote not in self.allowed:
            raise _HttpError(403)

    def _has_text_form(self, call: str) -> bool:
        """Whether this API version has the call's Text form (items by name)."""
        since = TEXT_SINCE.get(call)
        return since is None or _version(self.api_version) >= since

    def _names_allowed(self, request: web.Request) -> bool:
        """Whether this URL takes item names (a Text URL, or a plain one that does).

        A plain URL takes them only where the API version has the call's Text form.
        """
        return bool(request["text"]) or (
            self.text_urls in ("both", "plain") and self._has_text_form(request["base"])
        )

    def _session(self, request: web.Request) -> _Session:
        session_id = request.query.get("sessionid")
        if not session_id:
            raise _HttpError(400)
        if not self.opc_available:
            raise _HttpError(503)
        now = asyncio.get_running_loop().time()
        for known, idle in list(self.sessions.items()):
            if now - idle.seen > self.session_timeout:
                del self.sessions[known]
        if (session := self.sessions.get(session_id)) is None:
            raise _HttpError(409)
        session.seen = now
        return session

    async def _body(self, request: web.Request) -> Any:
        if not request.can_read_body:
            raise _HttpError(415)
        try:
            return json.loads(await request.text())
        except ValueError as err:
            raise _HttpError(500) from err

    # --- calls ------------------------------------------------------------------------

    async def _server_information(self, request: web.Request) -> Any:
        return {
            "opconn_version": CONNECTOR_VERSION,
            "version": self.reported_version or self.api_version,
            "currenttime": self.now().strftime(TIME_FORMAT),
            "starttime": self.started.strftime(TIME_FORMAT),
        }

    async def _zabbix(self, request: web.Request) -> Any:
        return [
            self._value(item, text=True)
            for item in self.building.items
            if item.channel_type == STATUS
        ]

    async def _new_session(self, request: web.Request) -> Any:
        if not self.opc_available:
            raise _HttpError(503)
        session_id = str(uuid.uuid4()).upper()
        self.sessions[session_id] = _Session(
            alldata=request.query.get("alldata") == "1",
            seen=asyncio.get_running_loop().time(),
        )
        return {"sessionid": session_id}

    async def _close_session(self, request: web.Request) -> Any:
        session_id = request.query.get("sessionid", "")
        self._session(request)
        del self.sessions[session_id]
        return {"result": "ok"}

    async def _hash(self, request: web.Request) -> Any:
        self._session(request)
        return {"result": self.building.hash()}

    async def _address_space(self, request: web.Request) -> Any:
        self._session(request)
        await self._pause(self.address_space_delay)
        return json.loads(self.building.address_space())

    def _named(
        self, request: web.Request, body: Any, by_id: str, by_name: str
    ) -> list[Item]:
        """The items a body names: by ID, or by name where the URL takes names."""
        if not isinstance(body, dict):
            raise _HttpError(500)
        found: list[Item] = []
        if isinstance(ids := body.get(by_id), list):
            found += [
                self.building.items[item_id]
                for item_id in ids
                if isinstance(item_id, int) and 0 <= item_id < len(self.building.items)
            ]
        if isinstance(names := body.get(by_name), list) and self._names_allowed(
            request
        ):
            found += [
                self.building.by_name[name]
                for name in names
                if isinstance(name, str) and name in self.building.by_name
            ]
        return found

    async def _subscriber(self, request: web.Request) -> Any:
        session = self._session(request)
        items = self._named(request, await self._body(request), "items", "itemstext")
        return {"result": self._subscribe(session, items)}

    async def _subscriber_all(self, request: web.Request) -> Any:
        session = self._session(request)
        return {"result": self._subscribe(session, self.building.items)}

    def _subscribe(self, session: _Session, items: Iterable[Item]) -> int:
        added = 0
        for item in items:
            if item.name in session.subscribed:
                continue
            session.subscribed.add(item.name)
            if self.initial_data:
                # OPC DA's initial update: its value comes with the next updates.
                _queue(session, item)
            added += 1
        return added

    async def _read_all(self, request: web.Request) -> Any:
        """Every subscribed item's value now comes with the next updates (0: none)."""
        session = self._session(request)
        items = [
            item
            for name in sorted(session.subscribed)
            if (item := self.building.by_name.get(name)) is not None
        ]
        for item in items:
            _queue(session, item)
        return {"result": len(items)}

    async def _unsubscriber(self, request: web.Request) -> Any:
        session = self._session(request)
        items = self._named(request, await self._body(request), "items", "itemstext")
        removed = 0
        for item in items:
            if item.name in session.subscribed:
                session.subscribed.discard(item.name)
                session.changes = [
                    change for change in session.changes if change.name != item.name
                ]
                removed += 1
        return {"result": removed}

    async def _updates(self, request: web.Request) -> Any:
        session = self._session(request)
        try:
            rid = int(request.query.get("rid", "0"))
        except ValueError as err:
            raise _HttpError(500) from err
        if rid == session.last_rid:
            return session.last_answer
        if rid < session.last_rid:
            return []
        text = bool(request["text"])
        answer = [self._value(change, text=text) for change in self._taken(session)]
        session.changes = []
        session.last_rid, session.last_answer = rid, answer
        return answer

    async def _read_sync(self, request: web.Request) -> Any:
        self._session(request)
        name = request.query.get("itemname")
        item: Item | None = None
        by_name = name is not None and self._names_allowed(request)
        if by_name:
            item = self.building.by_name.get(str(name))
        elif (item_id := request.query.get("item")) is not None and item_id.isdigit():
            index = int(item_id)
            item = (
                self.building.items[index] if index < len(self.building.items) else None
            )
        if item is None:
            return []
        return [self._value(item, text=by_name)]

    async def _write(self, request: web.Request) -> Any:
        session = self._session(request)
        body = await self._body(request)
        if not isinstance(body, list):
            raise _HttpError(500)
        if not self.writes_enabled:
            return {"result": -1}
        done = 0
        for entry in body:
            if not isinstance(entry, dict) or not isinstance(entry.get("Value"), str):
                continue
            item: Item | None = None
            if isinstance(name := entry.get("ItemName"), str) and self._names_allowed(
                request
            ):
                item = self.building.by_name.get(name)
            elif isinstance(item_id := entry.get("ItemID"), int):
                items = self.building.items
                item = items[item_id] if 0 <= item_id < len(items) else None
            if item is None or not item.writable:
                continue
            stored = self._parsed(item, entry["Value"])
            if stored is None:
                continue
            self.writes.append((item.name, entry["Value"]))
            if item.name not in session.subscribed:
                self._subscribe(session, [item])
            self.set_value(item.name, stored)
            done += 1
        return {"result": done}

    def _parsed(self, item: Item, text: str) -> str | None:
        """A written value as stored (None: the OPC server refuses it)."""
        if item.vartype in (VT_R4, VT_R8):
            pattern = _REAL_COMMA if self.decimal_commas else _REAL_DOT
            return text.replace(",", ".") if pattern.fullmatch(text) else None
        if item.vartype == VT_BOOL:
            return text if text in ("0", "1", "-1") else None
        if item.vartype in (18, 19, 3, 2, 16, 17, 20, 21, 22, 23):
            return text if _INTEGER.fullmatch(text) else None
        return text

    async def _subscribers_count(self, request: web.Request) -> Any:
        return {"result": len(self._session(request).subscribed)}

    async def _subscribers_text_list(self, request: web.Request) -> Any:
        return {"itemstext": sorted(self._session(request).subscribed)}

    # --- values ---------------------------------------------------------------------

    def _value(self, item: Item, *, text: bool) -> dict[str, Any]:
        """An item's value as the gateway sends it (by name or by ID)."""
        value = item.value
        if self.decimal_commas and item.vartype in (VT_R4, VT_R8):
            value = value.replace(".", ",")
        answer: dict[str, Any] = {"UpTime": item.time.strftime(TIME_FORMAT), "V": value}
        if text:
            answer["ItemName"] = item.name
        else:
            answer["ItemID"] = item.item_id
        answer["Qual"] = item.quality
        return answer

    def _taken(self, session: _Session) -> list[Item]:
        """What a session's updates answer: every change (alldata=1), else the last.

        In the order of the changes, or each item's together (``updates_order``).
        """
        changes = [
            change for change in session.changes if change.name in self.building.by_name
        ]
        if not session.alldata:
            # The last value of each item changed, in the order of its first change.
            return [self.building.by_name[name] for name in _first_seen(changes)]
        if self.updates_order == "items":
            order = {name: index for index, name in enumerate(_first_seen(changes))}
            return sorted(changes, key=lambda change: order[change.name])
        return changes

    def _changed(self, item: Item) -> None:
        for session in self.sessions.values():
            if item.name in session.subscribed:
                _queue(session, item)


def _first_seen(changes: Iterable[Item]) -> list[str]:
    """The names of the items changed, in the order of their first change."""
    return list(dict.fromkeys(change.name for change in changes))


def _version(text: str) -> tuple[int, ...]:
    """An API version as numbers: ``"2.1"`` → (2, 1)."""
    return tuple(int(part) for part in text.split(".") if part.isdigit())


def _queue(session: _Session, item: Item) -> None:
    """An item's value as it is now comes with the session's next updates."""
    session.changes.append(replace(item))
