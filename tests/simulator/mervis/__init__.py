"""A simulated Mervis (Unipi) controller speaking the web panel API, for tests and the demo.

See the *Mervis web panel* section of ``tests/simulator/README.md``;
run it with ``python -m tests.simulator.mervis --help``.
"""

from .project import (
    HOUSE_NAME,
    LIBRARIES,
    SHARED_NAME,
    SOLUTION_NAME,
    Project,
    ProjectError,
    Row,
    generated,
    house,
    solution,
)
from .server import MervisSimulator, RequestRecord, Switches

__all__ = [
    "HOUSE_NAME",
    "LIBRARIES",
    "SHARED_NAME",
    "SOLUTION_NAME",
    "MervisSimulator",
    "Project",
    "ProjectError",
    "RequestRecord",
    "Row",
    "Switches",
    "generated",
    "house",
    "solution",
]
