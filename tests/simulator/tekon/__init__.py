"""A simulated Tekon opcconnector gateway (WEB OPC HTTP API 2.2), for tests and the demo.

See ``tests/simulator/README.md`` (*Tekon gateway*); run it with
``python -m tests.simulator.tekon --help``.
"""

from .building import (
    Building,
    Item,
    channel,
    large_building,
    lift_state,
    small_building,
    status,
)
from .server import TekonGateway

__all__ = [
    "Building",
    "Item",
    "TekonGateway",
    "channel",
    "large_building",
    "lift_state",
    "small_building",
    "status",
]
