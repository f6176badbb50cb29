"""Run the simulator: `python -m tests.simulator --program demo --port 8080 ...`.

It prints the URL it serves, logs every request at INFO (never credentials), and
reads console commands from standard input (type `help`) until interrupted.
"""

import argparse
import asyncio
from collections.abc import Sequence
import contextlib
import sys
import threading

from .auth import AUTH_MODES
from .base import run, stop_signal, tls_context
from .console import CommandError, program_from_argument, run_command
from .faults import PLC_MODES, TEXT_ENCODINGS, TRANSPORT_FAULTS
from .plccoms import PlcComsOptions, PlcComsServer
from .program import ProgramError
from .server import Simulator


def parse_arguments(argv: Sequence[str] | None = None) -> argparse.Namespace:
    """The command line."""
    parser = argparse.ArgumentParser(
        prog="python -m tests.simulator",
        description="A simulated Tecomat PLC speaking TecoApi.",
    )
    parser.add_argument(
        "--program",
        default="demo",
        help="demo, manual, generated:POINTS[:SEED] or a .yaml/.json file (demo)",
    )
    parser.add_argument(
        "--host", default="127.0.0.1", help="address to bind (127.0.0.1)"
    )
    parser.add_argument(
        "--port", type=int, default=8080, help="0 picks a free port (8080)"
    )
    parser.add_argument("--user", default="admin", help="TecoApi user name (admin)")
    parser.add_argument(
        "--password", default="secret", help="TecoApi password (secret)"
    )
    parser.add_argument("--auth", choices=AUTH_MODES, default="digest")
    parser.add_argument("--nonce-max-uses", type=int, default=None)
    parser.add_argument("--nonce-ttl", type=float, default=None, help="seconds")
    parser.add_argument("--latency-ms", type=float, default=0.0)
    parser.add_argument("--latency-per-item-ms", type=float, default=0.0)
    parser.add_argument("--mode", choices=PLC_MODES, default="RUN")
    parser.add_argument(
        "--fault",
        action="append",
        default=[],
        choices=TRANSPORT_FAULTS,
        help="switch a transport fault on (repeatable)",
    )
    parser.add_argument(
        "--fault-count",
        type=int,
        default=None,
        help="the faults hit only this many requests",
    )
    parser.add_argument(
        "--hide",
        action="append",
        default=[],
        metavar="NAME",
        help="a root GetList leaves out (repeatable)",
    )
    parser.add_argument(
        "--reject",
        action="append",
        default=[],
        metavar="NAME",
        help="a root GetObject answers 400.005 for (repeatable)",
    )
    parser.add_argument(
        "--text-encoding",
        choices=TEXT_ENCODINGS,
        default="utf-8",
        help="how answers encode text; windows-1250 as Czech programs (utf-8)",
    )
    parser.add_argument(
        "--short-reals",
        action="store_true",
        help="print REALs as 29.0, as real devices do, not 29.000000",
    )
    parser.add_argument(
        "--exact-service-names",
        action="store_true",
        help="answer only the manual's spelling (/TecoApi/GetList), not any case",
    )
    parser.add_argument(
        "--link-rate",
        type=float,
        default=None,
        metavar="PER_S",
        help="links move a number this much a second, as a blind moves "
        "(default: at once)",
    )
    parser.add_argument("--tls-cert", default=None, help="PEM certificate: serve HTTPS")
    parser.add_argument("--tls-key", default=None, help="PEM private key of --tls-cert")
    parser.add_argument(
        "--no-console",
        action="store_true",
        help="do not read commands from standard input",
    )
    coms = parser.add_argument_group(
        "PLCComS", "a PLCComS server on the same simulated PLC (no authentication)"
    )
    coms.add_argument(
        "--plccoms-port",
        type=int,
        default=None,
        metavar="N",
        help="serve PLCComS on this port too (0 picks a free one; off by default)",
    )
    coms.add_argument(
        "--plccoms-lf", action="store_true", help="end lines with LF, not CRLF"
    )
    coms.add_argument(
        "--plccoms-decimal-comma",
        action="store_true",
        help="print reals with a decimal comma",
    )
    coms.add_argument(
        "--plccoms-scientific",
        action="store_true",
        help="print reals in scientific notation",
    )
    coms.add_argument(
        "--plccoms-decimals",
        type=int,
        default=None,
        metavar="N",
        help="print reals with N decimals (default: the shortest exact form)",
    )
    coms.add_argument(
        "--plccoms-scan-ms",
        type=float,
        default=100.0,
        metavar="MS",
        help="change detection period in milliseconds (100)",
    )
    arguments = parser.parse_args(argv)
    if arguments.plccoms_decimals is not None and arguments.plccoms_decimals < 0:
        parser.error("--plccoms-decimals must be >= 0")
    if arguments.plccoms_scan_ms <= 0:
        parser.error("--plccoms-scan-ms must be > 0")
    if (arguments.tls_cert is None) != (arguments.tls_key is None):
        parser.error("--tls-cert and --tls-key go together")
    return arguments


def build_simulator(arguments: argparse.Namespace) -> Simulator:
    """A simulator configured from the command line (not started)."""
    sim = Simulator(
        program_from_argument(arguments.program),
        username=arguments.user,
        password=arguments.password,
        auth=arguments.auth,
        nonce_max_uses=arguments.nonce_max_uses,
        nonce_ttl=arguments.nonce_ttl,
    )
    faults = sim.faults
    faults.latency = arguments.latency_ms / 1000
    faults.latency_per_item = arguments.latency_per_item_ms / 1000
    faults.mode = arguments.mode
    for fault in arguments.fault:
        setattr(faults, fault, True)
    faults.remaining = arguments.fault_count
    faults.hidden_from_list.update(arguments.hide)
    faults.rejected_by_object.update(arguments.reject)
    faults.text_encoding = arguments.text_encoding
    faults.short_reals = arguments.short_reals
    faults.exact_service_names = arguments.exact_service_names
    sim.link_motion.rate = arguments.link_rate
    return sim


def build_plccoms(sim: Simulator, arguments: argparse.Namespace) -> PlcComsServer:
    """A PLCComS server for the simulator, configured from the command line."""
    return PlcComsServer(
        sim,
        options=PlcComsOptions(
            crlf=not arguments.plccoms_lf,
            decimal_comma=arguments.plccoms_decimal_comma,
            scientific=arguments.plccoms_scientific,
            decimals=arguments.plccoms_decimals,
        ),
        scan_interval=arguments.plccoms_scan_ms / 1000,
    )


def _read_console(
    loop: asyncio.AbstractEventLoop, lines: asyncio.Queue[str | None]
) -> None:
    """Feed standard input's lines to the loop (a daemon thread: never joined)."""
    for line in sys.stdin:
        loop.call_soon_threadsafe(lines.put_nowait, line)
    loop.call_soon_threadsafe(lines.put_nowait, None)


async def serve(arguments: argparse.Namespace) -> None:
    """Run until SIGINT/SIGTERM (or `quit`)."""
    sim = build_simulator(arguments)
    loop = asyncio.get_running_loop()
    # Before the URL is printed: whoever reads it may signal right away.
    stop = stop_signal()
    await sim.start(
        arguments.host,
        arguments.port,
        tls_context(arguments.tls_cert, arguments.tls_key),
    )
    print(
        f"Serving {sim.url}/TecoApi/ program {sim.program.name!r} "
        f"stamp {sim.stamp} ({arguments.auth} auth)",
        flush=True,
    )
    lines: asyncio.Queue[str | None] = asyncio.Queue()
    coms: PlcComsServer | None = None
    stopping = asyncio.ensure_future(stop.wait())
    try:
        if arguments.plccoms_port is not None:
            coms = build_plccoms(sim, arguments)
            await coms.start(arguments.host, arguments.plccoms_port)
            print(
                f"Serving PLCComS on {coms.host}:{coms.port} (no authentication)",
                flush=True,
            )
        if not arguments.no_console:
            threading.Thread(
                target=_read_console, args=(loop, lines), daemon=True
            ).start()
        while not stop.is_set():
            next_line = asyncio.ensure_future(lines.get())
            await asyncio.wait(
                {stopping, next_line}, return_when=asyncio.FIRST_COMPLETED
            )
            if not next_line.done():
                next_line.cancel()
                break
            line = next_line.result()
            if line is None:
                continue  # standard input closed: keep serving until a signal
            if line.strip().lower() in {"quit", "exit"}:
                break
            try:
                reply = run_command(sim, line)
            except CommandError as err:
                reply = f"error: {err}"
            if reply:
                print(reply, flush=True)
    finally:
        stopping.cancel()
        if coms is not None:
            await coms.stop()
        await sim.stop()


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of `python -m tests.simulator`."""
    arguments = parse_arguments(argv)
    return run(lambda: serve(arguments), errors=(ProgramError, OSError))


if __name__ == "__main__":
    with contextlib.suppress(KeyboardInterrupt):
        sys.exit(main())
