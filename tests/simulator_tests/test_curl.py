"""The real curl binary against the simulator, as in the manual's transcripts."""

import asyncio
from collections.abc import AsyncIterator
from dataclasses import dataclass
import json
from pathlib import Path
import shutil

import pytest

from tests.simulator import Simulator
from tests.simulator_tests.conftest import manual_text

pytestmark = [
    pytest.mark.usefixtures("socket_enabled"),
    pytest.mark.skipif(shutil.which("curl") is None, reason="curl is not installed"),
]

USER, PASSWORD = "jmeno", "heslo"


@dataclass(frozen=True, slots=True)
class CurlResult:
    """The responses curl printed with -i: every status line, the final headers and body."""

    statuses: list[int]
    headers: dict[str, str]
    body: bytes


async def curl(*arguments: str) -> CurlResult:
    process = await asyncio.create_subprocess_exec(
        "curl",
        "--silent",
        "--show-error",
        "--include",
        *arguments,
        stdout=asyncio.subprocess.PIPE,
        stderr=asyncio.subprocess.PIPE,
    )
    output, errors = await process.communicate()
    assert process.returncode == 0, errors.decode()
    statuses: list[int] = []
    headers: dict[str, str] = {}
    rest = output
    while rest.startswith(b"HTTP/"):
        head, _, rest = rest.partition(b"\r\n\r\n")
        lines = head.decode().split("\r\n")
        status = int(lines[0].split()[1])
        if status >= 200:  # not "100 Continue" (curl -T may ask for it)
            statuses.append(status)
            headers = dict(line.split(": ", 1) for line in lines[1:])
    return CurlResult(statuses, headers, rest)


@pytest.fixture(params=["digest", "both"])
async def plc(request: pytest.FixtureRequest) -> AsyncIterator[Simulator]:
    async with Simulator(
        "manual", username=USER, password=PASSWORD, auth=request.param
    ) as sim:
        yield sim


@pytest.fixture
async def basic_plc() -> AsyncIterator[Simulator]:
    async with Simulator(
        "manual", username=USER, password=PASSWORD, auth="both"
    ) as sim:
        yield sim


async def test_curl_digest_follows_the_manual_transcript(plc: Simulator) -> None:
    result = await curl(
        "--digest", "-u", f"{USER}:{PASSWORD}", plc.url + "/TecoApi/GetObject?plcDesc"
    )

    assert result.statuses == [401, 200]
    assert [(r.status, r.authorized) for r in plc.requests] == [
        (401, False),
        (200, True),
    ]
    assert result.headers["Connection"] == "close"
    assert result.headers["Content-Type"] == "application/json"
    assert result.headers["Cache-Control"] == "no-cache"
    assert result.headers["Content-Length"] == "39"
    assert result.body == manual_text('{\n  "plcDesc": "for testing only"\n}')


async def test_curl_digest_get_info(plc: Simulator) -> None:
    result = await curl(
        "--digest", "-u", f"{USER}:{PASSWORD}", plc.url + "/TecoApi/GetInfo"
    )

    assert result.statuses[-1] == 200
    assert json.loads(result.body)["plc"]["userProg"]["stamp"] == plc.stamp


async def test_curl_digest_put(plc: Simulator, tmp_path: Path) -> None:
    body = tmp_path / "plcType.json"
    body.write_bytes(b'{ "plcType": 1005 }')

    result = await curl(
        "--digest",
        "-u",
        f"{USER}:{PASSWORD}",
        "-T",
        str(body),
        plc.url + "/TecoApi/PutObject",
    )

    assert result.statuses[-1] == 204
    assert plc.get_value("plcType") == 1005


async def test_curl_digest_wrong_password(plc: Simulator) -> None:
    result = await curl("--digest", "-u", f"{USER}:wrong", plc.url + "/TecoApi/GetInfo")

    assert result.statuses == [401, 401]
    assert json.loads(result.body)["error"]["code"] == "401.021"


async def test_curl_basic_like_the_manual_examples(
    basic_plc: Simulator, tmp_path: Path
) -> None:
    my_object = tmp_path / "myObject.json"
    my_object.write_bytes(b'{"myObject": {"first": "Mia", "registered": true}}')
    user = f"{USER}:{PASSWORD}"

    read = await curl(
        "--user", user, basic_plc.url + "/TecoApi/GetObject?myObject.favorites"
    )
    registered = await curl(
        "-u", user, basic_plc.url + "/TecoApi/SetObject?myObject.registered=true"
    )
    five = await curl(
        "-g", "-u", user, basic_plc.url + "/TecoApi/SetObject?arr1[5]=five"
    )
    put = await curl(
        "-T", str(my_object), "-u", user, basic_plc.url + "/TecoApi/PutObject?myObject"
    )
    missing = await curl("-u", user, basic_plc.url + "/TecoApi/GetData")

    assert read.statuses == [200]
    assert json.loads(read.body) == {
        "myObject": {
            "favorites": {"color": '"Blue"', "sport": "Soccer", "food": "Spaghetti"}
        }
    }
    assert (registered.statuses, registered.body) == ([200], b"")
    assert registered.headers["Content-Length"] == "0"
    assert five.statuses == [200]
    assert put.statuses == [204]
    assert basic_plc.get_value("arr1[5]") == "five"
    assert basic_plc.get_value("myObject.first") == "Mia"
    assert basic_plc.get_value("myObject.registered") is True
    assert missing.statuses == [501]
    assert json.loads(missing.body)["error"]["message"] == (
        "Unimplemented service 'HTTP GET | GetData'"
    )
    assert all(r.authorized for r in basic_plc.requests)


async def test_curl_basic_to_a_digest_only_plc(socket_enabled: None) -> None:
    async with Simulator("manual", username=USER, password=PASSWORD) as sim:
        result = await curl("-u", f"{USER}:{PASSWORD}", sim.url + "/TecoApi/GetInfo")

    assert result.statuses == [403]
    assert json.loads(result.body)["error"]["code"] == "403.022"
