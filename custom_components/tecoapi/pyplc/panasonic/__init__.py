"""Panasonic FP PLCs through the FP-I4C IoT gateway's REST API (``POST /plcpost``).

``FpI4cSource`` (a register map's points, one device per station, read at the
planner's bound) over ``FpI4cClient`` (HTTP, the gateway's answers read
strictly then as its manual prints them). Addresses are Panasonic's
(:mod:`.address`: ``DT100``, ``R1A``); :func:`plan_reads` is the planner.
"""

from .address import Address, Area, WireType, parse_address
from .client import FpI4cClient
from .mapping import check_point
from .planner import ReadPlan, Target, plan_reads
from .source import FpI4cSource

__all__ = [
    "Address",
    "Area",
    "FpI4cClient",
    "FpI4cSource",
    "ReadPlan",
    "Target",
    "WireType",
    "check_point",
    "parse_address",
    "plan_reads",
]
