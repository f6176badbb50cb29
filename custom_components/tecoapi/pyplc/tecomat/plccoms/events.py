"""What a PLCComS client tells its subscribers, and how its connection is doing.

Nothing here does I/O: :class:`~.client.PlcComsClient` emits these events to the
callbacks given to ``subscribe`` and describes itself in :class:`PlcComsHealth`.
"""

from collections.abc import Callable
from dataclasses import dataclass
from datetime import datetime
from typing import Any

from ...core.models import Catalogue


@dataclass(frozen=True, slots=True)
class ValueChanged:
    """A variable's new value: pushed (``DIFF:``) or read again after a reconnect.

    ``value`` is typed by the variable's kind (None if the text does not fit it);
    ``raw`` is the value's text on the wire for a push, "" for a value read again.
    """

    key: str
    name: str
    value: Any
    raw: str
    pushed: bool = True


@dataclass(frozen=True, slots=True)
class RunStateChanged:
    """``__PLC_RUN`` changed: the PLC runs its program, or it stopped (HALT/ERR)."""

    running: bool


@dataclass(frozen=True, slots=True)
class ConnectionChanged:
    """The client became ready (connected, listed, enabled) or lost its connection."""

    connected: bool
    reason: str = ""


@dataclass(frozen=True, slots=True)
class ProgramChanged:
    """``LIST:`` changed (a program download); the client has re-enabled its variables."""

    catalogue: Catalogue


type PlcComsEvent = ValueChanged | RunStateChanged | ConnectionChanged | ProgramChanged
type PlcComsCallback = Callable[[PlcComsEvent], None]


@dataclass(frozen=True, slots=True, kw_only=True)
class PlcComsHealth:
    """How the connection is doing, to decide whether push can be relied on.

    ``idle`` is seconds since the last line arrived (None before the first).
    Counters run for the client's life.
    """

    connected: bool
    plc_running: bool | None
    last_line_at: datetime | None
    idle: float | None
    lines_received: int
    lines_sent: int
    discarded_lines: int
    malformed_lines: int
    server_errors: int
    keepalives: int
    stalls: int
    reconnects: int
    reconnect_attempts: int
    last_error: str | None
