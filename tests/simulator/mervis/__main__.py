"""Run the simulated Mervis controller: ``python -m tests.simulator.mervis --port 8081``.

It prints the URL it serves and serves until interrupted (SIGINT, SIGTERM).
``--export-vlist PATH`` writes the project's ``.vlist`` (what the IDE would
export) before serving.
"""

import argparse
from collections.abc import Sequence
import contextlib
from datetime import UTC, datetime
from pathlib import Path
import sys

from tests.simulator.base import run, stop_signal, tls_context

from .project import Project, generated, house
from .server import ORDERS, SPELLINGS, WRITE_ENCODINGS, MervisSimulator, Switches


def parse_arguments(argv: Sequence[str] | None = None) -> argparse.Namespace:
    """The command line."""
    parser = argparse.ArgumentParser(
        prog="python -m tests.simulator.mervis",
        description="A simulated Mervis (Unipi) controller's web panel API.",
    )
    parser.add_argument(
        "--project", default="house", help="house or generated:N[:SEED]"
    )
    parser.add_argument("--host", default="127.0.0.1", help="address to bind")
    parser.add_argument("--port", type=int, default=8081, help="0 picks a free one")
    parser.add_argument("--user", default="admin", help="web panel user (admin)")
    parser.add_argument("--password", default="secret", help="its password (secret)")
    parser.add_argument(
        "--no-credentials", action="store_true", help="a project without credentials"
    )
    parser.add_argument("--spelling", choices=SPELLINGS, default="both")
    parser.add_argument("--quality", default="G", help="a good value's quality (G)")
    parser.add_argument("--order", choices=ORDERS, default="asked")
    parser.add_argument("--max-variables", type=int, default=None, metavar="N")
    parser.add_argument("--max-request-size", type=int, default=None, metavar="BYTES")
    parser.add_argument("--tell-limits", action="store_true")
    parser.add_argument("--write-encoding", choices=WRITE_ENCODINGS, default="plain")
    parser.add_argument("--session-requests", type=int, default=None, metavar="N")
    parser.add_argument("--export-vlist", default=None, metavar="PATH")
    parser.add_argument("--tls-cert", default=None, help="PEM certificate: serve HTTPS")
    parser.add_argument("--tls-key", default=None, help="PEM private key of --tls-cert")
    arguments = parser.parse_args(argv)
    if (arguments.tls_cert is None) != (arguments.tls_key is None):
        parser.error("--tls-cert and --tls-key go together")
    try:
        arguments.project = project_from_argument(arguments.project)
    except ValueError as err:
        parser.error(str(err))
    return arguments


def project_from_argument(text: str) -> Project:
    """``house`` (its clock live) or ``generated:N[:SEED]``."""
    if text == "house":
        return house(clock=lambda: datetime.now(UTC))
    name, _, rest = text.partition(":")
    if name == "generated":
        count, _, seed = rest.partition(":")
        if count.isdigit() and int(count) > 0 and (not seed or seed.isdigit()):
            return generated(int(count), seed=int(seed or 0))
    raise ValueError(f"unknown project {text!r} (house, generated:N[:SEED])")


def build_simulator(arguments: argparse.Namespace) -> MervisSimulator:
    """A simulator configured from the command line (not started)."""
    return MervisSimulator(
        arguments.project,
        username=None if arguments.no_credentials else arguments.user,
        password=arguments.password,
        switches=Switches(
            spelling=arguments.spelling,
            quality=arguments.quality,
            order=arguments.order,
            max_variables=arguments.max_variables,
            max_request_size=arguments.max_request_size,
            tell_limits=arguments.tell_limits,
            write_encoding=arguments.write_encoding,
            session_requests=arguments.session_requests,
        ),
    )


async def serve(arguments: argparse.Namespace) -> None:
    """Serve until SIGINT or SIGTERM."""
    sim = build_simulator(arguments)
    stop = stop_signal()
    await sim.start(
        arguments.host,
        arguments.port,
        tls_context(arguments.tls_cert, arguments.tls_key),
    )
    print(
        f"Serving {sim.url}/ (Mervis web panel) project {sim.project.name!r}, "
        f"{len(sim.project.rows)} rows",
        flush=True,
    )
    try:
        await stop.wait()
    finally:
        await sim.stop()


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of ``python -m tests.simulator.mervis``."""
    arguments = parse_arguments(argv)
    if arguments.export_vlist:
        vlist = arguments.project.vlist()
        Path(arguments.export_vlist).write_text(vlist, encoding="utf-8")
    return run(lambda: serve(arguments))


if __name__ == "__main__":
    with contextlib.suppress(KeyboardInterrupt):
        sys.exit(main())
