"""Generated programs: exact point counts, realistic names, deterministic, servable."""

from collections import Counter
from collections.abc import Iterator
from typing import Any

import aiohttp
import pytest

from tests.simulator import Simulator, generate_program
from tests.simulator.iec import ArrayOf, IecType, Struct, leaf_count
from tests.simulator.program import API_OBJECT_ATTR, Program
from tests.simulator_tests.conftest import fetch


def api_objects(program: Program) -> Iterator[tuple[str, str, Struct, Any]]:
    """(name, where, T_ApiObject type, value) for every T_ApiObject in a program."""

    def walk(name: str, where: str, iec_type: IecType, value: Any) -> Iterator[Any]:
        if (
            isinstance(iec_type, Struct)
            and iec_type.members.get("attr") == API_OBJECT_ATTR
        ):
            yield name, where, iec_type, value
        elif isinstance(iec_type, Struct):
            inner = "instance" if iec_type.type_name.startswith("prg") else "struct"
            for member, member_type in iec_type.members.items():
                yield from walk(
                    member,
                    where if where != "top" else inner,
                    member_type,
                    value[member],
                )
        elif isinstance(iec_type, ArrayOf):
            for element in value:
                yield from walk(name, "array", iec_type.element, element)

    for declaration in program.declarations:
        yield from walk(declaration.name, "top", declaration.type, declaration.initial)


@pytest.mark.parametrize("points", [0, 1, 7, 50, 300, 1000])
def test_exactly_the_requested_number_of_points(points: int) -> None:
    assert len(list(api_objects(generate_program(points)))) == points


def test_deterministic_for_a_seed() -> None:
    assert (
        generate_program(300, seed=4).to_mapping()
        == generate_program(300, seed=4).to_mapping()
    )
    assert generate_program(300, seed=4).stamp != generate_program(300, seed=5).stamp
    assert generate_program(300).stamp != generate_program(301).stamp


def test_names_are_realistic_and_unique() -> None:
    objects = list(api_objects(generate_program(1000, seed=7)))
    names = [name for name, where, _, _ in objects if where != "array"]
    array_names = {name for name, where, _, _ in objects if where == "array"}

    assert all(12 <= len(name) <= 30 for name in [*names, *array_names])
    assert len({name.lower() for name in names}) == len(names)
    assert max(len(name) for name in names) >= 25


def test_a_mix_of_kinds_placements_and_metadata() -> None:
    objects = list(api_objects(generate_program(1000, seed=1)))
    kinds = Counter(t.members["value"].type_name for _, _, t, _ in objects)
    places = Counter(where for _, where, _, _ in objects)
    attrs = [value["attr"] for _, _, _, value in objects]

    assert set(kinds) == {"REAL", "INT", "UINT", "BOOL", "STRING"}
    assert kinds["REAL"] > kinds["BOOL"] > kinds["STRING"]
    assert set(places) == {"top", "instance", "struct", "array"}
    assert places["top"] >= 300
    assert 0.4 < sum(a["readOnly"] for a in attrs) / len(attrs) < 0.8
    ranged = [a for a in attrs if a["minValue"] != a["maxValue"]]
    assert ranged
    assert all(not a["readOnly"] and a["minValue"] < a["maxValue"] for a in ranged)
    assert {a["units"] for a in attrs} >= {"°C", "%", "W", "kWh"}
    assert all(0 < len(a["title"]) <= 32 for a in attrs)


def test_nested_structs_and_plain_scalars() -> None:
    program = generate_program(300)
    nested = [
        d
        for d in program.declarations
        if isinstance(d.type, Struct)
        and any(
            isinstance(t, Struct) and t.members.get("attr") != API_OBJECT_ATTR
            for t in d.type.members.values()
        )
        and not d.type.type_name.startswith("prg")
    ]
    plain = [
        d for d in program.declarations if not isinstance(d.type, Struct | ArrayOf)
    ]

    assert nested
    assert {d.type.type_name for d in plain} >= {
        "BOOL",
        "UDINT",
        "REAL",
        "STRING",
        "DATE",
    }


@pytest.mark.parametrize(
    ("plc_type", "family"), [("CP-2080", "Fx2"), ("CP-1000", "Fx1")]
)
def test_plc_type(plc_type: str, family: str) -> None:
    plc = generate_program(10, plc_type=plc_type).plc

    assert (plc.type, plc.family) == (plc_type, family)


def test_negative_points_are_refused() -> None:
    with pytest.raises(ValueError, match="points"):
        generate_program(-1)


async def test_every_root_of_a_generated_program_fits_one_response(
    session: aiohttp.ClientSession, socket_enabled: None
) -> None:
    program = generate_program(300, seed=2, plc_type="CP-1000")
    sizes = {d.name: leaf_count(d.type) for d in program.declarations}
    async with Simulator(
        program, username="admin", password="s3cret-Pa55", auth="basic"
    ) as sim:
        roots = list((await fetch(session, sim, "/TecoApi/GetList")).json())
        statuses = {
            root: (await fetch(session, sim, f"/TecoApi/GetObject?{root}")).status
            for root in roots
        }

    assert roots == list(sizes)
    assert sim.item_limit == 128
    # GetList names roots only: a root larger than one response could never be
    # discovered by a client, so the generator keeps every root within the limit.
    assert max(sizes.values()) <= 128
    assert statuses == dict.fromkeys(sizes, 200)


def test_points_in_a_given_number_of_roots_each_fitting_one_response() -> None:
    program = generate_program(400, plc_type="CP-1000", roots=27)

    assert len(program.declarations) == 27
    assert len(list(api_objects(program))) == 400
    sizes = [leaf_count(declaration.type) for declaration in program.declarations]
    assert max(sizes) == 128
    assert min(sizes) >= 8
    places = Counter(where for _, where, _, _ in api_objects(program))
    assert set(places) == {"instance", "struct", "array"}
    with pytest.raises(ValueError):
        generate_program(400, plc_type="CP-1000", roots=20)
