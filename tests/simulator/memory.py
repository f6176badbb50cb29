"""The PLC's public variables: paths into them, reads, and all-or-nothing writes.

A path is what a TecoApi request names: a root variable (or program instance), then
`.member` and `[index]` steps (`Main.myObject3.value`, `arr2[1][3]`, `arr2[1,3]`).
Names are matched case-insensitively and answered in the PLC's own spelling.

A read answers nested by dotted segment: every segment of the path, with its indexes,
becomes one key of the response (`myObject.favorites.sport` ->
`{"myObject": {"favorites": {"sport": ...}}}`, `myObject.interests[1]` ->
`{"myObject": {"interests[1]": ...}}`, `arr2[1][3]` -> `{"arr2[1][3]": ...}`), and
answers to several paths are merged by root as in the manual's chapter 5.1.
"""

from collections.abc import Callable, Iterable, Mapping
import copy
from dataclasses import dataclass, field
import json
import math
import re
import time
from typing import Any, Final

from . import errors
from .iec import (
    ArrayOf,
    Elementary,
    IecType,
    RejectedValueError,
    Struct,
    from_json,
    from_query_text,
    leaf_count,
)
from .program import MAX_NAME_LENGTH, Program

_SEGMENT: Final = re.compile(r"([^\[\]]*)((?:\[[^\[\]]*\])*)")
_INDEXES: Final = re.compile(r"\[([^\[\]]*)\]")
_INDEX: Final = re.compile(r"\s*([0-9]+)\s*")

type Step = str | int


@dataclass(frozen=True, slots=True)
class Location:
    """A resolved path: where its value lives, its type, and its response keys."""

    requested: str
    root: str
    steps: tuple[Step, ...]
    keys: tuple[str, ...]
    type: IecType

    @property
    def items(self) -> int:
        """Leaf items this location adds to a response."""
        return leaf_count(self.type)


@dataclass(slots=True)
class LinkMotion:
    """How the program's links move a number to its new value: at once, or over time.

    ``rate`` None copies a written value at once (the default); a rate in units
    per second moves a linked number towards it instead, as a real blind moves
    to its target (20 takes a blind from open to closed in 5 s). ``clock`` gives
    the seconds the motion is measured in; a test may hand it a frozen clock.
    The PLC keeps its motion across program downloads.
    """

    rate: float | None = None
    clock: Callable[[], float] = field(default=time.monotonic)


@dataclass(slots=True)
class _Move:
    """A linked number on its way: from ``start`` at ``started`` to ``goal``."""

    target: Location
    start: float
    goal: float
    started: float
    integral: bool


def _number(value: Any) -> float | None:
    """A value a link can move gradually: a finite int or float, not a BOOL."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        return None
    return float(value) if math.isfinite(value) else None


class PlcMemory:
    """The values of one loaded program's public variables."""

    def __init__(self, program: Program, motion: LinkMotion | None = None) -> None:
        """Load the program's declarations with their initial values.

        The program's ``links`` are what its logic does with a written value: each
        copies a variable to another whenever a write changed it (a GTSAP1 light
        reaching the target level, a blind the target position) -- a demo's PLC
        that reacts, not the full program. With a ``motion`` rate, a number is not
        copied but moves there over time (see :class:`LinkMotion`); a read sees
        where it is now.
        """
        self._motion = motion if motion is not None else LinkMotion()
        self._moves: dict[tuple[str, tuple[Step, ...]], _Move] = {}
        self._types: dict[str, IecType] = {}
        self._spelling: dict[str, str] = {}
        self._values: dict[str, Any] = {}
        for declaration in program.declarations:
            self._types[declaration.name] = declaration.type
            self._spelling[declaration.name.lower()] = declaration.name
            self._values[declaration.name] = copy.deepcopy(declaration.initial)
        self._links = []
        for source, target in program.links:
            try:
                self._links.append((self.resolve(source), self.resolve(target)))
            except errors.TecoError:
                continue  # a link to a variable the program no longer has does nothing

    @property
    def names(self) -> list[str]:
        """The roots in declaration order, as the PLC spells them."""
        return list(self._values)

    def root(self, name: str) -> str | None:
        """The PLC's spelling of a root name, or None."""
        return self._spelling.get(name.lower())

    def resolve(self, path: str) -> Location:
        """The location a path names; 400.008 or 400.005 when it names none."""
        segments = path.split(".")
        for segment in segments:
            name_part = _SEGMENT.fullmatch(segment)
            if name_part is not None and len(name_part.group(1)) > MAX_NAME_LENGTH:
                raise errors.item_name_too_long(name_part.group(1))
        steps: list[Step] = []
        keys: list[str] = []
        root: str | None = None
        iec_type: IecType | None = None
        for segment in segments:
            match = _SEGMENT.fullmatch(segment)
            if match is None or not match.group(1):
                raise errors.not_found(path)
            if iec_type is None:
                root = self.root(match.group(1))
                if root is None:
                    raise errors.not_found(path)
                spelled = root
                iec_type = self._types[root]
            else:
                member = (
                    iec_type.member(match.group(1))
                    if isinstance(iec_type, Struct)
                    else None
                )
                if member is None or not isinstance(iec_type, Struct):
                    raise errors.not_found(path)
                spelled = member
                steps.append(member)
                iec_type = iec_type.members[member]
            key = spelled
            for index in _indexes(match.group(2), path):
                if not isinstance(iec_type, ArrayOf) or index >= iec_type.size:
                    raise errors.not_found(path)
                steps.append(index)
                key += f"[{index}]"
                iec_type = iec_type.element
            keys.append(key)
        assert root is not None
        assert iec_type is not None
        return Location(path, root, tuple(steps), tuple(keys), iec_type)

    def read(self, location: Location) -> Any:
        """A copy of the value at a location (where a moving value is now)."""
        self._advance()
        return self._read(location)

    def _read(self, location: Location) -> Any:
        return copy.deepcopy(_value_at(self._values[location.root], location.steps))

    @property
    def moving(self) -> bool:
        """Whether a linked value is still on its way."""
        self._advance()
        return bool(self._moves)

    def answer(self, locations: Iterable[Location]) -> dict[str, Any]:
        """A GetObject response body: the locations nested and merged by root."""
        self._advance()
        response: dict[str, Any] = {}
        for location in locations:
            node = response
            for key in location.keys[:-1]:
                child = node.get(key)
                if not isinstance(child, dict):
                    child = node[key] = {}
                node = child
            _merge_into(node, location.keys[-1], self._read(location))
        return response

    def transaction(self) -> "Transaction":
        """A set of writes that take effect together, or not at all."""
        self._advance()
        return Transaction(self)

    def _commit(self, staged: Mapping[str, Any]) -> None:
        before = {
            id(source): self._read(source)
            for source, _ in self._links
            if source.root in staged
        }
        moving = {
            key: self._read(move.target)
            for key, move in self._moves.items()
            if move.target.root in staged
        }
        self._values.update(staged)
        for key, value in moving.items():
            if self._read(self._moves[key].target) != value:
                del self._moves[key]  # written directly: the program's write wins
        copies = Transaction(self)
        for source, target in self._links:
            if id(source) in before and self._read(source) != before[id(source)]:
                if self._start_move(target, self._read(source)):
                    continue
                try:
                    copies.write_json(target, self._read(source))
                except errors.TecoError:
                    continue  # the target cannot hold it: the program would not copy
        if copies.staged:
            self._values.update(copies.staged)

    def _start_move(self, target: Location, value: Any) -> bool:
        """Move a linked number towards ``value`` at the motion's rate (False: copy it)."""
        rate = self._motion.rate
        current = self._read(target)
        start, goal = _number(current), _number(value)
        if rate is None or rate <= 0 or start is None or goal is None:
            return False
        try:
            Transaction(self).write_json(target, value)
        except errors.TecoError:
            return (
                True  # the target cannot hold it: nothing moves, as nothing is copied
            )
        self._moves[(target.root, target.steps)] = _Move(
            target=target,
            start=start,
            goal=goal,
            started=self._motion.clock(),
            integral=isinstance(current, int),
        )
        return True

    def _advance(self) -> None:
        """Bring every moving value to where its motion has taken it by now."""
        if not self._moves:
            return
        now = self._motion.clock()
        rate = self._motion.rate or math.inf
        moved = Transaction(self)
        for key, move in list(self._moves.items()):
            distance = move.goal - move.start
            travelled = min(rate * max(now - move.started, 0.0), abs(distance))
            value = move.start + math.copysign(travelled, distance)
            if travelled >= abs(distance):
                value = move.goal
                del self._moves[key]
            try:
                moved.write_json(move.target, round(value) if move.integral else value)
            except errors.TecoError:
                self._moves.pop(key, None)  # it cannot hold it: the motion ends
        if moved.staged:
            self._values.update(moved.staged)


class Transaction:
    """Writes staged on copies of the touched roots until `commit()`."""

    def __init__(self, memory: PlcMemory) -> None:
        """Start with nothing staged."""
        self._memory = memory
        self._staged: dict[str, Any] = {}

    def write_text(self, location: Location, text: str) -> None:
        """Stage SetObject's `name=text`; 400.015 unless it fits an elementary type."""
        iec_type = location.type
        if not isinstance(iec_type, Elementary):
            raise errors.value_not_written(text, location.requested, iec_type.type_name)
        try:
            value = from_query_text(iec_type, text)
        except RejectedValueError as err:
            raise errors.value_not_written(
                text, location.requested, iec_type.type_name
            ) from err
        self._assign(location, value)

    def write_json(self, location: Location, value: object) -> None:
        """Stage a PutObject value; structs may be partial, arrays a prefix."""
        current = _value_at(self._root_value(location.root), location.steps)
        self._assign(
            location, _converted(location.type, current, value, location.requested)
        )

    def write_value(self, location: Location, value: Any) -> None:
        """Stage a value the caller has already checked against the location's type.

        For PLCComS, whose strings are Windows-1250 rather than TecoApi's ASCII.
        """
        self._assign(location, value)

    @property
    def staged(self) -> Mapping[str, Any]:
        """The roots written so far (copies), by name."""
        return self._staged

    def commit(self) -> None:
        """Make every staged write visible at once."""
        self._memory._commit(self._staged)
        self._staged = {}

    def _root_value(self, root: str) -> Any:
        if root not in self._staged:
            self._staged[root] = copy.deepcopy(self._memory._values[root])
        return self._staged[root]

    def _assign(self, location: Location, value: Any) -> None:
        if not location.steps:
            self._root_value(location.root)
            self._staged[location.root] = value
            return
        parent = _value_at(self._root_value(location.root), location.steps[:-1])
        parent[location.steps[-1]] = value


def _indexes(text: str, path: str) -> list[int]:
    """`[1][3]` or `[1,3]` as a list of indexes; 400.005 for anything else."""
    indexes: list[int] = []
    for group in _INDEXES.findall(text):
        for part in group.split(","):
            match = _INDEX.fullmatch(part)
            if match is None:
                raise errors.not_found(path)
            indexes.append(int(match.group(1)))
    return indexes


def _value_at(value: Any, steps: Iterable[Step]) -> Any:
    for step in steps:
        value = value[step]
    return value


def _merge_into(node: dict[str, Any], key: str, value: Any) -> None:
    """Put `value` at `key`, merging with what an earlier path already put there."""
    existing = node.get(key)
    if isinstance(existing, dict) and isinstance(value, dict):
        for member, member_value in value.items():
            _merge_into(existing, member, member_value)
    else:
        node[key] = value


def _json_text(value: object) -> str:
    """A JSON value as a 400.015 message quotes it."""
    return json.dumps(value, ensure_ascii=True)


def _converted(iec_type: IecType, current: Any, value: object, name: str) -> Any:
    """The new value of a location after writing a JSON value into it."""
    if isinstance(iec_type, Struct):
        if not isinstance(value, dict):
            raise errors.value_not_written(_json_text(value), name, iec_type.type_name)
        result = dict(current)
        for key, member_value in value.items():
            member = iec_type.member(key)
            if member is None:
                raise errors.not_found(f"{name}.{key}")
            result[member] = _converted(
                iec_type.members[member],
                current[member],
                member_value,
                f"{name}.{member}",
            )
        return result
    if isinstance(iec_type, ArrayOf):
        if not isinstance(value, list) or len(value) > iec_type.size:
            raise errors.value_not_written(_json_text(value), name, iec_type.type_name)
        result_list = list(current)
        for index, element in enumerate(value):
            result_list[index] = _converted(
                iec_type.element, current[index], element, f"{name}[{index}]"
            )
        return result_list
    try:
        return from_json(iec_type, value)
    except RejectedValueError as err:
        raise errors.value_not_written(
            _json_text(value), name, iec_type.type_name
        ) from err
