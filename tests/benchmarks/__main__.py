"""`python -m tests.benchmarks [options]` (what `scripts/bench` runs); `... soak` for
the soak run, `... freshness` for the freshness run (issue 13), `... fpi4c` for the
Panasonic FP-I4C's (issue 24), `... tekon` for the Tekon gateway's (issue 22),
`... mervis` for the Mervis figures (issue 23)."""

import argparse
import asyncio
import logging
from pathlib import Path
import sys
from typing import Final

# Our integration, not the `custom_components` package phcc ships (see tests/conftest.py).
import custom_components.tecoapi  # noqa: F401

from .programs import DEFAULT_PROGRAMS, parse_program_labels
from .report import markdown, write_json
from .results import BenchSettings
from .runner import run_benchmark

DEFAULT_OUTPUT: Final = Path("bench-results/bench.json")
QUICK_PROGRAMS: Final = ("50", "demo")


def _percents(text: str) -> tuple[float, ...]:
    return tuple(float(part) for part in text.split(",") if part.strip())


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="scripts/bench",
        description=(
            "TecoApi performance benchmark: requests, wall time, Home Assistant CPU, "
            "discovery, memory and write latency against the simulated PLC, ours vs "
            "the peer approach. `scripts/bench soak --help` for the soak run, "
            "`scripts/bench freshness --help` for the freshness run."
        ),
    )
    parser.add_argument(
        "--quick",
        action="store_true",
        help=f"a short run: programs {','.join(QUICK_PROGRAMS)} (unless --sizes), "
        "3 polls per figure (unless --polls), 2 write samples",
    )
    parser.add_argument(
        "--sizes",
        type=parse_program_labels,
        help="comma-separated point counts and shipped programs "
        f"(default {','.join(DEFAULT_PROGRAMS)})",
    )
    parser.add_argument(
        "--latency-ms",
        type=float,
        default=20.0,
        help="PLC latency per request in ms (default 20)",
    )
    parser.add_argument(
        "--per-item-ms",
        type=float,
        default=0.05,
        help="PLC latency per returned item in ms (default 0.05)",
    )
    parser.add_argument(
        "--polls", type=int, help="polls per measured figure (default 10)"
    )
    parser.add_argument(
        "--peer-polls",
        type=int,
        default=1,
        help="polls of the peer baseline (default 1: it is slow and deterministic)",
    )
    parser.add_argument(
        "--percents",
        type=_percents,
        default=(0.0, 1.0, 100.0),
        help="shares of values changing between polls (default 0,1,100)",
    )
    parser.add_argument(
        "--seed", type=int, default=0, help="seed of the generated programs"
    )
    parser.add_argument(
        "--output",
        type=Path,
        default=DEFAULT_OUTPUT,
        help=f"JSON results file (default {DEFAULT_OUTPUT})",
    )
    parser.add_argument(
        "--verbose", action="store_true", help="log progress to standard error"
    )
    return parser


def main(argv: list[str]) -> int:
    """Run the benchmark (or the soak run) and print its report."""
    if argv[:1] == ["soak"]:
        from .soak import main as soak_main

        return soak_main(argv[1:])
    if argv[:1] == ["freshness"]:
        from .freshness import main as freshness_main

        return freshness_main(argv[1:])
    if argv[:1] == ["fpi4c"]:
        from .fpi4c import main as fpi4c_main

        return fpi4c_main(argv[1:])
    if argv[:1] == ["tekon"]:
        from .tekon import main as tekon_main

        return tekon_main(argv[1:])
    if argv[:1] == ["mervis"]:
        from .mervis import main as mervis_main

        return mervis_main(argv[1:])
    args = _parser().parse_args(argv)
    logging.basicConfig(level=logging.WARNING, format="%(asctime)s %(message)s")
    # "We found a custom integration tecoapi which has not been tested ...", per setup.
    logging.getLogger("homeassistant.loader").setLevel(logging.ERROR)
    if args.verbose:
        logging.getLogger(__package__).setLevel(logging.INFO)
    polls = args.polls or (3 if args.quick else 10)
    if polls < 1 or args.peer_polls < 1:
        raise SystemExit("--polls and --peer-polls must be at least 1")
    settings = BenchSettings(
        programs=args.sizes or (QUICK_PROGRAMS if args.quick else DEFAULT_PROGRAMS),
        latency_ms=args.latency_ms,
        per_item_ms=args.per_item_ms,
        polls=polls,
        peer_polls=args.peer_polls,
        percents=args.percents,
        write_samples=2 if args.quick else 5,
        seed=args.seed,
    )
    results = asyncio.run(run_benchmark(settings))
    print(markdown(results))
    write_json(results, args.output)
    print(f"Figures written to {args.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
