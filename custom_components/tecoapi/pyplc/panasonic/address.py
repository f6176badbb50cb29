"""Panasonic FP addresses as a register map writes them, and what the gateway reads.

An FP PLC's memory is areas of 16-bit words. Registers are written as the area
and the word's decimal number: ``DT100``, ``LD5``, ``WR3``, ``FL20``. Bits are
written as the area, the word's decimal number and the bit's hex digit:
``R1A`` is bit 10 of word 1 of the internal relays, ``Y18`` bit 8 of output
word 1, ``X0`` bit 0 of input word 0 (``R0`` … ``RF`` are the 16 bits of word
0). A bit area is its word area seen bit by bit: ``R`` is ``WR``, ``X`` is
``WX``, ``Y`` is ``WY``, ``L`` is ``WL``.

A register holds a 16-bit INT or UINT; a DINT, UDINT or REAL takes two
consecutive registers (the low word first); a STRING starts at its register
with the string's length words (the gateway decodes them). Bits are BOOL.

``FPI4C.md`` (the seed's facts) lists the areas; the highest word numbers here
are the largest of any FP series CPU (FP7, FP2SH), so that a map is refused
for an address no FP PLC has, and a smaller PLC answers an address it lacks
with its own error (its item's, at run time).
"""

from dataclasses import dataclass
from enum import StrEnum
import re
from typing import Final

from ..core.models import DataType, ValueKind
from ..core.texts import Template, Text


class Area(StrEnum):
    """A memory area of an FP PLC, as the gateway names it."""

    DT = "DT"
    """Data registers."""
    FL = "FL"
    """File registers (FP2/FP2SH, MEWTOCOL only)."""
    LD = "LD"
    """Link data registers."""
    WR = "WR"
    """Internal relays, by word."""
    WX = "WX"
    """Inputs, by word."""
    WY = "WY"
    """Outputs, by word."""
    WL = "WL"
    """Link relays, by word."""
    R = "R"
    """Internal relays, by bit."""
    X = "X"
    """Inputs, by bit."""
    Y = "Y"
    """Outputs, by bit."""
    L = "L"
    """Link relays, by bit."""

    @property
    def bits(self) -> bool:
        """Whether the area is addressed by bit (its values are BOOL)."""
        return self in BIT_AREAS

    @property
    def words(self) -> "Area":
        """The register area a bit area is a view of (a register area: itself)."""
        return BIT_WORDS.get(self, self)


BIT_AREAS: Final = frozenset({Area.R, Area.X, Area.Y, Area.L})
BIT_WORDS: Final = {Area.R: Area.WR, Area.X: Area.WX, Area.Y: Area.WY, Area.L: Area.WL}

MAX_WORD: Final = {
    Area.DT: 999_999,
    Area.FL: 32_767,
    Area.LD: 16_383,
    Area.WR: 9_999,
    Area.WX: 9_999,
    Area.WY: 9_999,
    Area.WL: 9_999,
}
"""The highest word number of each register area (a bit area: its words')."""

BITS_PER_WORD: Final = 16


class WireType(StrEnum):
    """A data type as the gateway names it (``type`` of a request)."""

    INT = "INT"
    UINT = "UINT"
    DINT = "DINT"
    UDINT = "UDINT"
    REAL = "REAL"
    STRING = "STRING"
    BOOL = "BOOL"

    @property
    def registers(self) -> int:
        """Registers one value takes (a STRING: its first; a BOOL: none)."""
        return REGISTERS[self]

    @property
    def answer_key(self) -> str:
        """The member of an answer's item that holds the values."""
        return "state" if self is WireType.BOOL else self.value.lower()


REGISTERS: Final = {
    WireType.INT: 1,
    WireType.UINT: 1,
    WireType.DINT: 2,
    WireType.UDINT: 2,
    WireType.REAL: 2,
    WireType.STRING: 1,
    WireType.BOOL: 0,
}

MAX_STRING: Final = 1000
"""The longest string the gateway writes (characters)."""

_REGISTER: Final = re.compile(r"(DT|FL|LD|WR|WX|WY|WL)([0-9]{1,6})")
_BIT: Final = re.compile(r"([RXYL])([0-9]{0,5})([0-9A-F])")


# Why a map's address or type is not one the FP-I4C reads.
NO_WORD_ABOVE: Final = Template(
    "fpi4c_no_word_above", "{address}: {area} has no word above {last}"
)
NOT_AN_ADDRESS: Final = Template(
    "fpi4c_not_address",
    "{address} is not an FP address: a register is DT, FL, LD, WR, WX, WY or WL "
    "and the word's number (DT100), a bit R, X, Y or L, the word's number and "
    "the bit's hex digit (R1A, Y18, X0)",
)
TYPES: Final = Template(
    "fpi4c_types", "the FP-I4C reads INT, UINT, DINT, UDINT, REAL, STRING and BOOL only"
)
A_BIT: Final = Template("fpi4c_bit", "{address} is a bit: its type is BOOL")
A_REGISTER: Final = Template(
    "fpi4c_register",
    "{address} is a register: a bit of it is written as a bit address "
    "(R, X, Y or L: R{word}0 is bit 0 of WR{word})",
)
PAST_THE_END: Final = Template(
    "fpi4c_past_end",
    "a {type} at {address} takes {first} and {last}, past the area's end",
)


class AddressError(ValueError):
    """Text that is not an FP address: ``text`` says why (the message in English)."""

    def __init__(self, text: Text) -> None:
        """Say why."""
        super().__init__(str(text))
        self.text = text


@dataclass(frozen=True, slots=True, order=True)
class Address:
    """One register or bit of an FP PLC.

    ``word`` is the word's number, ``bit`` the bit's (None for a register).
    """

    area: Area
    word: int
    bit: int | None = None

    @property
    def index(self) -> int:
        """The position in the area: the word for a register, word·16 + bit for a bit."""
        if self.bit is None:
            return self.word
        return self.word * BITS_PER_WORD + self.bit

    @property
    def start(self) -> int | str:
        """The ``start`` of a request: a number for a register, text for a bit."""
        if self.bit is None:
            return self.word
        return bit_start(self.index)

    def __str__(self) -> str:
        """Return the address as Panasonic writes it: ``DT100``, ``R1A``, ``X0``."""
        if self.bit is None:
            return f"{self.area}{self.word}"
        return f"{self.area}{bit_start(self.index)}"


def bit_start(index: int) -> str:
    """Return a bit's address without its area: word number, then hex bit digit."""
    word, bit = divmod(index, BITS_PER_WORD)
    return f"{word}{bit:X}" if word else f"{bit:X}"


def parse_address(text: str) -> Address:
    """Return the address a map writes (any letter case, spaces around).

    Raises :class:`AddressError` saying what is wrong.
    """
    cleaned = text.strip().upper()
    if (found := _REGISTER.fullmatch(cleaned)) is not None:
        area = Area(found[1])
        word = int(found[2])
        if word > MAX_WORD[area]:
            raise AddressError(
                NO_WORD_ABOVE(
                    address=cleaned, area=area, last=f"{area}{MAX_WORD[area]}"
                )
            )
        return Address(area, word)
    if (found := _BIT.fullmatch(cleaned)) is not None:
        area = Area(found[1])
        word = int(found[2] or "0")
        if word > MAX_WORD[area.words]:
            raise AddressError(
                NO_WORD_ABOVE(address=cleaned, area=area, last=MAX_WORD[area.words])
            )
        return Address(area, word, int(found[3], 16))
    raise AddressError(NOT_AN_ADDRESS(address=repr(text.strip())))


def wire_type(data_type: DataType) -> WireType | None:
    """Return the gateway's type of a data type (None: the gateway has none)."""
    match data_type.kind, data_type.bits, data_type.signed:
        case ValueKind.BOOL, _, _:
            return WireType.BOOL
        case ValueKind.INTEGER, 16, True:
            return WireType.INT
        case ValueKind.INTEGER, 16, False:
            return WireType.UINT
        case ValueKind.INTEGER, 32, True:
            return WireType.DINT
        case ValueKind.INTEGER, 32, False:
            return WireType.UDINT
        case ValueKind.REAL, 32, _:
            return WireType.REAL
        case ValueKind.STRING, _, _:
            return WireType.STRING
    return None


def type_problem(address: Address, wire: WireType | None) -> Text | None:
    """Return what is wrong with a type at an address (None: it fits)."""
    problem = kind_problem(address, wire)
    if problem is None and wire is not None:
        problem = end_problem(address, wire)
    return problem


def kind_problem(address: Address, wire: WireType | None) -> Text | None:
    """Return why a type is not one the FP-I4C reads at such an address (None: it is)."""
    if wire is None:
        return TYPES()
    if address.area.bits and wire is not WireType.BOOL:
        return A_BIT(address=address)
    if not address.area.bits and wire is WireType.BOOL:
        return A_REGISTER(address=address, word=address.word)
    return None


def end_problem(address: Address, wire: WireType) -> Text | None:
    """Return why a value of a type at an address runs past its area (None: it fits)."""
    last = address.word + wire.registers - 1
    if not address.area.bits and last > MAX_WORD[address.area]:
        return PAST_THE_END(
            type=wire,
            address=address,
            first=f"{address.area}{address.word}",
            last=f"{address.area}{last}",
        )
    return None
