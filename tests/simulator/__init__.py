"""A simulated Tecomat PLC speaking TecoApi, for tests and for trying the integration.

See `tests/simulator/README.md`; run it with `python -m tests.simulator --help`.
"""

from .faults import Faults
from .generator import generate_program
from .program import Program, ProgramError, load_program
from .server import RequestRecord, Simulator

__all__ = [
    "Faults",
    "Program",
    "ProgramError",
    "RequestRecord",
    "Simulator",
    "generate_program",
    "load_program",
]
