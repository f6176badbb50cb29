"""What the PLCComS-backed sources share: pushed values batched per burst, in kind.

PLCComS pushes one ``DIFF:`` line per changed variable, and a server writes the
lines of one change-detection pass (every 100 ms) together. A :class:`PushBatch`
gathers the values of such a burst and hands them on once, so that a listener
(Home Assistant's coordinator) writes its states once per burst, not once per
line. :func:`point_value` reads a PLCComS value the way TecoApi reads the same
point, so that both ways into a PLC show the same value. :func:`enable_points` has
PLCComS push the polled points (``EN:``) and nothing else (``DI:``).
"""

import asyncio
from collections.abc import Callable, Collection, Iterable, Mapping
from datetime import date, datetime
import logging
import math
from typing import Any, Final

from ...core.exceptions import (
    PlcConnectionError,
    PlcResponseError,
    VariableNotFoundError,
)
from ...core.models import Catalogue, Point, ValueKind
from ...core.scalars import format_date, format_datetime
from ..points import value_path
from ..tecoapi.values import parse_value
from .client import PlcComsClient
from .errors import VariableDisabledError

_LOGGER = logging.getLogger(__name__)

DEFAULT_BATCH_WINDOW: Final = 0.01
"""Seconds a burst of pushed values is gathered before it is handed on.

A server writes one pass's lines at once; over a network they may arrive in a
few TCP segments within milliseconds. Passes are 100 ms apart, so 10 ms keeps
one pass in one batch and adds at most 10 ms to a value's way.
"""

# TecoApi prints REALs with six decimals; a PLCComS server may print all of a
# float32's digits (0.100000001490116). Rounded alike, both read 0.1.
_REAL_DECIMALS: Final = 6


def point_value(point: Point, value: Any) -> Any:
    """Return a PLCComS value as TecoApi reads the same point (None if it does not fit).

    REALs are rounded to TecoApi's six decimals and integral numbers of an
    integer point become ``int``; a text becomes a DATE, DT or TIME when the point
    is one (TecoApi infers those kinds from a string's format, PLCComS may call the
    variable a STRING).
    """
    match point.kind:
        case ValueKind.REAL:
            if isinstance(value, bool) or not isinstance(value, int | float):
                return None
            return round(float(value), _REAL_DECIMALS) if math.isfinite(value) else None
        case ValueKind.INTEGER:
            if isinstance(value, float) and value.is_integer():
                return int(value)
            return value if type(value) is int else None
        case ValueKind.DATE | ValueKind.DATETIME | ValueKind.TIME if isinstance(
            value, str
        ):
            return parse_value(point.kind, value)
        case _:
            return value


# What refuses one variable of a read, not the read itself.
_REFUSED: Final = (VariableNotFoundError, VariableDisabledError)

# Values read with one GET: command; a program may have thousands.
GET_BATCH: Final = 500


async def read_values(
    client: PlcComsClient, names: Iterable[str]
) -> tuple[dict[str, Any], frozenset[str]]:
    """``GET:`` variables in batches: values by lower-case name, and those unread.

    A batch the server refuses a name of (unknown, or disabled) is read again
    name by name, so one vanished variable does not hide the others.
    """
    values: dict[str, Any] = {}
    unread: set[str] = set()
    todo = list(names)
    for start in range(0, len(todo), GET_BATCH):
        batch = todo[start : start + GET_BATCH]
        try:
            read = await client.get(batch)
        except _REFUSED:
            read = {}
            for name in batch:
                try:
                    read.update(await client.get([name]))
                except _REFUSED:
                    unread.add(name.lower())
        values.update((name.lower(), value) for name, value in read.items())
    return values, frozenset(unread)


async def enable_points(
    client: PlcComsClient,
    catalogue: Catalogue,
    wanted: Mapping[str, str],
    followed: Collection[str],
) -> tuple[list[Point], set[str]]:
    """``EN:`` the wanted points, ``DI:`` every other enabled public variable.

    ``wanted`` holds point keys by the lower-case PLCComS name of their value,
    ``followed`` the names followed so far (a wanted one not in it is enabled
    again). A refusal is logged, a lost connection raised. Returns the points
    asked to be enabled and the lower-case names enabled afterwards.
    """
    gone = [
        name
        for name in client.enabled
        if name.lower() not in wanted and not name.startswith("__")
    ]
    if gone:
        try:
            await client.disable(gone)
        except PlcConnectionError:
            raise
        except PlcResponseError as err:
            _LOGGER.debug("PLCComS refused to disable %s: %s", gone, err)
    enabled = {name.lower() for name in client.enabled}
    new = [
        catalogue.points[key]
        for name, key in wanted.items()
        if name not in enabled or name not in followed
    ]
    if new:
        try:
            await client.enable(value_path(point) for point in new)
        except PlcConnectionError:
            raise
        except PlcResponseError as err:
            _LOGGER.debug("PLCComS refused to enable some of %s: %s", new, err)
        enabled = {name.lower() for name in client.enabled}
    return new, enabled


def json_shaped(value: Any) -> Any:
    """Return a typed value as TecoApi's JSON spells it (dates as text)."""
    if isinstance(value, datetime):
        return format_datetime(value)
    if isinstance(value, date):
        return format_date(value)
    return value


class PushBatch:
    """Gathers pushed values by point key and hands each burst on once.

    ``deliver(values)`` is called ``window`` seconds after the first value of a
    burst (0: as soon as the event loop is free, after the lines already read).
    A later value of the same key replaces an earlier one in the same burst.
    """

    def __init__(
        self,
        deliver: Callable[[dict[str, Any]], None],
        window: float = DEFAULT_BATCH_WINDOW,
    ) -> None:
        """Hand bursts to ``deliver``; nothing is gathered yet."""
        if window < 0:
            raise ValueError("the batch window cannot be negative")
        self._deliver = deliver
        self._window = window
        self._values: dict[str, Any] = {}
        self._handle: asyncio.Handle | None = None
        self.bursts = 0
        self.values = 0

    def add(self, key: str, value: Any) -> None:
        """Add a pushed value to the current burst (starting one if none is open)."""
        self._values[key] = value
        self.values += 1
        if self._handle is None:
            loop = asyncio.get_running_loop()
            self._handle = (
                loop.call_later(self._window, self.flush)
                if self._window
                else loop.call_soon(self.flush)
            )

    def flush(self) -> None:
        """Hand the current burst on now (nothing if it is empty)."""
        if self._handle is not None:
            self._handle.cancel()
            self._handle = None
        values, self._values = self._values, {}
        if values:
            self.bursts += 1
            self._deliver(values)

    def cancel(self) -> None:
        """Drop the current burst without handing it on."""
        if self._handle is not None:
            self._handle.cancel()
            self._handle = None
        self._values = {}
