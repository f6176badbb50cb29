"""Variable IDs of the web panel API: ``svc://DefaultConnection/<CommUid>[<offset>,<length>]``.

A variable is a CommUid of the project (the IDE's ``.vlist`` lists them); an ID
reads ``length`` bytes of it from ``offset`` on, so one ID may read a whole
function block or struct, whose members are then sliced out locally. The
seed (an old design revision) writes ``svc:defaultConnection/…``, the released
revision ``svc://DefaultConnection/…``: both are read, and a client sends the
spelling the controller answers (:class:`IdStyle`). An answer is matched to a
request by the variable and its bytes (:func:`parse_id`), whatever the
spelling, letter case or spaces.
"""

from dataclasses import dataclass
from enum import StrEnum
import re
from typing import Final, Self

_ADDRESS: Final = re.compile(r"\s*([0-9]+)\s*\[\s*([0-9]+)\s*,\s*([0-9]+)\s*\]\s*")
_ID: Final = re.compile(r"\s*svc:(?://)?defaultconnection/(.*)", re.IGNORECASE)

MAX_BYTES: Final = 1 << 20
"""The most bytes an address may read (a megabyte: larger is not a variable)."""


class IdStyle(StrEnum):
    """How a controller spells the local connection in an ID."""

    RELEASED = "svc://DefaultConnection/"
    """The released web panel (2019 revision)."""
    SEED = "svc:defaultConnection/"
    """The old design revision (the seed)."""


@dataclass(frozen=True, slots=True, order=True)
class Address:
    """Some bytes of one variable: ``length`` of them from ``offset`` on."""

    commuid: int
    offset: int
    length: int

    @classmethod
    def parse(cls, text: str) -> Self:
        """Read ``CommUid[offset,length]``; ValueError for anything else."""
        match = _ADDRESS.fullmatch(text)
        if match is None:
            raise ValueError(f"{text!r} is not CommUid[offset,length]")
        commuid, offset, length = (int(part) for part in match.groups())
        if not 0 < length <= MAX_BYTES:
            raise ValueError(f"{text!r} reads {length} bytes")
        return cls(commuid, offset, length)

    @property
    def end(self) -> int:
        """The offset just past the bytes."""
        return self.offset + self.length

    def __str__(self) -> str:
        """Return the address as a ``.vlist`` writes it: ``7001[4,4]``."""
        return f"{self.commuid}[{self.offset},{self.length}]"

    def variable_id(self, style: IdStyle) -> str:
        """Return the ID of these bytes on the local connection."""
        return f"{style.value}{self}"


def parse_id(text: object) -> Address | None:
    """Return the bytes an ID of the local connection reads (None: not one)."""
    if not isinstance(text, str) or (match := _ID.fullmatch(text)) is None:
        return None
    try:
        return Address.parse(match.group(1))
    except ValueError:
        return None
