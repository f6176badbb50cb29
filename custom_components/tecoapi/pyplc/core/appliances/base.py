"""Appliances' base: a transcoder per role, and the appliance reading them.

A :class:`RoleValue` is a role's point key and how its value is read and
written (its transcoder); an :class:`Appliance` holds one per role of a typed
device, bound to a catalogue's points, and adds a flag or a number for a
role's point to a write batch in the point's kind.
"""

from collections.abc import Mapping
from types import MappingProxyType
from typing import Any, Final

from ..devices import Readings, Role, TypedDevice
from ..exceptions import MissingPointError
from ..models import Point

type Batch = dict[str, Any]
"""One command's writes: point key → value in the point's kind, in order."""

FULL: Final = 100.0
"""A light's full level, and a cover's open position (%)."""


class RoleValue:
    """A role's point and its transcoder: how its value is read and written.

    ``point`` is the catalogue's (None: not in the catalogue, nothing to write
    to); a flag read or written is its opposite when the point is inverted.
    """

    __slots__ = ("key", "point", "readings")

    def __init__(self, key: str, point: Point | None, readings: Readings) -> None:
        """Bind a point key to its point and the device's readings."""
        self.key = key
        self.point = point
        self.readings = readings

    def number(self, values: Mapping[str, Any]) -> float | None:
        """Read the value as a finite number (None: unknown or not one)."""
        return self.readings.number(values.get(self.key))

    def integer(self, values: Mapping[str, Any]) -> int | None:
        """Read the value as an integer (None: unknown or not one)."""
        return self.readings.integer(values.get(self.key))

    def flag(self, values: Mapping[str, Any]) -> bool | None:
        """Read the value as a flag, an inverted point's opposite (None: unknown)."""
        flag = self.readings.flag(values.get(self.key))
        if flag is None or self.point is None:
            return flag
        return self.point.flag(flag)

    def encode(self, value: bool | float) -> bool | int | float | str:
        """Return what to write for a flag or a number, in the point's kind.

        Raises the core's :class:`~..exceptions.MissingPointError` when the
        point is not in the catalogue (a source's write refuses it alike).
        """
        if self.point is None:
            raise MissingPointError(self.key)
        return self.readings.written(self.point, value)


class Appliance:
    """A typed device with a transcoder per role, read against a catalogue's points.

    :meth:`rebind` follows a new catalogue (a point may be inverted now); it
    costs nothing when the points are the same object.
    """

    __slots__ = ("_points", "_values", "device")

    def __init__(self, device: TypedDevice, points: Mapping[str, Point]) -> None:
        """Make a transcoder of each role's point."""
        self.device = device
        self._points: Mapping[str, Point] | None = None
        self._values: Mapping[Role, RoleValue] = MappingProxyType({})
        self.rebind(points)

    def rebind(self, points: Mapping[str, Point]) -> None:
        """Read and write the roles' points as ``points`` (a catalogue's) say."""
        if points is self._points:
            return
        self._points = points
        readings = self.device.readings
        self._values = MappingProxyType(
            {
                role: RoleValue(key, points.get(key), readings)
                for role, key in self.device.roles.items()
            }
        )

    def has(self, role: Role) -> bool:
        """Whether a point plays ``role``."""
        return role in self._values

    def value(self, role: Role) -> RoleValue:
        """Return the transcoder of a role (KeyError: no point plays it)."""
        return self._values[role]

    def number(self, role: Role, values: Mapping[str, Any]) -> float | None:
        """Read a role's value as a number (None: no such role, unknown)."""
        value = self._values.get(role)
        return None if value is None else value.number(values)

    def flag(self, role: Role, values: Mapping[str, Any]) -> bool | None:
        """Read a role's value as a flag (None: no such role, unknown)."""
        value = self._values.get(role)
        return None if value is None else value.flag(values)

    def write(self, batch: Batch, role: Role, value: bool | float) -> Batch:
        """Add a flag or a number for a role's point to a batch; return the batch."""
        transcoder = self._values[role]
        batch[transcoder.key] = transcoder.encode(value)
        return batch

    @property
    def motion(self) -> frozenset[str]:
        """The points to read while the PLC moves it to a target (none: it never moves)."""
        return frozenset()

    def moves(self, batch: Mapping[str, Any]) -> bool:
        """Whether a batch sends it on a way the PLC takes (read :attr:`motion` then)."""
        return False

    def arrived(self, values: Mapping[str, Any]) -> bool:
        """Whether it is where its target says: nothing is left to follow."""
        return True

    def _keys(self, *roles: Role) -> frozenset[str]:
        """Return the keys of the points playing those of ``roles`` it has."""
        return frozenset(
            value.key for role in roles if (value := self._values.get(role))
        )
