"""The conventions a Tecomat program's typed devices follow, in the order they are found.

GTSAP1 block families first, then our struct convention among the points no
family took. Every system's descriptor registers them: a Mervis program's
function blocks follow the struct convention, and a map's or a gateway's
names may follow either (they were found in every catalogue before systems
registered recognisers of their own).
"""

from typing import Final

from ..core.devices import Recogniser
from .gtsap1 import GTSAP1
from .structs import STRUCTS

RECOGNISERS: Final[tuple[Recogniser, ...]] = (GTSAP1, STRUCTS)
