"""A program's links: what its logic does with a written value (the demo reacts)."""

import pytest

from tests.simulator import Program, Simulator, load_program
from tests.simulator.program import ProgramError


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
