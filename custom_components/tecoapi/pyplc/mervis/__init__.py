"""Mervis (Unipi) controllers through their web panel API.

``MervisSource`` (the points of the project's ``.vlist``, the schedule) over
``MervisClient`` (``login.cgi``, ``values.cgi``, ``command.cgi``); the read
planner (:mod:`.planner`), the values' codec (:mod:`.codec`) and the variable
IDs (:mod:`.ids`).
"""

from .client import Item, MervisClient, RequestRefusedError
from .ids import Address, IdStyle
from .planner import ReadPlan, plan_reads
from .source import MervisSource

__all__ = [
    "Address",
    "IdStyle",
    "Item",
    "MervisClient",
    "MervisSource",
    "ReadPlan",
    "RequestRefusedError",
    "plan_reads",
]
