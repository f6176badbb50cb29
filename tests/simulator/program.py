"""A PLC program as the simulator runs it, read from a declarative YAML or JSON file.

The file format is documented in `tests/simulator/README.md`. A program declares the
PLC it was made for (kept by the simulator across program downloads), the user
program's name and compile time, STRUCT types, and the `{PUBLIC_API}` variables with
their IEC types and initial values; program instances group variables under the
instance name (the manual's root `Main`).
"""

from collections.abc import Mapping
import contextlib
import copy
from dataclasses import dataclass
import json
from pathlib import Path
import re
from typing import Any, Final
import zlib

import yaml

from .iec import (
    DEFAULT_STRING_LENGTH,
    ELEMENTARY_NAMES,
    MAX_STRING_LENGTH,
    ArrayOf,
    Elementary,
    IecType,
    RejectedValueError,
    Struct,
    default_value,
    from_program,
)

PROGRAMS_DIR: Final = Path(__file__).parent / "programs"
SHIPPED_PROGRAMS: Final = ("demo", "manual")
PUBLIC_FILE_STATES: Final = ("ok", "missing", "too_big", "unreadable", "empty")
MAX_NAME_LENGTH: Final = 64

_IDENTIFIER: Final = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
_ARRAY: Final = re.compile(
    r"ARRAY\s*\[([^\]]*)\]\s*OF\s+(.+)", re.IGNORECASE | re.DOTALL
)
_RANGE: Final = re.compile(r"\s*([0-9]+)\s*\.\.\s*([0-9]+)\s*")
_STRING: Final = re.compile(r"STRING\s*(?:\[\s*([0-9]+)\s*\])?", re.IGNORECASE)
_API_OBJECT: Final = re.compile(
    r"T_ApiObject(?:\s+OF\s+(.+))?", re.IGNORECASE | re.DOTALL
)

# Manual chapter 5.3: the metadata a T_ApiObject carries next to its value.
API_OBJECT_ATTR: Final = Struct(
    "T_ApiObjectAttr",
    {
        "enable": Elementary("BOOL"),
        "visibility": Elementary("BOOL"),
        "readOnly": Elementary("BOOL"),
        "title": Elementary("STRING", 32),
        "minValue": Elementary("REAL"),
        "maxValue": Elementary("REAL"),
        "units": Elementary("STRING", 16),
    },
)


class ProgramError(ValueError):
    """A program file that does not describe a valid PLC program."""


def api_object_type(value_type: IecType) -> Struct:
    """T_ApiObject of chapter 5.3 with `value` of the given type (REAL in the manual)."""
    name = "T_ApiObject"
    if value_type != Elementary("REAL"):
        name = f"T_ApiObject OF {value_type.type_name}"
    return Struct(name, {"value": value_type, "attr": API_OBJECT_ATTR})


def is_valid_name(name: str) -> bool:
    """An IEC 61131-3 identifier: ASCII letters, digits, single underscores, ≤ 64."""
    return (
        _IDENTIFIER.fullmatch(name) is not None
        and "__" not in name
        and len(name) <= MAX_NAME_LENGTH
    )


@dataclass(frozen=True, slots=True, kw_only=True)
class PlcIdentity:
    """The hardware GetInfo describes: it stays when a new program is downloaded."""

    family: str
    type: str
    serial_number: str
    version: str
    mac: str


@dataclass(frozen=True, slots=True, kw_only=True)
class Declaration:
    """One `{PUBLIC_API}` root: a global variable or a program instance."""

    name: str
    type: IecType
    initial: Any


@dataclass(frozen=True, slots=True, kw_only=True)
class Program:
    """A compiled PLC program: its identity, its public variables, its stamp."""

    name: str
    compiled: str
    plc: PlcIdentity
    declarations: tuple[Declaration, ...]
    public_file: str
    source: Mapping[str, Any]
    links: tuple[tuple[str, str], ...] = ()
    """(source, target) paths: the program copies a written source to its target."""

    @property
    def stamp(self) -> str:
        """`userProg.stamp`: 8 hex digits derived from everything but the hardware."""
        user_part = {key: value for key, value in self.source.items() if key != "plc"}
        canonical = json.dumps(user_part, sort_keys=True, default=str)
        return f"{zlib.crc32(canonical.encode()):08X}"

    def to_mapping(self) -> dict[str, Any]:
        """A copy of the mapping the program was read from, to edit and reload."""
        return copy.deepcopy(dict(self.source))

    @classmethod
    def from_mapping(cls, source: Mapping[str, Any]) -> "Program":
        """Read a program from its file's content (see README for the format)."""
        return _ProgramReader(source).read()

    @classmethod
    def from_file(cls, path: str | Path) -> "Program":
        """Read a `.yaml`, `.yml` or `.json` program file."""
        path = Path(path)
        text = path.read_text(encoding="utf-8")
        if path.suffix.lower() == ".json":
            source = json.loads(text)
        elif path.suffix.lower() in {".yaml", ".yml"}:
            source = yaml.safe_load(text)
        else:
            raise ProgramError(f"{path}: not a .yaml, .yml or .json file")
        if not isinstance(source, Mapping):
            raise ProgramError(f"{path}: the file does not hold a mapping")
        return cls.from_mapping(source)


def load_program(name_or_path: str) -> Program:
    """A shipped program (`demo`, `manual`) or one read from a file path."""
    if name_or_path in SHIPPED_PROGRAMS:
        return Program.from_file(PROGRAMS_DIR / f"{name_or_path}.yaml")
    path = Path(name_or_path)
    if not path.is_file():
        raise ProgramError(
            f"no program {name_or_path!r}: use {' or '.join(SHIPPED_PROGRAMS)} "
            "or the path of a .yaml/.json file"
        )
    return Program.from_file(path)


class _ProgramReader:
    """Turns a program mapping into typed declarations, checking it on the way."""

    def __init__(self, source: Mapping[str, Any]) -> None:
        self._source = source
        self._type_specs: dict[str, tuple[str, Any]] = {}
        self._structs: dict[str, Struct] = {}
        self._building: set[str] = set()

    def read(self) -> Program:
        source = self._source
        plc = self._section(source, "plc")
        user_program = self._section(source, "program")
        for type_name, members in self._section(
            source, "types", required=False
        ).items():
            self._check_name(type_name, "type")
            self._type_specs[type_name.lower()] = (type_name, members)
        for key in list(self._type_specs):
            self._struct(key)
        declarations = self._declarations(
            self._section(source, "variables", required=False), "variables"
        )
        public_file = str(source.get("publicFile", "ok"))
        if public_file not in PUBLIC_FILE_STATES:
            raise ProgramError(
                f"publicFile must be one of {', '.join(PUBLIC_FILE_STATES)}"
            )
        try:
            identity = PlcIdentity(
                family=str(plc["family"]),
                type=str(plc["type"]),
                serial_number=str(plc["serialNumber"]),
                version=str(plc["version"]),
                mac=str(plc["mac"]),
            )
            name = str(user_program["name"])
            compiled = str(user_program["compiled"])
        except KeyError as err:
            raise ProgramError(f"missing field {err.args[0]!r}") from err
        return Program(
            name=name,
            compiled=compiled,
            plc=identity,
            declarations=tuple(declarations),
            public_file=public_file,
            source=copy.deepcopy(dict(source)),
            links=self._links(source.get("links", [])),
        )

    @staticmethod
    def _links(entries: Any) -> tuple[tuple[str, str], ...]:
        """``links``: a list of ``{from: path, to: path}``."""
        if not isinstance(entries, list) or not all(
            isinstance(entry, Mapping)
            and isinstance(entry.get("from"), str)
            and isinstance(entry.get("to"), str)
            for entry in entries
        ):
            raise ProgramError("links must be a list of {from: path, to: path}")
        return tuple((entry["from"], entry["to"]) for entry in entries)

    @staticmethod
    def _section(
        source: Mapping[str, Any], key: str, *, required: bool = True
    ) -> Mapping[str, Any]:
        value = source.get(key)
        if value is None and not required:
            return {}
        if not isinstance(value, Mapping):
            raise ProgramError(f"{key!r} must be a mapping")
        return value

    @staticmethod
    def _check_name(name: object, what: str) -> None:
        if not isinstance(name, str) or not is_valid_name(name):
            raise ProgramError(f"{name!r} is not a valid IEC {what} name")

    def _declarations(
        self, entries: Mapping[str, Any], where: str
    ) -> list[Declaration]:
        declarations: list[Declaration] = []
        seen: set[str] = set()
        for name, spec in entries.items():
            self._check_name(name, "variable")
            if name.lower() in seen:
                raise ProgramError(f"{where}: {name!r} is declared twice")
            seen.add(name.lower())
            declarations.append(self._declaration(name, spec, f"{where}.{name}"))
        return declarations

    def _declaration(self, name: str, spec: Any, where: str) -> Declaration:
        if isinstance(spec, str):
            spec = {"type": spec}
        if not isinstance(spec, Mapping):
            raise ProgramError(f"{where}: expected a type or a mapping")
        if "program" in spec:
            members = self._declarations(
                self._section(spec, "variables", required=False), where
            )
            instance_type = Struct(
                str(spec["program"]), {m.name: m.type for m in members}
            )
            return Declaration(
                name=name,
                type=instance_type,
                initial={m.name: m.initial for m in members},
            )
        if "type" not in spec:
            raise ProgramError(f"{where}: needs 'type' (or 'program' for an instance)")
        iec_type = self.parse_type(str(spec["type"]), where)
        initial = self._initial(iec_type, spec.get("value"), where)
        return Declaration(name=name, type=iec_type, initial=initial)

    def parse_type(self, text: str, where: str) -> IecType:
        """A type expression: elementary, STRING[n], ARRAY[..] OF, T_ApiObject [OF], a STRUCT."""
        text = text.strip()
        if match := _ARRAY.fullmatch(text):
            sizes = []
            for bounds in match.group(1).split(","):
                range_match = _RANGE.fullmatch(bounds)
                if range_match is None or range_match.group(1) != "0":
                    raise ProgramError(f"{where}: arrays are indexed from 0 ({text!r})")
                sizes.append(int(range_match.group(2)) + 1)
            element = self.parse_type(match.group(2), where)
            element_name = element.type_name
            for depth in range(len(sizes) - 1, -1, -1):
                ranges = ", ".join(f"0..{size - 1}" for size in sizes[depth:])
                element = ArrayOf(
                    sizes[depth], element, f"ARRAY[{ranges}] OF {element_name}"
                )
            return element
        if match := _STRING.fullmatch(text):
            length = int(match.group(1) or DEFAULT_STRING_LENGTH)
            if not 1 <= length <= MAX_STRING_LENGTH:
                raise ProgramError(f"{where}: STRING length must be 1..255")
            return Elementary("STRING", length)
        if match := _API_OBJECT.fullmatch(text):
            value_type = (
                self.parse_type(match.group(1), where)
                if match.group(1)
                else Elementary("REAL")
            )
            return api_object_type(value_type)
        if text.upper() in ELEMENTARY_NAMES:
            return Elementary(text.upper())
        if text.lower() == API_OBJECT_ATTR.type_name.lower():
            return API_OBJECT_ATTR
        if text.lower() in self._type_specs:
            return self._struct(text.lower())
        raise ProgramError(f"{where}: unknown type {text!r}")

    def _struct(self, key: str) -> Struct:
        if key in self._structs:
            return self._structs[key]
        type_name, members = self._type_specs[key]
        if key in self._building:
            raise ProgramError(f"types.{type_name}: the type contains itself")
        if not isinstance(members, Mapping) or not members:
            raise ProgramError(f"types.{type_name}: a STRUCT needs members")
        self._building.add(key)
        member_types: dict[str, IecType] = {}
        for member, member_spec in members.items():
            self._check_name(member, "member")
            member_types[member] = self.parse_type(
                str(member_spec), f"types.{type_name}"
            )
        self._building.discard(key)
        struct = Struct(type_name, member_types)
        self._structs[key] = struct
        return struct

    def _initial(self, iec_type: IecType, raw: Any, where: str) -> Any:
        if raw is None:
            return default_value(iec_type)
        if isinstance(iec_type, Struct):
            if not isinstance(raw, Mapping):
                raise ProgramError(
                    f"{where}: a {iec_type.type_name} value is a mapping"
                )
            value = default_value(iec_type)
            for key, member_raw in raw.items():
                member = iec_type.member(str(key))
                if member is None:
                    raise ProgramError(f"{where}: {iec_type.type_name} has no {key!r}")
                value[member] = self._initial(
                    iec_type.members[member], member_raw, f"{where}.{member}"
                )
            return value
        if isinstance(iec_type, ArrayOf):
            if not isinstance(raw, list):
                raise ProgramError(f"{where}: an array value is a list")
            if isinstance(iec_type.element, ArrayOf) and not any(
                isinstance(item, list) for item in raw
            ):
                raw = _unflatten(iec_type, raw, where)
            if len(raw) > iec_type.size:
                raise ProgramError(f"{where}: more than {iec_type.size} elements")
            value = default_value(iec_type)
            for index, item in enumerate(raw):
                value[index] = self._initial(
                    iec_type.element, item, f"{where}[{index}]"
                )
            return value
        if iec_type.name == "STRING" and isinstance(raw, str):
            # The program's own text may hold what Mosaic's code page allows (the
            # manual's '°C'); only values written over TecoApi must be ASCII.
            if len(raw) <= (iec_type.length or 0):
                return raw
        else:
            with contextlib.suppress(RejectedValueError):
                return from_program(iec_type, raw)
        raise ProgramError(f"{where}: {raw!r} is not a valid {iec_type.type_name}")


def _unflatten(iec_type: ArrayOf, flat: list[Any], where: str) -> list[Any]:
    """A multi-dimensional initialiser written flat, as IEC allows, split into rows."""
    sizes = []
    node: IecType = iec_type
    while isinstance(node, ArrayOf):
        sizes.append(node.size)
        node = node.element
    total = 1
    for size in sizes:
        total *= size
    if len(flat) > total:
        raise ProgramError(f"{where}: more than {total} elements")
    padded: list[Any] = list(flat) + [None] * (total - len(flat))

    def rows(items: list[Any], dims: list[int]) -> list[Any]:
        if len(dims) == 1:
            return items
        step = len(items) // dims[0]
        return [
            rows(items[i * step : (i + 1) * step], dims[1:]) for i in range(dims[0])
        ]

    return rows(padded, sizes)
