"""A simulated Panasonic FP-I4C gateway and the FP PLCs behind it.

See ``tests/simulator/README.md`` (its FP-I4C section); run the demo's with
``python -m tests.simulator.fpi4c --help``.
"""

from .demo import EXAMPLE_CSV, demo_stations, tick
from .memory import StationMemory
from .server import NO_RESPONSE, FpI4cSimulator, Hold

__all__ = [
    "EXAMPLE_CSV",
    "NO_RESPONSE",
    "FpI4cSimulator",
    "Hold",
    "StationMemory",
    "demo_stations",
    "tick",
]
