"""The Mervis web panel client: one async class speaking JSON over HTTP POST.

Three services at the controller's web root: ``login.cgi`` (credentials in,
the ``c`` later requests carry out), ``values.cgi`` (variables' bytes by ID)
and ``command.cgi`` (a write; one variable per request, since a uPLC uses the
first item only). Every request is a POST of compact JSON; the aiohttp session
is injected and never closed here; requests go one at a time, each with the
client's timeout, and no answer is read past :func:`answer_limit` bytes.

Credentials travel in request bodies: nothing here logs a body, and no
message carries one.

What the documents leave open, and how the client copes (see MERVIS.md):

- **Limits.** ``maxVariablesInRequest`` and ``maxRequestSize`` are taken from
  any answer that tells them. Until then a read uses conservative defaults and
  learns from refusals (an answer whose ``code`` is not ``ok``, or HTTP 413):
  a search between the largest request taken and the smallest refused, on the
  body's bytes when a refused request held no more IDs than one taken but more
  bytes, else on the count of IDs. A full request taken tries halfway up to the smallest refused
  next, so the limits converge on the controller's in a few refusals
  (:meth:`learn_refusal`).
- **Sessions.** A refused signed-in request is sent again once after signing
  in again (a ``c`` that expired) unless the refusal tells the limits or
  speaks of them (:data:`_LIMIT_WORDS`, and not of authentication,
  :data:`_AUTH_WORDS`): that one is the limits' and costs no sign-in. A
  refusal that says nothing is a limit's only when it stands after a fresh
  sign-in (an expired session may refuse a read larger than any taken without
  a word: learning a limit from it would keep a wrong bound for good). A
  refusal that still speaks of authentication after signing in again is one;
  so is HTTP 401 or 403.
- **Kept limits.** :meth:`limits_state` is what was told or learned, JSON-shaped;
  :meth:`restore_limits` takes it back in a later run (the entry's store).
- **IDs.** Sent in the released spelling until the controller turns out to
  know only the seed's (:attr:`id_style`; the source decides).
- **Writes.** ``set`` carries the value as JSON (the seed's ``set: 5``), a
  bool also the ``defaultValue`` and ``"time": "0"`` a public client sends;
  a controller that refuses it gets the bytes as hex instead, and the form that
  was taken is kept (:attr:`write_format`).
"""

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
import json
import logging
import re
from typing import Any, Final, Literal, TypeGuard

import aiohttp

from ..core.exceptions import (
    MalformedResponseError,
    NotAPlcError,
    PlcAuthenticationError,
    PlcError,
    PlcResponseError,
    ValueRejectedError,
)
from ..core.host import normalize_host
from ..core.http import HttpClient, HttpExchange, Reply, utf8_or
from ..core.models import DataType, ValueKind
from .codec import hex_value, plain_value
from .ids import Address, IdStyle, parse_id
from .planner import DEFAULT_MAX_REQUEST_SIZE, DEFAULT_MAX_VARIABLES, request_body

_LOGGER = logging.getLogger(__name__)

LOGIN: Final = "/login.cgi"
VALUES: Final = "/values.cgi"
COMMAND: Final = "/command.cgi"
OK: Final = "ok"
GOOD_QUALITIES: Final = frozenset({"g", "good"})
"""The quality of a good value: ``G`` in the seed, ``good`` in the 2019 revision."""
MIN_ANSWER_BYTES: Final = 64 * 1024
"""Every answer may take this much (an error page, a login's ``c``)."""
ITEM_OVERHEAD_BYTES: Final = 512
"""What one answered item may take beside its value's hex (ID, quality, time)."""
_AUTH_WORDS: Final = re.compile(
    r"auth|login|logon|credential|password|session|unauthori[sz]ed|forbidden",
    re.IGNORECASE,
)
_LIMIT_WORDS: Final = re.compile(
    r"too (?:many|large|long|big)|limit|exceed|maxim|size", re.IGNORECASE
)
_TOLD_LIMITS: Final = ("maxVariablesInRequest", "maxRequestSize")

type WriteFormat = Literal["plain", "hex"]


@dataclass(frozen=True, slots=True)
class Item:
    """One variable of a ``values.cgi`` answer.

    ``value`` is its bytes (None with an error); ``quality`` as the controller
    spells it; ``error`` the item's error (``e``), if any.
    """

    value: bytes | None
    quality: str
    error: str | None = None

    @property
    def good(self) -> bool:
        """Whether the value may be shown."""
        return (
            self.error is None
            and self.value is not None
            and self.quality.lower() in GOOD_QUALITIES
        )


class RequestRefusedError(PlcResponseError):
    """The controller refused a request as a whole (its ``code`` is not ``ok``).

    ``variables`` and ``body_bytes`` are what the request held; the message
    is the controller's own (its code and message, or an item's error).
    """

    def __init__(
        self,
        message: str,
        *,
        code: str = "",
        status: int = 0,
        variables: int = 0,
        body_bytes: int = 0,
    ) -> None:
        """Keep what the refused request held."""
        super().__init__(message, code=code, status=status, said=message)
        self.variables = variables
        self.body_bytes = body_bytes


def answer_limit(lengths: Sequence[int]) -> int:
    """Return the most bytes an answer for variables of these lengths may take."""
    return MIN_ANSWER_BYTES + sum(
        2 * length + ITEM_OVERHEAD_BYTES for length in lengths
    )


class MervisClient(HttpClient):
    """An async client of one Mervis controller's web panel API.

    ``username`` empty: a project without credentials (no sign-in, no ``c``).
    ``request_count`` counts the requests sent (sign-ins included),
    ``logins`` the sign-ins. ``max_variables`` and ``max_request_size`` are
    the limits in use (told or learned); ``platform`` what the controller says
    it is, once it says.
    """

    def __init__(
        self,
        session: aiohttp.ClientSession,
        host: str,
        username: str = "",
        password: str = "",
        *,
        verify_ssl: bool = True,
        timeout: float = 10.0,
        max_variables: int = DEFAULT_MAX_VARIABLES,
        max_request_size: int = DEFAULT_MAX_REQUEST_SIZE,
    ) -> None:
        """Prepare a client; nothing is sent until the first call."""
        self.base_url = normalize_host(host)
        self._credentials: dict[str, str] | None = (
            {"u": username, "p": password} if username else None
        )
        self._c: Any = None
        # Whether this turn signed in already (a refusal then is no expired ``c``).
        self._fresh = False
        self._http = HttpExchange(
            session,
            self.base_url,
            sender="a Mervis web panel",
            limit=MIN_ANSWER_BYTES,
            timeout=timeout,
            verify_ssl=verify_ssl,
            statuses={401: self._unauthorized, 403: self._unauthorized},
            otherwise=_by_the_answer,
            renewal=self,
            decode=utf8_or("cp1250"),
        )
        self.max_variables = max_variables
        self.max_request_size = max_request_size
        self.limits_told = False
        # The largest request taken and the smallest refused, by count and bytes.
        self._taken = (0, 0)
        self._refused: tuple[int | None, int | None] = (None, None)
        self.platform: str | None = None
        self.id_style = IdStyle.RELEASED
        self.write_format: WriteFormat | None = None
        self.logins = 0

    @property
    def signs_in(self) -> bool:
        """Whether the project has credentials (requests carry ``c``)."""
        return self._credentials is not None

    @property
    def session_credentials(self) -> Any:
        """What a request carries as ``c`` now (None: nothing)."""
        return self._c

    # --- HTTP: what an answer means, an expired ``c`` --------------------------

    def _unauthorized(self, reply: Reply) -> PlcError:
        """Return what HTTP 401 or 403 means: the credentials are refused."""
        return PlcAuthenticationError(
            f"The controller refused the request (HTTP {reply.status})"
        )

    def _answer(self, reply: Reply) -> Mapping[str, Any]:
        """Return an answer's JSON object (the limits it tells learned)."""
        answer = _json_object(reply)
        status = reply.status
        if answer is None or "code" not in answer:
            if status == 413:
                return {"code": "413", "msg": "Request too large (HTTP 413)"}
            if reply.html or 200 <= status < 500:
                raise NotAPlcError(
                    f"{self.base_url}{reply.target} answered HTTP {status}, "
                    "not as a Mervis web panel"
                )
            raise PlcResponseError(f"HTTP {status} without an answer", status=status)
        self._learn_limits(answer)
        return answer

    async def prepare(self) -> None:
        """Sign in before a request when not signed in (a project with credentials)."""
        self._fresh = False
        if self._credentials is not None and self._c is None:
            await self._login()
            self._fresh = True

    async def renew(self, reply: Reply, resent: int) -> bool:
        """Sign in again once after a refusal that may be an expired ``c``.

        Whether to send the request again (see the module's docstring).
        """
        if reply.status in (401, 403):
            return False
        answer = self._answer(reply)
        if (
            answer.get("code") == OK
            or self._credentials is None
            or self._fresh
            or not _may_be_expired(answer)
        ):
            return False
        _LOGGER.debug("%s refused a request: signing in again", reply.target)
        await self._login()
        self._fresh = True
        return True

    def _learn_limits(self, answer: Mapping[str, Any]) -> None:
        """Take the limits and the platform an answer tells."""
        if (variables := _positive(answer.get("maxVariablesInRequest"))) is not None:
            self.max_variables = variables
            self.limits_told = True
        if (size := _positive(answer.get("maxRequestSize"))) is not None:
            self.max_request_size = size
            self.limits_told = True
        if isinstance(platform := answer.get("platform"), str) and platform:
            self.platform = platform

    # --- services ------------------------------------------------------------------

    async def login(self) -> None:
        """Sign in (a project without credentials needs nothing)."""
        if self._credentials is None:
            return
        async with self._http.turn():
            await self._login()

    async def _login(self) -> None:
        """Sign in, in the turn held."""
        assert self._credentials is not None
        self._c = None
        self.logins += 1
        body = json.dumps(
            {"ver": 1, "c": self._credentials}, separators=(",", ":")
        ).encode()
        reply = await self._http.send("POST", LOGIN, body=body)
        self._http.check(reply)
        answer = self._answer(reply)
        if answer.get("code") != OK:
            raise PlcAuthenticationError(
                f"The controller refused the credentials ({_said(answer)})"
            )
        returned = answer.get("c")
        self._c = returned if isinstance(returned, dict) else dict(self._credentials)
        _LOGGER.debug("Signed in to %s", self.base_url)

    async def _exchange(
        self, path: str, items: Sequence[Any], limit: int
    ) -> tuple[Mapping[str, Any], int]:
        """Send ``items`` signed in; return an answer whose code is ``ok``, and its body's bytes.

        A refused signed-in request is sent again once after signing in again.
        """
        reply = await self._http.request(
            "POST", path, body=lambda: request_body(self._c, items), limit=limit
        )
        answer = self._answer(reply)
        if answer.get("code") == OK:
            return answer, reply.sent
        if _AUTH_WORDS.search(_said(answer)):
            raise PlcAuthenticationError(
                f"The controller asks for credentials ({_said(answer)})"
            )
        raise RequestRefusedError(
            _said(answer),
            code=str(answer.get("code")),
            variables=len(items),
            body_bytes=reply.sent,
        )

    async def values(self, addresses: Sequence[Address]) -> dict[Address, Item]:
        """Read some variables' bytes in one request; the items by the bytes asked.

        A variable the answer does not hold is not in the result.
        """
        ids = [address.variable_id(self.id_style) for address in addresses]
        answer, body_bytes = await self._exchange(
            VALUES, ids, answer_limit([address.length for address in addresses])
        )
        self._learn_taken(len(ids), body_bytes)
        items = answer.get("v")
        if not isinstance(items, list):
            raise MalformedResponseError(
                "values.cgi answered without a list", status=200
            )
        asked = {address.folded: address for address in addresses}
        found: dict[Address, Item] = {}
        for raw in items:
            if not isinstance(raw, dict):
                continue
            address = parse_id(raw.get("i"))
            if address is None or (wanted := asked.get(address)) is None:
                continue
            found[wanted] = _item(raw)
        return found

    def learn_refusal(self, err: RequestRefusedError) -> bool:
        """Lower a limit after a refused request; whether a smaller one may pass.

        The bytes are blamed when the request held no more IDs than one taken
        but more bytes than any; else the count of IDs. A refusal of what was
        taken before means the controller's limits changed: what was learned
        is forgotten. Limits the controller told are kept while a refused
        request held more than they allow (a smaller one may pass); a refusal
        within them means the controller's are lower now (told before, or
        kept from an earlier run): they are learned from here on, as if
        never told.
        """
        if self.limits_told and (
            err.variables > self.max_variables or err.body_bytes > self.max_request_size
        ):
            return True
        if err.variables <= 1:
            return False
        self.limits_told = False
        taken_count, taken_bytes = self._taken
        refused_count, refused_bytes = self._refused
        if err.variables <= taken_count and err.body_bytes > taken_bytes:
            refused_bytes = min(refused_bytes or err.body_bytes, err.body_bytes)
            self.max_request_size = (taken_bytes + refused_bytes) // 2
        else:
            if err.variables <= taken_count:
                taken_count, refused_count, refused_bytes = 0, None, None
                self._taken = (0, 0)
            refused_count = min(refused_count or err.variables, err.variables)
            self.max_variables = max(1, (taken_count + refused_count) // 2)
        self._refused = (refused_count, refused_bytes)
        _LOGGER.debug(
            "A request of %d variables (%d bytes) was refused: at most %d and %d",
            err.variables,
            err.body_bytes,
            self.max_variables,
            self.max_request_size,
        )
        return True

    def _learn_taken(self, count: int, body_bytes: int) -> None:
        """Note a request taken; a full one tries halfway up to the smallest refused."""
        taken_count = max(self._taken[0], count)
        taken_bytes = max(self._taken[1], body_bytes)
        self._taken = (taken_count, taken_bytes)
        if self.limits_told:
            return
        refused_count, refused_bytes = self._refused
        if (
            count == self.max_variables
            and refused_count is not None
            and refused_count - taken_count > 1
        ):
            self.max_variables = (taken_count + refused_count) // 2
        if refused_bytes is not None and refused_bytes - taken_bytes > 1:
            self.max_request_size = max(
                self.max_request_size, (taken_bytes + refused_bytes) // 2
            )

    def limits_state(self) -> dict[str, Any]:
        """Return what is told or learned of the limits, JSON-shaped (no credentials)."""
        return {
            "max_variables": self.max_variables,
            "max_request_size": self.max_request_size,
            "told": self.limits_told,
            "taken": list(self._taken),
            "refused": list(self._refused),
            "platform": self.platform,
        }

    def restore_limits(self, state: Any) -> bool:
        """Take the limits of :meth:`limits_state` kept from an earlier run.

        Whether they were taken: anything else (another version's, a damaged
        store) leaves the defaults, to be learned again.
        """
        if not isinstance(state, dict):
            return False
        variables = _positive(state.get("max_variables"))
        size = _positive(state.get("max_request_size"))
        taken = state.get("taken")
        refused = state.get("refused")
        platform = state.get("platform")
        told = state.get("told")
        if (
            variables is None
            or size is None
            or not isinstance(told, bool)
            or not _pair(taken, allow_none=False)
            or not _pair(refused, allow_none=True)
            or not (platform is None or isinstance(platform, str))
        ):
            return False
        self.max_variables, self.max_request_size = variables, size
        self.limits_told = told
        self._taken = (taken[0], taken[1])
        self._refused = (refused[0], refused[1])
        self.platform = self.platform or platform
        return True

    async def write(
        self, address: Address, data_type: DataType, path: str, value: Any
    ) -> None:
        """Write one variable (a checked raw value); returns once it is taken.

        Both forms are made first: a value neither can carry is refused before
        anything is sent.
        """
        forms = self.write_forms(address, data_type, path, value)
        tried: list[WriteFormat] = (
            [self.write_format] if self.write_format else ["plain", "hex"]
        )
        refusal: RequestRefusedError | None = None
        for form in tried:
            item: dict[str, Any] = {
                "i": address.variable_id(self.id_style),
                "set": forms[form],
            }
            if data_type.kind is ValueKind.BOOL and form == "plain":
                item["defaultValue"] = forms[form]
                item["time"] = "0"
            try:
                answer, _ = await self._exchange(COMMAND, [item], MIN_ANSWER_BYTES)
            except RequestRefusedError as err:
                refusal = err
                continue
            if (error := _item_error(answer)) is not None:
                refusal = RequestRefusedError(error, code="e", variables=1)
                continue
            self.write_format = form
            return
        assert refusal is not None
        raise ValueRejectedError(
            refusal.message,
            path=path,
            value=value,
            code=refusal.code,
            said=refusal.said,
        )

    @staticmethod
    def write_forms(
        address: Address, data_type: DataType, path: str, value: Any
    ) -> dict[WriteFormat, Any]:
        """Return a raw value's wire forms; one neither can carry is refused."""
        return {
            "plain": plain_value(data_type, address.length, path, value),
            "hex": hex_value(data_type, address.length, path, value),
        }


def _positive(value: Any) -> int | None:
    """Return a positive whole number an answer tells, or None."""
    if isinstance(value, int) and not isinstance(value, bool) and value > 0:
        return value
    return None


def _pair(value: Any, *, allow_none: bool) -> TypeGuard[list[Any]]:
    """Whether a kept value is two whole numbers (or None, where allowed)."""
    return (
        isinstance(value, list)
        and len(value) == 2
        and all(
            (item is None and allow_none)
            or (isinstance(item, int) and not isinstance(item, bool) and item >= 0)
            for item in value
        )
    )


def _may_be_expired(answer: Mapping[str, Any]) -> bool:
    """Whether a refusal may be a session that expired (see the module's docstring)."""
    said = _said(answer)
    return bool(_AUTH_WORDS.search(said)) or not (
        _LIMIT_WORDS.search(said) or any(key in answer for key in _TOLD_LIMITS)
    )


def _said(answer: Mapping[str, Any]) -> str:
    """Return what an answer says of itself: its code and message."""
    message = answer.get("msg")
    code = answer.get("code")
    return f"{code}: {message}" if message else str(code)


def _item(raw: Mapping[str, Any]) -> Item:
    """One answered variable: its bytes, quality and error."""
    quality = raw.get("q")
    quality = quality if isinstance(quality, str) else ""
    if (error := raw.get("e")) is not None:
        return Item(None, quality, str(error) or "error")
    value = raw.get("v")
    try:
        data = bytes.fromhex(value) if isinstance(value, str) else None
    except ValueError:
        data = None
    if data is None:
        return Item(None, quality, "not hex")
    return Item(data, quality)


def _item_error(answer: Mapping[str, Any]) -> str | None:
    """Return the error of a command's item, if its answer has one."""
    items = answer.get("v")
    if isinstance(items, list):
        for item in items:
            if isinstance(item, dict) and item.get("e") is not None:
                return str(item["e"]) or "error"
    return None


def _json_object(reply: Reply) -> dict[str, Any] | None:
    """Return an answer's JSON object (UTF-8, else Windows-1250), or None."""
    try:
        answer = reply.json()
    except (ValueError, RecursionError):
        return None
    return answer if isinstance(answer, dict) else None


def _by_the_answer(reply: Reply) -> None:
    """Any status but 401 and 403: the answer itself says what it means."""
