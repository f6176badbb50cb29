"""The soak of every source, a few seeded cycles: no wrong value, no write lost or doubled.

`scripts/bench soak --source S` runs thousands of cycles with random faults;
here each source's adapter runs a few dozen with a fault in every other cycle
and a write in most, against its simulator on 127.0.0.1, so that an adapter
that cannot start its device, switch a fault on or off, or tell a write held
fails here rather than in a long run. Time and memory are not asserted.
"""

import pytest

from tests.benchmarks.soak import SOURCES, SoakSettings, run_soak


@pytest.mark.parametrize("source", SOURCES)
async def test_soak_loses_no_write(socket_enabled: None, source: str) -> None:
    """Faults come and go; every write is held once; the entities come back."""
    results = await run_soak(
        SoakSettings(
            program="50",
            cycles=12,
            fault_rate=0.5,
            change_percent=5.0,
            write_rate=0.7,
            latency_ms=0.0,
            seed=1,
            source=source,
        )
    )

    assert results.faults.total() > 0
    assert results.writes > 0
    assert results.writes_lost == 0
    assert results.writes_doubled == 0
    assert results.faults_not_recovered == 0
    assert results.unhandled_exceptions == 0
    assert results.values_checked > 0
    assert results.wrong_values == 0, results.wrong_examples
