"""Run the demo's FP-I4C gateway: ``python -m tests.simulator.fpi4c --port 2000``.

A heating plant at station 1 and a garage door at station 2 (their points:
``docs/fpi4c-example.csv``); the door moves toward its target every second.
It prints the URL it serves and runs until interrupted.
"""

import argparse
import asyncio
from collections.abc import Sequence
import contextlib
import sys

from tests.simulator.base import run, stop_signal

from .demo import demo_stations, tick
from .server import FpI4cSimulator

TICK_SECONDS = 1.0


def parse_arguments(argv: Sequence[str] | None = None) -> argparse.Namespace:
    """Read the command line."""
    parser = argparse.ArgumentParser(
        prog="python -m tests.simulator.fpi4c",
        description="A simulated Panasonic FP-I4C gateway with two FP PLCs.",
    )
    parser.add_argument("--host", default="127.0.0.1", help="address (127.0.0.1)")
    parser.add_argument("--port", type=int, default=2000, help="0: a free one (2000)")
    parser.add_argument(
        "--lenient", action="store_true", help="answer as the manual prints JSON"
    )
    parser.add_argument(
        "--silent",
        type=int,
        action="append",
        default=[],
        help="a station that does not answer (repeatable)",
    )
    return parser.parse_args(argv)


async def serve(arguments: argparse.Namespace, stop: asyncio.Event) -> None:
    """Serve until ``stop`` is set, moving the garage door every second."""
    stations = demo_stations()
    simulator = FpI4cSimulator(stations, station=1, lenient=arguments.lenient)
    simulator.silent.update(arguments.silent)
    await simulator.start(arguments.host, arguments.port)
    print(f"FP-I4C REST API on {simulator.url}/plcpost", flush=True)
    try:
        while not stop.is_set():
            with contextlib.suppress(TimeoutError):
                await asyncio.wait_for(stop.wait(), TICK_SECONDS)
            tick(stations)
    finally:
        await simulator.stop()


def main(argv: Sequence[str] | None = None) -> int:
    """Run the gateway until SIGINT or SIGTERM."""
    arguments = parse_arguments(argv)
    return run(lambda: serve(arguments, stop_signal()))


if __name__ == "__main__":
    with contextlib.suppress(KeyboardInterrupt):
        sys.exit(main())
