"""One benchmark run: for each program a simulated PLC, the client figures, then Home
Assistant's."""

import asyncio
import logging
import time
from typing import Final

from tests.simulator import load_program

from .integration import CREDENTIALS, measure_integration, warm_up
from .machine import machine_info
from .memory import measure as measure_memory
from .plc_thread import PlcThread
from .polling import measure_polling
from .programs import bench_program
from .results import BenchResults, BenchSettings, ProgramResult

_LOGGER: Final = logging.getLogger(__name__)


def _plc(program_label: str, settings: BenchSettings) -> PlcThread:
    return PlcThread(
        bench_program(program_label, seed=settings.seed).program,
        username=CREDENTIALS.username,
        password=CREDENTIALS.password,
        latency=settings.latency_ms / 1000,
        latency_per_item=settings.per_item_ms / 1000,
    )


async def run_benchmark(settings: BenchSettings) -> BenchResults:
    """Measure every program of the settings, in order."""
    started = time.perf_counter()
    results = BenchResults(machine=machine_info(), settings=settings)
    _LOGGER.info("Warming up Home Assistant (imports, platforms)")
    async with PlcThread(
        load_program("demo"),
        username=CREDENTIALS.username,
        password=CREDENTIALS.password,
    ) as plc:
        await warm_up(plc, CREDENTIALS)
    for label in settings.programs:
        _LOGGER.info("Program %s: client and peer polls", label)
        async with _plc(label, settings) as plc:
            polling = await measure_polling(
                plc,
                CREDENTIALS.username,
                CREDENTIALS.password,
                polls=settings.polls,
                peer_polls=settings.peer_polls,
            )
        _LOGGER.info("Program %s: memory, in a fresh process", label)
        memory = await asyncio.to_thread(measure_memory, label, settings.seed)
        _LOGGER.info("Program %s: Home Assistant", label)
        async with _plc(label, settings) as plc:
            integration = await measure_integration(
                plc,
                CREDENTIALS,
                polls=settings.polls,
                percents=settings.percents,
                write_samples=settings.write_samples,
                memory=memory,
                seed=settings.seed,
            )
        results.programs.append(
            ProgramResult(label=label, polling=polling, integration=integration)
        )
    results.seconds = time.perf_counter() - started
    return results
