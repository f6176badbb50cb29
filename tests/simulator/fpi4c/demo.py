"""The live demo's gateway: a heating plant at station 1, a garage door at station 2.

Their points are ``docs/fpi4c-example.csv``; :func:`demo_stations` holds the
values that map reads, and :func:`tick` moves the garage door toward its
target a step at a time (the demo calls it every second).
"""

from pathlib import Path
from typing import Final

from .memory import StationMemory

EXAMPLE_CSV: Final = Path(__file__).resolve().parents[3] / "docs" / "fpi4c-example.csv"
"""The demo's register map (the example of the documentation)."""
HEATING: Final = 1
GARAGE: Final = 2
DOOR_STEP: Final = 10
"""Percent the door moves a tick."""


def demo_stations() -> dict[int, StationMemory]:
    """Return the two stations' PLCs, holding what the example map reads."""
    heating, garage = StationMemory(), StationMemory()
    for index, tenths in enumerate((652, 452, 381, -35, 498, 214)):
        heating.write("DT", "INT", index, [tenths])
    heating.write("DT", "INT", 100, [450, 215, 550])
    heating.write("DT", "UDINT", 200, [12_345, 3_456])
    heating.write("DT", "REAL", 210, [1.8])
    heating.write_string("DT", 300, "Heating")
    heating.write("Y", "BOOL", 0, [True, False])
    heating.write("R", "BOOL", 16, [True])  # R10
    heating.write("X", "BOOL", 0, [True, False])
    garage.write("DT", "INT", 10, [0, 0])
    garage.write("R", "BOOL", 0, [False])
    garage.write("X", "BOOL", 0, [True, True])
    garage.write("Y", "BOOL", 0, [False])
    return {HEATING: heating, GARAGE: garage}


def tick(stations: dict[int, StationMemory]) -> None:
    """Move the garage door a step toward its target (R0 says it moves)."""
    garage = stations.get(GARAGE)
    if garage is None:
        return
    position, target = garage.read("DT", "INT", 10, 2)
    step = max(-DOOR_STEP, min(DOOR_STEP, target - position))
    position += step
    garage.write("DT", "INT", 10, [position])
    garage.write("R", "BOOL", 0, [position != target])
    garage.write("X", "BOOL", 0, [position == 0])
