"""Variable IDs of the web panel API: ``svc://<connection>/<CommUid>[<offset>,<length>]``.

A variable is a CommUid of the project (the IDE's ``.vlist`` lists them); an ID
reads ``length`` bytes of it from ``offset`` on, so one ID may read a whole
function block or struct, whose members are then sliced out locally. The
seed (an old design revision) writes ``svc:defaultConnection/…``, the released
revision ``svc://DefaultConnection/…``: both are read, and a client sends the
spelling the controller answers (:class:`IdStyle`). A variable of the
controller's own project is on its default connection; the seed also names
variables of another connection (``svc:otherConnection/…``: data the controller
reads from another source), which a map may address in full
(``svc://Other/8776[0,2]``). An answer is matched to a request by the
connection, the variable and its bytes (:func:`parse_id`), whatever the
spelling, letter case or spaces.
"""

from dataclasses import dataclass, replace
from enum import StrEnum
import re
from typing import Final, Self

_ADDRESS: Final = re.compile(r"\s*([0-9]+)\s*\[\s*([0-9]+)\s*,\s*([0-9]+)\s*\]\s*")
_ID: Final = re.compile(r"\s*svc:(?://)?([^/\s]+)/(.*)", re.IGNORECASE)
DEFAULT_CONNECTION: Final = "defaultconnection"
"""The local connection's name, folded (an address of it names none)."""

MAX_BYTES: Final = 1 << 20
"""The most bytes an address may read (a megabyte: larger is not a variable)."""


class IdStyle(StrEnum):
    """How a controller spells the local connection in an ID."""

    RELEASED = "svc://DefaultConnection/"
    """The released web panel (2019 revision)."""
    SEED = "svc:defaultConnection/"
    """The old design revision (the seed)."""

    def prefix(self, connection: str) -> str:
        """Return the prefix of an ID of a connection ("": the local one) in this style."""
        if not connection:
            return self.value
        return (
            f"svc://{connection}/" if self is IdStyle.RELEASED else f"svc:{connection}/"
        )


@dataclass(frozen=True, slots=True, order=True)
class Address:
    """Some bytes of one variable: ``length`` of them from ``offset`` on.

    ``connection`` is the connection the variable is read through, as the map
    names it ("": the controller's own, the default connection).
    """

    commuid: int
    offset: int
    length: int
    connection: str = ""

    @classmethod
    def parse(cls, text: str) -> Self:
        """Read ``CommUid[offset,length]``, or a whole ID; ValueError for anything else.

        An ID of the default connection is its ``CommUid[offset,length]``.
        """
        connection = ""
        if (named := _ID.fullmatch(text)) is not None:
            connection, text = named.groups()
            if connection.lower() == DEFAULT_CONNECTION:
                connection = ""
        match = _ADDRESS.fullmatch(text)
        if match is None:
            raise ValueError(f"{text!r} is not CommUid[offset,length]")
        commuid, offset, length = (int(part) for part in match.groups())
        if not 0 < length <= MAX_BYTES:
            raise ValueError(f"{text!r} reads {length} bytes")
        return cls(commuid, offset, length, connection)

    @property
    def end(self) -> int:
        """The offset just past the bytes."""
        return self.offset + self.length

    @property
    def variable(self) -> tuple[str, int]:
        """The variable the bytes are of: its connection (folded) and CommUid."""
        return (self.connection.lower(), self.commuid)

    @property
    def folded(self) -> "Address":
        """The address with its connection in lower case (answers are matched so)."""
        return replace(self, connection=self.connection.lower())

    def with_bytes(self, offset: int, length: int) -> "Address":
        """Return other bytes of the same variable."""
        return replace(self, offset=offset, length=length)

    def __str__(self) -> str:
        """Return the address as a map writes it: ``7001[4,4]``, ``svc://Other/7001[4,4]``."""
        own = f"{self.commuid}[{self.offset},{self.length}]"
        return f"svc://{self.connection}/{own}" if self.connection else own

    def variable_id(self, style: IdStyle) -> str:
        """Return the ID of these bytes, in a style's spelling."""
        return f"{style.prefix(self.connection)}{self.commuid}[{self.offset},{self.length}]"


def parse_id(text: object) -> Address | None:
    """Return the bytes an ID reads, its connection folded (None: not an ID)."""
    if not isinstance(text, str) or _ID.fullmatch(text) is None:
        return None
    try:
        return Address.parse(text).folded
    except ValueError:
        return None
