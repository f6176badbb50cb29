"""The deterministic counts behind ``scripts/bench mervis`` (issue 23), asserted.

Requests per poll of generated projects of realistic structure, ours against the
naive client's (one ID per variable, 64 IDs a request), over real HTTP against
the simulated controller on a thread of its own, as the benchmark runs. Time is
never asserted.
"""

import pytest

from tests.benchmarks.mervis import (
    PollFigures,
    cottage_map,
    measure_polls,
    naive_requests,
    report,
)


@pytest.mark.parametrize(
    ("size", "commuids", "ours", "naive"),
    [(50, 9, 1, 1), (300, 57, 1, 5), (1000, 194, 4, 16)],
)
async def test_requests_per_poll_against_the_naive_client(
    socket_enabled: None, size: int, commuids: int, ours: int, naive: int
) -> None:
    figures = await measure_polls(size, polls=1)
    assert (figures.variables, figures.commuids) == (size, commuids)
    assert figures.ours == figures.lower_bound == ours
    assert figures.naive == naive_requests(size) == naive


def test_the_report_says_both_and_the_write_budget() -> None:
    figures = [PollFigures(300, 57, 1, 1, 5, 1.0, 3.0)]
    text = report(figures, [1.0, 2.0, 150.0])
    assert "| 300 | 57 | 1 | 1 | 5 | 1.00 | 3.00 |" in text
    assert "max 150.0 ms (budget 100 ms: NOT met)" in text
    assert "met)" in report(figures, [1.0])
    assert "write" not in report(figures, [])


def test_the_cottage_s_relay_is_writable() -> None:
    assert cottage_map().by_key()["hw.neuron_l203_ro_2.01"].access.writable
