"""The simulated Mervis controller over raw HTTP: its messages, each switch, its projects."""

import asyncio
from collections.abc import AsyncIterator
from datetime import UTC, datetime, timedelta
from pathlib import Path
import re
import signal
import sys
from typing import Any

import aiohttp
import pytest

from custom_components.tecoapi.pyplc.mervis.vlist import load_vlist
from tests.simulator.mervis import (
    HOUSE_NAME,
    LIBRARIES,
    SHARED_NAME,
    SOLUTION_NAME,
    MervisSimulator,
    ProjectError,
    Row,
    Switches,
    generated,
    house,
    solution,
)
from tests.simulator.mervis.__main__ import (
    build_simulator,
    parse_arguments,
    project_from_argument,
)
from tests.simulator.mervis.project import decode, encode

pytestmark = pytest.mark.usefixtures("socket_enabled")

REPOSITORY = Path(__file__).resolve().parents[2]
RELEASED = "svc://DefaultConnection/"
SEED = "svc:defaultConnection/"
LINE_TIMEOUT = 60


@pytest.fixture
async def sim() -> AsyncIterator[MervisSimulator]:
    simulator = MervisSimulator(house(), username="admin", password="secret")
    await simulator.start()
    try:
        yield simulator
    finally:
        await simulator.stop()


async def post(sim: MervisSimulator, service: str, body: Any) -> dict[str, Any]:
    async with (
        aiohttp.ClientSession() as http,
        http.post(f"{sim.url}/{service}.cgi", json=body) as response,
    ):
        assert response.status == 200
        answer: dict[str, Any] = await response.json()
        return answer


async def login(sim: MervisSimulator) -> dict[str, Any]:
    answer = await post(sim, "login", {"ver": 1, "c": {"u": "admin", "p": "secret"}})
    assert answer["code"] == "ok"
    c: dict[str, Any] = answer["c"]
    return c


def ident(sim: MervisSimulator, name: str, prefix: str = RELEASED) -> str:
    row = sim.project.row(name)
    return f"{prefix}{row.commuid}[{row.offset},{row.length}]"


async def test_login_gives_a_c_that_reads(sim: MervisSimulator) -> None:
    c = await login(sim)
    assert c["u"] == "admin"
    assert re.fullmatch(r"[0-9a-f]{32}", c["p"])
    answer = await post(
        sim, "values", {"ver": 1, "c": c, "v": [ident(sim, "koupelna.temperature")]}
    )
    assert answer["code"] == "ok"
    (item,) = answer["v"]
    assert (item["v"], item["q"]) == ("41AC0000", "G")
    assert isinstance(item["t"], int)
    assert [record.service for record in sim.requests] == ["login", "values"]


async def test_a_whole_block_is_read_as_one_range(sim: MervisSimulator) -> None:
    row = sim.project.row("koupelna.temperature")
    answer = await post(
        sim,
        "values",
        {
            "ver": 1,
            "c": {"u": "admin", "p": "secret"},
            "v": [f"{RELEASED}{row.commuid}[0,13]"],
        },
    )
    # temperature, setpoint, heating, mode
    assert answer["v"][0]["v"] == "41AC0000" + "41B00000" + "01" + "00000001"


@pytest.mark.parametrize(
    ("c", "code"),
    [
        (None, "unauthorized"),
        ({"u": "admin", "p": "wrong"}, "unauthorized"),
        ({"u": "other", "p": "secret"}, "unauthorized"),
        ({"u": "admin", "p": "secret"}, "ok"),
    ],
)
async def test_credentials_are_checked(
    sim: MervisSimulator, c: dict[str, str] | None, code: str
) -> None:
    body: dict[str, Any] = {"ver": 1, "v": [ident(sim, "away")]}
    if c is not None:
        body["c"] = c
    assert (await post(sim, "values", body))["code"] == code
    login_body: dict[str, Any] = {"ver": 1, "c": c}
    expected = "ok" if code == "ok" else "unauthorized"
    assert (await post(sim, "login", login_body))["code"] == expected


async def test_a_project_without_credentials_takes_anyone() -> None:
    async with MervisSimulator(username=None) as sim:
        assert (await post(sim, "login", {"ver": 1}))["code"] == "ok"
        answer = await post(sim, "values", {"ver": 1, "v": [ident(sim, "away")]})
        assert answer["v"][0]["v"] == "00"


async def test_sessions_expire(sim: MervisSimulator) -> None:
    sim.switches.session_requests = 1
    sim.switches.accept_plain = False
    c = await login(sim)
    body = {"ver": 1, "c": c, "v": [ident(sim, "away")]}
    assert (await post(sim, "values", body))["code"] == "ok"
    assert (await post(sim, "values", body))["code"] == "unauthorized"
    c = await login(sim)
    sim.expire_sessions()
    assert (await post(sim, "values", {**body, "c": c}))["code"] == "unauthorized"
    plain = {**body, "c": {"u": "admin", "p": "secret"}}
    assert (await post(sim, "values", plain))["code"] == "unauthorized"


@pytest.mark.parametrize(
    ("spelling", "known"),
    [("released", {RELEASED}), ("seed", {SEED}), ("both", {RELEASED, SEED})],
)
async def test_the_id_spellings_a_controller_knows(
    sim: MervisSimulator, spelling: str, known: set[str]
) -> None:
    sim.switches.spelling = spelling  # type: ignore[assignment]
    ids = [ident(sim, "away", RELEASED), ident(sim, "away", SEED)]
    answer = await post(sim, "values", {"ver": 1, "c": await login(sim), "v": ids})
    for asked, item in zip(ids, answer["v"], strict=True):
        prefix = RELEASED if asked.startswith(RELEASED) else SEED
        if prefix in known:
            assert item["v"] == "00"
            own = asked if spelling == "both" else ident(sim, "away", prefix)
            assert item["i"] == own
        else:
            assert item == {"i": asked, "e": "unknown variable"}


async def test_qualities_item_errors_and_order(sim: MervisSimulator) -> None:
    names = ["away", "boost", "clock", "outside_temp"]
    sim.switches.quality = "good"
    sim.switches.qualities[sim.project.row("boost").commuid] = "B"
    sim.switches.item_errors.add(sim.project.row("clock").commuid)
    sim.switches.order = "reversed"
    ids = [ident(sim, name) for name in names]
    answer = await post(sim, "values", {"ver": 1, "c": await login(sim), "v": ids})
    items = {item["i"]: item for item in answer["v"]}
    assert [item["i"] for item in answer["v"]] == ids[::-1]
    assert items[ids[0]]["q"] == "good"
    assert items[ids[1]]["q"] == "B"
    assert items[ids[2]] == {"i": ids[2], "e": "unknown variable"}
    sim.switches.order = "shuffled"
    shuffled = await post(
        sim, "values", {"ver": 1, "c": await login(sim), "v": ids * 3}
    )
    assert sorted(item["i"] for item in shuffled["v"]) == sorted(ids * 3)


async def test_bytes_beyond_a_variable_are_an_item_error(sim: MervisSimulator) -> None:
    row = sim.project.row("away")
    ids = [f"{RELEASED}{row.commuid}[0,2]", f"{RELEASED}99999[0,1]", "garbage"]
    answer = await post(sim, "values", {"ver": 1, "c": await login(sim), "v": ids})
    assert all("e" in item for item in answer["v"])


async def test_limits_are_enforced_and_told(sim: MervisSimulator) -> None:
    sim.switches.max_variables = 2
    sim.switches.max_request_size = 300
    c = await login(sim)
    ids = [ident(sim, name) for name in ("away", "boost", "clock")]
    refused = await post(sim, "values", {"ver": 1, "c": c, "v": ids})
    assert (refused["code"], refused["msg"]) == ("error", "too many variables")
    assert "maxVariablesInRequest" not in refused
    long_ids = [f"{RELEASED}{'1' * 300}[0,1]"]
    refused = await post(sim, "values", {"ver": 1, "c": c, "v": long_ids})
    assert refused["msg"] == "request too large"
    sim.switches.tell_limits = True
    told = await post(sim, "login", {"ver": 1, "c": {"u": "admin", "p": "secret"}})
    assert (
        told["maxVariablesInRequest"],
        told["maxRequestSize"],
        told["platform"],
    ) == (2, 300, "uPLC")
    refused = await post(sim, "values", {"ver": 1, "c": c, "v": ids})
    assert refused["maxVariablesInRequest"] == 2


async def test_commands_take_the_first_item_as_a_value(sim: MervisSimulator) -> None:
    c = await login(sim)
    setpoint, relay = ident(sim, "koupelna.setpoint"), ident(sim, "away")
    answer = await post(
        sim,
        "command",
        {"ver": 1, "c": c, "v": [{"i": setpoint, "set": 23.5}, {"i": relay, "set": 1}]},
    )
    assert answer["code"] == "ok"
    assert sim.project.get("koupelna.setpoint") == 23.5
    assert sim.project.get("away") is False
    assert sim.writes == [("koupelna.setpoint", 23.5)]


@pytest.mark.parametrize(
    ("encoding", "value", "code"),
    [
        ("plain", 22.5, "ok"),
        ("plain", "41B40000", "error"),
        ("hex", "41B40000", "ok"),
        ("hex", 22.5, "error"),
        ("hex", "41B4", "error"),
        ("both", "41B40000", "ok"),
        ("both", 22.5, "ok"),
        ("plain", 1e39, "error"),
        ("plain", "text", "error"),
    ],
)
async def test_write_encodings(
    sim: MervisSimulator, encoding: str, value: Any, code: str
) -> None:
    sim.switches.write_encoding = encoding  # type: ignore[assignment]
    answer = await post(
        sim,
        "command",
        {
            "ver": 1,
            "c": await login(sim),
            "v": [{"i": ident(sim, "jidelna.setpoint"), "set": value}],
        },
    )
    assert answer["code"] == code
    assert sim.project.get("jidelna.setpoint") == (22.5 if code == "ok" else 21.0)


@pytest.mark.parametrize(
    "items",
    [[], ["x"], [{"i": "x"}], [{"i": f"{RELEASED}1[0,1]", "set": 1}]],
)
async def test_commands_that_are_none(sim: MervisSimulator, items: list[Any]) -> None:
    answer = await post(sim, "command", {"ver": 1, "c": await login(sim), "v": items})
    assert answer["code"] == "error"


async def test_what_is_no_message(sim: MervisSimulator) -> None:
    async with aiohttp.ClientSession() as http:
        async with http.get(f"{sim.url}/") as response:
            assert response.content_type == "text/html"
        async with http.post(f"{sim.url}/values.cgi", data=b"{") as response:
            assert (await response.json())["msg"] == "not JSON"
        async with http.post(f"{sim.url}/values.cgi", json={"ver": 2}) as response:
            assert (await response.json())["msg"] == "unknown version"
        async with http.post(f"{sim.url}/values.cgi", json={"ver": 1}) as response:
            assert (await response.json())["msg"] == "no variables"
    await sim.wait_for_requests(3)
    assert sim.count("values") == 3


async def test_a_started_simulator_cannot_start_again(sim: MervisSimulator) -> None:
    with pytest.raises(RuntimeError, match="already running"):
        await sim.start()
    assert sim.host == f"127.0.0.1:{sim.port}"
    sim.clear_requests()
    assert sim.requests == []


# --- projects ------------------------------------------------------------------------


def test_the_shipped_vlist_is_the_house_s() -> None:
    shipped = (REPOSITORY / "tests/simulator/mervis/house.vlist").read_text("utf-8")
    assert shipped == house().vlist()
    point_map = load_vlist(shipped)
    assert point_map.properties == {"project": HOUSE_NAME}
    assert point_map.skipped == ()
    assert len(point_map.points) == 64


def test_the_house_s_clock_is_live() -> None:
    moment = datetime(2026, 5, 1, 7, 30, tzinfo=UTC)
    assert house(clock=lambda: moment).get("clock") == moment


@pytest.mark.parametrize("count", [1, 50, 300, 1000])
def test_a_generated_project_has_exactly_its_points(count: int) -> None:
    project = generated(count, seed=7)
    point_map = load_vlist(project.vlist())
    assert len(point_map.points) == count
    assert point_map.skipped == ()
    assert generated(count, seed=7).vlist() == project.vlist()
    families = {point.details["family"] for point in point_map.points}
    if count >= 300:
        assert families == {"fb", "struct", "array", "none"}


@pytest.mark.parametrize(
    ("type_name", "length", "value"),
    [
        ("bool", 1, True),
        ("sint", 1, -5),
        ("lword", 8, 2**64 - 1),
        ("real", 4, 21.5),
        ("lreal", 8, 0.1),
        ("dt", 8, datetime(2026, 1, 1, tzinfo=UTC)),
        ("date", 8, datetime(2026, 1, 1, tzinfo=UTC).date()),
        ("time", 8, timedelta(seconds=5)),
        ("tod", 8, timedelta(hours=6)),
        ("string", 8, "Kuchyň"),
    ],
)
def test_the_simulator_s_own_encoding(type_name: str, length: int, value: Any) -> None:
    row = Row("x", type_name, 1, 0, length)
    assert decode(row, encode(row, value)) == value


@pytest.mark.parametrize(
    ("type_name", "length", "value"),
    [
        ("bool", 1, 2),
        ("int", 2, 1.5),
        ("int", 2, 40000),
        ("real", 4, "x"),
        ("dt", 8, "soon"),
        ("string", 2, "long"),
        ("T_RECIPE", 64, 1),
    ],
)
def test_what_the_simulator_refuses_to_store(
    type_name: str, length: int, value: Any
) -> None:
    with pytest.raises(ProjectError):
        encode(Row("x", type_name, 1, 0, length), value)


def test_a_project_knows_its_variables_by_bytes() -> None:
    project = house()
    row = project.row("koupelna.mode")
    assert project.at(row.commuid, row.offset, row.length) == row
    assert project.at(row.commuid, 0, 16) is None
    assert project.read(row.commuid, 0, 0) is None
    with pytest.raises(KeyError):
        project.row("nothing")
    project.set("koupelna.mode", 2)
    assert project.get("koupelna.mode") == 2


# --- the command line ------------------------------------------------------------------


def test_the_command_line_sets_every_switch() -> None:
    arguments = parse_arguments(
        [
            "--project",
            "generated:20:3",
            "--no-credentials",
            "--spelling",
            "seed",
            "--quality",
            "good",
            "--order",
            "shuffled",
            "--max-variables",
            "5",
            "--max-request-size",
            "1500",
            "--tell-limits",
            "--write-encoding",
            "hex",
            "--session-requests",
            "10",
        ]
    )
    sim = build_simulator(arguments)
    assert sim.username is None
    assert sim.switches == Switches(
        spelling="seed",
        quality="good",
        order="shuffled",
        max_variables=5,
        max_request_size=1500,
        tell_limits=True,
        write_encoding="hex",
        session_requests=10,
    )
    assert len(load_vlist(sim.project.vlist()).points) == 20


@pytest.mark.parametrize("text", ["nothing", "generated:x", "generated:0", "gen:5"])
def test_an_unknown_project_is_refused(text: str) -> None:
    with pytest.raises(ValueError, match="unknown project"):
        project_from_argument(text)
    with pytest.raises(SystemExit):
        parse_arguments(["--project", text])


def test_tls_needs_both_halves() -> None:
    with pytest.raises(SystemExit):
        parse_arguments(["--tls-cert", "cert.pem"])


async def test_run_as_a_program_it_exports_its_vlist_and_serves(
    tmp_path: Path,
) -> None:
    exported = tmp_path / "house.vlist"
    process = await asyncio.create_subprocess_exec(
        sys.executable,
        "-m",
        "tests.simulator.mervis",
        "--port",
        "0",
        "--export-vlist",
        str(exported),
        cwd=REPOSITORY,
        stdout=asyncio.subprocess.PIPE,
        stderr=asyncio.subprocess.PIPE,
    )
    assert process.stdout is not None
    line = await asyncio.wait_for(process.stdout.readline(), LINE_TIMEOUT)
    match = re.match(rb"Serving (http://127\.0\.0\.1:\d+)/ \(Mervis web panel\)", line)
    assert match is not None, line
    async with aiohttp.ClientSession() as http:
        body = {"ver": 1, "c": {"u": "admin", "p": "secret"}}
        async with http.post(
            f"{match.group(1).decode()}/login.cgi", json=body
        ) as reply:
            assert (await reply.json())["code"] == "ok"
    process.send_signal(signal.SIGTERM)
    await asyncio.wait_for(process.communicate(), LINE_TIMEOUT)
    assert process.returncode == 0
    assert exported.read_text("utf-8").startswith("#ver:1.0\n")


async def test_a_port_taken_is_an_error(sim: MervisSimulator) -> None:
    process = await asyncio.create_subprocess_exec(
        sys.executable,
        "-m",
        "tests.simulator.mervis",
        "--port",
        str(sim.port),
        cwd=REPOSITORY,
        stdout=asyncio.subprocess.PIPE,
        stderr=asyncio.subprocess.PIPE,
    )
    _, errors = await asyncio.wait_for(process.communicate(), LINE_TIMEOUT)
    assert process.returncode == 1
    assert b"error:" in errors


# --- real exports' shape, other connections ------------------------------------------


def test_the_solution_is_exported_as_real_exports_are() -> None:
    """Libraries first, a shared project of more rows, arrays' elements as segments."""
    project = solution()
    text = project.vlist(bom=True)
    assert text.startswith("\ufeff#ver:1.0\n")
    rows = text.lstrip("\ufeff").splitlines()[2:]
    projects = [row.split(";", 1)[0] for row in rows]
    assert projects[: len(LIBRARIES)] == list(LIBRARIES)
    assert projects.count(SHARED_NAME) > projects.count(SOLUTION_NAME) > 0
    assert f"{SHARED_NAME};$in$.$[2]$;$bool$;3014;1;1;array;" in rows
    assert (
        f"{SOLUTION_NAME};$kotelna$.$ekviterm$;$lib$.$core$.$v1_0$.$linear$;3016;0;20;"
        "none;" in rows
    )
    assert re.fullmatch(
        rf"{SOLUTION_NAME}_[0-9a-f]{{8}}(-[0-9a-f]{{4}}){{3}}-[0-9a-f]{{12}}\.vlist",
        project.export_name,
    )
    assert project.row("in[2]").key == "in[2]"
    assert project.get("in/[2]") is False
    assert project.get("kotelna.ekviterm.en") is True
    assert project.get("hw_hidden/markcom3.mxio.ai08.transformation") == 21.25


def test_generated_arrays_are_elements_of_their_own() -> None:
    text = generated(300, seed=1).vlist()
    assert re.search(r"\$arr_[0-9]+\$\.\$\[0\]\$", text)


async def test_another_connection_s_variables_are_read_as_asked() -> None:
    """The seed names ``svc:otherConnection/…``: a connection it serves, or an item error."""
    other = generated(10, seed=2)
    row = next(row for row in other.rows if row.type == "real" and row.family == "none")
    async with MervisSimulator(house(), username=None, switches=Switches()) as sim:
        sim.connections["plc2"] = other
        asked = [
            f"svc:PLC2/{row.commuid}[0,4]",
            f"svc://plc2/{row.commuid}[0,4]",
            f"svc://plc3/{row.commuid}[0,4]",
        ]
        answer = await post(sim, "values", {"ver": 1, "v": asked})
        first, second, unknown = answer["v"]
        assert first["i"] == asked[0]
        assert first["v"] == second["v"] == other.read(row.commuid, 0, 4).hex().upper()
        assert unknown == {"i": asked[2], "e": "unknown variable"}
        command = await post(
            sim, "command", {"ver": 1, "v": [{"i": asked[1], "set": 1.5}]}
        )
        assert (command["code"], command["msg"]) == ("error", "unknown variable")
