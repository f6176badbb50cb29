"""Discovery's batching of roots, driven by hand: answers, 413s and missing roots."""

from typing import Any

import pytest

from custom_components.tecoapi.pyplc import (
    InvalidPathError,
    TooManyItemsError,
    VariableNotFoundError,
)
from custom_components.tecoapi.pyplc.tecomat.tecoapi.roots import (
    RootReading,
    leaf_items,
    lower_bound,
)


def answer(sizes: dict[str, int], batch: list[str]) -> dict[str, Any]:
    """A GetObject answer: each root an array of its size's items."""
    return {name: list(range(sizes[name])) for name in batch}


def run(sizes: dict[str, int], limit: int) -> tuple[RootReading, list[list[str]]]:
    """Read roots of the given sizes as a PLC with ``limit`` items per answer would."""
    reading = RootReading(list(sizes), item_limit=limit)
    sent: list[list[str]] = []
    while (batch := reading.next_batch()) is not None:
        sent.append(batch)
        if sum(sizes[name] for name in batch) > limit:
            reading.failed(batch, TooManyItemsError("too many", allowed=limit), limit)
        else:
            reading.answered(batch, answer(sizes, batch))
    return reading, sent


def test_roots_that_fit_are_read_in_one_request() -> None:
    reading, sent = run({"a": 1, "b": 20, "c": 3}, 128)
    assert sent == [["a", "b", "c"]]
    stats = reading.stats()
    assert (stats.requests, stats.lower_bound, stats.too_large) == (2, 2, 0)


def test_one_413_per_root_too_big_to_share_then_sized_batches() -> None:
    sizes = {"a": 8, "b": 8, "big": 100, "c": 90, "d": 10, "e": 10, "f": 10, "g": 10}
    reading, sent = run(sizes, 128)
    # The first batch overflows; roots are read alone up to the first above its
    # share (128 / 8 = 16): big. The rest is batched by the largest of the last
    # four sizes: big or c (90) is among them up to g, so each goes alone.
    assert sent == [
        list(sizes),
        ["a"],
        ["b"],
        ["big"],
        ["c"],
        ["d"],
        ["e"],
        ["f"],
        ["g"],
    ]
    stats = reading.stats()
    assert (stats.too_large, stats.overflowing_groups, stats.oversized_groups) == (
        1,
        1,
        0,
    )
    assert stats.requests == 10
    # Knowing the sizes: big with a, b and d; c with e, f and g.
    assert stats.lower_bound == 1 + 2
    assert sorted(reading.tree) == sorted(sizes)


def test_a_missing_root_not_named_halves_the_batch() -> None:
    reading = RootReading(["a", "b", "c", "d"], item_limit=128)
    batch = reading.next_batch()
    assert batch == ["a", "b", "c", "d"]
    reading.failed(batch, VariableNotFoundError("gone", path="A.x"), 128)
    assert reading.next_batch() == ["a", "b"]
    reading.answered(["a", "b"], {"a": 1, "b": 2})
    second = reading.next_batch()
    assert second == ["c", "d"]
    reading.failed(second, VariableNotFoundError("gone", path="d"), 128)
    assert reading.next_batch() == ["c"]
    reading.failed(["c"], VariableNotFoundError("gone"), 128)
    assert reading.next_batch() is None
    assert reading.skipped == ["d", "c"]


def test_other_errors_end_discovery() -> None:
    reading = RootReading(["a"], item_limit=128)
    batch = reading.next_batch()
    assert batch is not None
    with pytest.raises(InvalidPathError):
        reading.failed(batch, InvalidPathError("name too long"), 128)


def test_leaf_items_and_the_bound() -> None:
    assert leaf_items({"v": 1, "attr": {"a": True, "b": [1, 2, {"c": "x"}]}}) == 5
    assert leaf_items(3.5) == 1
    assert lower_bound([], 128) == 0
    assert lower_bound([("a", 100), ("b", 100), ("c", 10)], 128) == 2
    assert lower_bound([("x" * 100, 1), ("y" * 100, 1), ("z" * 100, 1)], 128) == 2
