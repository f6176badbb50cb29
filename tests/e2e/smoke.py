"""The smoke run on the newest Home Assistant release: `python -m tests.e2e.smoke`.

scripts/smoke runs it in an environment of its own (the newest release, none of the
tests' packages), and scripts/test --e2e (so CI) runs scripts/smoke. It starts the
demo's four simulators in this process, each on a free port of 127.0.0.1 (the demo
PLC with PLCComS beside it, the FP-I4C gateway's two stations, the Tekon building,
the Mervis house), and a real `hass` as a user runs it, on a fresh configuration
directory. Then, as a user would through the REST and WebSocket APIs:

1. onboarding and the demo's four entries (tests/e2e/provision.py), push switched on
   for the PLC in its options (PLCComS);
2. an entity of each system operated: a service call that writes, and the
   simulator has it;
3. the thermostat's entity ID renamed (2026.11 renames in place), and operated
   under its new ID;
4. each entry reloaded, and each entity operated again;
5. Home Assistant restarted, and each entity operated again;
6. a clean stop, then the log read: any warning or error the integration caused
   (tests/e2e/home_assistant.py: INTEGRATION_TROUBLE) fails the run.

It prints each step and, on failure, the lines that failed it; the configuration
directory and log are kept with `--keep DIR`.
"""

import argparse
import asyncio
from collections.abc import Awaitable, Callable, Sequence
from contextlib import AsyncExitStack
from dataclasses import dataclass
from pathlib import Path
import socket
import sys
import tempfile
import time
from typing import Any, Final, Self

import aiohttp
from homeassistant.const import __version__ as ha_version

from tests.e2e.configuration import DASHBOARD_URL_PATH, REPO_ROOT, write_configuration
from tests.e2e.home_assistant import HomeAssistantProcess, integration_trouble
from tests.e2e.provision import (
    DOMAIN,
    GATEWAY_TITLE,
    MERVIS_TITLE,
    TEKON_TITLE,
    GatewayAccess,
    HomeAssistantApi,
    MervisAccess,
    PlcAccess,
    ProvisioningError,
    provision,
    suggested_values,
)
from tests.simulator import Simulator
from tests.simulator.fpi4c.demo import demo_stations
from tests.simulator.fpi4c.server import FpI4cSimulator
from tests.simulator.mervis.server import MervisSimulator
from tests.simulator.plccoms import PlcComsServer
from tests.simulator.tekon.server import TekonGateway

USERNAME: Final = "admin"
PLC_PASSWORD: Final = "smoke-Pa55"  # a simulator on 127.0.0.1 only
MERVIS_PASSWORD: Final = "smoke-mervis"
FPI4C_MAP: Final = REPO_ROOT / "docs" / "fpi4c-example.csv"
MERVIS_VLIST: Final = REPO_ROOT / "tests" / "simulator" / "mervis" / "house.vlist"
WRITE_TIMEOUT: Final = 30.0
"""How long a write may take to reach a simulator (it polls; a poll is seconds)."""
POLL_INTERVAL: Final = 0.1

# The demo's entities operated, by the IDs the demo dashboard shows them under.
THERMOSTAT: Final = "climate.obyvak_thermostat"
THERMOSTAT_SETPOINT: Final = "Termostaty.OBYVAK_GTSAP1_THERMOSTAT_setpoint"
RENAMED_THERMOSTAT: Final = "climate.smoke_renamed_thermostat"
GARAGE_LIGHT: Final = "switch.door_controller_garage_light"
STAIRWELL_LIGHT: Final = "switch.kun_ip8_1_osveshchenie_podezda"
MERVIS_AWAY: Final = "switch.chata_lipno_away"


class SmokeError(Exception):
    """A step of the smoke run failed."""


def free_port() -> int:
    """A TCP port free on 127.0.0.1 now (Home Assistant binds it a moment later)."""
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        port: int = probe.getsockname()[1]
        return port


async def eventually(what: str, check: Callable[[], bool]) -> None:
    """Wait until `check()` holds: a write has reached a simulator.

    Home Assistant answers an action once it has run, so a write normally is there
    at once; one through PLCComS is sent on its own. The four simulators share no
    event to wait for, so their state is looked at again every POLL_INTERVAL.
    """
    try:
        async with asyncio.timeout(WRITE_TIMEOUT):
            while not check():  # noqa: ASYNC110 - see above
                await asyncio.sleep(POLL_INTERVAL)
    except TimeoutError:
        raise SmokeError(f"{what}: not within {WRITE_TIMEOUT:.0f} s") from None
    print(f"smoke:   {what}", flush=True)


def written(
    writes: Sequence[tuple[str, Any]], before: int, name: str
) -> Callable[[], bool]:
    """Whether a simulator's writes after the first `before` include one to `name`."""
    return lambda: any(str(key).endswith(name) for key, _ in writes[before:])


@dataclass(slots=True)
class Simulators:
    """The demo's four simulators, running in this process."""

    plc: Simulator
    plccoms: PlcComsServer
    fpi4c: FpI4cSimulator
    tekon: TekonGateway
    mervis: MervisSimulator

    @classmethod
    async def start(cls, stack: AsyncExitStack) -> Self:
        """Start them all (each stops when the stack closes)."""
        plc = Simulator("demo", username=USERNAME, password=PLC_PASSWORD)
        simulators = cls(
            plc=plc,
            plccoms=PlcComsServer(plc),
            fpi4c=FpI4cSimulator(demo_stations(), station=1),
            tekon=TekonGateway(),
            mervis=MervisSimulator(username=USERNAME, password=MERVIS_PASSWORD),
        )
        for server in (
            simulators.plc,
            simulators.plccoms,
            simulators.fpi4c,
            simulators.tekon,
            simulators.mervis,
        ):
            await server.start()
            stack.push_async_callback(server.stop)
        return simulators


class Smoke:
    """One Home Assistant, its API and the simulators it talks to."""

    def __init__(
        self,
        session: aiohttp.ClientSession,
        process: HomeAssistantProcess,
        simulators: Simulators,
    ) -> None:
        """Drive `process` (started) against `simulators`."""
        self.session = session
        self.process = process
        self.sims = simulators
        self.api = HomeAssistantApi(session, process.url)
        self.thermostat = THERMOSTAT
        self.setpoint = 21.0

    async def sign_in(self) -> None:
        """Sign in as the owner (trusted networks: this machine, no password)."""
        await self.api.sign_in(await self.api.trusted_network_code())

    async def entry_ids(self) -> dict[str, str]:
        """The integration's entries: title -> entry ID."""
        entries = await self.api.request(
            "GET", f"/api/config/config_entries/entry?domain={DOMAIN}"
        )
        return {entry["title"]: entry["entry_id"] for entry in entries}

    async def state(self, entity_id: str) -> dict[str, Any]:
        """An entity's state; it must be there and available."""
        state: dict[str, Any] = await self.api.request(
            "GET", f"/api/states/{entity_id}"
        )
        if state["state"] in ("unavailable", "unknown"):
            raise SmokeError(f"{entity_id} is {state['state']}")
        return state

    async def call(self, domain: str, service: str, data: dict[str, Any]) -> None:
        """Call an action, as the frontend does."""
        await self.api.request("POST", f"/api/services/{domain}/{service}", data)

    async def toggle(self, entity_id: str) -> bool:
        """Switch a switch over; return what it was switched to."""
        on: bool = (await self.state(entity_id))["state"] != "on"
        await self.call(
            "switch", "turn_on" if on else "turn_off", {"entity_id": entity_id}
        )
        return on

    async def operate(self) -> None:
        """Operate an entity of each system; each simulator must get the write."""
        sims = self.sims
        self.setpoint = 22.5 if self.setpoint != 22.5 else 21.0
        await self.state(self.thermostat)
        await self.call(
            "climate",
            "set_temperature",
            {"entity_id": self.thermostat, "temperature": self.setpoint},
        )
        await eventually(
            f"TecoApi: {self.thermostat} set to {self.setpoint} °C",
            lambda: sims.plc.get_value(THERMOSTAT_SETPOINT) == self.setpoint,
        )
        garage = sims.fpi4c.stations[2]
        on = await self.toggle(GARAGE_LIGHT)
        await eventually(
            f"FP-I4C: {GARAGE_LIGHT} {'on' if on else 'off'}",
            lambda: bool(garage.bit("Y", 0)) is on,
        )
        for system, entity_id, writes, name in (
            ("Tekon", STAIRWELL_LIGHT, sims.tekon.writes, ".Освещение"),
            ("Mervis", MERVIS_AWAY, sims.mervis.writes, "away"),
        ):
            before = len(writes)
            on = await self.toggle(entity_id)
            await eventually(
                f"{system}: {entity_id} {'on' if on else 'off'}",
                written(writes, before, name),
            )

    async def switch_push_on(self, entry_id: str) -> None:
        """Switch the PLC's push on in its options (PLCComS beside it)."""
        flow = await self.api.request(
            "POST", "/api/config/config_entries/options/flow", {"handler": entry_id}
        )
        # The options open on their menu; push is among the settings.
        if flow["type"] != "menu" or "settings" not in flow["menu_options"]:
            raise SmokeError(f"the options do not offer their settings: {flow}")
        flow = await self.api.request(
            "POST",
            f"/api/config/config_entries/options/flow/{flow['flow_id']}",
            {"next_step_id": "settings"},
        )
        shown = suggested_values(flow)
        push = {"host": "127.0.0.1", "port": self.sims.plccoms.port}
        result = await self.api.request(
            "POST",
            f"/api/config/config_entries/options/flow/{flow['flow_id']}",
            {**shown, "push": push},
        )
        if result["type"] != "create_entry":
            raise SmokeError(f"push was refused: {result.get('errors')}")
        # The entry swaps its source in place: the new one has read the PLC's points
        # once it has PLCComS push them (EN: each name, after its own EN:__PLC_RUN).
        await eventually(
            "PLCComS: Home Assistant has the points pushed",
            lambda: any(
                command.startswith("EN:") and "__PLC_RUN" not in command
                for command in self.sims.plccoms.commands
            ),
        )

    async def rename_thermostat(self) -> None:
        """Give the thermostat another entity ID, as a user does in its settings."""
        await self.api.websocket_command(
            {
                "type": "config/entity_registry/update",
                "entity_id": self.thermostat,
                "new_entity_id": RENAMED_THERMOSTAT,
            }
        )
        self.thermostat = RENAMED_THERMOSTAT
        print(f"smoke:   renamed {THERMOSTAT} to {RENAMED_THERMOSTAT}", flush=True)

    async def reload_each(self) -> None:
        """Reload each entry of the integration, one after another."""
        for title, entry_id in (await self.entry_ids()).items():
            answer = await self.api.request(
                "POST", f"/api/config/config_entries/entry/{entry_id}/reload"
            )
            if answer.get("require_restart"):
                raise SmokeError(f"reloading {title!r} asks for a restart")
            await self.api.wait_until_loaded(DOMAIN)
            print(f"smoke:   reloaded {title!r}", flush=True)


async def step(name: str, action: Awaitable[None]) -> None:
    """Run one step of the run, saying what it is and how long it took."""
    print(f"smoke: {name}", flush=True)
    started = time.monotonic()
    await action
    print(f"smoke: {name}: done in {time.monotonic() - started:.1f} s", flush=True)


async def run(config_dir: Path) -> list[str]:
    """The whole run on a fresh `config_dir`; return the log's lines of trouble."""
    port = free_port()
    write_configuration(
        config_dir,
        port=port,
        listen=("127.0.0.1",),
        trusted_local_login=True,
        demo=True,
    )
    log = config_dir / "smoke.log"
    process = HomeAssistantProcess(config_dir, port, log)
    async with AsyncExitStack() as stack:
        sims = await Simulators.start(stack)
        session = await stack.enter_async_context(aiohttp.ClientSession())
        stack.push_async_callback(process.stop)
        smoke = Smoke(session, process, sims)

        async def set_up() -> None:
            await process.start(session)
            await provision(
                session,
                process.url,
                PlcAccess(host=sims.plc.host, username=USERNAME, password=PLC_PASSWORD),
                None,
                DASHBOARD_URL_PATH,
                gateway=GatewayAccess(
                    host=f"127.0.0.1:{sims.fpi4c.port}", point_map=FPI4C_MAP
                ),
                tekon=sims.tekon.url,
                mervis=MervisAccess(
                    host=sims.mervis.host,
                    username=USERNAME,
                    password=MERVIS_PASSWORD,
                    vlist=MERVIS_VLIST,
                    content=MERVIS_VLIST.read_bytes(),
                ),
            )
            await smoke.sign_in()
            entries = await smoke.entry_ids()
            plc = next(
                entry_id
                for title, entry_id in entries.items()
                if title not in (GATEWAY_TITLE, TEKON_TITLE)
                and not title.startswith(MERVIS_TITLE)
            )
            await smoke.switch_push_on(plc)

        async def restart() -> None:
            status = await process.stop()
            if status != 0:
                raise SmokeError(f"Home Assistant stopped with status {status}")
            await process.start(session)
            await smoke.api.wait_until_loaded(DOMAIN)
            await smoke.api.wait_until_running()

        await step(f"start Home Assistant {ha_version} with the four entries", set_up())
        await step("operate an entity of each system", smoke.operate())
        await step("rename the thermostat's entity ID", smoke.rename_thermostat())
        await step("operate the renamed thermostat", smoke.operate())
        await step("reload each entry", smoke.reload_each())
        await step("operate after the reloads", smoke.operate())
        await step("restart Home Assistant", restart())
        await step("operate after the restart", smoke.operate())
        status = await process.stop()
        if status != 0:
            raise SmokeError(f"Home Assistant stopped with status {status}")
    return integration_trouble(log.read_text("utf-8"))


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of `python -m tests.e2e.smoke`."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--keep",
        type=Path,
        metavar="DIR",
        help="run in DIR (it must not exist) and keep it, with smoke.log",
    )
    arguments = parser.parse_args(argv)
    started = time.monotonic()
    with tempfile.TemporaryDirectory(prefix="tecoapi-smoke-") as scratch:
        config_dir = arguments.keep or Path(scratch) / "config"
        if arguments.keep is not None and arguments.keep.exists():
            parser.error(f"{arguments.keep} exists: the run needs a fresh directory")
        try:
            trouble = asyncio.run(run(config_dir))
        except (
            SmokeError,
            ProvisioningError,
            aiohttp.ClientError,
            TimeoutError,
        ) as err:
            print(f"smoke: FAILED: {err!r}", file=sys.stderr)
            log = config_dir / "smoke.log"
            if log.exists():
                print(log.read_text("utf-8")[-20_000:], file=sys.stderr)
            return 1
    elapsed = time.monotonic() - started
    if trouble:
        print(
            f"smoke: FAILED: Home Assistant {ha_version} logged trouble of the "
            "integration:",
            *trouble,
            sep="\n",
            file=sys.stderr,
        )
        return 1
    print(
        f"smoke: passed on Home Assistant {ha_version} in {elapsed:.0f} s; the "
        "integration logged no warning or error"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
