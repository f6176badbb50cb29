"""An FP PLC's memory: areas of 16-bit words, read and written by type.

Registers (DT, FL, LD, WR, WX, WY, WL) are words; the bit areas R, X, Y and L
are WR, WX, WY and WL seen bit by bit (``R1A`` is bit 10 of ``WR1``). A DINT,
UDINT or REAL takes two words, the low word first (the seed's ANY example:
DT100 = 1 and DT101 = 2 read as the UDINT 131073). A STRING at DTn is the
FP's string: DTn its capacity in bytes, DTn+1 its length, then its bytes,
two to a word, the first in the low byte. Each area has a size: an address
past it is the PLC's *data error*.
"""

from collections.abc import Mapping
from dataclasses import dataclass, field
import struct
from typing import Any, Final

REGISTER_AREAS: Final = ("DT", "FL", "LD", "WR", "WX", "WY", "WL")
BIT_AREAS: Final[Mapping[str, str]] = {"R": "WR", "X": "WX", "Y": "WY", "L": "WL"}
TYPES: Final = ("INT", "UINT", "DINT", "UDINT", "REAL", "STRING", "BOOL")
WORDS: Final[Mapping[str, int]] = {
    "INT": 1,
    "UINT": 1,
    "DINT": 2,
    "UDINT": 2,
    "REAL": 2,
    "STRING": 1,
}
SIZES: Final[Mapping[str, int]] = {
    "DT": 32_765,
    "FL": 32_765,
    "LD": 256,
    "WR": 512,
    "WX": 128,
    "WY": 128,
    "WL": 128,
}
"""Words of each area (an FP-X-like CPU; special relays left out)."""
_BOUNDS: Final[Mapping[str, tuple[int, int]]] = {
    "INT": (-(1 << 15), (1 << 15) - 1),
    "UINT": (0, (1 << 16) - 1),
    "DINT": (-(1 << 31), (1 << 31) - 1),
    "UDINT": (0, (1 << 32) - 1),
}


class RefusalError(ValueError):
    """A read or write the PLC refuses: ``code`` its MEWTOCOL error."""

    def __init__(self, message: str, code: int) -> None:
        super().__init__(message)
        self.code = code
        self.message = message


DATA_ERROR: Final = 61
"""MEWTOCOL's *data error* (an address or a value the PLC cannot take)."""


@dataclass
class StationMemory:
    """One station's PLC: its words by area (0 where never written)."""

    words: dict[str, dict[int, int]] = field(
        default_factory=lambda: {area: {} for area in REGISTER_AREAS}
    )
    sizes: Mapping[str, int] = field(default_factory=lambda: dict(SIZES))

    # --- words -----------------------------------------------------------------

    def _word_area(self, area: str) -> str:
        return BIT_AREAS.get(area, area)

    def word(self, area: str, index: int) -> int:
        """Return a word (unsigned), checking the address."""
        self._check(area, index, 1)
        return self.words[area].get(index, 0)

    def set_word(self, area: str, index: int, value: int) -> None:
        """Set a word (unsigned 16 bits)."""
        self._check(area, index, 1)
        self.words[area][index] = value & 0xFFFF

    def _check(self, area: str, index: int, words: int) -> None:
        if index < 0 or index + words > self.sizes[area]:
            raise RefusalError(
                f"{area}{index}..{area}{index + words - 1} is past {area}"
                f"{self.sizes[area] - 1}",
                DATA_ERROR,
            )

    # --- typed values ------------------------------------------------------------

    def read(self, area: str, type_: str, start: int, count: int) -> list[Any]:
        """Return ``count`` values of a type from ``start`` (a bit's index for BOOL)."""
        if type_ == "BOOL":
            return [self.bit(area, start + offset) for offset in range(count)]
        width = WORDS[type_]
        self._check(area, start, width * count)
        return [
            self._value(area, type_, start + offset * width) for offset in range(count)
        ]

    def _value(self, area: str, type_: str, index: int) -> Any:
        low = self.word(area, index)
        match type_:
            case "INT":
                return low - 0x10000 if low & 0x8000 else low
            case "UINT":
                return low
        high = self.word(area, index + 1)
        double = high << 16 | low
        match type_:
            case "DINT":
                return double - (1 << 32) if double & 0x80000000 else double
            case "UDINT":
                return double
        value: float = struct.unpack("<f", struct.pack("<I", double))[0]
        return value

    def write(self, area: str, type_: str, start: int, values: list[Any]) -> None:
        """Write values of a type from ``start``; all or nothing."""
        if type_ == "BOOL":
            checked = [_flag(value) for value in values]
            for offset in range(len(checked)):
                self._check(self._word_area(area), (start + offset) // 16, 1)
            for offset, flag in enumerate(checked):
                self.set_bit(area, start + offset, flag)
            return
        width = WORDS[type_]
        self._check(area, start, width * len(values))
        words = [word for value in values for word in _words(type_, value)]
        for offset, word in enumerate(words):
            self.set_word(area, start + offset, word)

    def bit(self, area: str, index: int) -> int:
        """Return a bit of a bit area (0 or 1)."""
        word = self.word(self._word_area(area), index // 16)
        return word >> (index % 16) & 1

    def set_bit(self, area: str, index: int, on: bool) -> None:
        """Set a bit of a bit area."""
        words = self._word_area(area)
        word = self.word(words, index // 16)
        mask = 1 << (index % 16)
        self.set_word(words, index // 16, word | mask if on else word & ~mask)

    def read_string(self, area: str, start: int) -> str:
        """Return the string at a register (its length word says how long)."""
        length = self.word(area, start + 1)
        data = bytearray()
        for offset in range((length + 1) // 2):
            word = self.word(area, start + 2 + offset)
            data += bytes((word & 0xFF, word >> 8))
        return data[:length].decode("latin-1")

    def write_string(self, area: str, start: int, text: str) -> None:
        """Write a string (its capacity grows to fit it)."""
        try:
            data = text.encode("latin-1")
        except UnicodeEncodeError:
            raise RefusalError("a character the PLC cannot hold", DATA_ERROR) from None
        self._check(area, start, 2 + (len(data) + 1) // 2)
        capacity = max(self.word(area, start), len(data))
        self.set_word(area, start, capacity)
        self.set_word(area, start + 1, len(data))
        padded = data + b"\0" * (len(data) % 2)
        for offset in range(0, len(padded), 2):
            self.set_word(
                area, start + 2 + offset // 2, padded[offset] | padded[offset + 1] << 8
            )


def _flag(value: Any) -> bool:
    if value in (0, 1) or isinstance(value, bool):
        return bool(value)
    raise RefusalError(f"{value!r} is not a bit", DATA_ERROR)


def _words(type_: str, value: Any) -> list[int]:
    """Return a value's words, the low word first; refuse what the type cannot hold."""
    if type_ == "REAL":
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise RefusalError(f"{value!r} is not a REAL", DATA_ERROR)
        try:
            (double,) = struct.unpack("<I", struct.pack("<f", float(value)))
        except OverflowError:
            raise RefusalError(f"{value!r} is outside a REAL", DATA_ERROR) from None
        return [double & 0xFFFF, double >> 16]
    if isinstance(value, float) and value.is_integer():
        value = int(value)
    if isinstance(value, bool) or not isinstance(value, int):
        raise RefusalError(f"{value!r} is not an integer", DATA_ERROR)
    low, high = _BOUNDS[type_]
    if not low <= value <= high:
        raise RefusalError(f"{value} is outside {type_}", DATA_ERROR)
    unsigned = value & 0xFFFFFFFF
    if WORDS[type_] == 1:
        return [unsigned & 0xFFFF]
    return [unsigned & 0xFFFF, unsigned >> 16]
