"""Commands that change a running simulator, typed line by line on the command line.

`help` lists them. Each command returns the text to print; a bad command raises
`CommandError` with the reason.
"""

import json
import shlex
from typing import Final, cast

from .auth import AUTH_MODES, AuthMode
from .faults import PLC_MODES, TEXT_ENCODINGS, TRANSPORT_FAULTS
from .generator import generate_program
from .program import Program, ProgramError
from .server import Simulator

HELP: Final = """\
fault NAME on|off     transport fault: hang, drop_connection, http_500,
                      huge_body, endless_body, truncated_json, malformed_json
remaining N|none      the transport faults hit only the next N requests
latency MS            milliseconds added to every request
latency-per-item MS   milliseconds added per item returned
mode RUN|HALT|ERR     the PLC mode GetInfo reports
hide NAME / unhide NAME       GetList leaves NAME out
reject NAME / unreject NAME   GetObject answers 400.005 for NAME
encoding utf-8|windows-1250  how answers encode text (titles, units, strings)
short-reals on|off    REALs as 29.0 (real devices) or 29.000000 (the manual)
exact-service-names on|off    only /TecoApi/GetList, or any case (real devices)
link-rate PER_S|off   links move a number this much a second (a blind), or at once
clear                 no faults, RUN mode, the default encoding and printing
get PATH              print a value
set PATH JSON         change a value as the PLC program would
load PROGRAM          download another program (demo, manual, generated:N, a file)
password SECRET       change the password (clients' credentials are revoked)
auth digest|basic|both        the authentication offered
status                faults, stamp and requests served
help                  this text"""


class CommandError(ValueError):
    """A console command that cannot be carried out."""


def _switch(word: str) -> bool:
    if word.lower() in {"on", "true", "1"}:
        return True
    if word.lower() in {"off", "false", "0"}:
        return False
    raise CommandError(f"expected on or off, not {word!r}")


def _count(word: str) -> int:
    if not word.isdigit():
        raise CommandError(f"expected a count, not {word!r}")
    return int(word)


def _milliseconds(word: str) -> float:
    try:
        value = float(word)
    except ValueError:
        raise CommandError(f"expected milliseconds, not {word!r}") from None
    if value < 0:
        raise CommandError("milliseconds must be >= 0")
    return value / 1000


def _rate(word: str) -> float:
    try:
        value = float(word)
    except ValueError:
        raise CommandError(f"expected units a second or off, not {word!r}") from None
    if not value > 0:
        raise CommandError("the rate must be > 0")
    return value


def run_command(sim: Simulator, line: str) -> str:
    """Carry out one console line on the simulator; the reply to print."""
    try:
        words = shlex.split(line)
    except ValueError as err:
        raise CommandError(str(err)) from err
    if not words:
        return ""
    command, arguments = words[0].lower(), words[1:]
    faults = sim.faults
    match command, arguments:
        case "help", []:
            return HELP
        case "fault", [name, state] if name in TRANSPORT_FAULTS:
            setattr(faults, name, _switch(state))
        case "remaining", [count]:
            faults.remaining = None if count.lower() == "none" else _count(count)
        case "latency", [ms]:
            faults.latency = _milliseconds(ms)
        case "latency-per-item", [ms]:
            faults.latency_per_item = _milliseconds(ms)
        case "mode", [mode] if mode.upper() in PLC_MODES:
            sim.mode = mode.upper()
        case "hide", [name]:
            faults.hidden_from_list.add(name)
        case "unhide", [name]:
            faults.hidden_from_list.discard(name)
        case "reject", [name]:
            faults.rejected_by_object.add(name)
        case "unreject", [name]:
            faults.rejected_by_object.discard(name)
        case "encoding", [encoding] if encoding.lower() in TEXT_ENCODINGS:
            faults.text_encoding = encoding.lower()
        case "short-reals", [state]:
            faults.short_reals = _switch(state)
        case "exact-service-names", [state]:
            faults.exact_service_names = _switch(state)
        case "link-rate", [rate]:
            sim.link_motion.rate = None if rate.lower() == "off" else _rate(rate)
        case "clear", []:
            faults.clear()
        case "get", [path]:
            try:
                return json.dumps(sim.get_value(path), ensure_ascii=False)
            except KeyError as err:
                raise CommandError(f"no variable {path!r}") from err
        case "set", [path, text]:
            try:
                sim.set_value(path, json.loads(text))
            except json.JSONDecodeError as err:
                raise CommandError(f"not JSON: {text!r}") from err
            except (KeyError, ValueError) as err:
                raise CommandError(str(err)) from err
        case "load", [program]:
            try:
                sim.load_program(program_from_argument(program))
            except (ProgramError, OSError) as err:
                raise CommandError(str(err)) from err
            return f"program loaded, stamp {sim.stamp}"
        case "password", [secret]:
            sim.password = secret
        case "auth", [mode] if mode in AUTH_MODES:
            sim.auth = cast("AuthMode", mode)
        case "status", []:
            return (
                f"{sim.url} stamp {sim.stamp} mode {sim.mode} "
                f"requests {len(sim.requests)} faults {faults!r}"
            )
        case _:
            raise CommandError(f"unknown command {line.strip()!r}; try help")
    return "ok"


def program_from_argument(argument: str) -> str | Program:
    """A `--program`/`load` argument: `generated:N[:SEED]` or a name/path as given."""
    if argument.startswith("generated:"):
        parts = argument.split(":")
        try:
            points = int(parts[1])
            seed = int(parts[2]) if len(parts) > 2 else 0
        except (ValueError, IndexError) as err:
            raise ProgramError("use generated:POINTS or generated:POINTS:SEED") from err
        return generate_program(points, seed=seed)
    return argument
