"""Displays: a measured value, with its unit and precision where the PLC tells them."""

from collections.abc import Mapping
from typing import Any, Final

from ..devices import Measurement, Role, TypedDevice
from ..models import Point
from .base import Appliance

MAX_PRECISION: Final = 6
"""The most decimals a display's ``precision`` point may ask for."""


class Display(Appliance):
    """A display: the ``value`` point as a number.

    What it measures (``measurement``, from its symbol) says its unit and class
    where it is known; else its ``unit`` point's text is the unit. Its
    ``precision`` point says how many decimals to show (0 to
    :data:`MAX_PRECISION`). The value may be text (``"21,5"``) when the
    device's readings read text: a decimal comma is read, and text that is
    not a number is unknown.
    """

    __slots__ = ("measurement",)

    def __init__(self, device: TypedDevice, points: Mapping[str, Point]) -> None:
        """Fix what it measures (None: its symbol does not say)."""
        super().__init__(device, points)
        self.measurement: Measurement | None = device.measurement

    def state(self, values: Mapping[str, Any]) -> float | None:
        """Read the value as a number (None: unknown, or not a number)."""
        return self.number(Role.VALUE, values)

    def unit(self, values: Mapping[str, Any]) -> str | None:
        """Read the ``unit`` point's text, stripped (None: none, blank, not text)."""
        if not self.has(Role.UNIT):
            return None
        text = values.get(self.value(Role.UNIT).key)
        return text.strip() or None if isinstance(text, str) else None

    def precision(self, values: Mapping[str, Any]) -> int | None:
        """Read the decimals ``precision`` asks for (None: none, outside 0-6)."""
        if not self.has(Role.PRECISION):
            return None
        precision = self.value(Role.PRECISION).integer(values)
        if precision is None or not 0 <= precision <= MAX_PRECISION:
            return None
        return precision
