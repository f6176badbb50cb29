"""Switches: a relay or a socket (an outlet) switched by its ``onoff`` point."""

from collections.abc import Mapping
from typing import Any

from ..devices import Role, SwitchClass, TypedDevice
from ..models import Point
from .base import Appliance, Batch


class Switch(Appliance):
    """A switch: on or off, read and written through its ``onoff`` point.

    ``outlet`` says whether it is a socket. An inverted ``onoff`` is read and
    written as its opposite.
    """

    __slots__ = ("outlet",)

    def __init__(self, device: TypedDevice, points: Mapping[str, Point]) -> None:
        """Fix whether it is a socket."""
        super().__init__(device, points)
        self.outlet = device.switch_class is SwitchClass.OUTLET

    def state(self, values: Mapping[str, Any]) -> bool | None:
        """Whether it is on (None: unknown)."""
        return self.flag(Role.ONOFF, values)

    def turn_on(self) -> Batch:
        """Switch it on."""
        return self.write({}, Role.ONOFF, True)

    def turn_off(self) -> Batch:
        """Switch it off."""
        return self.write({}, Role.ONOFF, False)
