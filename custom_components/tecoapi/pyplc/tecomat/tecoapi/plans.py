"""The read planner's models: the GetObject requests of a poll and what they read."""

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from ...core.models import PointAttributes
from .info import ITEM_LIMIT_UNKNOWN


@dataclass(frozen=True, slots=True)
class PlannedRequest:
    """One GetObject request of a read plan.

    ``point_keys`` are the polled points this request answers for.
    """

    names: tuple[str, ...]
    target: str
    items: int
    point_keys: frozenset[str] = field(default_factory=frozenset)


@dataclass(frozen=True, slots=True)
class ReadPlan:
    """The GetObject requests of one poll and the bound they were measured against.

    ``item_limit`` is the limit the plan was made for (re-plan when the client's
    learned limit drops below it); ``unreadable`` are polled points no request can
    reach within the limits (reported as missing by every read).
    """

    requests: tuple[PlannedRequest, ...]
    lower_bound: int
    with_attrs: bool
    point_keys: frozenset[str]
    item_limit: int = ITEM_LIMIT_UNKNOWN
    unreadable: frozenset[str] = field(default_factory=frozenset)


@dataclass(frozen=True, slots=True)
class PollResult:
    """The typed values of one poll.

    A value is ``None`` when the PLC's value no longer fits the point's kind
    (its program changed the variable's type).
    """

    values: Mapping[str, Any]
    attributes: Mapping[str, PointAttributes]
    missing: frozenset[str]
