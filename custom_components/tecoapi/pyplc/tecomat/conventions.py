"""The conventions a Tecomat program's typed devices follow, in the order they are found.

Teco's GTSAP1 block families first (a library only a Tecomat program can
contain), then the core's struct convention among the points no family took.
Tecomat's descriptors (TecoApi, PLCComS) register them; the other systems
register the core's struct convention alone.
"""

from typing import Final

from ..core.devices import Recogniser
from ..core.structs import STRUCTS
from .gtsap1 import GTSAP1

RECOGNISERS: Final[tuple[Recogniser, ...]] = (GTSAP1, STRUCTS)
