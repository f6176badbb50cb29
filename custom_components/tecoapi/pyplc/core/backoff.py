"""The waits between attempts at something that keeps failing: doubling, capped.

A PLCComS connection opened again after it was lost, a gateway's OPC server
asked again after it was unavailable: each waits ``base`` seconds after the
first failure, twice as long after each next one, never more than ``maximum``,
and starts again from ``base`` once an attempt succeeds (:class:`Backoff`).
"""

from typing import Final

_MAX_DOUBLINGS: Final = 62
"""Doublings past which the wait is the maximum anyway (2**62 stays an int)."""


def backoff_delay(attempt: int, base: float, maximum: float) -> float:
    """Return the wait before attempt ``attempt`` (from 0): doubling, capped."""
    return float(min(base * 2 ** min(attempt, _MAX_DOUBLINGS), maximum))


class Backoff:
    """The waits of one thing retried: :meth:`failed` gives the next, :meth:`reset` starts again."""

    __slots__ = ("_base", "_maximum", "failures", "seconds")

    def __init__(self, base: float, maximum: float) -> None:
        """Wait ``base`` seconds after the first failure, at most ``maximum``."""
        self._base = base
        self._maximum = maximum
        self.failures = 0
        """Failures since the last success."""
        self.seconds = 0.0
        """The wait :meth:`failed` gave last (0 after a success)."""

    def failed(self) -> float:
        """Count a failure; return the seconds to wait before the next attempt."""
        self.seconds = backoff_delay(self.failures, self._base, self._maximum)
        self.failures += 1
        return self.seconds

    def reset(self) -> None:
        """Start again: an attempt succeeded, the next failure waits ``base``."""
        self.failures = 0
        self.seconds = 0.0
