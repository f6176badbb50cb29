"""Generated PLC programs of any size, for the read planner's tests and the benchmark.

`generate_program(points)` declares exactly `points` T_ApiObject variables of mixed
value kinds (REAL, INT, UINT, BOOL, STRING), about 60 % read-only, writable numbers
with a min/max range, numbers with units; names of 12-30 characters built from
house-automation words. About a third sit at the top level, the rest inside program
instances, structs (some nested) and arrays of T_ApiObject; a few plain scalars
come along. The same arguments always give the same program.

`generate_program(points, roots=N)` puts all the points into exactly `N` roots
instead (program instances, structs and arrays, no plain scalars), each as full as
one response of the CPU allows: the shape of a large CP-1xxx installation, where
nearly every root is too big to share a GetObject answer with another.
"""

from collections.abc import Iterator
import random
import re
from typing import Any, Final

from .plc import limit_for_type
from .program import Program

MIN_NAME_LENGTH: Final = 12
MAX_NAME_LENGTH: Final = 30
MAX_TITLE_LENGTH: Final = 32

_PLACES: Final = (
    "livingRoom",
    "kitchen",
    "bedroom",
    "bathroom",
    "hallway",
    "garage",
    "office",
    "cellar",
    "attic",
    "terrace",
    "garden",
    "workshop",
    "laundry",
    "pantry",
    "staircase",
    "guestRoom",
    "kidsRoom",
    "diningRoom",
    "boilerRoom",
    "entrance",
    "wellnessZone",
    "northWing",
    "southFacade",
)
# value kind -> (weight, quantities as (name part, units or None))
_QUANTITIES: Final[dict[str, tuple[int, tuple[tuple[str, str | None], ...]]]] = {
    "REAL": (
        50,
        (
            ("Temperature", "°C"),
            ("TempSetpoint", "°C"),
            ("ReturnTemperature", "°C"),
            ("HeatingSetpoint", "°C"),
            ("Humidity", "%"),
            ("Power", "W"),
            ("Energy", "kWh"),
            ("Pressure", "bar"),
            ("AirQuality", "ppm"),
            ("Illuminance", "lx"),
            ("FlowRate", "l/min"),
            ("Voltage", "V"),
        ),
    ),
    "INT": (10, (("Offset", "K"), ("Correction", None), ("Balance", None))),
    "UINT": (10, (("Counter", None), ("Level", "%"), ("Position", "%"))),
    "BOOL": (
        20,
        (("Light", None), ("Window", None), ("Motion", None), ("Valve", None)),
    ),
    "STRING": (10, (("Message", None), ("StatusText", None), ("Label", None))),
}
_INSTANCES: Final = (
    "Heating",
    "Lighting",
    "Climate",
    "Security",
    "Shading",
    "Irrigation",
    "Ventilation",
    "Metering",
)
_PLAIN_SCALARS: Final = (
    ("systemUptimeSeconds", "UDINT", 864000),
    ("alarmSystemArmed", "BOOL", False),
    ("outdoorIlluminance", "REAL", 1250.5),
    ("controllerNoteText", "STRING", "generated program"),
    ("commissioningDate", "DATE", "2024-04-01"),
)


def generate_program(
    points: int,
    *,
    seed: int = 0,
    plc_type: str = "CP-2080",
    roots: int | None = None,
) -> Program:
    """A program with exactly `points` T_ApiObjects, the same for the same arguments.

    With `roots`, the points fill exactly that many roots, none holding more
    T_ApiObjects than one response of `plc_type` takes (8 items each).
    """
    if points < 0:
        raise ValueError("points must be >= 0")
    if roots is not None and not 0 < roots * (limit_for_type(plc_type) // 8) >= points:
        raise ValueError("roots must be > 0 and able to hold the points")
    return Program.from_mapping(
        _Generator(random.Random(seed), seed).program(points, plc_type, roots)
    )


class _Generator:
    def __init__(self, rng: random.Random, seed: int) -> None:
        self._rng = rng
        self._seed = seed
        self._used: set[str] = set()
        self._types: dict[str, dict[str, str]] = {}

    def program(
        self, points: int, plc_type: str, roots: int | None = None
    ) -> dict[str, Any]:
        # A root must fit one response (GetList names roots only, so a client can
        # learn a root's members only by reading it whole): a T_ApiObject is 8 items.
        most = limit_for_type(plc_type) // 8
        variables: dict[str, Any] = {}
        if roots is not None:
            self._rooted(points, roots, most, variables)
        else:
            in_arrays = points * 15 // 100
            in_structs = points * 20 // 100
            in_instances = points * 30 // 100
            top_level = points - in_arrays - in_structs - in_instances
            for _ in range(top_level):
                name, kind = self._point_name()
                variables[name] = self._api_object(kind, name)
            self._arrays(in_arrays, variables)
            self._structs(in_structs, variables)
            self._instances(in_instances, variables, most)
            for name, type_name, value in _PLAIN_SCALARS:
                variables[name] = {"type": type_name, "value": value}
        digits = re.sub(r"[^0-9]", "", plc_type) or "0000"
        family = "Fx2" if digits.startswith("2") else "Fx1"
        return {
            "plc": {
                "family": family,
                "type": plc_type,
                "serialNumber": f"GN {self._seed % 10000:04d}",
                "version": f"{family} CP{digits}I v1.1",
                "mac": "00-0A-14-{:02X}-{:02X}-{:02X}".format(*self._rng.randbytes(3)),
            },
            "program": {
                "name": f"GENERATED_{points} v1.0",
                "compiled": "2026-01-15T10:00:00.000Z",
            },
            "types": self._types,
            "variables": variables,
        }

    def _kind(self) -> str:
        kinds = list(_QUANTITIES)
        return self._rng.choices(kinds, weights=[_QUANTITIES[k][0] for k in kinds])[0]

    def _point_name(self, kind: str | None = None) -> tuple[str, str]:
        """A fresh name of 12-30 characters and the value kind it suggests."""
        kind = kind or self._kind()
        while True:
            quantity, _ = self._rng.choice(_QUANTITIES[kind][1])
            name = self._rng.choice(_PLACES) + quantity
            if len(name) < MIN_NAME_LENGTH or name.lower() in self._used:
                name += str(self._rng.randint(1, 99))
            if (
                MIN_NAME_LENGTH <= len(name) <= MAX_NAME_LENGTH
                and name.lower() not in self._used
            ):
                self._used.add(name.lower())
                return name, kind

    def _fresh(self, base: str) -> str:
        """A fresh container name from a word, padded to at least 12 characters."""
        for number in range(1, 10000):
            name = f"{base}Group{number:02d}"
            if name.lower() not in self._used:
                self._used.add(name.lower())
                return name
        raise RuntimeError("no free name")  # pragma: no cover

    def _api_object(self, kind: str, name: str) -> dict[str, Any]:
        """A T_ApiObject declaration with a value and attributes fitting its name."""
        return {"type": _type_of(kind), "value": self._api_value(kind, name)}

    def _api_value(
        self, kind: str, name: str, number: int | None = None
    ) -> dict[str, Any]:
        rng = self._rng
        title = _title(name)
        if number is not None:
            title = f"{title[: MAX_TITLE_LENGTH - 4]} {number}"
        read_only = rng.random() < 0.6
        units = next(
            (u for q, u in _QUANTITIES[kind][1] if q.lower() in name.lower()), None
        )
        attr: dict[str, Any] = {
            "enable": rng.random() < 0.95,
            "visibility": rng.random() < 0.9,
            "readOnly": read_only,
            "title": title,
        }
        value: Any
        if kind == "BOOL":
            value = rng.random() < 0.5
        elif kind == "STRING":
            value = rng.choice(("OK", "Idle", "Running", "Check filter", "Away"))
        else:
            low, high = {"REAL": (-20.0, 80.0), "INT": (-10, 10), "UINT": (0, 100)}[
                kind
            ]
            if not read_only:
                attr["minValue"], attr["maxValue"] = float(low), float(high)
            value = (
                round(rng.uniform(low, high), 1)
                if kind == "REAL"
                else rng.randint(int(low), int(high))
            )
        if units is not None:
            attr["units"] = units
        return {"value": value, "attr": attr}

    def _rooted(
        self, points: int, roots: int, most: int, variables: dict[str, Any]
    ) -> None:
        """`points` T_ApiObjects in exactly `roots` roots of at most `most` each.

        Sizes start even and are then shuffled between random pairs of roots, so
        that they vary (some roots full, some half full) but stay within 1..most.
        """
        sizes = [points // roots + (index < points % roots) for index in range(roots)]
        for _ in range(roots):
            give, take = self._rng.randrange(roots), self._rng.randrange(roots)
            amount = self._rng.randint(0, most)
            amount = min(amount, sizes[give] - 1, most - sizes[take])
            if give != take and amount > 0:
                sizes[give] -= amount
                sizes[take] += amount
        for number, size in enumerate(sizes):
            shape = self._rng.random()
            if shape < 0.5:
                self._instance(number, size, variables)
            elif shape < 0.8:
                self._struct(number, size, variables)
            else:
                self._array(size, variables)

    def _arrays(self, count: int, variables: dict[str, Any]) -> None:
        for size in _chunks(count, 4, 12, self._rng):
            self._array(size, variables)

    def _array(self, size: int, variables: dict[str, Any]) -> None:
        kind = self._kind()
        name, _ = self._point_name(kind)
        variables[name] = {
            "type": f"ARRAY[0..{size - 1}] OF {_type_of(kind)}",
            "value": [self._api_value(kind, name, i + 1) for i in range(size)],
        }

    def _structs(self, count: int, variables: dict[str, Any]) -> None:
        for number, size in enumerate(_chunks(count, 3, 10, self._rng)):
            self._struct(number, size, variables)

    def _struct(self, number: int, size: int, variables: dict[str, Any]) -> None:
        root = self._fresh(self._rng.choice(_PLACES))
        type_name = f"T{root[0].upper()}{root[1:]}"
        members, value = self._members(size)
        if number % 3 == 2 and size >= 4:
            # Every third struct keeps part of its points in a nested struct.
            inner_size = size // 2
            inner_members, inner_value = self._members(inner_size)
            for member in list(members)[:inner_size]:
                del members[member]
                del value[member]
            self._types[f"{type_name}Detail"] = inner_members
            members["details"] = f"{type_name}Detail"
            value["details"] = inner_value
        self._types[type_name] = members
        variables[root] = {"type": type_name, "value": value}

    def _members(self, size: int) -> tuple[dict[str, str], dict[str, Any]]:
        members: dict[str, str] = {}
        value: dict[str, Any] = {}
        for _ in range(size):
            name, kind = self._point_name()
            members[name] = _type_of(kind)
            value[name] = self._api_value(kind, name)
        return members, value

    def _instances(self, count: int, variables: dict[str, Any], most: int) -> None:
        for number, size in enumerate(_chunks(count, 5, min(40, most), self._rng)):
            self._instance(number, size, variables)

    def _instance(self, number: int, size: int, variables: dict[str, Any]) -> None:
        base = _INSTANCES[number % len(_INSTANCES)]
        name = base if base.lower() not in self._used else self._fresh(base)
        self._used.add(name.lower())
        members: dict[str, Any] = {}
        for _ in range(size):
            member, kind = self._point_name()
            members[member] = self._api_object(kind, member)
        variables[name] = {"program": f"prg{name}", "variables": members}


def _type_of(kind: str) -> str:
    return "T_ApiObject" if kind == "REAL" else f"T_ApiObject OF {kind}"


def _title(name: str) -> str:
    """`livingRoomTemperature2` -> `Living room temperature 2` (at most 32 characters)."""
    words = re.findall(r"[A-Z]?[a-z]+|[A-Z]+(?![a-z])|[0-9]+", name)
    text = " ".join(word.lower() for word in words)
    return (text[:1].upper() + text[1:])[:MAX_TITLE_LENGTH]


def _chunks(total: int, low: int, high: int, rng: random.Random) -> Iterator[int]:
    """Sizes between `low` and `high` (the last may be smaller) adding up to `total`."""
    while total > 0:
        size = min(total, rng.randint(low, high))
        total -= size
        yield size
