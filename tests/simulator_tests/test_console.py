"""Console commands that change a running simulator from the command line."""

import pytest

from tests.simulator import Simulator
from tests.simulator.console import CommandError, program_from_argument, run_command


@pytest.fixture
def sim() -> Simulator:
    return Simulator("manual")


@pytest.mark.parametrize(
    "name",
    [
        "hang",
        "drop_connection",
        "http_500",
        "huge_body",
        "endless_body",
        "truncated_json",
        "malformed_json",
    ],
)
def test_fault_on_and_off(sim: Simulator, name: str) -> None:
    assert run_command(sim, f"fault {name} on") == "ok"
    assert getattr(sim.faults, name) is True
    run_command(sim, f"fault {name} off")
    assert getattr(sim.faults, name) is False


def test_timing_mode_and_lists(sim: Simulator) -> None:
    for line in (
        "latency 20",
        "latency-per-item 0.5",
        "remaining 3",
        "mode halt",
        "hide myObject",
        "reject arr1",
    ):
        assert run_command(sim, line) == "ok"

    faults = sim.faults
    assert (faults.latency, faults.latency_per_item, faults.remaining) == (
        0.02,
        0.0005,
        3,
    )
    assert sim.mode == "HALT"
    assert (faults.hidden_from_list, faults.rejected_by_object) == (
        {"myObject"},
        {"arr1"},
    )

    run_command(sim, "unhide myObject")
    run_command(sim, "unreject arr1")
    run_command(sim, "remaining none")
    assert (faults.hidden_from_list, faults.rejected_by_object, faults.remaining) == (
        set(),
        set(),
        None,
    )
    run_command(sim, "clear")
    assert (sim.mode, faults.latency) == ("RUN", 0.0)


def test_real_device_behaviours(sim: Simulator) -> None:
    for line in (
        "encoding windows-1250",
        "short-reals on",
        "exact-service-names on",
    ):
        assert run_command(sim, line) == "ok"

    faults = sim.faults
    assert (faults.text_encoding, faults.short_reals, faults.exact_service_names) == (
        "windows-1250",
        True,
        True,
    )
    with pytest.raises(CommandError):
        run_command(sim, "encoding latin-1")
    run_command(sim, "short-reals off")
    assert faults.short_reals is False
    assert run_command(sim, "link-rate 12.5") == "ok"
    assert sim.link_motion.rate == 12.5
    for wrong in ("link-rate 0", "link-rate fast"):
        with pytest.raises(CommandError):
            run_command(sim, wrong)
    run_command(sim, "link-rate off")
    assert sim.link_motion.rate is None
    run_command(sim, "clear")
    assert (faults.text_encoding, faults.exact_service_names) == ("utf-8", False)


def test_values_programs_and_credentials(sim: Simulator) -> None:
    assert run_command(sim, "get Main.myObject3.attr.units") == '"°C"'
    assert run_command(sim, "set plcType 7") == "ok"
    assert run_command(sim, "set plcDesc '\"two words\"'") == "ok"
    assert sim.get_value("plcType") == 7
    assert sim.get_value("plcDesc") == "two words"
    assert run_command(sim, "password other") == "ok"
    assert sim.password == "other"
    assert run_command(sim, "auth both") == "ok"
    assert sim.auth == "both"
    reply = run_command(sim, "load generated:20:3")
    assert reply == f"program loaded, stamp {sim.stamp}"
    assert sim.program.name == "GENERATED_20 v1.0"
    assert "stamp" in run_command(sim, "status")
    assert "fault NAME" in run_command(sim, "help")
    assert run_command(sim, "   ") == ""


@pytest.mark.parametrize(
    ("line", "message"),
    [
        ("fault nothing on", "unknown command"),
        ("fault hang maybe", "expected on or off"),
        ("latency fast", "expected milliseconds"),
        ("latency -1", ">= 0"),
        ("remaining -1", "expected a count"),
        ("mode STOP", "unknown command"),
        ("get nothing", "no variable"),
        ("set plcType notjson", "not JSON"),
        ("set plcType 70000", "not written"),
        ("set nothing 1", "nothing"),
        ("load nowhere.yaml", "no program"),
        ("load generated:x", "generated:POINTS"),
        ("auth ntlm", "unknown command"),
        ("say 'unclosed", "quotation"),
        ("bogus", "unknown command"),
    ],
)
def test_bad_commands(sim: Simulator, line: str, message: str) -> None:
    with pytest.raises(CommandError, match=message):
        run_command(sim, line)


def test_program_arguments() -> None:
    assert program_from_argument("demo") == "demo"
    generated = program_from_argument("generated:12")
    assert not isinstance(generated, str)
    assert generated.name == "GENERATED_12 v1.0"
