"""Reading the public roots in discovery: batched by what the PLC has told so far.

GetList names the roots only, so a root's size (its leaf items, which count toward
the CPU's per-answer limit ``L``: 128 on a CP-1xxx, 256 on a CP-2xxx) is known only
once it has been read. Roots are read in GetList order, in requests of at most 256
characters, as follows.

- Until an answer is too large (413), batches are cut by characters only: a small
  program (the manual's) is read in one request.
- After that, a batch of ``k`` roots never yet read is predicted to hold ``k · P``
  items, ``P`` the largest size among the last four roots read (GetList keeps the
  declaration order, and neighbours tend to be alike: scalars, then T_ApiObjects,
  then program instances), and takes as many roots as fit ``L``.
- A batch of ``k`` roots answered 413 (whose message states the allowed ``L``,
  which the client adopts) holds more than ``L`` items, so at least one of its roots
  holds more than its share ``L / k``: its roots are then read one at a time until
  the first such root, which *turned out too big to share the request*. The roots
  after it go back to be batched again, with ``P`` now at least its size.

So each 413 is charged to its own root, one that is read alone afterwards; a root
too big for any answer costs one more (it is read alone once, to be sure, and
skipped). Halving a batch on 413, as this client did before, costs up to
``log2 k`` answers 413 for one large root: 25 on a CP-1000 whose 400 T_ApiObjects
sit in 27 roots of up to 128 items each, where this costs one.

The bound reported (``DiscoveryCost.lower_bound``): GetList plus the fewest
GetObject requests that read the roots read, knowing their sizes beforehand:
``max(⌈Σ items / L⌉, ⌈Σ characters / B⌉, #roots of more than L/2 items)``, ``B``
the characters for names in one target. Measured (GetList included; requests /
bound / answers 413), against the simulator: the 400-point CP-1000 program above
29 / 28 / 1 (halving: 53 / 28 / 25); the demo 9 / 3 / 1 (halving: 6 / 3 / 2);
the manual 2 / 2 / 0; generated 1000-point programs (seeds 0-1, CP-1000 and
CP-2080) 69-118 / 33-64 / 3-5 (halving: 81-146 / 33-64 / 24-56). The gap to the
bound is the price of not knowing sizes: after a 413 the roots before the one
that overflowed are read alone, and small roots after a large one share requests
only once the large one has left the last four.
"""

from collections import deque
from collections.abc import Iterable, Sequence
import math
from typing import Any, Final

from ...core.exceptions import (
    PlcResponseError,
    TooManyItemsError,
    VariableNotFoundError,
)
from ...core.models import DiscoveryCost
from .paths import GET_OBJECT, MAX_TARGET_LENGTH, encode_name, member, merge_into

NAME_BUDGET: Final = MAX_TARGET_LENGTH - len(GET_OBJECT) + 1
"""Characters for names in one target, counting one separator (``?``/``&``) each."""
RECENT_ROOTS: Final = 4
"""The roots read last whose largest size predicts the next roots' sizes."""


def _chars(name: str) -> int:
    """Characters a name takes in a target, with its separator."""
    return len(encode_name(name)) + 1


def leaf_items(node: Any) -> int:
    """Count the items an answer's node holds, as the PLC counts them: its leaves."""
    count = 0
    stack = [node]
    while stack:
        current = stack.pop()
        if isinstance(current, dict):
            stack.extend(current.values())
        elif isinstance(current, list):
            stack.extend(current)
        else:
            count += 1
    return count


class RootReading:
    """Which roots to read next, and what the answers taught (see the module doc).

    ``next_batch`` gives the names of the next GetObject request (None when done);
    ``answered`` or ``failed`` tells how it went. ``tree`` holds the merged answers.
    """

    def __init__(self, roots: Sequence[str], *, item_limit: int) -> None:
        """Read ``roots`` (GetList's) under the client's current item limit."""
        self.tree: dict[str, Any] = {}
        self.skipped: list[str] = []
        self.item_limit = item_limit
        self._queue: deque[str] = deque(roots)
        self._forced: deque[list[str]] = deque()
        self._search: deque[str] = deque()
        self._searched: frozenset[str] = frozenset()
        self._share = 0.0
        self._sizes: dict[str, int] = {}
        self._recent: deque[int] = deque(maxlen=RECENT_ROOTS)
        self._requests = 1  # GetList
        self._too_large = 0
        self._overflowing = 0
        self._oversized = 0

    def next_batch(self) -> list[str] | None:
        """Return the roots to read in the next request, None when all are read."""
        if self._search:
            batch = [self._search.popleft()]
        elif self._forced:
            self._searched = frozenset()
            batch = self._forced.popleft()
        elif self._queue:
            self._searched = frozenset()
            batch = self._take()
        else:
            return None
        self._requests += 1
        return batch

    def _take(self) -> list[str]:
        """Take the next batch from the queue: characters, then predicted items."""
        predicted = max(self._recent) if self._recent else 0
        batch: list[str] = []
        chars = 0
        while self._queue:
            name = self._queue[0]
            if batch and (
                chars + _chars(name) > NAME_BUDGET
                or (len(batch) + 1) * predicted > self.item_limit
            ):
                break
            batch.append(self._queue.popleft())
            chars += _chars(name)
        return batch

    def answered(self, batch: Sequence[str], answer: dict[str, Any]) -> None:
        """Take an answer: merge it, learn its roots' sizes, end a search."""
        merge_into(self.tree, answer)
        for name in batch:
            size = leaf_items(member(answer, name))
            self._sizes[name] = size
            self._recent.append(size)
            if name in self._searched and size > self._share:
                self._found_offender()

    def failed(self, batch: list[str], err: PlcResponseError, item_limit: int) -> None:
        """Take a failed request; re-raise what reading in parts cannot help."""
        self.item_limit = item_limit
        if isinstance(err, TooManyItemsError):
            self._too_large += 1
            if len(batch) == 1:
                self.skipped.append(batch[0])
                self._oversized += 1
                if batch[0] in self._searched:
                    self._found_offender()
                return
            # More than L items: some root holds more than L / k of them.
            self._search.extendleft(reversed(batch))
            self._searched = frozenset(batch)
            self._share = item_limit / len(batch)
            return
        if not isinstance(err, VariableNotFoundError):
            raise err
        if len(batch) == 1:
            self.skipped.append(batch[0])
            return
        wanted = err.path.lower()
        named = next((name for name in batch if name.lower() == wanted), None)
        if named is None:
            middle = len(batch) // 2
            self._forced.extendleft([batch[middle:], batch[:middle]])
            return
        self.skipped.append(named)
        self._queue.extendleft(reversed([name for name in batch if name != named]))

    def _found_offender(self) -> None:
        """End a search: the roots not yet read go back to be batched again."""
        self._overflowing += 1
        self._queue.extendleft(reversed(self._search))
        self._search.clear()
        self._searched = frozenset()
        self._share = 0.0

    def stats(self) -> DiscoveryCost:
        """Return what reading the roots cost, and the bound of the module docstring."""
        return DiscoveryCost(
            requests=self._requests,
            lower_bound=1 + lower_bound(self._read_sizes(), self.item_limit),
            too_large=self._too_large,
            overflowing_groups=self._overflowing,
            oversized_groups=self._oversized,
            item_limit=self.item_limit,
        )

    def _read_sizes(self) -> list[tuple[str, int]]:
        skipped = set(self.skipped)
        return [
            (name, size) for name, size in self._sizes.items() if name not in skipped
        ]


def lower_bound(roots: Iterable[tuple[str, int]], item_limit: int) -> int:
    """Return the fewest GetObject requests that read these ``(name, items)`` roots."""
    sizes = list(roots)
    if not sizes:
        return 0
    items = math.ceil(sum(size for _, size in sizes) / item_limit)
    chars = math.ceil(sum(_chars(name) for name, _ in sizes) / NAME_BUDGET)
    large = sum(2 * size > item_limit for _, size in sizes)
    return max(items, chars, large)
