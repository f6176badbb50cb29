"""Make a fresh Home Assistant ready to use through its REST and WebSocket APIs, as the UI would.

Onboarding: the owner account (its password random and never stored: the configuration
that goes with this signs in from this machine through trusted networks), then the
remaining onboarding steps; the HTTP settings from configuration.yaml confirmed; the
demo dashboard as the one to open on. Then the TecoApi config flow with the PLC's
address and credentials, once; when given, the FP-I4C config flow with the
gateway's address and its register map uploaded, once; and, given one, the Tekon
gateway's flow with its URL; and, when one is given, the Mervis config flow with the
controller's address, credentials and its project's .vlist (uploaded as the frontend
uploads it), once, complete: what a user would set in its options (the variables the
demo dashboard writes writable, thermostats' setpoints and relays; units) is in the
map's own columns after the IDE's (demo_vlist), so no point changes later. Every step is skipped when already done, so a second start costs a few
requests. It ends when the entities exist and Home Assistant has finished starting
(its recorder too).

    TECOAPI_PLC_PASSWORD=... TECOAPI_MERVIS_PASSWORD=... python -m tests.e2e.provision \
        --port 8123 --plc-host 127.0.0.1:8080 --plc-username admin \
        [--fpi4c-host 127.0.0.1:2000 --fpi4c-map docs/fpi4c-example.csv] \
        [--gateway-url http://127.0.0.1:8090] \
        [--mervis-host 127.0.0.1:8081 --mervis-username admin \
         --mervis-vlist tests/simulator/mervis/house.vlist]
"""

import argparse
import asyncio
from collections.abc import AsyncIterator, Sequence
from contextlib import asynccontextmanager
from dataclasses import dataclass
import os
from pathlib import Path
import secrets
import sys
from typing import Any, Final

import aiohttp
from yarl import URL

from .configuration import DASHBOARD_URL_PATH, http_settings
from .home_assistant import POLL_INTERVAL, STARTUP_TIMEOUT, wait_until_serving

DOMAIN: Final = "tecoapi"
MERVIS_PASSWORD_VARIABLE: Final = "TECOAPI_MERVIS_PASSWORD"
MERVIS_TITLE: Final = "Mervis · "
"""How a Mervis entry's title starts (its model, then its project)."""
_CELSIUS: Final = {"unit": "°C"}
_SETPOINT: Final = {"unit": "°C", "writable": True, "min": 15.0, "max": 28.0}
MERVIS_DEMO_POINTS: Final[dict[str, dict[str, Any]]] = {
    # A block of a temperature and a writable setpoint is a thermostat.
    **{f"{room}.setpoint": _SETPOINT for room in ("koupelna", "jidelna", "sklep")},
    **{f"{room}.temperature": _CELSIUS for room in ("koupelna", "jidelna", "sklep")},
    "kotel.water_temp": _CELSIUS,
    "kotel.return_temp": _CELSIUS,
    "outside_temp": _CELSIUS,
    "energie.power": {"unit": "W"},
    "energie.total": {"unit": "kWh"},
    # Relays are switches once writable.
    **{f"hw.neuron_l203_ro_2.0{index}": {"writable": True} for index in range(1, 5)},
    "away": {"writable": True},
}
"""What the Mervis demo's map says of its points beyond the IDE's .vlist (see demo_vlist)."""
DEMO_COLUMNS: Final = {
    "unit": "Unit",
    "writable": "Writable",
    "min": "Min",
    "max": "Max",
}
"""The map's own columns demo_vlist adds after the IDE's, by MERVIS_DEMO_POINTS's keys."""


def demo_vlist(content: bytes) -> bytes:
    """Return a .vlist with MERVIS_DEMO_POINTS in the map's own columns after the IDE's.

    The controller is added with its map complete, once: its entities are created
    with their units (a sensor that gained a unit later would leave recorded states
    of another unit, which long-term statistics cannot convert), and no point is
    changed afterwards.
    """
    lines = content.decode("utf-8").splitlines()
    header = lines[1].split(";")
    width = len(header)
    out = [lines[0], ";".join([*header, *DEMO_COLUMNS.values()])]
    for line in lines[2:]:
        cells = line.split(";")
        ident = cells[1].replace("$", "") if len(cells) > 1 else ""
        changes = MERVIS_DEMO_POINTS.get(ident.lower(), {})
        own = [_cell(changes.get(key)) for key in DEMO_COLUMNS]
        out.append(";".join([*cells, *[""] * (width - len(cells)), *own]))
    return ("\n".join(out) + "\n").encode("utf-8")


def _cell(value: object) -> str:
    """A map's cell for a value of MERVIS_DEMO_POINTS (none: empty)."""
    if isinstance(value, bool):
        return "yes" if value else "no"
    return "" if value is None else str(value)


SETUP_TIMEOUT: Final = 60.0
# Final: Home Assistant retries a `setup_retry` by itself, so that one is waited out.
SETUP_FAILURES: Final = frozenset({"setup_error", "migration_error", "failed_unload"})


TEKON_TITLE: Final = "ASUD.SCADA OPC-HTTP"
"""The title the config flow gives a Tekon gateway's entry."""
OWNER_NAME: Final = "Demo owner"
OWNER_USERNAME: Final = "owner"
ONBOARDING_STEPS: Final = ("core_config", "analytics", "integration")
PASSWORD_VARIABLE: Final = "TECOAPI_PLC_PASSWORD"
SETUP_TIMEOUT: Final = 60.0
# Final: Home Assistant retries a `setup_retry` by itself, so that one is waited out.
SETUP_FAILURES: Final = frozenset({"setup_error", "migration_error", "failed_unload"})


class ProvisioningError(Exception):
    """Home Assistant refused a provisioning step."""

    def __init__(self, message: str, code: str | None = None) -> None:
        """Describe the refusal; `code` is the WebSocket API's error code, if any."""
        super().__init__(message)
        self.code = code


@dataclass(frozen=True, slots=True, kw_only=True)
class PlcAccess:
    """Where the PLC is and the TecoApi user to sign in with."""

    host: str
    username: str
    password: str


@dataclass(frozen=True, slots=True, kw_only=True)
class GatewayAccess:
    """Where the FP-I4C gateway is (its REST API's host:port) and its register map."""

    host: str
    point_map: Path


GATEWAY_TITLE: Final = "FP-I4C · "
"""How an FP-I4C entry's title starts (its model, then the address it reaches)."""


@dataclass(frozen=True, slots=True, kw_only=True)
class MervisAccess:
    """Where the Mervis controller is, its web panel user, and its project's .vlist."""

    host: str
    username: str
    password: str
    vlist: Path
    content: bytes
    """The file's bytes (read before the event loop runs)."""


def suggested_values(form: dict[str, Any]) -> dict[str, Any]:
    """What a flow's form shows in its fields (their suggested values), by name."""
    return {
        field["name"]: field["description"]["suggested_value"]
        for field in form["data_schema"]
        if "suggested_value" in (field.get("description") or {})
    }


class HomeAssistantApi:
    """The few REST and WebSocket calls provisioning needs, signed in once a token is known."""

    def __init__(self, session: aiohttp.ClientSession, url: str) -> None:
        """Talk to Home Assistant at `url` (no trailing slash)."""
        self._session = session
        self.url = url
        self.client_id = f"{url}/"
        self._token: str | None = None

    async def request(
        self, method: str, path: str, payload: dict[str, Any] | None = None
    ) -> Any:
        """Send a JSON request (with the token once there is one); return the answer."""
        headers = {"Authorization": f"Bearer {self._token}"} if self._token else {}
        async with self._session.request(
            method, f"{self.url}{path}", json=payload, headers=headers
        ) as response:
            if response.status >= 400:
                raise ProvisioningError(
                    f"{method} {path}: HTTP {response.status} {await response.text()}"
                )
            return await response.json()

    async def sign_in(self, auth_code: str) -> None:
        """Exchange an authorization code for an access token."""
        async with self._session.post(
            f"{self.url}/auth/token",
            data={
                "grant_type": "authorization_code",
                "code": auth_code,
                "client_id": self.client_id,
            },
        ) as response:
            if response.status != 200:
                raise ProvisioningError(f"/auth/token: HTTP {response.status}")
            self._token = (await response.json())["access_token"]

    async def create_owner(self) -> str:
        """Onboarding's first step: create the owner; return an authorization code."""
        answer = await self.request(
            "POST",
            "/api/onboarding/users",
            {
                "client_id": self.client_id,
                "name": OWNER_NAME,
                "username": OWNER_USERNAME,
                "password": secrets.token_urlsafe(32),
                "language": "en",
            },
        )
        code: str = answer["auth_code"]
        return code

    async def password_code(self, username: str, password: str) -> str:
        """Sign in with a user's password (its login flow); return an authorization code."""
        flow = await self.request(
            "POST",
            "/auth/login_flow",
            {
                "client_id": self.client_id,
                "handler": ["homeassistant", None],
                "redirect_uri": self.client_id,
            },
        )
        done = await self.request(
            "POST",
            f"/auth/login_flow/{flow['flow_id']}",
            {"client_id": self.client_id, "username": username, "password": password},
        )
        if done["type"] != "create_entry":
            raise ProvisioningError(f"{username!r} could not sign in: {done['type']}")
        code: str = done["result"]
        return code

    async def trusted_network_code(self) -> str:
        """Sign in through the trusted-networks provider; return an authorization code."""
        flow = await self.request(
            "POST",
            "/auth/login_flow",
            {
                "client_id": self.client_id,
                "handler": ["trusted_networks", None],
                "redirect_uri": self.client_id,
            },
        )
        if flow["type"] == "form":
            # More than one user: any of them may provision; take the first offered.
            users = flow["data_schema"][0]["options"]
            flow = await self.request(
                "POST",
                f"/auth/login_flow/{flow['flow_id']}",
                {"client_id": self.client_id, "user": users[0][0]},
            )
        if flow["type"] != "create_entry":
            raise ProvisioningError(
                f"trusted-network sign-in refused: {flow.get('reason', flow['type'])}"
            )
        code: str = flow["result"]
        return code

    async def finish_onboarding_step(self, step: str) -> None:
        """Complete one of the onboarding steps after the owner's."""
        payload = (
            {"client_id": self.client_id, "redirect_uri": self.client_id}
            if step == "integration"
            else {}
        )
        await self.request("POST", f"/api/onboarding/{step}", payload)

    @asynccontextmanager
    async def websocket(self) -> AsyncIterator[aiohttp.ClientWebSocketResponse]:
        """A WebSocket API connection, signed in with the token."""
        async with self._session.ws_connect(f"{self.url}/api/websocket") as socket:
            await socket.receive_json()  # auth_required
            await socket.send_json({"type": "auth", "access_token": self._token})
            if (await socket.receive_json())["type"] != "auth_ok":
                raise ProvisioningError("the WebSocket API refused the access token")
            yield socket

    async def websocket_command(self, command: dict[str, Any]) -> Any:
        """Send one command over the WebSocket API; return its result."""
        async with self.websocket() as socket:
            await socket.send_json({"id": 1, **command})
            answer = await socket.receive_json()
        if not answer["success"]:
            error = answer["error"]
            raise ProvisioningError(
                f"{command['type']}: {error['message']}", code=error["code"]
            )
        return answer["result"]

    async def wait_until_loaded(self, domain: str) -> None:
        """Wait until the config entries of `domain` are set up (entities exist then).

        Home Assistant pushes every entry's state to a subscriber, first all of them,
        then each change; setting up ends in `loaded` or in a failure state.
        """
        async with asyncio.timeout(SETUP_TIMEOUT), self.websocket() as socket:
            await socket.send_json({"id": 1, "type": "config_entries/subscribe"})
            states: dict[str, str] = {}
            while True:
                message = await socket.receive_json()
                if message["type"] == "result":
                    if not message["success"]:
                        raise ProvisioningError(message["error"]["message"])
                    continue
                for change in message["event"]:
                    entry = change["entry"]
                    if entry["domain"] == domain:
                        states[entry["entry_id"]] = entry["state"]
                if states and all(state == "loaded" for state in states.values()):
                    return
                if failed := set(states.values()) & SETUP_FAILURES:
                    raise ProvisioningError(f"{domain} did not set up: {failed}")

    async def wait_until_running(self) -> None:
        """Wait until Home Assistant has finished starting (it serves HTTP before)."""
        async with asyncio.timeout(SETUP_TIMEOUT), self.websocket() as socket:
            await socket.send_json(
                {
                    "id": 1,
                    "type": "subscribe_events",
                    "event_type": "homeassistant_started",
                }
            )
            await socket.send_json({"id": 2, "type": "get_config"})
            while True:
                message = await socket.receive_json()
                if message["type"] == "event" or (
                    message.get("id") == 2 and message["result"]["state"] == "RUNNING"
                ):
                    return

    async def wait_until_recording(self) -> None:
        """Wait until the recorder writes history (it tells no event when it starts).

        A Home Assistant stopped before that may wait a minute for the recorder.
        """
        async with asyncio.timeout(SETUP_TIMEOUT):
            while True:
                info = await self.websocket_command({"type": "recorder/info"})
                if info["recording"]:
                    return
                await asyncio.sleep(POLL_INTERVAL)

    async def confirm_http_config(self, expected: dict[str, Any]) -> bool:
        """Confirm the HTTP settings Home Assistant took from configuration.yaml.

        Since 2026.10 it moves them into its storage as a trial that reverts itself
        (to listening on every interface) unless confirmed within five minutes.
        Only a trial matching `expected` is confirmed; return whether one was.
        """
        try:
            config = await self.websocket_command({"type": "http/config"})
        except ProvisioningError as err:
            if err.code == "unknown_command":  # before 2026.10: YAML is the setting
                return False
            raise
        pending = config["pending"]
        if (
            pending is None
            or pending.get("error") is not None
            or any(pending.get(key) != value for key, value in expected.items())
        ):
            return False
        await self.websocket_command({"type": "http/config/promote"})
        return True

    async def open_on_dashboard(self, url_path: str) -> bool:
        """Make a dashboard the one Home Assistant opens on, unless one was chosen.

        Returns whether it was set (the frontend keeps the choice in its system data).
        """
        try:
            core = await self.websocket_command(
                {"type": "frontend/get_system_data", "key": "core"}
            )
        except ProvisioningError as err:
            if err.code == "unknown_command":  # before 2026.x: a per-browser choice
                return False
            raise
        settings = core["value"] or {}
        if settings.get("default_panel"):
            return False
        await self.websocket_command(
            {
                "type": "frontend/set_system_data",
                "key": "core",
                "value": {**settings, "default_panel": url_path},
            }
        )
        return True

    async def entry_titles(self, domain: str) -> list[str]:
        """Titles of the config entries of `domain`."""
        entries = await self.request(
            "GET", f"/api/config/config_entries/entry?domain={domain}"
        )
        return [entry["title"] for entry in entries]

    async def upload(self, path: Path) -> str:
        """Upload a file as the frontend's file selector does; return its ID."""
        form = aiohttp.FormData()
        content = await asyncio.to_thread(path.read_bytes)
        form.add_field("file", content, filename=path.name, content_type="text/csv")
        async with self._session.post(
            f"{self.url}/api/file_upload",
            data=form,
            headers={"Authorization": f"Bearer {self._token}"},
        ) as response:
            if response.status != 200:
                raise ProvisioningError(f"/api/file_upload: HTTP {response.status}")
            file_id: str = (await response.json())["file_id"]
            return file_id

    async def upload_content(self, name: str, content: bytes) -> str:
        """Upload a file as the frontend does (``file_upload``); return its ID."""
        form = aiohttp.FormData()
        form.add_field("file", content, filename=name)
        async with self._session.post(
            f"{self.url}/api/file_upload",
            data=form,
            headers={"Authorization": f"Bearer {self._token}"},
        ) as response:
            if response.status != 200:
                raise ProvisioningError(f"/api/file_upload: HTTP {response.status}")
            file_id: str = (await response.json())["file_id"]
            return file_id

    async def add_mervis(self, mervis: MervisAccess) -> str:
        """Add a Mervis controller with its demo map (demo_vlist); return its title."""
        flow = await self.request(
            "POST",
            "/api/config/config_entries/flow",
            {"handler": DOMAIN, "show_advanced_options": False},
        )
        path = f"/api/config/config_entries/flow/{flow['flow_id']}"
        await self.request("POST", path, {"next_step_id": "mervis"})
        result = await self.request(
            "POST",
            path,
            {
                "host": mervis.host,
                "username": mervis.username,
                "password": mervis.password,
                "verify_ssl": True,
                "point_map": await self.upload_content(
                    mervis.vlist.name, demo_vlist(mervis.content)
                ),
            },
        )
        if result["type"] != "create_entry":
            raise ProvisioningError(
                "the Mervis config flow did not create an entry: "
                f"{result.get('errors') or result.get('reason') or result['type']}"
            )
        title: str = result["title"]
        return title

    async def add_integration(
        self, domain: str, user_input: dict[str, Any], *, menu_choice: str | None = None
    ) -> str:
        """Run a config flow with `user_input`; return the entry's title.

        `menu_choice` is picked first when the flow opens on a menu.
        """
        flow = await self.request(
            "POST",
            "/api/config/config_entries/flow",
            {"handler": domain, "show_advanced_options": False},
        )
        path = f"/api/config/config_entries/flow/{flow['flow_id']}"
        if flow["type"] == "menu":
            if menu_choice not in flow["menu_options"]:
                raise ProvisioningError(
                    f"the {domain} config flow offers {flow['menu_options']}, "
                    f"not {menu_choice!r}"
                )
            await self.request("POST", path, {"next_step_id": menu_choice})
        result = await self.request("POST", path, user_input)
        if result["type"] != "create_entry":
            raise ProvisioningError(
                f"the {domain} config flow did not create an entry: "
                f"{result.get('errors') or result.get('reason') or result['type']}"
            )
        title: str = result["title"]
        return title


async def provision(
    session: aiohttp.ClientSession,
    url: str,
    plc: PlcAccess,
    http_settings: dict[str, Any] | None = None,
    dashboard: str | None = None,
    *,
    gateway: GatewayAccess | None = None,
    tekon: str | None = None,
    mervis: MervisAccess | None = None,
) -> list[str]:
    """Onboard Home Assistant and add the PLC unless done; return what was done.

    `http_settings` (`server_host`, `server_port`) are the HTTP settings written in
    configuration.yaml, to confirm when Home Assistant tries them out; `dashboard` is
    the URL path of the dashboard to open on when none was chosen yet; `gateway` an
    FP-I4C gateway to add as another entry, its register map uploaded; `tekon` the
    URL of a Tekon gateway to add as well (unless it is); `mervis` a Mervis
    controller to add too (its demo points changed, see MERVIS_DEMO_POINTS).
    """
    api = HomeAssistantApi(session, url)
    status = await wait_until_serving(session, url)
    done = (
        {"user", *ONBOARDING_STEPS}
        if status is None
        else {step["step"] for step in status if step["done"]}
    )
    actions: list[str] = []
    if "user" in done:
        await api.sign_in(await api.trusted_network_code())
    else:
        await api.sign_in(await api.create_owner())
        actions.append(f"created the owner account {OWNER_USERNAME!r}")
    for step in ONBOARDING_STEPS:
        if step not in done:
            await api.finish_onboarding_step(step)
            actions.append(f"finished onboarding step {step!r}")
    if http_settings is not None and await api.confirm_http_config(http_settings):
        actions.append(f"confirmed the HTTP settings {http_settings}")
    if dashboard is not None and await api.open_on_dashboard(dashboard):
        actions.append(f"made /{dashboard} the dashboard Home Assistant opens on")
    titles = await api.entry_titles(DOMAIN)
    if not [
        title
        for title in titles
        if title != TEKON_TITLE and not title.startswith((MERVIS_TITLE, GATEWAY_TITLE))
    ]:
        title = await api.add_integration(
            DOMAIN,
            {
                "host": plc.host,
                "username": plc.username,
                "password": plc.password,
                "verify_ssl": True,
            },
            menu_choice="tecoapi",
        )
        actions.append(f"added the PLC {title!r}")
    if gateway is not None and not any(
        title.startswith(GATEWAY_TITLE) for title in titles
    ):
        title = await api.add_integration(
            DOMAIN,
            {"host": gateway.host, "point_map": await api.upload(gateway.point_map)},
            menu_choice="fpi4c",
        )
        actions.append(f"added the gateway {title!r}")
    if tekon is not None and TEKON_TITLE not in titles:
        title = await api.add_integration(
            DOMAIN, {"host": tekon, "verify_ssl": True}, menu_choice="tekon"
        )
        actions.append(f"added the gateway {title!r}")
    if mervis is not None and not any(
        title.startswith(MERVIS_TITLE) for title in await api.entry_titles(DOMAIN)
    ):
        title = await api.add_mervis(mervis)
        actions.append(
            f"added the Mervis controller {title!r} (its map with units, setpoints "
            "and relays writable)"
        )
    await api.wait_until_loaded(DOMAIN)
    await api.wait_until_running()
    await api.wait_until_recording()
    return actions


async def wait_until_listening(host: str, port: int) -> None:
    """Wait until something accepts TCP connections at `host`:`port` (a starting PLC)."""
    async with asyncio.timeout(STARTUP_TIMEOUT):
        while True:
            try:
                _, writer = await asyncio.open_connection(host, port)
            except OSError:
                await asyncio.sleep(POLL_INTERVAL)
            else:
                writer.close()
                await writer.wait_closed()
                return


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of `python -m tests.e2e.provision`; the PLC password comes from the environment."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--port", type=int, default=8123, help="Home Assistant's port on 127.0.0.1"
    )
    parser.add_argument("--plc-host", required=True, help="HOST:PORT")
    parser.add_argument("--plc-username", required=True)
    parser.add_argument(
        "--fpi4c-host", help="HOST:PORT of an FP-I4C gateway to add too (its REST API)"
    )
    parser.add_argument(
        "--fpi4c-map", type=Path, help="the gateway's register map (a CSV file)"
    )
    parser.add_argument(
        "--gateway-url", default=None, help="a Tekon gateway to add as well"
    )
    parser.add_argument("--mervis-host", help="HOST:PORT of a Mervis controller")
    parser.add_argument("--mervis-username", default="")
    parser.add_argument("--mervis-vlist", type=Path, help="its project's .vlist")
    arguments = parser.parse_args(argv)
    if (arguments.fpi4c_host is None) != (arguments.fpi4c_map is None):
        parser.error("--fpi4c-host and --fpi4c-map go together")
    gateway = (
        None
        if arguments.fpi4c_host is None
        else GatewayAccess(host=arguments.fpi4c_host, point_map=arguments.fpi4c_map)
    )
    mervis = None
    if arguments.mervis_host:
        if arguments.mervis_vlist is None:
            parser.error("--mervis-host needs --mervis-vlist")
        mervis = MervisAccess(
            host=arguments.mervis_host,
            username=arguments.mervis_username,
            password=os.environ.get(MERVIS_PASSWORD_VARIABLE, ""),
            vlist=arguments.mervis_vlist,
            content=arguments.mervis_vlist.read_bytes(),
        )
    password = os.environ.get(PASSWORD_VARIABLE)
    if not password:
        parser.error(f"set {PASSWORD_VARIABLE} to the PLC's TecoApi password")
    plc = PlcAccess(
        host=arguments.plc_host, username=arguments.plc_username, password=password
    )

    async def run() -> list[str]:
        for address in (
            plc.host,
            *([gateway.host] if gateway else []),
            *([mervis.host] if mervis else []),
        ):
            host, _, port = address.rpartition(":")
            await wait_until_listening(host, int(port))
        host, _, port = plc.host.rpartition(":")
        await wait_until_listening(host, int(port))
        if arguments.gateway_url is not None:
            tekon = URL(arguments.gateway_url)
            await wait_until_listening(str(tekon.host), int(tekon.port or 80))
        async with aiohttp.ClientSession() as session:
            return await provision(
                session,
                f"http://127.0.0.1:{arguments.port}",
                plc,
                http_settings(arguments.port),
                DASHBOARD_URL_PATH,
                gateway=gateway,
                tekon=arguments.gateway_url,
                mervis=mervis,
            )

    try:
        actions = asyncio.run(run())
    except TimeoutError:
        print(
            f"provisioning failed: no answer within {STARTUP_TIMEOUT:.0f} s",
            file=sys.stderr,
        )
        return 1
    except (ProvisioningError, aiohttp.ClientError) as err:
        print(f"provisioning failed: {err}", file=sys.stderr)
        return 1
    for action in actions or ["nothing to do: onboarded, the devices already added"]:
        print(f"provisioned: {action}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
