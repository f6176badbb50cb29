"""Memory an entry's setup costs, measured in a fresh process of its own.

`python -m tests.benchmarks.memory LABEL [--seed N]` starts the program's simulated
PLC and a Home Assistant, sets up an entry of the small `manual` program first (so
that imports and platforms are loaded), removes it, then sets up the program's entry
and prints one JSON line: the traced Python heap the setup kept (tracemalloc) and the
growth of the process's peak resident set size (`ru_maxrss`). A peak only grows, so
the figure cannot be negative; a setup that fits in memory the process had already
touched grows it by 0. Measured in the same process as other programs and Home
Assistant instances, a resident set size difference mostly measures what the
allocator returned meanwhile (it once read -107.6 MiB per 1000 entities).
"""

import argparse
import asyncio
import gc
import json
import resource
import subprocess
import sys
import tracemalloc

from homeassistant.helpers import entity_registry as er

from .home_assistant import bench_home_assistant
from .integration import CREDENTIALS, MemoryFigures, setup_bench_entry
from .plc_thread import PlcThread
from .programs import bench_program


def peak_resident_bytes() -> int:
    """The process's peak resident set size so far, in bytes (Linux: KiB units)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024


async def _measure(label: str, seed: int) -> dict[str, int]:
    """Set up the program's entry after a warm-up entry; its memory figures."""
    async with (
        PlcThread(
            bench_program("manual").program,
            username=CREDENTIALS.username,
            password=CREDENTIALS.password,
        ) as warm_plc,
        PlcThread(
            bench_program(label, seed=seed).program,
            username=CREDENTIALS.username,
            password=CREDENTIALS.password,
        ) as plc,
        bench_home_assistant() as hass,
    ):
        warm_entry = await setup_bench_entry(hass, warm_plc, CREDENTIALS)
        await hass.config_entries.async_remove(warm_entry.entry_id)
        await hass.async_block_till_done()
        gc.collect()
        peak = peak_resident_bytes()
        tracemalloc.start()
        try:
            before = tracemalloc.get_traced_memory()[0]
            entry = await setup_bench_entry(hass, plc, CREDENTIALS)
            gc.collect()
            traced = tracemalloc.get_traced_memory()[0] - before
        finally:
            tracemalloc.stop()
        entities = len(
            er.async_entries_for_config_entry(er.async_get(hass), entry.entry_id)
        )
        return {
            "entities": entities,
            "traced_bytes": traced,
            "peak_resident_growth_bytes": peak_resident_bytes() - peak,
        }


def measure(label: str, seed: int) -> MemoryFigures:
    """Run the measurement in a new Python process and return its figures."""
    result = subprocess.run(  # noqa: S603 - our own interpreter and module
        [sys.executable, "-m", "tests.benchmarks.memory", label, "--seed", str(seed)],
        capture_output=True,
        text=True,
        check=True,
        timeout=600,
    )
    figures: dict[str, int] = json.loads(result.stdout.strip().splitlines()[-1])
    return MemoryFigures(**figures)


def main() -> None:
    """Measure one program and print its figures as one JSON line."""
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("label")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    print(json.dumps(asyncio.run(_measure(args.label, args.seed))))


if __name__ == "__main__":
    main()
