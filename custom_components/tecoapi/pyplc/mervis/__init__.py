"""Mervis (Unipi) controllers through their web panel API.

``MervisSource`` (the points of the project's ``.vlist``, the schedule) over
``MervisClient`` (``login.cgi``, ``values.cgi``, ``command.cgi``); the read
planner (:mod:`.planner`), the values' codec (:mod:`.codec`) and the variable
IDs (:mod:`.ids`), the point map of the IDE's ``.vlist`` (:mod:`.vlist`).
"""

from .client import Item, MervisClient, RequestRefusedError
from .ids import Address, IdStyle
from .planner import ReadPlan, plan_reads
from .source import MervisSource
from .vlist import load_vlist

__all__ = [
    "Address",
    "IdStyle",
    "Item",
    "MervisClient",
    "MervisSource",
    "ReadPlan",
    "RequestRefusedError",
    "load_vlist",
    "plan_reads",
]
