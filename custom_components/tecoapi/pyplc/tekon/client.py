"""The opcconnector client: one async class speaking Tekon's WEB OPC HTTP API.

``opcconnector.exe`` (Tekon's ASUD.SCADA) is an HTTP gateway in front of an OPC
DA server. A client opens a session (``alldata=1``: every change between two
updates, not only the last), reads the address space (only when its hash
changed), subscribes items by name and polls their updates with a growing
``rid``; it writes by name. The aiohttp session is injected and never closed
here; requests go out one at a time, each with the client's timeout.

**The ``…Text`` calls.** API 2.1 added ``SubscriberText``, ``GetUpdatesText``
and the like (items by name rather than by ``ItemID``, which moves when the
address space changes); API 2.2 added the Text forms of the reads and writes,
which the seed's own examples reach at the URL *without* ``Text``
(``/WriteItemsValues`` with ``ItemName``); before 2.1 everything went by
``ItemID``. Each Text call is tried at its ``…Text`` URL first; a gateway that
answers 404 there is asked at the plain URL from then on, with each item's
name *and* its ``ItemID`` (:attr:`TekonClient.item_id`: the IDs of the address
space the current session's hash was checked against): a 2.2 gateway that
takes names there and a 2.1 or 2.0 one that takes IDs only are both answered
right. A call the version ``ServerInformation`` told has no Text form yet is
asked at the plain URL at once (a gateway that tells a wrong version, or none,
is still answered right: a 404 moves a call there). A plain ``GetUpdates``
answers ``ItemID``s: :class:`ItemUpdate` then carries the ID and no name.

**Sizes.** Nothing a gateway sends may grow memory without bound: an answer is
read a chunk at a time and refused past its cap (:data:`MAX_ANSWER_BYTES` for
small answers, :data:`MAX_UPDATES_BYTES` for updates,
:data:`MAX_ADDRESS_SPACE_BYTES` for the address space).

**Errors** by HTTP status: 403 :class:`AccessDeniedError` (this client's
address is not on the gateway's allow-list), 409 :class:`SessionLostError` (the
session is gone: open a new one), 503 :class:`ServiceUnavailableError` (the OPC
server is unavailable, being restarted), anything else
:class:`PlcResponseError`. A session ID is never part of a message.
"""

from collections import Counter
from collections.abc import Callable, Collection, Iterable, Mapping, Sequence
import contextlib
from dataclasses import dataclass
from datetime import datetime
import json
from typing import Any, Final
from urllib.parse import urlencode

import aiohttp

from ..core.exceptions import (
    AccessDeniedError,
    MalformedResponseError,
    NotAPlcError,
    PlcConnectionError,
    PlcError,
    PlcResponseError,
    ServiceUnavailableError,
    ValueRejectedError,
    WritesDisabledError,
)
from ..core.host import normalize_host
from ..core.http import HttpClient, HttpExchange, Reply, utf8_or

MAX_ANSWER_BYTES: Final = 1024 * 1024
"""The most bytes of a small answer (a session, a hash, a count, a write's result)."""
MAX_UPDATES_BYTES: Final = 32 * 1024 * 1024
"""The most bytes of an updates answer (some 300,000 changes; a larger one is skipped)."""
MAX_ADDRESS_SPACE_BYTES: Final = 128 * 1024 * 1024
"""The most bytes of an address space: some 100,000 items of a dozen properties."""
SUBSCRIBE_BATCH: Final = 1000
"""Names per subscription request."""
FALLBACK_ENCODING: Final = "cp1251"
"""What a Russian Windows program writes when it is not UTF-8."""
TIME_FORMAT: Final = "%Y-%m-%d %H:%M:%S"
WRITES_DISABLED: Final = -1
SERVER_INFORMATION: Final = "ServerInformation"
"""The call a gateway answers without a session: its versions and its clock."""

TEXT_SINCE: Final[Mapping[str, tuple[int, ...]]] = {
    "Subscriber": (2, 1),
    "UnSubscriber": (2, 1),
    "GetUpdates": (2, 1),
    "ReadItemValueSync": (2, 2),
    "WriteItemsValues": (2, 2),
}
"""The API version each call's Text form came with (the seed's version history)."""

type ItemIds = Callable[[str], int | None]
"""An item's ``ItemID`` by its name, in one address space (None: not in it)."""


class SessionLostError(PlcResponseError):
    """The gateway no longer knows the session (409): open a new one."""


@dataclass(frozen=True, slots=True, kw_only=True)
class ServerInformation:
    """What ``ServerInformation`` tells without a session.

    ``current_time`` and ``start_time`` are the gateway's local time (no zone).
    ``version`` is the API version as numbers (None: not one).
    """

    api_version: str
    connector_version: str
    current_time: datetime | None
    start_time: datetime | None

    @property
    def version(self) -> tuple[int, ...] | None:
        """The API version as numbers: ``"2.1"`` is (2, 1) (None: not a version)."""
        return api_version(self.api_version)


def api_version(text: str) -> tuple[int, ...] | None:
    """Read an API version: ``"2.1"`` is (2, 1); anything else None."""
    parts = text.strip().split(".")
    if not all(part.isdigit() for part in parts):
        return None
    return tuple(int(part) for part in parts)


@dataclass(frozen=True, slots=True, kw_only=True)
class AddressItem:
    """One item of the address space: its name, its ID now, its properties by ID."""

    name: str
    item_id: int
    properties: Mapping[int, str]


@dataclass(frozen=True, slots=True, kw_only=True)
class ItemUpdate:
    """One value of an updates answer (or of a read).

    ``name`` is None where the gateway answered by ``ItemID`` only; ``time`` is
    the gateway's local time of the value (None: none given).
    """

    name: str | None
    item_id: int | None
    value: str
    quality: int
    time: datetime | None


def parse_time(text: Any) -> datetime | None:
    """Parse the gateway's ``YYYY-MM-DD hh:mm:ss`` (naive: its local time)."""
    if not isinstance(text, str):
        return None
    try:
        return datetime.strptime(text.strip(), TIME_FORMAT)  # noqa: DTZ007 (local)
    except ValueError:
        return None


decode: Final = utf8_or(FALLBACK_ENCODING)
"""Decode an answer: UTF-8, else Windows-1251."""


class TekonClient(HttpClient):
    """An async client of one opcconnector gateway (see the module's docstring).

    ``request_count`` counts the requests sent, ``calls`` them by call name
    (``GetUpdatesText``); ``last_request`` is the monotonic time of the latest.
    ``item_id`` gives an item's ``ItemID`` by its name in the address space
    the session's hash was last checked against (None: not checked in this
    session); its caller sets it. ``max_updates_bytes`` caps an updates answer.
    """

    def __init__(
        self,
        session: aiohttp.ClientSession,
        host: str,
        *,
        verify_ssl: bool = True,
        timeout: float = 10.0,
        alldata: bool = True,
    ) -> None:
        """Prepare a client; nothing is sent until the first call."""
        self.base_url = normalize_host(host)
        self._http = HttpExchange(
            session,
            self.base_url,
            sender="a gateway",
            limit=MAX_ANSWER_BYTES,
            timeout=timeout,
            verify_ssl=verify_ssl,
            statuses={
                range(201, 300): self._unexpected,
                403: self._access_denied,
                409: self._session_lost,
                503: self._unavailable,
            },
            otherwise=self._unexpected,
            decode=decode,
        )
        self._alldata = alldata
        self._session_id: str | None = None
        # Text calls this gateway answers only at the URL without "Text".
        self.plain_text_calls: set[str] = set()
        self.item_id: ItemIds | None = None
        self.max_updates_bytes = MAX_UPDATES_BYTES
        self.calls: Counter[str] = Counter()

    @property
    def last_request(self) -> float:
        """The monotonic time of the latest request."""
        return self._http.last_sent

    @property
    def alldata(self) -> bool:
        """Whether sessions are opened for every change (``alldata=1``), not the last."""
        return self._alldata

    @property
    def session_id(self) -> str | None:
        """The open session's ID (None: none open)."""
        return self._session_id

    def forget_session(self) -> None:
        """Count the session as gone (the gateway closed it, or its server restarted)."""
        self._session_id = None

    # --- HTTP -----------------------------------------------------------------

    async def _request(
        self,
        call: str,
        *,
        params: Mapping[str, str | int] | None = None,
        body: Any = None,
        limit: int = MAX_ANSWER_BYTES,
        session: bool = True,
        check: bool = True,
    ) -> Reply:
        """Send one request of a call; return its answer (its status ``check``-ed)."""
        query = dict(params or {})
        if session:
            if self._session_id is None:
                raise SessionLostError("No session is open", status=409)
            query = {"sessionid": self._session_id, **query}
        target = f"/{call}"
        if query:
            target += "?" + urlencode(query)
        data = None if body is None else json.dumps(body, ensure_ascii=False).encode()
        self.calls[call] += 1
        return await self._http.request(
            "GET" if data is None else "POST",
            target,
            body=data,
            limit=limit,
            check=check,
        )

    async def _json(
        self,
        call: str,
        *,
        params: Mapping[str, str | int] | None = None,
        body: Any = None,
        limit: int = MAX_ANSWER_BYTES,
        session: bool = True,
    ) -> Any:
        """Send a call and return its JSON answer; raise for an error status."""
        reply = await self._request(
            call, params=params, body=body, limit=limit, session=session
        )
        return _loads(call, reply)

    async def _text_call(
        self,
        call: str,
        *,
        params: Mapping[str, str | int] | None = None,
        body: Any = None,
        plain_params: Mapping[str, str | int] | None = None,
        plain_body: Any = None,
        limit: int = MAX_ANSWER_BYTES,
    ) -> Any:
        """Send a ``…Text`` call: to its Text URL, or without ``Text`` where only that answers.

        The plain URL is sent ``plain_params`` and ``plain_body`` where given
        (the items by name and by ``ItemID``), else the Text call's own.
        """
        if call not in self.plain_text_calls:
            reply = await self._request(
                f"{call}Text", params=params, body=body, limit=limit, check=False
            )
            if reply.status != 404:
                self._http.check(reply)
                return _loads(f"{call}Text", reply)
            self.plain_text_calls.add(call)
        return await self._json(
            call,
            params=params if plain_params is None else plain_params,
            body=body if plain_body is None else plain_body,
            limit=limit,
        )

    def _id_of(self, name: str) -> int | None:
        """Return an item's ``ItemID`` in the checked address space (None: not known)."""
        return None if self.item_id is None else self.item_id(name)

    def _access_denied(self, reply: Reply) -> PlcError:
        """Return what HTTP 403 means: this address is not on the allow-list."""
        return AccessDeniedError(
            "The gateway refuses connections from this address (its allow-list)"
        )

    def _session_lost(self, reply: Reply) -> PlcError:
        """Return what HTTP 409 means: the session is gone (forgotten here)."""
        self._session_id = None
        return SessionLostError("The gateway no longer knows the session", status=409)

    def _unavailable(self, reply: Reply) -> PlcError:
        """Return what HTTP 503 means: the OPC server is away (the session with it)."""
        self._session_id = None
        return ServiceUnavailableError(
            "The gateway's OPC server is unavailable (being restarted?)"
        )

    def _unexpected(self, reply: Reply) -> PlcError:
        """Return what any other status but 200 means."""
        call = reply.target.partition("?")[0].removeprefix("/")
        return PlcResponseError(
            f"{call} answered HTTP {reply.status}", status=reply.status
        )

    # --- without a session ------------------------------------------------------

    async def server_information(self) -> ServerInformation:
        """``ServerInformation``: the gateway's versions and clock.

        Anything but its JSON object is not an opcconnector (:class:`NotAPlcError`).
        """
        try:
            answer = await self._json(SERVER_INFORMATION, session=False)
        except PlcResponseError as err:
            raise NotAPlcError(
                f"{self.base_url} does not answer as an opcconnector gateway"
            ) from err
        if not isinstance(answer, dict) or not isinstance(answer.get("version"), str):
            raise NotAPlcError(
                f"{self.base_url} does not answer as an opcconnector gateway"
            )
        server = ServerInformation(
            api_version=answer["version"],
            connector_version=str(answer.get("opconn_version", "")),
            current_time=parse_time(answer.get("currenttime")),
            start_time=parse_time(answer.get("starttime")),
        )
        if (version := server.version) is not None:
            # What the version has no Text form of yet is asked without Text.
            self.plain_text_calls.update(
                call for call, since in TEXT_SINCE.items() if version < since
            )
        return server

    # --- the session ------------------------------------------------------------

    async def open_session(self) -> str:
        """``NewSession``: open a session (the one this client uses from now on)."""
        answer = await self._json(
            "NewSession", params={"alldata": int(self._alldata)}, session=False
        )
        session_id = answer.get("sessionid") if isinstance(answer, dict) else None
        if not isinstance(session_id, str) or not session_id:
            raise MalformedResponseError("NewSession answered no session ID")
        self._session_id = session_id
        # The IDs count once the new session's hash was checked.
        self.item_id = None
        return session_id

    async def close_session(self) -> None:
        """``CloseSession``: close the session, if one is open (failures ignored)."""
        if self._session_id is None:
            return
        with contextlib.suppress(PlcConnectionError):
            await self._request("CloseSession", check=False)
        self._session_id = None

    async def address_space_hash(self) -> str:
        """``GetAddressSpaceHash``: what changes when the address space does."""
        result = _result(await self._json("GetAddressSpaceHash"))
        if not isinstance(result, str) or not result:
            raise MalformedResponseError("GetAddressSpaceHash answered no hash")
        return result

    async def address_space(
        self, keep: Collection[int] | None = None
    ) -> list[AddressItem]:
        """``GetAddressSpace``: every item, its ID now and its properties.

        ``keep`` are the properties kept (None: all). An item without a name is
        left out, and so is a property the server could not read (the others are
        not lost for it).
        """
        answer = await self._json("GetAddressSpace", limit=MAX_ADDRESS_SPACE_BYTES)
        if not isinstance(answer, list):
            raise MalformedResponseError("GetAddressSpace answered no list")
        items = [
            item for raw in answer if (item := address_item(raw, keep)) is not None
        ]
        del answer
        return items

    async def subscribe(self, names: Sequence[str]) -> int:
        """``SubscriberText``: subscribe items by name, a thousand at a time."""
        return await self._by_thousands("Subscriber", names)

    async def unsubscribe(self, names: Sequence[str]) -> int:
        """``UnSubscriberText``: stop the updates of items, a thousand at a time."""
        return await self._by_thousands("UnSubscriber", names)

    async def _by_thousands(self, call: str, names: Sequence[str]) -> int:
        """Send a call of item names in batches; return the items it counted.

        Without Text, each batch names its items by ``ItemID`` too.
        """
        counted = 0
        for start in range(0, len(names), SUBSCRIBE_BATCH):
            batch = list(names[start : start + SUBSCRIBE_BATCH])
            ids = [
                item_id for name in batch if (item_id := self._id_of(name)) is not None
            ]
            counted += _count(
                await self._text_call(
                    call,
                    body={"itemstext": batch},
                    plain_body={"items": ids, "itemstext": batch},
                )
            )
        return counted

    async def updates(self, rid: int) -> list[ItemUpdate]:
        """``GetUpdatesText``: the values changed since the previous request.

        ``rid`` must grow after every answered request; asked again, the same
        ``rid`` is answered again (an answer lost on the way is not lost).
        """
        answer = await self._text_call(
            "GetUpdates", params={"rid": rid}, limit=self.max_updates_bytes
        )
        return item_updates(answer)

    async def read_all(self) -> int:
        """``ReadAllItemsValues``: every subscribed item's value comes with the next updates.

        A gateway sends an item's value only once it changed (the seed's
        ``GetUpdates``: "only data updated since the previous request"): this
        asks for the current ones. Returns the items to be updated (0: none
        subscribed).
        """
        return _count(await self._json("ReadAllItemsValues"))

    async def read(self, name: str) -> ItemUpdate | None:
        """``ReadItemValueSyncText``: one item's value now (None: the gateway has none).

        Without Text, the item is named by its ``ItemID`` too.
        """
        item_id = self._id_of(name)
        answer = await self._text_call(
            "ReadItemValueSync",
            params={"itemname": name},
            plain_params={"itemname": name}
            if item_id is None
            else {"item": item_id, "itemname": name},
        )
        found = item_updates(answer)
        return found[0] if found else None

    async def write(self, values: Iterable[tuple[str, str]]) -> int:
        """``WriteItemsValuesText``: write values by name; return the items processed.

        -1 (writing is disabled in the gateway's settings) is
        :class:`WritesDisabledError`.
        """
        body = [{"ItemName": name, "Value": value} for name, value in values]
        plain = [
            entry
            if (item_id := self._id_of(entry["ItemName"])) is None
            else {"ItemID": item_id, **entry}
            for entry in body
        ]
        count = _count(
            await self._text_call("WriteItemsValues", body=body, plain_body=plain)
        )
        if count == WRITES_DISABLED:
            raise WritesDisabledError(
                "Writing is disabled in the gateway's settings", code="-1"
            )
        if count < len(body):
            name, value = body[-1]["ItemName"], body[-1]["Value"]
            raise ValueRejectedError(
                f"the gateway took {count} of {len(body)} values",
                path=name,
                value=value,
            )
        return count

    async def subscribers_count(self) -> int:
        """``GetSubscribersCount``: the items subscribed (a request that keeps a session)."""
        return _count(await self._json("GetSubscribersCount"))


def _loads(call: str, reply: Reply) -> Any:
    """Return an answer's JSON; malformed JSON is :class:`MalformedResponseError`."""
    try:
        return reply.json()
    except (ValueError, RecursionError) as err:
        raise MalformedResponseError(
            f"{call} answered malformed JSON", status=reply.status
        ) from err


def _result(answer: Any) -> Any:
    """Return the ``result`` of a ``{"result": …}`` answer."""
    if not isinstance(answer, dict) or "result" not in answer:
        raise MalformedResponseError("The gateway answered no result")
    return answer["result"]


def _count(answer: Any) -> int:
    """Return the integer ``result`` of an answer."""
    result = _result(answer)
    if isinstance(result, bool) or not isinstance(result, int):
        try:
            return int(str(result))
        except ValueError as err:
            raise MalformedResponseError("The gateway answered no count") from err
    return result


def address_item(raw: Any, keep: Collection[int] | None = None) -> AddressItem | None:
    """One item of ``GetAddressSpace`` (None: not an item); ``keep``: its properties kept."""
    if not isinstance(raw, dict):
        return None
    name = raw.get("ItemName")
    item_id = raw.get("ItemID")
    props = raw.get("ItemProps")
    if (
        not isinstance(name, str)
        or not name.strip()
        or isinstance(item_id, bool)
        or not isinstance(item_id, int)
    ):
        return None
    properties: dict[int, str] = {}
    for prop in props if isinstance(props, list) else ():
        if not isinstance(prop, dict) or prop.get("Error", 0) not in (0, None):
            continue
        prop_id = prop.get("ID")
        value = prop.get("Value")
        if (
            isinstance(prop_id, int)
            and not isinstance(prop_id, bool)
            and (keep is None or prop_id in keep)
        ):
            properties[prop_id] = "" if value is None else str(value)
    return AddressItem(name=name, item_id=item_id, properties=properties)


def item_updates(answer: Any) -> list[ItemUpdate]:
    """Return the values of an updates (or read) answer, malformed entries left out."""
    if not isinstance(answer, list):
        raise MalformedResponseError("The gateway answered no list of values")
    found: list[ItemUpdate] = []
    for raw in answer:
        if not isinstance(raw, dict):
            continue
        name = raw.get("ItemName")
        item_id = raw.get("ItemID")
        quality = raw.get("Qual")
        if isinstance(quality, bool) or not isinstance(quality, int):
            continue
        if not isinstance(name, str):
            name = None
        if isinstance(item_id, bool) or not isinstance(item_id, int):
            item_id = None
        if name is None and item_id is None:
            continue
        value = raw.get("V")
        found.append(
            ItemUpdate(
                name=name,
                item_id=item_id,
                value="" if value is None else str(value),
                quality=quality,
                time=parse_time(raw.get("UpTime")),
            )
        )
    return found
