"""An updates answer's changes in the order they happened, bounded per item.

A session opened with ``alldata=1`` (the seed's *NewSession*) gets every change
of an item since the previous updates, each with its ``UpTime``: a door that
opened and closed within one poll comes as two entries. :func:`in_order` puts an
answer's entries in their ``UpTime`` order (the answer's own order where the
times are equal: ``UpTime`` has whole seconds; an entry without one keeps its
place after the one before it) and keeps at most ``most`` changes of an item:
its first ``most - 1`` and its last, the ones between collapsed (a chattering
contact costs neither memory nor state changes without limit, and its last
value is the one shown). :func:`states` cuts the ordered changes into the
successive states to show: a new state begins where an item changes again.
"""

from collections import Counter
from collections.abc import Hashable, Iterable, Iterator
from dataclasses import dataclass
from datetime import datetime
from typing import Final

from .client import ItemUpdate

MOST_CHANGES: Final = 16
"""The most changes of one item an answer applies (the first 15 and the last)."""


@dataclass(frozen=True, slots=True)
class Ordered:
    """An answer's changes in order, and how many were collapsed."""

    changes: list[ItemUpdate]
    collapsed: int = 0


def item_of(update: ItemUpdate) -> Hashable:
    """Return what tells an update's item apart: its name (any case), else its ID."""
    return update.name.lower() if update.name is not None else update.item_id


def in_order(updates: Iterable[ItemUpdate], most: int = MOST_CHANGES) -> Ordered:
    """Return the changes in their ``UpTime`` order, at most ``most`` of an item."""
    listed = list(updates)
    times: list[datetime] = []
    previous = datetime.min  # noqa: DTZ901 (the gateway's local time, no zone)
    for update in listed:
        previous = update.time or previous
        times.append(previous)
    # A stable sort: changes of the same UpTime keep the answer's order.
    order = sorted(range(len(listed)), key=times.__getitem__)
    changes = [listed[index] for index in order]
    counts = Counter(item_of(update) for update in changes)
    if max(counts.values(), default=0) <= most:
        return Ordered(changes)
    kept: list[ItemUpdate] = []
    seen: Counter[Hashable] = Counter()
    for update in changes:
        item = item_of(update)
        seen[item] += 1
        if most <= seen[item] < counts[item]:
            continue
        kept.append(update)
    return Ordered(kept, len(changes) - len(kept))


def states(changes: Iterable[ItemUpdate]) -> Iterator[list[ItemUpdate]]:
    """Cut ordered changes into successive states: a new one where an item changes again."""
    state: list[ItemUpdate] = []
    items: set[Hashable] = set()
    for update in changes:
        item = item_of(update)
        if item in items:
            yield state
            state, items = [], set()
        state.append(update)
        items.add(item)
    if state:
        yield state
