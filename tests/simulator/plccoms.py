"""A simulated PLCComS server, serving the same PLC memory as the TecoApi simulator.

PLCComS is Teco's text protocol with push. By default the server behaves as Teco's
manual (TXV 138 63) and the server's changelog say; what this project assumed
before is kept as options (`PlcComsOptions`), and `tests/simulator/README.md` names
the source of every behaviour. A write
through either protocol is seen through both: this server holds the Simulator's
`Plc`, whose memory a TecoApi SetObject/PutObject changes.

```python
async with Simulator("demo") as sim, PlcComsServer(sim, scan_interval=None) as coms:
    coms.port                      # where a client connects (127.0.0.1)
    sim.set_value("outsideTemp.value", 5.5)
    await coms.scan()              # one change-detection pass now: DIFF: lines go out
    coms.faults.stall = True       # keep TCP open, answer and push nothing
    coms.faults.plc_unreachable = True  # ERROR:10 to all but GETINFO:
    await coms.restart()           # drop every connection, keep accepting
```
"""

import asyncio
from collections.abc import Collection, Iterable, Iterator
import contextlib
from dataclasses import dataclass, field
import datetime as dt
from decimal import Decimal
import logging
import math
import re
import struct
from typing import Any, Final

from .base import Progress, Served
from .errors import TecoError
from .iec import (
    INTEGER_RANGES,
    MAX_TIME_MS,
    REAL_LIMITS,
    ArrayOf,
    Elementary,
    IecType,
    RejectedValueError,
    Struct,
    from_json,
)
from .memory import Location, PlcMemory
from .server import Simulator

_LOGGER: Final = logging.getLogger(__package__ + ".plccoms")

ENCODING: Final = "cp1250"
SERVER_VERSION: Final = "6.1"
SERVER_BUILD: Final = f"Ver {SERVER_VERSION} Jun  1 2023 13:15:36"
EPSNET_PORT: Final = 61682
EPSNET_ADDRESS: Final = 126
MAX_CONNECTIONS: Final = 128
PLC_RUN: Final = "__PLC_RUN"
PF_CRC: Final = "__PF_CRC"
# The fixed public file's variables: always pushed, EN:/DI: do not apply.
FIXED: Final = frozenset({PLC_RUN, PF_CRC})
FIXED_FILE: Final = "FIXED_Foxtrot.pub"
UNREACHABLE: Final = "ERROR:10 Unable to connect to PLC."
DEFAULT_SCAN_INTERVAL: Final = 0.1
# Longest command line the server takes (bytes); longer ones are refused.
MAX_COMMAND_LENGTH: Final = 4096
_EPOCH: Final = dt.datetime(1970, 1, 1, tzinfo=dt.UTC)
_DAY_MS: Final = 24 * 3600 * 1000
_INTEGER: Final = re.compile(r"[+-]?[0-9]+")
_NUMBER: Final = re.compile(
    r"[+-]?(?:[0-9]+(?:[.,][0-9]*)?|[.,][0-9]+)(?:[eE][+-]?[0-9]+)?"
)
_CLOCK: Final = re.compile(r"([0-9]{1,3}):([0-5][0-9]):([0-5][0-9])(?:\.([0-9]{1,3}))?")
_DATE: Final = re.compile(r"[0-9]{4}-[0-9]{2}-[0-9]{2}")
_DT: Final = re.compile(r"([0-9]{4}-[0-9]{2}-[0-9]{2})T([0-9:.]+)Z?")
_UNSIGNED: Final = re.compile(r"[0-9]+")


@dataclass(slots=True, kw_only=True)
class PlcComsOptions:
    """The server's settings (PLCComS.ini), and the older forms as switches.

    Settings: `crlf` (`END_LINE_CRLF`); `decimals` None prints the shortest plain
    form (`21.8`), a number that many decimals (`NUM_OF_DECIMALS`); `scientific`
    prints `2.180000e+01` (`SCIENT_NOTATION`); `decimal_comma` swaps the point for
    a comma; `var_disabled` (`PF_VAR_DISABLED`, Yes as shipped): a connection's
    variables start disabled, else enabled; `date_time_decimal`
    (`DATE_TIME_DECIMAL`): DATE and DT as a decimal double, not its 8 bytes as an
    integer.

    Older forms (what servers do or what this project assumed before the
    manual; every one off by default): `flags_after_name` (`LIST:name*,TYPE`),
    `enabled_flag` (`*` marks the variables this connection enabled),
    `enable_answer` ("warning" as the manual, "value": `GET:name,value` per
    variable as older servers, "none": nothing), `legacy_errors` (this project's
    old codes and texts, `ERROR:2 Variable 'x' not found`), `date_seconds` (DATE
    and DT as an integer count of seconds), `lower_case_info` (the old
    `GETINFO:` keys and values, a bare `GETINFO:` after one key too).
    """

    crlf: bool = True
    decimal_comma: bool = False
    scientific: bool = False
    decimals: int | None = None
    var_disabled: bool = True
    date_time_decimal: bool = False
    flags_after_name: bool = False
    enabled_flag: bool = False
    enable_answer: str = "warning"
    legacy_errors: bool = False
    date_seconds: bool = False
    lower_case_info: bool = False


@dataclass(slots=True)
class PlcComsFaults:
    """What is wrong with the server right now; every field may change at any time.

    `stall`: connections stay open, but nothing is read, answered or pushed until it
    is switched off. `out_of_order`: the GET: answers to the commands of one read
    come back in reverse order. `split_writes`: every line goes out in two TCP
    writes. `refuse`: new connections are closed at once, before a byte (a server
    that is not ready). `plc_unreachable`: the server cannot reach its PLC (Teco's
    server 6.1 seen so): every command but GETINFO: is answered
    `ERROR:10 Unable to connect to PLC.`, nothing is pushed, VERSION_PLC is blank.
    `raw_values`: the text sent for a variable (by its name in any case) instead of
    its value, as from a PLC holding what its type cannot (a DT beyond 9999).
    """

    stall: bool = False
    out_of_order: bool = False
    split_writes: bool = False
    refuse: bool = False
    plc_unreachable: bool = False
    raw_values: dict[str, str] = field(default_factory=dict)
    _changed: asyncio.Event | None = field(
        default=None, init=False, repr=False, compare=False
    )

    def __setattr__(self, name: str, value: Any) -> None:
        """Set a field and wake connections waiting for a stall to end."""
        object.__setattr__(self, name, value)
        changed = getattr(self, "_changed", None)
        if name != "_changed" and changed is not None:
            changed.set()
            object.__setattr__(self, "_changed", asyncio.Event())

    async def wait_unstalled(self) -> None:
        """Return once `stall` is off."""
        while self.stall:
            if self._changed is None:
                object.__setattr__(self, "_changed", asyncio.Event())
            assert self._changed is not None
            await self._changed.wait()


@dataclass(frozen=True, slots=True)
class ComsVariable:
    """One variable LIST: shows: a leaf of the program's public variables."""

    name: str
    type: Elementary
    location: Location

    @property
    def type_name(self) -> str:
        """The type LIST: prints: the elementary type without a string length."""
        return self.type.name


@dataclass(eq=False)
class _Client:
    """One connection: its streams, enabled variables (with deltas), values sent."""

    reader: asyncio.StreamReader
    writer: asyncio.StreamWriter
    task: asyncio.Task[None] | None
    enabled: dict[str, float] = field(default_factory=dict)
    sent: dict[str, Any] = field(default_factory=dict)
    hidden: set[str] = field(default_factory=set)
    lock: asyncio.Lock = field(default_factory=asyncio.Lock)
    connected_at: dt.datetime = field(default_factory=lambda: dt.datetime.now(dt.UTC))


# ERROR: lines by what went wrong: the manual's codes and texts (chapter 5; the
# texts of 32, 60 and 30 are assumed), and this project's older ones.
_ERRORS: Final = {
    "command": (32, "Unknown command in request: '{request}'"),
    "variable": (33, "Unknown variable name in request: '{request}'"),
    "value": (35, "Wrong parameter value in request: '{request}'"),
    "delta": (35, "Wrong parameter value in request: '{request}'"),
    "fixed": (35, "Wrong parameter value in request: '{request}'"),
    "info": (60, "Unknown GETINFO name in request: '{request}'"),
    "long": (30, "Request too long"),
}
_LEGACY_ERRORS: Final = {
    "command": (1, "Unknown command '{command}'"),
    "variable": (2, "Variable '{name}' not found"),
    "value": (3, "Invalid value '{value}' of variable '{name}' ({type})"),
    "delta": (4, "Invalid delta '{value}' of variable '{name}'"),
    "fixed": (5, "Variable '{name}' cannot be set to '{value}'"),
    "info": (6, "Unknown GETINFO key '{name}'"),
    "long": (7, "Line too long"),
}


class _CommandError(Exception):
    """A command the server answers with an ERROR: line (see `_ERRORS`)."""

    def __init__(self, kind: str, **details: str) -> None:
        super().__init__(kind)
        self.kind = kind
        self.details = details


@dataclass(slots=True)
class _Answers:
    """What one read's commands produce, sent in this order: immediate, GET, DIFF."""

    immediate: list[str] = field(default_factory=list)
    values: list[str] = field(default_factory=list)
    diffs: list[str] = field(default_factory=list)


def leaves(name: str, iec_type: IecType) -> Iterator[tuple[str, Elementary]]:
    """The elementary variables under a declaration: `a.b`, `a[1][2]`, in order."""
    if isinstance(iec_type, Struct):
        for member, member_type in iec_type.members.items():
            yield from leaves(f"{name}.{member}", member_type)
    elif isinstance(iec_type, ArrayOf):
        for index in range(iec_type.size):
            yield from leaves(f"{name}[{index}]", iec_type.element)
    else:
        yield name, iec_type


def _pattern(mask: str) -> re.Pattern[str]:
    """A `*` mask (any number of stars) as a case-insensitive pattern."""
    return re.compile(
        ".*".join(re.escape(part) for part in mask.split("*")), re.IGNORECASE
    )


class PlcComsServer(Served):
    """A PLCComS server on a Simulator's PLC: LIST:, GET:, SET:, EN:, DI:, GETINFO:.

    Change detection runs every `scan_interval` seconds (None: only when a test
    calls `scan()`); `__PLC_RUN` follows the simulator's mode, and a program
    download shows as `__PLC_RUN` 0 for one scan, then 1, with LIST: changed.
    """

    def __init__(
        self,
        simulator: Simulator,
        *,
        options: PlcComsOptions | None = None,
        scan_interval: float | None = DEFAULT_SCAN_INTERVAL,
        unpublished: Collection[str] = (),
    ) -> None:
        """Prepare a server for the simulator's PLC (not started).

        ``unpublished`` names variables of the program that the server's public
        file lacks: not listed, unknown to every command.
        """
        super().__init__()
        self._sim = simulator
        self.unpublished = frozenset(name.lower() for name in unpublished)
        self.options = options or PlcComsOptions()
        self.faults = PlcComsFaults()
        self.scan_interval = scan_interval
        self.commands: list[str] = []
        self.lines_sent = 0
        self.writes = 0
        self.connections_accepted = 0
        self.scans = 0
        self.restarts = 0
        self._clients: set[_Client] = set()
        self._server: asyncio.Server | None = None
        self._scanner: asyncio.Task[None] | None = None
        self._memory: PlcMemory | None = None
        self._variables: dict[str, ComsVariable] = {}
        self._download_scans = 0

    # --- lifecycle ---------------------------------------------------------------------

    async def start(self, host: str = "127.0.0.1", port: int = 0) -> None:
        """Listen on host:port (0 picks a free port) and start scanning."""
        if self._server is not None:
            raise RuntimeError("the PLCComS server is already running")
        self._progress = Progress()
        self._refresh()
        self._server = await asyncio.start_server(self._serve, host, port)
        self._bound_host = host
        self._port = self._server.sockets[0].getsockname()[1]
        if self.scan_interval is not None:
            self._scanner = asyncio.create_task(self._scan_periodically())

    async def stop(self) -> None:
        """Stop listening and drop every connection. Idempotent."""
        server, self._server = self._server, None
        if server is None:
            return
        if self._scanner is not None:
            self._scanner.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await self._scanner
            self._scanner = None
        server.close()
        await self._drop_all()
        await server.wait_closed()

    async def restart(self) -> None:
        """Drop every connection, as a restarting server does; keep accepting."""
        self.restarts += 1
        await self._drop_all()

    # --- what a test reads -------------------------------------------------------------

    @property
    def host(self) -> str:
        """The address served."""
        return self._bound_host

    @property
    def connections(self) -> int:
        """Connections open now."""
        return len(self._clients)

    @property
    def variables(self) -> list[ComsVariable]:
        """What LIST: shows now, in order (the server's own `__*` first)."""
        self._refresh()
        return list(self._variables.values())

    def enabled(self) -> list[set[str]]:
        """The lower-case names each open connection has enabled."""
        return [set(client.enabled) for client in self._clients]

    async def wait_for_commands(self, count: int) -> None:
        """Wait until `commands` holds at least `count` lines."""
        await self._progress.wait_until(lambda: len(self.commands) >= count)

    async def wait_for_scans(self, count: int) -> None:
        """Wait until at least `count` change-detection passes have run."""
        await self._progress.wait_until(lambda: self.scans >= count)

    async def wait_for_connections(self, count: int) -> None:
        """Wait until at least `count` connections have been accepted in all."""
        await self._progress.wait_until(lambda: self.connections_accepted >= count)

    async def wait_for_open_connections(self, count: int) -> None:
        """Wait until exactly `count` connections are open (set up to read commands)."""
        await self._progress.wait_until(lambda: len(self._clients) == count)

    # --- change detection --------------------------------------------------------------

    async def scan(self) -> int:
        """One change-detection pass now: DIFF: to every connection; lines sent."""
        self._refresh()
        sent = 0
        for client in list(self._clients):
            if self.faults.stall or self.faults.plc_unreachable:
                break
            diffs = self._changes(client)
            if diffs:
                await self._write(client, diffs)
                sent += len(diffs)
        if self._download_scans:
            self._download_scans -= 1
        self.scans += 1
        self._notify()
        return sent

    def _changes(self, client: _Client) -> list[str]:
        """The DIFF: lines of one connection's enabled variables that changed.

        The fixed variables (`__PLC_RUN`, `__PF_CRC`) are always followed.
        """
        lines: list[str] = []
        fixed = {name.lower(): 0.0 for name in FIXED}
        for key, delta in (fixed | client.enabled).items():
            variable = self._variables.get(key)
            if variable is None:
                continue
            value = self._read(variable)
            if key in client.sent and not _changed(client.sent[key], value, delta):
                continue
            client.sent[key] = value
            lines.append(f"DIFF:{variable.name},{self._text(variable, value)}")
        return lines

    async def _scan_periodically(self) -> None:
        while self.scan_interval is not None:
            await asyncio.sleep(self.scan_interval)
            try:
                await self.scan()
            except (ConnectionError, OSError):  # pragma: no cover - a client vanished
                _LOGGER.debug("a PLCComS client vanished during a scan")

    # --- the program -------------------------------------------------------------------

    def _refresh(self) -> None:
        """Follow a program download: a new variable list, __PLC_RUN 0 for one scan."""
        memory = self._sim.plc.memory
        if memory is self._memory:
            return
        first = self._memory is None
        self._memory = memory
        variables: dict[str, ComsVariable] = {}
        for name, iec_type in (
            (PLC_RUN, Elementary("BOOL")),
            (PF_CRC, Elementary("DWORD")),
        ):
            variables[name.lower()] = ComsVariable(
                name, iec_type, Location(name, name, (), (name,), iec_type)
            )
        for declaration in self._sim.plc.program.declarations:
            for name, elementary in leaves(declaration.name, declaration.type):
                if name.lower() in self.unpublished:
                    continue
                variables[name.lower()] = ComsVariable(
                    name, elementary, memory.resolve(name)
                )
        self._variables = variables
        for client in self._clients:
            for key in [key for key in client.enabled if key not in variables]:
                del client.enabled[key]
                client.sent.pop(key, None)
        if not first:
            self._download_scans = 1

    def _read(self, variable: ComsVariable) -> Any:
        if variable.name == PLC_RUN:
            return self._sim.mode == "RUN" and not self._download_scans
        if variable.name == PF_CRC:
            return int(self._sim.stamp, 16)
        return self._sim.plc.memory.read(variable.location)

    def _lookup(self, name: str) -> ComsVariable:
        variable = self._variables.get(name.strip().lower())
        if variable is None:
            raise _CommandError("variable", name=name.strip())
        return variable

    def _matching(
        self, mask: str, client: _Client | None = None, *, hidden: bool = False
    ) -> list[ComsVariable]:
        """The variables a name or `*` mask names (a plain unknown name is an error).

        A mask leaves out the connection's hidden variables (changelog 4.1), unless
        `hidden`.
        """
        if "*" not in mask:
            return [self._lookup(mask)]
        pattern = _pattern(mask.strip())
        skipped = set() if client is None or hidden else client.hidden
        return [
            v
            for v in self._variables.values()
            if pattern.fullmatch(v.name) and v.name.lower() not in skipped
        ]

    # --- values as text ----------------------------------------------------------------

    def _text(self, variable: ComsVariable, value: Any) -> str:
        """A value as the server prints it, after the options."""
        raw = {key.lower(): text for key, text in self.faults.raw_values.items()}
        if (text := raw.get(variable.name.lower())) is not None:
            return text
        name = variable.type.name
        if name == "BOOL":
            return "1" if value else "0"
        if name in INTEGER_RANGES:
            return str(value)
        if name in REAL_LIMITS:
            return self._real_text(float(value))
        if name == "STRING":
            return f'"{value}"'
        if name in {"TIME", "TOD"}:
            return str(_clock_ms(value))
        moment = dt.datetime.fromisoformat(value)
        seconds = _seconds(moment if name == "DT" else moment.replace(tzinfo=dt.UTC))
        if self.options.date_seconds:
            return str(math.floor(seconds))
        if self.options.date_time_decimal:
            return self._real_text(seconds)
        # DATE_TIME_DECIMAL = No: the double's 8 bytes as an unsigned integer.
        return str(int.from_bytes(struct.pack("<d", seconds), "little"))

    def _real_text(self, value: float) -> str:
        options = self.options
        if options.scientific:
            decimals = 6 if options.decimals is None else options.decimals
            text = f"{value:.{decimals}e}"
        elif options.decimals is not None:
            text = f"{value:.{options.decimals}f}"
        else:
            text = format(Decimal(repr(value)), "f")
        return text.replace(".", ",") if options.decimal_comma else text

    def _parse(self, variable: ComsVariable, text: str) -> Any:
        """A SET: value as the memory holds it; RejectedValueError if it does not fit."""
        elementary = variable.type
        name = elementary.name
        if name == "STRING":
            if len(text) >= 2 and text[0] == text[-1] == '"':
                text = text[1:-1]
            try:
                text.encode(ENCODING)
            except UnicodeEncodeError as err:
                raise RejectedValueError(text) from err
            if len(text) > (elementary.length or 0) or '"' in text:
                raise RejectedValueError(text)
            return text
        if name == "BOOL":
            if text.lower() in {"1", "true", "0", "false"}:
                return text.lower() in {"1", "true"}
            raise RejectedValueError(text)
        if name in INTEGER_RANGES:
            if _INTEGER.fullmatch(text) is None:
                raise RejectedValueError(text)
            return from_json(elementary, int(text))
        if name in REAL_LIMITS:
            if _NUMBER.fullmatch(text) is None:
                raise RejectedValueError(text)
            return from_json(elementary, float(text.replace(",", ".")))
        return from_json(elementary, self._time_text(name, text))

    def _time_text(self, name: str, text: str) -> str:
        """A SET: of TIME/TOD (ms or hh:mm:ss.zzz), DATE or DT as the memory holds it.

        DATE and DT take the server's own form (see `_text`) or ISO text.
        """
        if name in {"TIME", "TOD"}:
            return _clock_text(name, text)
        if name == "DATE" and _DATE.fullmatch(text):
            return text
        if name == "DT" and _DT.fullmatch(text):
            return text if text.endswith("Z") else f"{text}Z"
        seconds = self._date_seconds(text)
        try:
            moment = _EPOCH + dt.timedelta(milliseconds=round(seconds * 1000))
        except (OverflowError, ValueError) as err:
            raise RejectedValueError(text) from err
        if name == "DATE":
            return moment.date().isoformat()
        return (
            moment.strftime("%Y-%m-%dT%H:%M:%S.") + f"{moment.microsecond // 1000:03d}Z"
        )

    def _date_seconds(self, text: str) -> float:
        """Seconds since 1970 of a DATE/DT number in the server's form."""
        options = self.options
        if options.date_time_decimal and _NUMBER.fullmatch(text):
            seconds = float(text.replace(",", "."))
        elif _UNSIGNED.fullmatch(text) and options.date_seconds:
            seconds = float(int(text))
        elif _UNSIGNED.fullmatch(text) and int(text) < 2**64:
            (seconds,) = struct.unpack("<d", int(text).to_bytes(8, "little"))
        else:
            raise RejectedValueError(text)
        if not math.isfinite(seconds) or seconds < 0:
            raise RejectedValueError(text)
        return seconds

    # --- connections -------------------------------------------------------------------

    async def _serve(
        self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter
    ) -> None:
        self.connections_accepted += 1
        if self.faults.refuse:
            writer.transport.abort()
            self._notify()
            return
        client = _Client(reader, writer, asyncio.current_task())
        self._refresh()
        for variable in self._variables.values():
            key = variable.name.lower()
            if variable.name in FIXED:
                client.sent[key] = self._read(variable)
            elif not self.options.var_disabled:
                # PF_VAR_DISABLED = No: every variable starts enabled.
                client.enabled[key] = 0.0
                client.sent[key] = self._read(variable)
        self._clients.add(client)
        self._notify()
        buffer = bytearray()
        # Inside a line over MAX_COMMAND_LENGTH: refused once, skipped to its end.
        discarding = False
        try:
            while True:
                await self.faults.wait_unstalled()
                data = await reader.read(65536)
                if not data:
                    break
                # A stall that began while waiting for data holds it unanswered.
                await self.faults.wait_unstalled()
                buffer += data
                *lines, rest = bytes(buffer).split(b"\n")
                buffer = bytearray(rest)
                answers = _Answers()
                too_long = self._error_line(_CommandError("long"), "")
                for line in lines:
                    if discarding:
                        discarding = False
                    elif len(line) > MAX_COMMAND_LENGTH:
                        answers.immediate.append(too_long)
                    else:
                        self._command(client, line.decode(ENCODING, "replace"), answers)
                if len(buffer) > MAX_COMMAND_LENGTH:
                    buffer.clear()
                    if not discarding:
                        answers.immediate.append(too_long)
                    discarding = True
                await self._send(client, answers)
        except (ConnectionError, OSError):
            _LOGGER.debug("a PLCComS client's connection failed")
        finally:
            self._clients.discard(client)
            writer.transport.abort()
            self._notify()

    async def _send(self, client: _Client, answers: _Answers) -> None:
        values = answers.values
        if self.faults.out_of_order:
            values = list(reversed(values))
        lines = [*answers.immediate, *values, *answers.diffs]
        if lines:
            await self._write(client, lines)

    async def _write(self, client: _Client, lines: Iterable[str]) -> None:
        end = "\r\n" if self.options.crlf else "\n"
        chunks = [f"{line}{end}".encode(ENCODING, "replace") for line in lines]
        async with client.lock:
            if self.faults.split_writes:
                for chunk in chunks:
                    middle = max(1, len(chunk) // 2)
                    for part in (chunk[:middle], chunk[middle:]):
                        client.writer.write(part)
                        self.writes += 1
                        await client.writer.drain()
                        # Let the loop send it before the next part is queued.
                        await asyncio.sleep(0)
            else:
                client.writer.write(b"".join(chunks))
                self.writes += 1
                await client.writer.drain()
        self.lines_sent += len(chunks)

    async def _drop_all(self) -> None:
        clients = list(self._clients)
        for client in clients:
            client.writer.transport.abort()
            if client.task is not None:
                client.task.cancel()
        await asyncio.gather(
            *(client.task for client in clients if client.task is not None),
            return_exceptions=True,
        )

    def _notify(self) -> None:
        self._progress.notify()

    # --- commands ------------------------------------------------------------------------

    def _command(self, client: _Client, line: str, answers: _Answers) -> None:
        """Carry out one command line, adding its answer lines."""
        line = line.rstrip("\r")
        if not line.strip():
            return
        self.commands.append(line)
        self._notify()
        self._refresh()
        command, colon, argument = line.partition(":")
        try:
            self._dispatch(
                client, command.strip().upper() if colon else line, argument, answers
            )
        except _CommandError as error:
            answers.immediate.append(self._error_line(error, line.strip()))

    def _error_line(self, error: _CommandError, request: str) -> str:
        """The ERROR: line of a refused request, in the manual's or the old form."""
        table = _LEGACY_ERRORS if self.options.legacy_errors else _ERRORS
        code, text = table[error.kind]
        details = {"command": "", "name": "", "value": "", "type": ""}
        return f"ERROR:{code} " + text.format(
            **(details | error.details), request=request
        )

    def _dispatch(
        self, client: _Client, command: str, argument: str, answers: _Answers
    ) -> None:
        """Carry out one command; _CommandError for what the server refuses."""
        if self.faults.plc_unreachable and command != "GETINFO":
            answers.immediate.append(UNREACHABLE)
            return
        match command:
            case "LIST":
                answers.immediate.extend(self._list(client, argument.strip()))
            case "GET":
                answers.values.extend(
                    f"GET:{v.name},{self._text(v, self._read(v))}"
                    for v in self._matching(argument, client)
                )
            case "SET":
                answers.diffs.append(self._set(client, argument))
            case "EN" | "DI":
                self._activate(client, command == "EN", argument, answers)
            case "HIDE" | "UNHIDE":
                self._hide(client, command == "HIDE", argument, answers)
            case "GETINFO":
                answers.immediate.extend(self._info(client, argument.strip()))
            case _:
                raise _CommandError("command", command=command)

    def _list(self, client: _Client, mask: str) -> list[str]:
        pattern = _pattern(mask) if mask else None
        lines: list[str] = []
        for v in self._variables.values():
            if pattern is not None and not pattern.fullmatch(v.name):
                continue
            key = v.name.lower()
            enabled = key in client.enabled
            if self.options.enabled_flag:
                flags = "*" if enabled else ""
            else:
                flags = "" if enabled or v.name in FIXED else "*"
            flags += "~" if key in client.hidden else ""
            if self.options.flags_after_name:
                lines.append(f"LIST:{v.name}{flags},{v.type_name}")
            else:
                lines.append(f"LIST:{v.name},{v.type_name}{flags}")
        return [*lines, "LIST:"]

    def _set(self, client: _Client, argument: str) -> str:
        name, comma, text = argument.partition(",")
        variable = self._lookup(name)
        details = {"name": variable.name, "value": text.strip()}
        if variable.name in FIXED or not comma:
            raise _CommandError("fixed", **details)
        try:
            value = self._parse(variable, text.strip())
        except RejectedValueError as err:
            raise _CommandError(
                "value", type=variable.type.type_name, **details
            ) from err
        transaction = self._sim.plc.memory.transaction()
        try:
            transaction.write_value(variable.location, value)
        except TecoError as err:  # pragma: no cover - the location was resolved
            raise _CommandError("value", **details) from err
        transaction.commit()
        # Since server 6.1 a SET: always produces a DIFF: for its variable.
        stored = self._read(variable)
        if variable.name.lower() in client.enabled:
            client.sent[variable.name.lower()] = stored
        return f"DIFF:{variable.name},{self._text(variable, stored)}"

    def _activate(
        self, client: _Client, enable: bool, argument: str, answers: _Answers
    ) -> None:
        """EN: or DI: a name or mask (bare: all), with a delta for EN:."""
        parts = argument.split() or ["*"]
        if len(parts) > 2:
            raise _CommandError("variable", name=argument.strip())
        delta = 0.0
        if len(parts) == 2:
            if (
                _NUMBER.fullmatch(parts[1]) is None
                or float(parts[1].replace(",", ".")) < 0
            ):
                raise _CommandError("delta", name=parts[0], value=parts[1])
            delta = float(parts[1].replace(",", "."))
        matched = [v for v in self._matching(parts[0], client) if v.name not in FIXED]
        for variable in matched:
            key = variable.name.lower()
            if enable:
                client.enabled[key] = delta
                # Changes are pushed from now on; the value is read with GET:.
                client.sent[key] = self._read(variable)
            else:
                client.enabled.pop(key, None)
                client.sent.pop(key, None)
        match self.options.enable_answer:
            case "warning":
                total = sum(
                    1 for name in self._variables.values() if name.name not in FIXED
                )
                answers.immediate.append(
                    "WARNING:252 Changed active variables in public file: "
                    f"'[{len(client.enabled)}/{total}]'"
                )
            case "value":
                answers.values.extend(
                    f"GET:{v.name},{self._text(v, self._read(v))}" for v in matched
                )

    def _hide(
        self, client: _Client, hide: bool, argument: str, answers: _Answers
    ) -> None:
        """HIDE: or UNHIDE: a name or mask: hidden ones are left out of masks."""
        for variable in self._matching(argument.strip() or "*", client, hidden=True):
            if hide:
                client.hidden.add(variable.name.lower())
            else:
                client.hidden.discard(variable.name.lower())
        answers.immediate.append(
            "WARNING:253 Changed hidden variables in public file: "
            f"'[{len(client.hidden)}/{len(self._variables)}]'"
        )

    def _info(self, client: _Client, key: str) -> list[str]:
        if self.options.lower_case_info:
            return self._old_info(key)
        identity = self._sim.plc.identity
        ip = self._sim.host.partition(":")[0] or "127.0.0.1"
        info: list[tuple[str, str]] = [
            ("VERSION", SERVER_BUILD),
            ("VERSION_EPSNET", "Ver 2.7"),
            ("VERSION_INI", "Ver 1.4"),
            ("VERSION_PLC", "" if self.faults.plc_unreachable else identity.version),
            ("IPADDR", ip),
            ("EPSADDR", str(EPSNET_ADDRESS)),
            ("EPSPORT", str(EPSNET_PORT)),
            ("PUBFILE", f"2/2 [{FIXED_FILE},{self._sim.program.name}.pub]"),
        ]
        clients = sorted(self._clients, key=lambda c: c.connected_at)
        info.extend(
            (
                "NETWORK",
                f"{index}/{MAX_CONNECTIONS} [127.0.0.1  {other.connected_at:%Y-%m-%d %H:%M:%S}]",
            )
            for index, other in enumerate(clients, 1)
        )
        lines = [f"GETINFO:{name},{value}" for name, value in info]
        if not key:
            return [*lines, "GETINFO:"]
        chosen = [
            line
            for (name, _), line in zip(info, lines, strict=True)
            if name == key.upper()
        ]
        if not chosen:
            raise _CommandError("info", name=key)
        # One key answers its line; NETWORK is a list, ended as one (changelog 5.8).
        return [*chosen, "GETINFO:"] if key.upper() == "NETWORK" else chosen

    def _old_info(self, key: str) -> list[str]:
        """GETINFO: as this project assumed before the manual (lower-case keys)."""
        identity = self._sim.plc.identity
        info = {
            "version": SERVER_VERSION,
            "version_plc": identity.version,
            "ipaddr": self._sim.host.partition(":")[0] or "127.0.0.1",
            "epsport": str(EPSNET_PORT),
            "pubfile": f"{self._sim.program.name}.pub",
            "network": f"{len(self._clients)} clients",
        }
        if key:
            if key.lower() not in info:
                raise _CommandError("info", name=key)
            info = {key.lower(): info[key.lower()]}
        return [
            *(f"GETINFO:{name},{value}" for name, value in info.items()),
            "GETINFO:",
        ]


def _changed(before: Any, after: Any, delta: float) -> bool:
    """Whether a change is reported: numbers by at least `delta`, others any change."""
    numbers = all(
        isinstance(value, int | float) and not isinstance(value, bool)
        for value in (before, after)
    )
    if numbers and delta > 0:
        return bool(abs(after - before) >= delta)
    return bool(before != after)


def _clock_ms(text: str) -> int:
    hours, minutes, rest = text.split(":")
    seconds = float(rest)
    return (int(hours) * 3600 + int(minutes) * 60) * 1000 + round(seconds * 1000)


def _seconds(moment: dt.datetime) -> float:
    """Seconds since 1970 (to the millisecond) of an aware moment."""
    return round((moment - _EPOCH).total_seconds() * 1000) / 1000


def _format_clock(milliseconds: int) -> str:
    seconds, ms = divmod(milliseconds, 1000)
    minutes, seconds = divmod(seconds, 60)
    hours, minutes = divmod(minutes, 60)
    return f"{hours:02d}:{minutes:02d}:{seconds:02d}.{ms:03d}"


def _clock_text(name: str, text: str) -> str:
    """A SET: of TIME/TOD (milliseconds or hh:mm:ss.zzz) as the memory holds it."""
    if _INTEGER.fullmatch(text):
        limit = MAX_TIME_MS if name == "TIME" else _DAY_MS - 1
        if not 0 <= int(text) <= limit:
            raise RejectedValueError(text)
        return _format_clock(int(text))
    if _CLOCK.fullmatch(text) is None:
        raise RejectedValueError(text)
    return text
