"""A Mervis project in the simulator: its variables' bytes, and the ``.vlist`` it exports.

A project is a list of rows as the IDE exports them (name, type, CommUid,
offset, length, the parent's type family) over one memory per CommUid. Values
are stored as the web panel sends them: big-endian bytes (the seed's *Encoding
of values, version 1*). This module has its own encoding, written from the
seed and independent of the library's, so a test compares two readings.

:func:`house` is the demo cottage, *Chata Lipno* (a Unipi Neuron L203 with its inputs, outputs
and relays, rooms as function blocks with temperatures and setpoints, a boiler,
an energy meter struct and a ``dt`` clock); :func:`generated` a project of a
given number of variables with a realistic structure (function blocks of a few
members, structs, arrays, ``hw`` variables, top-level ones) for the benchmark.
"""

from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from datetime import UTC, date, datetime, timedelta
import random
import struct
from typing import Any, Final

EPOCH: Final = datetime(1, 1, 1, tzinfo=UTC)
EXPORT_GUID: Final = "5f0c2e7a-93b1-4d6e-a8f2-1c7d9e4b3a60"
"""The GUID of the simulated exports' file names (any GUID of the IDE's form)."""

# type: (bytes, signed) for integers; the others by name.
INTEGERS: Final[Mapping[str, tuple[int, bool]]] = {
    "byte": (1, False),
    "usint": (1, False),
    "sint": (1, True),
    "word": (2, False),
    "uint": (2, False),
    "int": (2, True),
    "dword": (4, False),
    "udint": (4, False),
    "dint": (4, True),
    "lword": (8, False),
    "ulint": (8, False),
    "lint": (8, True),
}
TICKS: Final = frozenset({"dt", "date", "time", "tod"})
BOOLS: Final = frozenset({"bool", "bool_1"})
"""Flags: ``bool_1`` is a block's ``en`` input in real exports (MERVIS.md)."""


class ProjectError(ValueError):
    """A value that does not fit its variable (a write is refused)."""


@dataclass(frozen=True, slots=True)
class Row:
    """One row of a ``.vlist``: a variable, a member, or a container of members.

    ``name`` is its segments joined by ``/`` (an array's element a segment of
    its own, ``in/[1]``). ``enum`` marks a 4-byte type of the project's own
    (an enumeration); ``project`` the project the row is of, when not the
    exported one's (a shared project, a library). A ``type`` with dots is
    written as its segments (a library block's type: ``lib.core.v1_0.linear``).
    """

    name: str
    type: str
    commuid: int
    offset: int
    length: int
    family: str = "none"
    enum: bool = False
    project: str = ""

    @property
    def dollar_name(self) -> str:
        """The name as the IDE writes it: ``$a$.$b$``, ``$in$.$[1]$``."""
        return ".".join(f"${part}$" for part in self.name.split("/"))

    @property
    def dollar_type(self) -> str:
        """The type as the IDE writes it: ``$real$``, ``$lib$.$core$.$v1_0$.$linear$``."""
        return ".".join(f"${part}$" for part in self.type.split("."))

    @property
    def key(self) -> str:
        """The name with dots, an element's index after its array's (the point's ID)."""
        return dotted(self.name)


def dotted(name: str) -> str:
    """Return a name of ``/``-joined segments as a point's ID: ``in/[1]`` is ``in[1]``."""
    key = ""
    for part in name.split("/"):
        key += part if part.startswith("[") or not key else f".{part}"
    return key


def encode(row: Row, value: Any) -> bytes:
    """Return a value's bytes as the row's type holds them; ProjectError if it does not fit."""
    kind = row.type.lower()
    try:
        if kind in BOOLS:
            if not isinstance(value, bool | int) or value not in (0, 1):
                raise ProjectError(f"{value!r} is no bool")
            return b"\x01" if value else b"\x00"
        if kind in INTEGERS or row.enum:
            width, signed = INTEGERS.get(kind, (4, True))
            if isinstance(value, bool) or not isinstance(value, int):
                raise ProjectError(f"{value!r} is no integer")
            return value.to_bytes(width, "big", signed=signed)
        if kind == "real":
            return struct.pack(">f", float(value))
        if kind == "lreal":
            return struct.pack(">d", float(value))
        if kind in TICKS:
            return _ticks(value).to_bytes(row.length, "big", signed=True)
        if kind == "string":
            raw = str(value).encode()
            if len(raw) > row.length:
                raise ProjectError(f"{value!r} is longer than {row.length} bytes")
            return raw.ljust(row.length, b"\x00")
    except (OverflowError, struct.error, TypeError, ValueError) as err:
        if isinstance(err, ProjectError):
            raise
        raise ProjectError(f"{value!r} does not fit {row.type}: {err}") from err
    raise ProjectError(f"a {row.type} holds no value")


def _ticks(value: Any) -> int:
    """Return 100-ns ticks: a date and time's since 0001-01-01, a duration's."""
    if isinstance(value, datetime):
        return (value - EPOCH) // timedelta(microseconds=1) * 10
    if isinstance(value, date):
        midnight = datetime(value.year, value.month, value.day, tzinfo=UTC)
        return (midnight - EPOCH) // timedelta(microseconds=1) * 10
    if isinstance(value, timedelta):
        return value // timedelta(microseconds=1) * 10
    if isinstance(value, int) and not isinstance(value, bool):
        return value
    raise ProjectError(f"{value!r} is no date, time or count of ticks")


def decode(row: Row, raw: bytes) -> Any:
    """Return the value of a row's bytes."""
    kind = row.type.lower()
    if kind in BOOLS:
        return raw != b"\x00"
    if kind in INTEGERS or row.enum:
        _, signed = INTEGERS.get(kind, (4, True))
        return int.from_bytes(raw, "big", signed=signed)
    if kind == "real":
        return struct.unpack(">f", raw)[0]
    if kind == "lreal":
        return struct.unpack(">d", raw)[0]
    ticks = int.from_bytes(raw, "big", signed=True)
    if kind in ("dt", "date"):
        moment = EPOCH + timedelta(microseconds=ticks // 10)
        return moment if kind == "dt" else moment.date()
    if kind in ("time", "tod"):
        return timedelta(microseconds=ticks // 10)
    return raw.split(b"\x00", 1)[0].decode()


@dataclass
class Project:
    """A project's rows and the bytes of each CommUid (see the module's docstring).

    ``live`` values are computed when read (the clock).
    """

    name: str
    rows: list[Row]
    memory: dict[int, bytearray] = field(default_factory=dict)
    live: dict[str, Callable[[], Any]] = field(default_factory=dict)

    def __post_init__(self) -> None:
        """Give each CommUid the bytes its rows span."""
        for row in self.rows:
            memory = self.memory.setdefault(row.commuid, bytearray())
            if len(memory) < row.offset + row.length:
                memory.extend(b"\x00" * (row.offset + row.length - len(memory)))

    def row(self, name: str) -> Row:
        """Return the row of a name (dots or slashes, any case); KeyError if none."""
        wanted = (dotted(name) if "/" in name else name).lower()
        for row in self.rows:
            if row.key.lower() == wanted:
                return row
        raise KeyError(name)

    def at(self, commuid: int, offset: int, length: int) -> Row | None:
        """Return the variable (not a container) of exactly these bytes, if any."""
        for row in self.rows:
            if (row.commuid, row.offset, row.length) == (commuid, offset, length) and (
                row.type.lower() in INTEGERS
                or row.type.lower() in TICKS
                or row.type.lower() in (*BOOLS, "real", "lreal", "string")
                or row.enum
            ):
                return row
        return None

    def read(self, commuid: int, offset: int, length: int) -> bytes | None:
        """Return some bytes of a variable (None: no such variable or bytes)."""
        for name, value in self.live.items():
            row = self.row(name)
            self._store(row, encode(row, value()))
        memory = self.memory.get(commuid)
        if memory is None or offset + length > len(memory) or length == 0:
            return None
        return bytes(memory[offset : offset + length])

    def write(self, commuid: int, offset: int, raw: bytes) -> None:
        """Change some bytes of a variable."""
        self.memory[commuid][offset : offset + len(raw)] = raw

    def get(self, name: str) -> Any:
        """Return a variable's value."""
        row = self.row(name)
        raw = self.read(row.commuid, row.offset, row.length)
        assert raw is not None
        return decode(row, raw)

    def set(self, name: str, value: Any) -> None:
        """Change a variable's value as the program would."""
        row = self.row(name)
        self._store(row, encode(row, value))

    def _store(self, row: Row, raw: bytes) -> None:
        self.memory[row.commuid][row.offset : row.offset + row.length] = raw

    def vlist(self, *, bom: bool = False) -> str:
        """Return the ``.vlist`` the IDE exports of the project (LF line ends).

        ``bom``: with the byte order mark a copy re-saved by an editor has.
        """
        lines = [
            "#ver:1.0",
            "Project;Name;Type;CommUid;Offset;Length;ParentTypeFamily;HistoryId",
        ]
        lines.extend(
            f"{row.project or self.name};{row.dollar_name};{row.dollar_type};"
            f"{row.commuid};{row.offset};{row.length};{row.family};"
            for row in self.rows
        )
        return ("\ufeff" if bom else "") + "\n".join(lines) + "\n"

    @property
    def export_name(self) -> str:
        """The file name the IDE gives the export: ``<project>_<guid>.vlist``."""
        return f"{self.name}_{EXPORT_GUID}.vlist"


WIDTHS: Final[Mapping[str, int]] = {
    "bool": 1,
    "bool_1": 1,
    "real": 4,
    "lreal": 8,
    "dt": 8,
    "date": 8,
    "time": 8,
    "tod": 8,
    **{name: width for name, (width, _) in INTEGERS.items()},
}


class _Builder:
    """Rows and values, CommUid by CommUid."""

    def __init__(self, start: int) -> None:
        self.rows: list[Row] = []
        self.values: dict[str, Any] = {}
        self.next_commuid = start

    def variable(self, name: str, type_name: str, value: Any, length: int = 0) -> None:
        """A variable of its own CommUid."""
        commuid = self._commuid()
        self.rows.append(
            Row(name, type_name, commuid, 0, length or WIDTHS[type_name.lower()])
        )
        self.values[name] = value

    def block(
        self,
        name: str,
        type_name: str,
        members: Iterable[tuple[str, str, Any]],
        family: str = "fb",
    ) -> None:
        """A function block (or struct) instance: a container row, then its members."""
        commuid = self._commuid()
        offset = 0
        rows = []
        for member, member_type, value in members:
            enum = member_type.startswith("T_")
            width = 4 if enum else WIDTHS[member_type.lower()]
            rows.append(
                Row(
                    f"{name}/{member}",
                    member_type,
                    commuid,
                    offset,
                    width,
                    family,
                    enum,
                )
            )
            self.values[f"{name}/{member}"] = value
            offset += width
        self.rows.append(Row(name, type_name, commuid, 0, offset))
        self.rows.extend(rows)

    def _commuid(self) -> int:
        commuid = self.next_commuid
        self.next_commuid += 1
        return commuid

    def project(self, name: str) -> Project:
        project = Project(name, self.rows)
        for key, value in self.values.items():
            project.set(key, value)
        return project


HOUSE_NAME: Final = "Chata Lipno"
"""The demo house's project."""
NEURON: Final = "neuron_l203"


def house(clock: Callable[[], datetime] | None = None) -> Project:
    """The demo house (see the module's docstring); ``clock`` drives its ``dt`` clock."""
    built = _Builder(17000)
    inputs = (False, True, False, False)
    for index, state in enumerate(inputs, start=1):
        built.variable(f"hw/{NEURON}_di_1.0{index}", "bool", state)
    for index in range(1, 5):
        built.variable(f"hw/{NEURON}_do_1.0{index}", "bool", False)
    built.variable(f"hw/{NEURON}_ai_1.01", "real", 4.5)
    built.variable(f"hw/{NEURON}_ao_1.01", "real", 0.0)
    for index in range(1, 9):
        built.variable(f"hw/{NEURON}_ro_2.0{index}", "bool", index == 2)
    # What a Unipi board exports beside its I/O: settings, counters, registers.
    for index in range(1, 5):
        built.variable(f"hw/{NEURON}_di_1.0{index}_counter", "udint", 17 * index)
        built.variable(f"hw/{NEURON}_di_1.0{index}_debounce", "uint", 50)
        built.variable(f"hw/{NEURON}_led_1.0{index}", "bool", False)
    for index in range(1, 9):
        built.variable(f"hw/{NEURON}_ro_2.0{index}_pwm_duty", "uint", 0)
    built.variable(f"hw/{NEURON}_fw_version", "uint", 1540)
    built.variable(f"hw/{NEURON}_uart_1_baudrate", "udint", 19200)
    built.variable(f"hw/{NEURON}_watchdog_timeout", "uint", 5000)
    built.next_commuid = 6000
    for room, temperature, setpoint in (
        ("koupelna", 21.5, 22.0),
        ("jidelna", 20.5, 21.0),
        ("sklep", 19.0, 19.5),
    ):
        built.block(
            room,
            "T_ROOM",
            (
                ("temperature", "real", temperature),
                ("setpoint", "real", setpoint),
                ("heating", "bool", temperature < setpoint),
                ("mode", "T_MODE", 1),
            ),
        )
    built.block(
        "kotel",
        "T_BOILER",
        (
            ("water_temp", "real", 58.5),
            ("return_temp", "real", 44.0),
            ("burner", "bool", True),
            ("starts", "udint", 1234),
            ("runtime", "time", timedelta(hours=813, minutes=20)),
        ),
    )
    built.block(
        "energie",
        "T_ENERGY",
        (("power", "real", 1840.0), ("total", "lreal", 15234.25)),
        family="struct",
    )
    built.next_commuid = 7000
    built.variable("outside_temp", "real", 4.5)
    built.variable("away", "bool", False)
    built.variable("boost", "time", timedelta(minutes=30))
    built.variable("clock", "dt", datetime(2026, 3, 14, 10, 0, tzinfo=UTC))
    project = built.project(HOUSE_NAME)
    if clock is not None:
        project.live["clock"] = clock
    return project


SOLUTION_NAME: Final = "Chalupa"
"""The installation's project of :func:`solution`."""
SHARED_NAME: Final = "Spolecne"
"""The shared project of :func:`solution` (more rows than the installation's)."""
LIBRARIES: Final = ("Lib.Core", "Lib.Iec", "Lib.Hvac", "base")


def solution() -> Project:
    """An export shaped as real ones are (MERVIS.md, *What real exports show*).

    Written from that description, not copied from a real file: libraries'
    rows first (``Lib.Core``, ``Lib.Iec``, ``Lib.Hvac``, ``base``), then a
    shared project's, more than the installation's own (a Unipi board's I/O,
    ``hw_hidden`` names with dots inside a segment, an array whose elements are
    segments ``$in$.$[1]$``, a struct), then the installation's (*Chalupa*: a
    library block instance, its type ``$lib$.$core$.$v1_0$.$linear$``, its
    members rows of their own, its ``en`` a ``bool_1``; a boiler block; a few
    variables). Its file name is ``Chalupa_<guid>.vlist`` (:attr:`Project.export_name`).
    """
    rows: list[Row] = []
    values: dict[str, Any] = {}
    commuid = iter(range(3000, 4000))

    def variable(name: str, type_name: str, value: Any, project: str) -> None:
        rows.append(
            Row(name, type_name, next(commuid), 0, WIDTHS[type_name], project=project)
        )
        values[name] = value

    def members(
        name: str,
        type_name: str,
        fields: Iterable[tuple[str, str, Any]],
        family: str,
        project: str,
    ) -> None:
        number = next(commuid)
        offset, inner = 0, []
        for member, member_type, value in fields:
            width = WIDTHS[member_type]
            # A member sits at its type's alignment (the block's en first).
            offset += -offset % width
            inner.append(
                Row(
                    f"{name}/{member}",
                    member_type,
                    number,
                    offset,
                    width,
                    family,
                    project=project,
                )
            )
            if value is not None:
                values[f"{name}/{member}"] = value
            offset += width
        rows.append(Row(name, type_name, number, 0, offset, project=project))
        rows.extend(inner)

    variable("core/cycle_time", "time", timedelta(milliseconds=20), "Lib.Core")
    variable("iec/scans", "udint", 81234, "Lib.Iec")
    rows.append(
        Row(
            "hvac/season",
            "T_SEASON",
            next(commuid),
            0,
            4,
            enum=True,
            project="Lib.Hvac",
        )
    )
    values["hvac/season"] = 2
    variable("sys/uptime", "time", timedelta(days=3, hours=4), "base")
    for index in range(1, 5):
        variable(f"hw/{NEURON}_di_1.0{index}", "bool", index == 3, SHARED_NAME)
    for index in range(1, 5):
        variable(f"hw/{NEURON}_ro_2.0{index}", "bool", False, SHARED_NAME)
    for index, value in ((8, 21.25), (9, 3.5)):
        variable(
            f"hw_hidden/markcom3.mxio.ai0{index}.transformation",
            "real",
            value,
            SHARED_NAME,
        )
    members(
        "in",
        "ARRAY",
        ((f"[{index}]", "bool", index % 2 == 1) for index in range(1, 5)),
        "array",
        SHARED_NAME,
    )
    members(
        "meteo",
        "T_METEO",
        (("temperature", "real", -3.5), ("wind", "real", 4.25)),
        "struct",
        SHARED_NAME,
    )
    members(
        "kotelna/ekviterm",
        "lib.core.v1_0.linear",
        (
            ("en", "bool_1", True),
            ("x", "real", -3.5),
            ("y", "real", 52.0),
            ("gain", "real", -1.2),
            ("offset", "real", 48.0),
        ),
        "fb",
        SOLUTION_NAME,
    )
    members(
        "kotel",
        "T_BOILER",
        (("teplota_vody", "real", 51.5), ("hori", "bool", True)),
        "fb",
        SOLUTION_NAME,
    )
    variable("cerpadlo", "bool", True, SOLUTION_NAME)
    variable("venku", "real", -3.5, SOLUTION_NAME)
    project = Project(SOLUTION_NAME, rows)
    for key, value in values.items():
        project.set(key, value)
    return project


def generated(points: int, *, seed: int = 0, name: str = "Generated") -> Project:
    """A project of exactly ``points`` variables, structured as real projects are.

    About 60 % are members of function block instances of 3 to 12 members
    (reals, bools, ints, an enum now and then), 10 % members of structs, 5 %
    elements of arrays, 15 % ``hw`` inputs and outputs, 10 % top-level
    variables. Same arguments, same project.
    """
    rng = random.Random(seed)
    built = _Builder(1000)
    left = points
    number = 0

    def take(count: int) -> int:
        nonlocal left
        count = max(1, min(count, left))
        left -= count
        return count

    member_types = ("real", "real", "bool", "int", "udint", "T_MODE", "lreal")
    while left > 0:
        number += 1
        draw = rng.random()
        if draw < 0.6:
            count = take(rng.randint(3, 12))
            built.block(
                f"fb_{number}",
                "T_BLOCK",
                (
                    (f"m{index}", member, _sample_value(member, rng))
                    for index, member in enumerate(
                        rng.choice(member_types) for _ in range(count)
                    )
                ),
            )
        elif draw < 0.7:
            count = take(rng.randint(2, 6))
            built.block(
                f"st_{number}",
                "T_STRUCT",
                ((f"f{index}", "real", rng.uniform(0, 100)) for index in range(count)),
                family="struct",
            )
        elif draw < 0.75:
            count = take(rng.randint(4, 10))
            commuid = built._commuid()
            built.rows.append(Row(f"arr_{number}", "ARRAY", commuid, 0, 4 * count))
            for index in range(count):
                element = f"arr_{number}/[{index}]"
                built.rows.append(Row(element, "dint", commuid, 4 * index, 4, "array"))
                built.values[element] = rng.randint(-1000, 1000)
        elif draw < 0.9:
            take(1)
            built.variable(f"hw/neuron_{number}_di_1.01", "bool", rng.random() < 0.5)
        else:
            take(1)
            built.variable(f"var_{number}", "real", rng.uniform(-50, 50))
    return built.project(name)


def _sample_value(type_name: str, rng: random.Random) -> Any:
    match type_name:
        case "real" | "lreal":
            return round(rng.uniform(-40, 120), 2)
        case "bool":
            return rng.random() < 0.5
        case "int":
            return rng.randint(-3000, 3000)
        case "udint":
            return rng.randint(0, 100000)
        case _:
            return rng.randint(0, 3)
