"""A simulated Panasonic FP-I4C gateway: ``POST /plcpost`` (and ``GET /plcget``).

See ``tests/simulator/README.md`` (the FP-I4C section) for which behaviour comes
from the seed and which is assumed. In short:

- the gateway reaches stations (FP PLCs, :class:`StationMemory`) on one
  interface (``interface``); a POST names its interface and station, or
  gets the gateway's (``interface``, ``station``);
- it answers one POST at a time, item by item in request order, each item's
  failure its own (a read's ``err``, ``err_msg``, ``err_code``; a write's
  ``err`` and ``err_code`` only, as the seed's write answers);
- it enforces the documented limits: 20 requests a POST (the POST is refused:
  ``err`` at the root), 100 registers or bits a request, 1000 characters a
  string written (the item fails);
- switches: ``lenient`` prints answers as the manual does (trailing commas),
  ``silent`` are stations that do not answer (their items fail with
  :data:`NO_RESPONSE`), ``item_errors`` (and ``write_errors``, for writes
  only) make the items that cover an address fail with a code, ``dropped``
  are stations whose POSTs the gateway drops (the connection closes
  unanswered), ``broken`` cuts every answer in the middle, ``get_form``
  serves ``GET /plcget``, ``write_messages`` adds ``err_msg`` to a failed
  write's item (our older assumption);
- :meth:`FpI4cSimulator.hold` holds the next answer until released (a test
  makes a POST and a write cross without sleeping).
"""

import asyncio
from collections.abc import AsyncIterator, Mapping
import contextlib
from dataclasses import dataclass, field
import json
import re
from typing import Any, Final

from aiohttp import web

from tests.simulator.base import ConnectionDroppedError, HttpSimulator

from .memory import (
    BIT_AREAS,
    DATA_ERROR,
    REGISTER_AREAS,
    TYPES,
    WORDS,
    RefusalError,
    StationMemory,
)

MAX_REQUESTS: Final = 20
MAX_COUNT: Final = 100
MAX_STRING: Final = 1000
NO_RESPONSE: Final = (28, "No response from the PLC")
"""What an item of a station that does not answer fails with (an assumption)."""
GATEWAY: Final = 0
"""The code of an item the gateway itself refuses (no PLC was asked)."""

_BIT_START: Final = re.compile(r"([0-9]{0,5})([0-9A-Fa-f])")
_ADDRESS: Final = re.compile(r"(DT|FL|LD|WR|WX|WY|WL|DDT|DLD|DFL|R|X|Y|L)(\w+)")
_TRAILING_COMMA: Final = re.compile(r",(\s*[\]}])")
_BARE_WORD: Final = re.compile(r"(:\s*)([A-Za-z0-9]+)(\s*[,}\]])")


class _RefusedError(Exception):
    """A POST refused as a whole: ``err`` at the answer's root."""


@dataclass
class Hold:
    """The next answer, held until released."""

    reached_event: asyncio.Event = field(default_factory=asyncio.Event)
    released: asyncio.Event = field(default_factory=asyncio.Event)

    async def reached(self) -> None:
        """Wait until a POST is held (its memory read already)."""
        await self.reached_event.wait()

    def release(self) -> None:
        """Let the held answer go."""
        self.released.set()


class FpI4cSimulator(HttpSimulator[str]):
    """An FP-I4C gateway and its stations (see the module's docstring)."""

    def __init__(
        self,
        stations: Mapping[int, StationMemory] | None = None,
        *,
        interface: int = 4,
        station: int = 1,
        lenient: bool = False,
        get_form: bool = True,
        write_messages: bool = False,
    ) -> None:
        """Prepare a gateway; ``station`` and ``interface`` are those set in it."""
        super().__init__(serialize=True)
        self.stations: dict[int, StationMemory] = dict(
            stations if stations is not None else {station: StationMemory()}
        )
        self.interface = interface
        self.station = station
        self.lenient = lenient
        self.get_form = get_form
        self.write_messages = write_messages
        """A failed write's item has an ``err_msg`` (the seed's has none)."""
        self.silent: set[int] = set()
        self.broken = False
        """Answers are cut in the middle (JSON no parser reads)."""
        self.dropped: set[int] = set()
        """Stations whose POSTs the gateway drops: the connection closes unanswered."""
        self.item_errors: dict[tuple[int, str], tuple[int, str]] = {}
        """(station, ``DT100``) -> (``err_code``, ``err_msg``) of the items covering it."""
        self.write_errors: dict[tuple[int, str], tuple[int, str]] = {}
        """The same, for the writes covering it only (a protected register)."""
        self.max_requests = MAX_REQUESTS
        """Requests a POST may carry; a POST with more is refused as a whole."""
        self.posts: list[dict[str, Any]] = []
        """The bodies of the POSTs answered, in order."""
        self.bytes_received = 0
        self.bytes_sent = 0
        self._hold: Hold | None = None

    # --- lifecycle ----------------------------------------------------------------

    def _routes(self, app: web.Application) -> None:
        app.router.add_post("/plcpost", self._handle_post)
        app.router.add_get("/plcget", self._handle_get)

    def _stopped(self) -> None:
        if self._hold is not None:
            self._hold.release()

    @contextlib.asynccontextmanager
    async def hold(self) -> AsyncIterator[Hold]:
        """Hold the next answer (after its memory is read) until released."""
        hold = self._hold = Hold()
        try:
            yield hold
        finally:
            hold.release()
            if self._hold is hold:
                self._hold = None

    # --- memory, as a test sets and reads it ------------------------------------------

    def set(self, station: int, address: str, type_: str, value: Any) -> None:
        """Set a value at an address (``DT100``, ``R1A``) of a station's PLC."""
        area, start = _address(address)
        if type_ == "STRING":
            self.stations[station].write_string(area, start, value)
        else:
            self.stations[station].write(area, type_, start, [value])

    def get(self, station: int, address: str, type_: str) -> Any:
        """Return the value at an address of a station's PLC."""
        area, start = _address(address)
        memory = self.stations[station]
        if type_ == "STRING":
            return memory.read_string(area, start)
        value = memory.read(area, type_, start, 1)[0]
        return bool(value) if type_ == "BOOL" else value

    # --- the REST API -----------------------------------------------------------------

    async def _handle_post(self, request: web.Request) -> web.Response:
        self._record("plcpost")
        body = await request.read()
        async with self._turn():
            self.bytes_received += len(body)
            try:
                parsed = _parse_request(body.decode("utf-8", errors="replace"))
                if isinstance(parsed, dict) and parsed.get("station") in self.dropped:
                    raise ConnectionDroppedError(reset=False)
                answer = {"err": False, "err_msg": "", "data": self._answer(parsed)}
            except _RefusedError as err:
                answer = {"err": True, "err_msg": str(err), "data": []}
            text = self._render(answer)
            if self.broken:
                text = text[: len(text) // 2]
            if (hold := self._hold) is not None:
                self._hold = None
                hold.reached_event.set()
                await hold.released.wait()
            self.bytes_sent += len(text.encode())
            return web.Response(text=text, content_type="application/json")

    async def _handle_get(self, request: web.Request) -> web.Response:
        """``GET /plcget?DT100`` (read) or ``?DT100=122`` (write), ``&I=..&A=..``."""
        self._record("plcget")
        if not self.get_form:
            raise web.HTTPNotFound
        parameters = [
            part.partition("=") for part in request.query_string.split("&") if part
        ]
        if not parameters:
            raise web.HTTPBadRequest(text="no address")
        (name, has_value, value), *rest = parameters
        options = {key.upper(): text for key, _, text in rest}
        if ("I" in options) != ("A" in options):
            raise web.HTTPBadRequest(text="I and A go together")
        body: dict[str, Any] = {"req": [_get_request(name.upper(), has_value, value)]}
        if "I" in options:
            body.update(interface=_int(options["I"]), station=_int(options["A"]))
        async with self._turn():
            try:
                answer = {"err": False, "err_msg": "", "data": self._answer(body)}
            except _RefusedError as err:
                answer = {"err": True, "err_msg": str(err), "data": []}
            return web.Response(
                text=self._render(answer), content_type="application/json"
            )

    def _answer(self, body: Any) -> list[dict[str, Any]]:
        """Answer a POST's requests (or refuse it as a whole)."""
        if not isinstance(body, dict) or not isinstance(body.get("req"), list):
            raise _RefusedError("The body has no request list (req)")
        requests = body["req"]
        if len(requests) > self.max_requests:
            raise _RefusedError(f"Too many requests: at most {self.max_requests}")
        interface = body.get("interface", self.interface)
        if interface != self.interface:
            raise _RefusedError(f"Interface {interface} is not enabled")
        station = body.get("station", self.station)
        if (
            not isinstance(station, int)
            or isinstance(station, bool)
            or not 0 <= station <= 99
        ):
            raise _RefusedError(f"Invalid station {station!r}")
        self.posts.append(body)
        return [self._item(station, request) for request in requests]

    def _item(self, station: int, request: Any) -> dict[str, Any]:
        """Answer one request of a station (a write's item as the seed's: no message)."""
        item = self._answer_item(station, request)
        writing = isinstance(request, dict) and "value" in request
        if item["err"] and writing and not self.write_messages:
            del item["err_msg"]
        return item

    def _answer_item(self, station: int, request: Any) -> dict[str, Any]:
        """Answer one request of a station."""
        if not isinstance(request, dict):
            return _failed("?", GATEWAY, "The request is not an object")
        area = str(request.get("area", "")).upper()
        type_ = str(request.get("type", "")).upper()
        name = f"{area}{request.get('start', '')}"
        try:
            start, count = _range(area, type_, request)
        except RefusalError as err:
            return _failed(name, err.code, err.message)
        if area in BIT_AREAS:
            word, bit = divmod(start, 16)
            name = f"{area}{word}{bit:X}" if word else f"{area}{bit:X}"
        writing = "value" in request
        memory = self.stations.get(station)
        if memory is None or station in self.silent:
            return _failed(name, *NO_RESPONSE)
        words = count * WORDS.get(type_, 1) if type_ != "BOOL" else count
        errors = {**self.item_errors, **(self.write_errors if writing else {})}
        for (where, address), (code, message) in errors.items():
            if where == station and _covers(area, start, words, address):
                return _failed(name, code, message)
        try:
            if writing:
                self._write(memory, area, type_, (start, count), request["value"])
                return {"request": name, "err": False, "err_code": 0}
            values = self._read(memory, area, type_, start, count)
        except RefusalError as err:
            return _failed(name, err.code, err.message)
        return {"err": False, "err_msg": "", "err_code": 0, "request": name, **values}

    def _read(
        self, memory: StationMemory, area: str, type_: str, start: int, count: int
    ) -> dict[str, Any]:
        if type_ == "STRING":
            return {"string": memory.read_string(area, start)}
        if type_ == "ANY":
            return _any(memory, area, start, count)
        values = memory.read(area, type_, start, count)
        key = "state" if type_ == "BOOL" else type_.lower()
        return {key: values[0] if count == 1 else values}

    def _write(
        self,
        memory: StationMemory,
        area: str,
        type_: str,
        where: tuple[int, int],
        value: Any,
    ) -> None:
        start, count = where
        if type_ == "ANY":
            raise RefusalError("ANY is read-only", GATEWAY)
        if type_ == "STRING":
            if not isinstance(value, str) or len(value) > MAX_STRING:
                raise RefusalError(
                    f"A string is text of at most {MAX_STRING} characters", GATEWAY
                )
            memory.write_string(area, start, value)
            return
        values = value if isinstance(value, list) else [value]
        if len(values) != count:
            raise RefusalError(f"{len(values)} values for count {count}", GATEWAY)
        memory.write(area, type_, start, values)

    def _render(self, answer: Mapping[str, Any]) -> str:
        """The answer's text: JSON, or as the manual prints it."""
        if not self.lenient:
            return json.dumps(answer)
        return _manual_json(answer, 0, root=True)


def _parse_request(text: str) -> Any:
    """Read a POST's body: JSON, or as the manual writes requests (``"start": f,``)."""
    try:
        return json.loads(text)
    except ValueError:
        pass
    # The manual's pages indent with no-break spaces.
    cleaned = text.replace("\u00a0", " ")
    cleaned = _BARE_WORD.sub(_quoted, _TRAILING_COMMA.sub(r"\1", cleaned))
    try:
        return json.loads(cleaned)
    except ValueError:
        raise _RefusedError("The body is not JSON") from None


def _quoted(found: re.Match[str]) -> str:
    """Quote a bare word that is no JSON (``f``), keep one that is (``10``, ``true``)."""
    word = found[2]
    if word.isdigit() or word in ("true", "false", "null"):
        return found[0]
    return f'{found[1]}"{word}"{found[3]}'


def _range(area: str, type_: str, request: Mapping[str, Any]) -> tuple[int, int]:
    """Return a request's first value (a bit's index) and count; refuse a bad one."""
    if type_ not in (*TYPES, "ANY"):
        raise RefusalError(f"Invalid type {type_!r}", GATEWAY)
    start = request.get("start")
    if area in BIT_AREAS:
        if type_ != "BOOL":
            raise RefusalError(f"{area} holds BOOL only", GATEWAY)
        # The manual says a string; its own example sends 0 too.
        found = (
            _BIT_START.fullmatch(str(start)) if isinstance(start, str | int) else None
        )
        if found is None:
            raise RefusalError(f"Invalid flag address {start!r}", GATEWAY)
        index = int(found[1] or "0") * 16 + int(found[2], 16)
    elif area in REGISTER_AREAS:
        if type_ == "BOOL":
            raise RefusalError(f"{area} holds registers, not BOOL", GATEWAY)
        if not isinstance(start, int) or isinstance(start, bool) or start < 0:
            raise RefusalError(
                f"A register's start is a number, not {start!r}", GATEWAY
            )
        index = start
    else:
        raise RefusalError(f"Invalid area {area!r}", GATEWAY)
    if type_ == "STRING":
        return index, 1
    count = request.get("count", 1)
    if not isinstance(count, int) or isinstance(count, bool) or count < 1:
        raise RefusalError(f"Invalid count {count!r}", GATEWAY)
    registers = count * WORDS.get(type_, 1) if type_ not in ("BOOL", "ANY") else count
    if registers > MAX_COUNT:
        raise RefusalError(
            f"At most {MAX_COUNT} registers or flags a request ({registers})", GATEWAY
        )
    return index, count


def _covers(area: str, start: int, count: int, address: str) -> bool:
    """Whether a request's values include an address (``DT100``, ``R1A``)."""
    where, index = _address(address)
    return where == area and start <= index < start + count


def _address(address: str) -> tuple[str, int]:
    """Return an address's area and index (a bit's word·16 + bit)."""
    found = _ADDRESS.fullmatch(address.upper())
    if found is None:
        raise ValueError(f"{address!r} is not an address")
    area, rest = found[1], found[2]
    if area in BIT_AREAS:
        return area, int(rest[:-1] or "0") * 16 + int(rest[-1], 16)
    return area, int(rest)


def _get_request(name: str, has_value: str, value: str) -> dict[str, Any]:
    """A GET form's address (``DDT`` … a double word) as a POST's request."""
    found = _ADDRESS.fullmatch(name)
    if found is None:
        raise web.HTTPBadRequest(text=f"{name!r} is not an address")
    area, rest = found[1], found[2]
    request: dict[str, Any]
    if area in BIT_AREAS:
        request = {"area": area, "type": "BOOL", "start": rest, "count": 1}
    elif area.startswith("D") and area != "DT":
        request = {"area": area[1:], "type": "DINT", "start": _int(rest), "count": 1}
    else:
        request = {"area": area, "type": "INT", "start": _int(rest), "count": 1}
    if has_value:
        request["value"] = _int(value)
    return request


def _int(text: str) -> int:
    try:
        return int(text)
    except ValueError:
        raise web.HTTPBadRequest(text=f"{text!r} is not a number") from None


def _any(memory: StationMemory, area: str, start: int, count: int) -> dict[str, Any]:
    """Every type of a run of registers at once (the seed's ANY answer)."""
    words = memory.read(area, "UINT", start, count)
    doubles = count // 2
    return {
        "int": memory.read(area, "INT", start, count),
        "uint": words,
        "udint": memory.read(area, "UDINT", start, doubles),
        "dint": memory.read(area, "DINT", start, doubles),
        "hex": [f"{word:04X}" for word in words],
        "real": memory.read(area, "REAL", start, doubles),
        "string": "",
    }


def _failed(name: str, code: int, message: str) -> dict[str, Any]:
    return {"err": True, "err_msg": message, "err_code": code, "request": name}


def _manual_json(value: Any, depth: int, *, root: bool = False) -> str:
    """JSON as the manual prints it: one member a line, a comma after each.

    The root object's last member has none (as in the manual); an ANY
    answer's hex words go bare (``000A``).
    """
    indent = "     " * (depth + 1)
    close = "     " * depth
    if isinstance(value, dict):
        lines = []
        for index, (key, member) in enumerate(value.items()):
            text = (
                ", ".join(member) if key == "hex" else _manual_json(member, depth + 1)
            )
            if key == "hex":
                text = f"[{text},]" if member else "[]"
            comma = "" if root and index == len(value) - 1 else ","
            lines.append(f"{indent}{json.dumps(key)}: {text}{comma}")
        return "{\n" + "\n".join(lines) + f"\n{close}}}"
    if isinstance(value, list):
        if not value:
            return "[]"
        lines = [f"{indent}{_manual_json(item, depth + 1)}," for item in value]
        return "[\n" + "\n".join(lines) + f"\n{close}]"
    return json.dumps(value)


__all__ = ["DATA_ERROR", "NO_RESPONSE", "FpI4cSimulator", "Hold", "StationMemory"]
