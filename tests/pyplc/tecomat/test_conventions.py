"""Which systems' catalogues Tecomat's typed-device conventions are searched in.

Teco's GTSAP1 families are a library only a Tecomat program can contain: Tecomat's
descriptors register them, before the core's struct convention; the other systems
register the struct convention alone. Before, every system registered both (in
Tecomat's order): each gateway's demo catalogue still makes the same typed devices.
"""

from collections.abc import AsyncIterator, Awaitable, Callable
from dataclasses import replace
from typing import Final

import aiohttp
import pytest

from custom_components.tecoapi.pyplc.core import registry
from custom_components.tecoapi.pyplc.core.devices import Recogniser, find_devices
from custom_components.tecoapi.pyplc.core.models import Access, Catalogue
from custom_components.tecoapi.pyplc.core.pointmap import PointMap, load_csv
from custom_components.tecoapi.pyplc.core.structs import STRUCTS
from custom_components.tecoapi.pyplc.mervis import MervisClient, MervisSource
from custom_components.tecoapi.pyplc.mervis.vlist import load_vlist
from custom_components.tecoapi.pyplc.panasonic import (
    FpI4cClient,
    FpI4cSource,
    check_point,
)
from custom_components.tecoapi.pyplc.tecomat.conventions import RECOGNISERS
from custom_components.tecoapi.pyplc.tecomat.gtsap1 import GTSAP1
from custom_components.tecoapi.pyplc.tekon import TekonClient, TekonSource
from tests.simulator.fpi4c import EXAMPLE_CSV, FpI4cSimulator, demo_stations
from tests.simulator.mervis import MervisSimulator
from tests.simulator.mervis.project import Project, house, solution
from tests.simulator.tekon import TekonGateway

TECOMAT: Final = ("tecoapi", "plccoms")
GATEWAYS: Final = ("mervis", "fpi4c", "tekon")

type Found = tuple[list[str], list[str]]
"""The keys of the typed devices found, and of those skipped with a reason."""


def test_gtsap1_families_come_before_structs() -> None:
    assert RECOGNISERS == (GTSAP1, STRUCTS)
    assert [recogniser.name for recogniser in RECOGNISERS] == ["gtsap1", "struct"]


def test_tecomat_registers_gtsap1_and_the_others_the_struct_convention_alone() -> None:
    builtin = {
        descriptor.name: descriptor.recognisers
        for descriptor in registry.sources()
        if descriptor.name in {*TECOMAT, *GATEWAYS}
    }
    assert builtin == dict.fromkeys(TECOMAT, RECOGNISERS) | dict.fromkeys(
        GATEWAYS, (STRUCTS,)
    )


def _recognisers(name: str) -> tuple[Recogniser, ...]:
    return next(item.recognisers for item in registry.sources() if item.name == name)


def _found(catalogue: Catalogue, recognisers: tuple[Recogniser, ...]) -> Found:
    found = find_devices(catalogue.points, catalogue.values, recognisers)
    return sorted(found.devices), sorted(found.skipped)


def _writable_setpoints(point_map: PointMap) -> PointMap:
    """The house's rooms' setpoints marked writable, as a user marks them."""
    for room in ("jidelna", "koupelna", "sklep"):
        setpoint = point_map.by_key()[f"{room}.setpoint"]
        point_map = point_map.with_point(
            replace(setpoint, access=Access.READ_WRITE, minimum=15.0, maximum=28.0)
        )
    return point_map


async def _mervis(
    http: aiohttp.ClientSession,
    project: Project,
    mark: Callable[[PointMap], PointMap] = lambda point_map: point_map,
) -> Catalogue:
    async with MervisSimulator(project, username=None) as sim:
        source = MervisSource(
            MervisClient(http, sim.url), mark(load_vlist(project.vlist()))
        )
        return (await source.poll(())).catalogue


async def _fpi4c(http: aiohttp.ClientSession) -> Catalogue:
    async with FpI4cSimulator(demo_stations(), station=1) as gateway:
        point_map = load_csv(EXAMPLE_CSV.read_text(encoding="utf-8"), check_point)
        source = FpI4cSource(
            FpI4cClient(http, gateway.url), point_map, identity="gateway"
        )
        return (await source.poll(())).catalogue


async def _tekon(http: aiohttp.ClientSession) -> Catalogue:
    async with TekonGateway() as gateway:
        source = TekonSource(TekonClient(http, gateway.url))
        try:
            return (await source.poll(())).catalogue
        finally:
            await source.close()


CATALOGUES: Final[
    dict[str, tuple[str, Callable[[aiohttp.ClientSession], Awaitable[Catalogue]]]]
] = {
    "the Mervis demo (Chata Lipno)": ("mervis", lambda http: _mervis(http, house())),
    "the Mervis demo, its setpoints writable": (
        "mervis",
        lambda http: _mervis(http, house(), _writable_setpoints),
    ),
    "a real Mervis export": ("mervis", lambda http: _mervis(http, solution())),
    "the FP-I4C demo": ("fpi4c", _fpi4c),
    "the Tekon demo": ("tekon", _tekon),
}

FOUND_BEFORE: Final[dict[str, Found]] = {
    "the Mervis demo (Chata Lipno)": (
        [],
        ["struct:climate:jidelna", "struct:climate:koupelna", "struct:climate:sklep"],
    ),
    "the Mervis demo, its setpoints writable": (
        ["struct:climate:jidelna", "struct:climate:koupelna", "struct:climate:sklep"],
        [],
    ),
    "a real Mervis export": ([], []),
    "the FP-I4C demo": ([], []),
    "the Tekon demo": ([], []),
}
"""What the recognisers of every system (GTSAP1, then structs) found at engine-base."""


@pytest.fixture
async def http(socket_enabled: None) -> AsyncIterator[aiohttp.ClientSession]:
    async with aiohttp.ClientSession() as session:
        yield session


@pytest.mark.parametrize("catalogue", CATALOGUES)
async def test_no_gateway_catalogue_loses_a_device(
    http: aiohttp.ClientSession, catalogue: str
) -> None:
    """The system's recognisers find what Tecomat's order found, device for device."""
    system, discover = CATALOGUES[catalogue]
    discovered = await discover(http)
    assert _found(discovered, _recognisers(system)) == FOUND_BEFORE[catalogue]
    found = find_devices(discovered.points, discovered.values, _recognisers(system))
    before = find_devices(discovered.points, discovered.values, RECOGNISERS)
    assert found == before
