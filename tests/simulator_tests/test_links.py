"""A program's links: what its logic does with a written value (the demo reacts)."""

import pytest

from tests.simulator import Program, Simulator, load_program
from tests.simulator.program import ProgramError

BLIND = "Stineni.OBYVAK_ZALUZIE_GTSAP1_OPENER"


def program_with_links(links: object) -> Program:
    source = load_program("manual").to_mapping()
    source["links"] = links
    return Program.from_mapping(source)


def test_a_write_is_copied_to_its_link() -> None:
    sim = Simulator(program_with_links([{"from": "plcName", "to": "plcDesc"}]))
    sim.set_value("plcName", "Foxy")
    assert sim.get_value("plcDesc") == "Foxy"
    assert sim.get_value("plcName") == "Foxy"


def test_a_write_that_changes_nothing_copies_nothing() -> None:
    sim = Simulator(program_with_links([{"from": "plcName", "to": "plcDesc"}]))
    before = sim.get_value("plcDesc")
    sim.set_value("plcName", sim.get_value("plcName"))
    sim.set_value("plcType", 7)
    assert sim.get_value("plcDesc") == before


def test_a_value_the_target_cannot_hold_is_not_copied() -> None:
    sim = Simulator(program_with_links([{"from": "plcName", "to": "plcType"}]))
    before = sim.get_value("plcType")
    sim.set_value("plcName", "Foxy")
    assert sim.get_value("plcName") == "Foxy"
    assert sim.get_value("plcType") == before


def test_a_link_to_a_missing_variable_does_nothing() -> None:
    sim = Simulator(program_with_links([{"from": "plcName", "to": "gone"}]))
    sim.set_value("plcName", "Foxy")
    assert sim.get_value("plcName") == "Foxy"


def test_demo_blinds_and_dimmers_follow_their_targets() -> None:
    sim = Simulator("demo")
    sim.set_value("Stineni.OBYVAK_ZALUZIE_GTSAP1_OPENER_target", 30)
    sim.set_value("OBYVAK_STROP_GTSAP1_LIGHT_tgtlevel", 15.0)
    assert sim.get_value("Stineni.OBYVAK_ZALUZIE_GTSAP1_OPENER_current") == 30
    assert sim.get_value("OBYVAK_STROP_GTSAP1_LIGHT_dimlevel") == 15.0


@pytest.mark.parametrize("links", [{"from": "a"}, [{"from": "plcName"}], ["x"]])
def test_malformed_links_are_refused(links: object) -> None:
    with pytest.raises(ProgramError, match="links"):
        program_with_links(links)


class Clock:
    """Seconds that pass only when a test says so."""

    def __init__(self) -> None:
        self.now = 1000.0

    def __call__(self) -> float:
        return self.now


def moving_demo(rate: float = 20.0) -> tuple[Simulator, Clock]:
    """The demo whose links move 20 units a second on a clock the test moves."""
    sim = Simulator("demo")
    clock = Clock()
    sim.link_motion.clock = clock
    sim.link_motion.rate = rate
    return sim, clock


def test_a_blind_moves_to_its_target_over_time() -> None:
    sim, clock = moving_demo()
    sim.set_value(f"{BLIND}_target", 0)

    positions = [sim.get_value(f"{BLIND}_current")]
    for _ in range(6):
        clock.now += 1.5
        positions.append(sim.get_value(f"{BLIND}_current"))

    assert positions == [100, 70, 40, 10, 0, 0, 0]
    assert sim.get_value(f"{BLIND}_target") == 0
    assert sim.plc.memory.moving is False


def test_a_moving_dimmer_keeps_its_fractions() -> None:
    sim, clock = moving_demo(rate=10.0)
    sim.set_value("OBYVAK_STROP_GTSAP1_LIGHT_tgtlevel", 64.0)
    clock.now += 0.25
    assert sim.get_value("OBYVAK_STROP_GTSAP1_LIGHT_dimlevel") == 62.5
    assert sim.plc.memory.moving is True


def test_a_new_target_turns_the_blind_where_it_is() -> None:
    sim, clock = moving_demo()
    sim.set_value(f"{BLIND}_target", 0)
    clock.now += 1.5
    sim.set_value(f"{BLIND}_target", 90)  # at 70 on its way down: up again
    clock.now += 0.5
    assert sim.get_value(f"{BLIND}_current") == 80
    clock.now += 10
    assert sim.get_value(f"{BLIND}_current") == 90


def test_a_write_to_the_moving_value_stops_its_motion() -> None:
    sim, clock = moving_demo()
    sim.set_value(f"{BLIND}_target", 0)
    clock.now += 1
    sim.set_value(f"{BLIND}_current", 55)  # the program stops it there
    clock.now += 10
    assert sim.get_value(f"{BLIND}_current") == 55
    assert sim.plc.memory.moving is False


def test_what_cannot_move_is_copied_or_skipped_as_before() -> None:
    sim = Simulator(program_with_links([{"from": "plcName", "to": "plcDesc"}]))
    sim.link_motion.rate = 20.0
    sim.set_value("plcName", "Foxy")  # text: copied at once
    assert sim.get_value("plcDesc") == "Foxy"
    number = Simulator(
        program_with_links([{"from": "Main.myObject3.value", "to": "plcType"}])
    )
    number.link_motion.rate = 20.0
    before = number.get_value("plcType")
    number.set_value("Main.myObject3.value", 12.5)  # a UINT cannot hold it
    assert number.get_value("plcType") == before
    assert number.plc.memory.moving is False


def test_the_motion_outlives_a_program_download() -> None:
    sim, _ = moving_demo()
    sim.load_program("demo")
    sim.set_value(f"{BLIND}_target", 0)
    assert sim.get_value(f"{BLIND}_current") == 100
