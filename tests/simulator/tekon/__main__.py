"""Run the simulated gateway: ``python -m tests.simulator.tekon --port 8090 ...``.

It prints the URL it serves and, with ``--animate``, lives like a building:
the lift travels between floors and opens its doors, the meters count, the
entrance's temperature wanders and its door opens now and then.
"""

import argparse
import asyncio
from collections.abc import Sequence
import contextlib
import itertools
import sys

from tests.simulator.base import run, stop_signal

from .building import (
    CONTROLLER,
    LIFT,
    METERS,
    large_building,
    lift_state,
    small_building,
)
from .server import API_VERSIONS, TEXT_URLS, TekonGateway


def parse_arguments(argv: Sequence[str] | None = None) -> argparse.Namespace:
    """The command line."""
    parser = argparse.ArgumentParser(
        prog="python -m tests.simulator.tekon",
        description="A simulated Tekon opcconnector (WEB OPC HTTP API 2.2).",
    )
    parser.add_argument("--host", default="127.0.0.1", help="address to bind")
    parser.add_argument(
        "--port", type=int, default=8090, help="0 picks a free port (8090)"
    )
    parser.add_argument(
        "--items",
        type=int,
        default=0,
        help="a large address space of this many items (0: the small building)",
    )
    parser.add_argument("--decimal-commas", action="store_true")
    parser.add_argument("--text-urls", choices=TEXT_URLS, default="both")
    parser.add_argument(
        "--api-version",
        choices=API_VERSIONS,
        default=API_VERSIONS[0],
        help="2.1: no Text reads and writes; 2.0: no Text calls at all (2.2)",
    )
    parser.add_argument(
        "--initial-data",
        action="store_true",
        help="send a newly subscribed item's value at once (OPC DA's initial update)",
    )
    parser.add_argument(
        "--animate",
        type=float,
        default=0.0,
        metavar="SECONDS",
        help="change the building's values every SECONDS (0: never)",
    )
    return parser.parse_args(argv)


async def animate(gateway: TekonGateway, every: float) -> None:
    """Live like a building: a lift, meters, a temperature, a door."""
    floors = itertools.cycle([1, 2, 3, 4, 5, 6, 7, 8, 9, 8, 7, 6, 5, 4, 3, 2])
    energy, water = 1520.5, 312.25
    for tick in itertools.count():
        await asyncio.sleep(every)
        floor = next(floors)
        stopped = floor in (1, 5, 9)
        gateway.set_value(
            f"{LIFT}.Состояние",
            lift_state(
                "Стоянка" if stopped else "Движение",
                floor,
                "нет" if stopped else ("вверх" if tick % 16 < 8 else "вниз"),
                "открыта" if stopped else "закрыта",
            ),
        )
        energy += 0.1
        water += 0.01
        gateway.set_value(f"{METERS}.Электросчётчик.Энергия", f"{energy:.1f}")
        gateway.set_value(f"{METERS}.Водосчётчик.Объём", f"{water:.2f}")
        gateway.set_value(f"{CONTROLLER}.Температура", f"{20.5 + (tick % 10) / 10:.1f}")
        gateway.set_value(
            f"{CONTROLLER}.Дверь подъезда", "1" if tick % 12 == 0 else "0"
        )


async def serve(arguments: argparse.Namespace) -> None:
    """Serve until interrupted."""
    building = large_building(arguments.items) if arguments.items else small_building()
    gateway = TekonGateway(
        building,
        decimal_commas=arguments.decimal_commas,
        text_urls=arguments.text_urls,
        initial_data=arguments.initial_data,
        api_version=arguments.api_version,
    )
    stop = stop_signal()
    await gateway.start(arguments.host, arguments.port)
    print(f"Tekon gateway at {gateway.url}", flush=True)
    living = (
        asyncio.create_task(animate(gateway, arguments.animate))
        if arguments.animate > 0
        else None
    )
    try:
        await stop.wait()
    finally:
        if living is not None:
            living.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await living
        await gateway.stop()


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point."""
    arguments = parse_arguments(argv)
    return run(lambda: serve(arguments))


if __name__ == "__main__":
    with contextlib.suppress(KeyboardInterrupt):
        sys.exit(main())
