"""Placeholder until the program generator lands."""

from .program import Program


def generate_program(
    points: int, *, seed: int = 0, plc_type: str = "CP-2080"
) -> Program:
    """Not yet implemented."""
    raise NotImplementedError
