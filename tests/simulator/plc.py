"""The simulated PLC: its hardware identity, the loaded program and its memory."""

import dataclasses
import re
from typing import Any, Final

from .errors import TecoError
from .memory import LinkMotion, PlcMemory
from .program import Program

# Manual chapter 3.7: CP-1xxx answer at most 128 variables/items per request and take
# names up to 128 characters, CP-2xxx 256; other types are taken as the smaller.
_CP_FAMILY: Final = re.compile(r"CP-?([12])[0-9]{3}", re.IGNORECASE)
SMALL_LIMIT: Final = 128
LARGE_LIMIT: Final = 256


def limit_for_type(plc_type: str) -> int:
    """Items per response (and characters per variable name) for a PLC type."""
    match = _CP_FAMILY.match(plc_type.strip())
    if match is not None and match.group(1) == "2":
        return LARGE_LIMIT
    return SMALL_LIMIT


class Plc:
    """One PLC: a program can be downloaded into it; its hardware stays."""

    def __init__(self, program: Program) -> None:
        """A PLC made for `program` (its `plc` section), running it."""
        self.identity = program.plc
        self.program = program
        self.motion = LinkMotion()
        """How the program's links move what they copy (at once by default)."""
        self.memory = PlcMemory(program, self.motion)

    @property
    def limit(self) -> int:
        """Items per response, variables per request and characters per name."""
        return limit_for_type(self.identity.type)

    def download(self, program: Program) -> None:
        """Replace the running program, as Mosaic does; values restart from its initials."""
        self.program = program
        self.memory = PlcMemory(program, self.motion)

    def set_identity(self, **changes: str) -> None:
        """Change hardware fields (`serial_number`, `type`, ...)."""
        self.identity = dataclasses.replace(self.identity, **changes)

    def get_value(self, path: str) -> Any:
        """The JSON-shaped value at a path; KeyError if there is none."""
        try:
            return self.memory.read(self.memory.resolve(path))
        except TecoError as err:
            raise KeyError(path) from err

    def set_value(self, path: str, value: Any) -> None:
        """Write as the PLC program would; KeyError/ValueError as a PutObject would fail."""
        try:
            location = self.memory.resolve(path)
        except TecoError as err:
            raise KeyError(path) from err
        transaction = self.memory.transaction()
        try:
            transaction.write_json(location, value)
        except TecoError as err:
            if err.teco_code == 5:
                raise KeyError(err.message) from err
            raise ValueError(err.message) from err
        transaction.commit()
