"""The FP-I4C client: ``POST /plcpost`` to a Panasonic FP-I4C gateway.

One async class; the aiohttp session is injected and never closed here. A
POST carries up to 20 requests for one station (the body's ``interface`` and
``station``; without them the gateway uses those set on its web pages) and
is answered item by item, in order: each item its own ``err``, ``err_msg``
and ``err_code`` (the PLC protocol's own number: MEWTOCOL, MEWTOCOL7 or
Modbus) and its values under the type's name (``"int": [...]``, ``"state"``
for bits; a single value when the count is 1). One failed item fails nothing
else: :meth:`FpI4cClient.post` returns every item's values or its
:class:`ItemError`.

POSTs go out one at a time (an embedded gateway, and a poll and a write must
not pass each other on the wire). An answer is read up to
:data:`MAX_BODY_BYTES` and parsed strictly, then as the manual prints JSON
(``lenient``).
"""

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
import json
import math
import struct
from typing import Any, Final

import aiohttp

from ..core.exceptions import (
    MalformedResponseError,
    NotAPlcError,
    PlcError,
    PlcResponseError,
)
from ..core.host import normalize_host
from ..core.http import HttpClient, HttpExchange, Reply
from .address import WireType
from .lenient import LenientJsonError, loads

PATH: Final = "/plcpost"

ITEM_BYTES: Final = 16 * 1024
"""The most one item of an answer takes: 100 values of at most 64 bytes each as
the manual prints them (a REAL's 24 characters, indentation, a comma, a line
end), or a string of 1,000 characters each at most 6 bytes escaped, with the
item's ``err``, ``err_msg``, ``err_code`` and ``request`` around them."""
MAX_BODY_BYTES: Final = 20 * ITEM_BYTES + 4096
"""The most bytes of an answer the client reads: 20 items and the envelope."""
READ_CHUNK: Final = 16 * 1024


class GatewayError(PlcResponseError):
    """The gateway refused a POST as a whole (its answer's ``err``, ``err_msg``)."""


class ItemError(PlcResponseError):
    """One item of an answer failed: ``code`` is the PLC protocol's ``err_code``.

    ``request`` names the item as the gateway does (``DT10``); ``message``
    is empty where the gateway gave none (a write's item, in the seed).
    """

    def __init__(self, message: str, *, code: str, request: str) -> None:
        """Keep the gateway's message, the protocol's code and the item's name."""
        super().__init__(message, code=code)
        self.request = request
        self.args = (f"{request}: {self.detail}",)

    @property
    def detail(self) -> str:
        """The message and the code: ``Protect error (err_code 65)``, or the code."""
        if not self.message:
            return f"err_code {self.code}"
        return f"{self.message} (err_code {self.code})"


class PlcNotAnsweringError(PlcResponseError):
    """The gateway answers, but the PLC behind it does not (its item failed).

    ``code`` and ``message`` are the failed item's ``err_code`` and ``err_msg``.
    """


class StationNotAnsweringError(PlcNotAnsweringError):
    """The gateway answers, but the PLC at a station does not.

    ``station`` is its number (text, as a form shows it).
    """

    def __init__(self, message: str, *, code: str, station: int) -> None:
        """Keep the item's message and code, and the station's number."""
        super().__init__(message, code=code, said=f"{message} (err_code {code})")
        self.args = (f"Station {station}: {message} (err_code {code})",)
        self.station = str(station)


@dataclass(frozen=True, slots=True)
class ItemAnswer:
    """One item of an answer: its values (None where one is unreadable) or its error."""

    request: str
    values: tuple[Any, ...] = ()
    error: ItemError | None = None


@dataclass(frozen=True, slots=True)
class WireStatistics:
    """What went over the wire: POSTs, bytes each way, answers read leniently."""

    posts: int = 0
    bytes_sent: int = 0
    bytes_received: int = 0
    lenient_answers: int = 0


class FpI4cClient(HttpClient):
    """An async client of one FP-I4C gateway's REST API.

    ``host`` is its address with the REST API's port (``http://192.168.1.5:2000``);
    ``interface`` the PLC interface every POST names (None: the gateway's).
    """

    def __init__(
        self,
        session: aiohttp.ClientSession,
        host: str,
        *,
        interface: int | None = None,
        timeout: float = 10.0,
    ) -> None:
        """Prepare a client; nothing is sent until the first call."""
        self.base_url = normalize_host(host)
        self.interface = interface
        self._lenient_answers = 0
        self._http = HttpExchange(
            session,
            self.base_url,
            sender="an FP-I4C",
            limit=MAX_BODY_BYTES,
            timeout=timeout,
            statuses={
                range(300, 400): self._not_a_gateway,
                404: self._not_a_gateway,
                405: self._not_a_gateway,
            },
            otherwise=_by_the_answer,
            chunk_size=READ_CHUNK,
        )

    @property
    def statistics(self) -> WireStatistics:
        """What went over the wire so far, and the answers read leniently."""
        wire = self._http.wire
        return WireStatistics(
            posts=wire.requests,
            bytes_sent=wire.bytes_sent,
            bytes_received=wire.bytes_received,
            lenient_answers=self._lenient_answers,
        )

    async def post(
        self,
        requests: Sequence[Mapping[str, Any]],
        station: int | None = None,
    ) -> list[ItemAnswer]:
        """Send one POST of requests for a station; return each item's answer.

        A read request's values are decoded by its ``type`` and ``count``; a
        write's item has no values. Raises :class:`PlcConnectionError` when
        nothing answers, :class:`NotAPlcError` when something other than an
        FP-I4C does, :class:`GatewayError` when the gateway refuses the POST,
        :class:`MalformedResponseError` for an answer that cannot be read.
        """
        body: dict[str, Any] = {"req": list(requests)}
        if self.interface is not None:
            body["interface"] = self.interface
        if station is not None:
            body["station"] = station
        payload = json.dumps(body, separators=(",", ":")).encode()
        answer = self._answer(await self._http.request("POST", PATH, body=payload))
        data = answer["data"]
        if len(data) != len(requests):
            raise MalformedResponseError(
                f"The gateway answered {len(data)} items for {len(requests)} requests"
            )
        return [
            _item(item, request) for item, request in zip(data, requests, strict=True)
        ]

    def _not_a_gateway(self, reply: Reply) -> PlcError:
        """Return what a redirect, 404 or 405 means: something else answers."""
        return NotAPlcError(
            f"{self.base_url} answered HTTP {reply.status} to {PATH}: not an FP-I4C"
        )

    def _answer(self, reply: Reply) -> dict[str, Any]:
        """Return an answer's JSON object; raise for anything else."""
        status = reply.status
        text = reply.body.decode("utf-8", errors="replace")
        if reply.content_type == "text/html" or text.lstrip().startswith("<"):
            raise NotAPlcError(f"{self.base_url} answered a web page: not an FP-I4C")
        if not reply.ok:
            raise PlcResponseError(
                f"The gateway answered HTTP {status}", code=str(status), status=status
            )
        try:
            answer, lenient = loads(text)
        except LenientJsonError as err:
            if not text.lstrip().startswith("{"):
                raise NotAPlcError(
                    f"{self.base_url} answered something other than JSON: not an FP-I4C"
                ) from err
            raise MalformedResponseError(
                f"The gateway's answer is not JSON ({err})", status=status
            ) from err
        if lenient:
            self._lenient_answers += 1
        if not isinstance(answer, dict) or not isinstance(answer.get("data"), list):
            raise NotAPlcError(
                f"{self.base_url} answered JSON, but not as an FP-I4C does"
            )
        if _true(answer.get("err")):
            raise GatewayError(str(answer.get("err_msg") or "refused"))
        return answer


def _by_the_answer(reply: Reply) -> None:
    """Any other status: the answer says what it means (a web page, an error)."""


def _true(flag: Any) -> bool:
    """Whether an answer's ``err`` says an error (``true``, 1, or the text)."""
    return (
        flag is True or flag == 1 or (isinstance(flag, str) and flag.lower() == "true")
    )


def _item(item: Any, request: Mapping[str, Any]) -> ItemAnswer:
    """Decode one item of an answer by the request it answers."""
    name = _request_name(request)
    if not isinstance(item, dict):
        return ItemAnswer(
            name, error=ItemError("the item is not an object", code="", request=name)
        )
    name = str(item.get("request") or name)
    if _true(item.get("err")):
        return ItemAnswer(
            name,
            error=ItemError(
                # The seed's write items carry no message: the code says it all.
                str(item.get("err_msg") or ("" if "value" in request else "failed")),
                code=str(item.get("err_code", "")),
                request=name,
            ),
        )
    if "value" in request:
        return ItemAnswer(name)
    wire = WireType(str(request["type"]).upper())
    found = item.get(wire.answer_key)
    if found is None:
        return ItemAnswer(
            name,
            error=ItemError(
                f"the item has no {wire.answer_key!r}", code="", request=name
            ),
        )
    if wire is WireType.STRING:
        return ItemAnswer(name, (decode_value(wire, found),))
    count = int(request.get("count", 1))
    listed = found if isinstance(found, list) else [found]
    return ItemAnswer(
        name,
        tuple(
            decode_value(wire, listed[index]) if index < len(listed) else None
            for index in range(count)
        ),
    )


def _request_name(request: Mapping[str, Any]) -> str:
    """Return a request's name as the gateway writes it (``DT10``, ``Y1A``)."""
    return f"{str(request.get('area', '')).upper()}{request.get('start', '')}"


_INTEGER_BOUNDS: Final = {
    WireType.INT: (-(1 << 15), (1 << 15) - 1),
    WireType.UINT: (0, (1 << 16) - 1),
    WireType.DINT: (-(1 << 31), (1 << 31) - 1),
    WireType.UDINT: (0, (1 << 32) - 1),
}


def decode_value(wire: WireType, value: Any) -> Any:
    """Return an answer's value as its type reads (None: not one of the type)."""
    match wire:
        case WireType.BOOL:
            if value in (0, 1) or isinstance(value, bool):
                return bool(value)
            return None
        case WireType.REAL:
            if isinstance(value, bool) or not isinstance(value, int | float):
                return None
            return as_real(float(value))
        case WireType.STRING:
            return value if isinstance(value, str) else None
        case _:
            if isinstance(value, float) and value.is_integer():
                value = int(value)
            if isinstance(value, bool) or not isinstance(value, int):
                return None
            low, high = _INTEGER_BOUNDS[wire]
            return value if low <= value <= high else None


def as_real(value: float) -> float | None:
    """Return a REAL as a 32-bit float holds it, shown to its 7 significant digits.

    A gateway may print a REAL's float32 value in full (22.8799991607666 for
    22.88); what is shown is what the user wrote. None: not a finite float32.
    """
    if not math.isfinite(value):
        return None
    try:
        single = struct.unpack("<f", struct.pack("<f", value))[0]
    except OverflowError:
        return None
    return float(f"{single:.7g}")


def real_fits(value: float) -> bool:
    """Whether a number fits a REAL (a finite 32-bit float)."""
    return as_real(value) is not None
