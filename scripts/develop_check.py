#!/usr/bin/env python3
"""Check scripts/develop the way a user runs it, on the host (it enters the environment itself).

    python3 scripts/develop_check.py

Three runs on a temporary configuration directory and free ports:
1. a first start onboards Home Assistant and adds the PLC, then Ctrl-C (SIGINT to the
   script's process group, as a terminal sends it) stops everything, exit status 0;
2. a second start reuses the directory (the time to the banner is printed), then a
   TERM to the script alone stops everything, exit status 0;
3. the simulated PLC dies: the script stops Home Assistant too, exit status 1.
Each run's Home Assistant has a temporary directory of its own (TMPDIR: config/tmp).
"Everything stopped" means: Home Assistant exited cleanly (status 0), nothing listens on
any of its ports (the simulator's TecoApi and PLCComS, the Mervis simulator's, the simulated Tekon
and FP-I4C gateways',
Home Assistant's), no server process is left.
"""

from collections.abc import Callable
import os
from pathlib import Path
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time

REPO_ROOT = Path(__file__).resolve().parents[1]
BANNER = "Ctrl-C stops them all"
START_TIMEOUT = 600.0  # the first start may install the frontend
STOP_TIMEOUT = 60.0


def free_port() -> int:
    """A TCP port nothing listens on now, on 127.0.0.1."""
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        port: int = probe.getsockname()[1]
        return port


def listening(port: int) -> bool:
    """Whether something accepts connections on 127.0.0.1:`port`."""
    with socket.socket() as probe:
        return probe.connect_ex(("127.0.0.1", port)) == 0


class Develop:
    """One run of scripts/develop in its own process group, its output in a file."""

    def __init__(
        self,
        config: Path,
        ports: tuple[int, int, int, int, int, int],
        name: str,
    ) -> None:
        self.config = config
        self.ports = ports
        (
            self.sim_port,
            self.ha_port,
            self.coms_port,
            self.tekon_port,
            self.fpi4c_port,
            self.mervis_port,
        ) = ports
        self.log = config.parent / f"{name}.log"
        env = {
            **os.environ,
            "TECOAPI_DEVELOP_CONFIG": str(config),
            "TECOAPI_SIM_PORT": str(self.sim_port),
            "TECOAPI_HA_PORT": str(self.ha_port),
            "TECOAPI_PLCCOMS_PORT": str(self.coms_port),
            "TECOAPI_TEKON_PORT": str(self.tekon_port),
            "TECOAPI_FPI4C_PORT": str(self.fpi4c_port),
            "TECOAPI_MERVIS_PORT": str(self.mervis_port),
        }
        with self.log.open("wb") as output:
            self.process = subprocess.Popen(
                [str(REPO_ROOT / "scripts" / "develop")],
                cwd=REPO_ROOT,
                env=env,
                stdin=subprocess.DEVNULL,
                stdout=output,
                stderr=subprocess.STDOUT,
                start_new_session=True,  # a terminal's foreground job: its own group
                preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),  # noqa: PLW1509
            )

    def output(self) -> str:
        """Everything the run printed so far."""
        return self.log.read_text(encoding="utf-8", errors="replace")

    def wait_for_banner(self) -> float:
        """Wait until the URL banner is printed; return the seconds it took."""
        started = time.monotonic()
        while BANNER not in self.output():
            if self.process.poll() is not None:
                sys.exit(f"scripts/develop exited early:\n{self.output()[-3000:]}")
            if time.monotonic() - started > START_TIMEOUT:
                sys.exit("scripts/develop printed no URL in time")
            time.sleep(0.2)  # a file written by another process: nothing to wait on
        return time.monotonic() - started

    def servers(self) -> list[str]:
        """Process IDs of this run's simulators and Home Assistant still running."""
        patterns = (
            f"tests.simulator --program demo --host 127.0.0.1 --port {self.sim_port} ",
            f"tests.simulator.tekon --host 127.0.0.1 --port {self.tekon_port} ",
            f"tests.simulator.fpi4c --host 127.0.0.1 --port {self.fpi4c_port}",
            f"tests.simulator.mervis --host 127.0.0.1 --port {self.mervis_port} ",
            f"hass --config {self.config} ",
        )
        found = []
        for pattern in patterns:
            result = subprocess.run(
                ["pgrep", "-f", pattern], capture_output=True, text=True, check=False
            )
            found += result.stdout.split()
        return found

    def check_temp_dir(self) -> None:
        """Home Assistant's TMPDIR is its own (config/tmp), not the machine's /tmp."""
        (hass,) = subprocess.run(
            ["pgrep", "-f", f"hass --config {self.config} "],
            capture_output=True,
            text=True,
            check=False,
        ).stdout.split()
        environment = Path(f"/proc/{hass}/environ").read_bytes().split(b"\0")
        wanted = f"TMPDIR={self.config / 'tmp'}".encode()
        if wanted not in environment:
            sys.exit(f"Home Assistant runs without {wanted.decode()}")

    def stopped(self, expected_status: int) -> float:
        """Wait for the script to exit; check its status and that nothing is left.

        Home Assistant must have stopped cleanly (exit status 0, which the script
        reports otherwise).
        """
        started = time.monotonic()
        status = self.process.wait(timeout=STOP_TIMEOUT)
        took = time.monotonic() - started
        problems = []
        if status != expected_status:
            problems.append(f"exit status {status}, not {expected_status}")
        if "did not stop cleanly" in self.output():
            problems.append("Home Assistant did not stop cleanly")
        if left := self.servers():
            problems.append(f"servers still running: {left}")
        problems.extend(
            f"something still listens on port {port}"
            for port in self.ports
            if listening(port)
        )
        if problems:
            sys.exit("; ".join(problems) + f"\n{self.output()[-3000:]}")
        return took


def run_check(
    config: Path,
    ports: tuple[int, int, int, int, int, int],
    name: str,
    stop: Callable[[Develop], None],
) -> tuple[float, float]:
    """Start scripts/develop, stop it with `stop`; return (seconds to URL, to exit)."""
    develop = Develop(config, ports, name)
    ready = develop.wait_for_banner()
    develop.check_temp_dir()
    stop(develop)
    expected = 1 if name == "crash" else 0
    return ready, develop.stopped(expected)


def ctrl_c(develop: Develop) -> None:
    """What a terminal does on Ctrl-C: SIGINT to the foreground process group."""
    os.killpg(develop.process.pid, signal.SIGINT)


def term_script(develop: Develop) -> None:
    """What `kill PID` does: TERM to the script alone."""
    develop.process.terminate()


def kill_simulator(develop: Develop) -> None:
    """The simulated PLC goes away on its own."""
    sim = develop.servers()[0]
    os.kill(int(sim), signal.SIGTERM)


def main() -> None:
    """Run the three checks and report."""
    workdir = Path(tempfile.mkdtemp(prefix="tecoapi-develop-", dir="/tmp"))
    config = workdir / "config"
    ports = (
        free_port(),
        free_port(),
        free_port(),
        free_port(),
        free_port(),
        free_port(),
    )
    try:
        for name, stop, what in (
            ("first", ctrl_c, "first start, then Ctrl-C"),
            ("second", term_script, "second start, then TERM to the script"),
            ("crash", kill_simulator, "third start, then the simulator dies"),
        ):
            ready, took = run_check(config, ports, name, stop)
            print(
                f"ok  {what}: URL after {ready:.1f} s, all stopped {took:.1f} s later"
            )
    finally:
        shutil.rmtree(workdir, ignore_errors=True)


if __name__ == "__main__":
    main()
