"""The waits between attempts: doubling from the base, capped, started again by a success."""

from custom_components.tecoapi.pyplc.core.backoff import Backoff, backoff_delay


def test_backoff_delay() -> None:
    assert [backoff_delay(n, 1.0, 60.0) for n in range(8)] == [
        1.0,
        2.0,
        4.0,
        8.0,
        16.0,
        32.0,
        60.0,
        60.0,
    ]
    assert backoff_delay(10_000, 1.0, 60.0) == 60.0


def test_each_failure_waits_twice_as_long_up_to_the_maximum() -> None:
    backoff = Backoff(0.5, 3.0)
    assert (backoff.failures, backoff.seconds) == (0, 0.0)
    assert [backoff.failed() for _ in range(5)] == [0.5, 1.0, 2.0, 3.0, 3.0]
    assert (backoff.failures, backoff.seconds) == (5, 3.0)


def test_a_success_starts_again_from_the_base() -> None:
    backoff = Backoff(1.0, 60.0)
    backoff.failed()
    backoff.failed()
    backoff.reset()
    assert (backoff.failures, backoff.seconds) == (0, 0.0)
    assert backoff.failed() == 1.0


def test_a_maximum_below_the_base_is_the_wait() -> None:
    assert [Backoff(1.0, 0.25).failed() for _ in range(2)] == [0.25, 0.25]
