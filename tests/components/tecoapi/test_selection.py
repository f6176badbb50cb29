"""What of a catalogue becomes entities and devices: the options and compositions decide.

The include and exclude patterns choose the points, the plain-variables option
whether variables without metadata become entities, the device grouping which
devices they sit on (a group per top-level name or device the source declares,
a room's area where a name says one), and the user's compositions add typed
devices (a broken one is kept as what breaks it).
"""

from types import SimpleNamespace
from typing import Final

import pytest

from custom_components.tecoapi.compat import AREA_IN_ENTITY_ID
from custom_components.tecoapi.const import DeviceGrouping, PlainVariables
from custom_components.tecoapi.options import PlcOptions
from custom_components.tecoapi.pyplc.core.devices import DeviceKind
from custom_components.tecoapi.pyplc.core.models import DeviceNode
from custom_components.tecoapi.selection import (
    Composition,
    compositions_of,
    joined,
    select,
)
from tests.components.tecoapi.catalogues import BOOL, catalogue, point

HOUSE: Final = catalogue(
    point("Outside", title="Outside temperature"),
    point("Kitchen.temp", title="Temperature"),
    point("Kitchen.debug", title="Debug"),
    point("Heating.pump", kind=BOOL, title="Pump", writable=True),
    point("Heating.counter", described=False),
    point("Station.level", title="Level", device="station"),
    groups=("Outside", "Kitchen", "Heating", "Station"),
    devices={"station": DeviceNode(key="station", name="Garage", model="S-2")},
)


def test_the_patterns_choose_the_points() -> None:
    chosen = select(HOUSE, PlcOptions(include=("kitchen.*",), exclude=("*debug",)))

    assert set(chosen.points) == {"kitchen.temp"}
    assert chosen.watched == {"kitchen.temp"}


@pytest.mark.parametrize(
    ("plain", "shown"),
    [
        (PlainVariables.IGNORED, False),
        (PlainVariables.DISABLED, True),
        (PlainVariables.ENABLED, True),
    ],
)
def test_plain_variables_are_shown_as_the_option_says(
    plain: PlainVariables, shown: bool
) -> None:
    chosen = select(HOUSE, PlcOptions(plain_variables=plain))

    assert ("heating.counter" in chosen.points) is shown
    if shown:
        description = chosen.descriptions["heating.counter"]
        assert description.enabled_default is (plain is PlainVariables.ENABLED)


def test_a_group_per_top_level_name_and_declared_device() -> None:
    chosen = select(HOUSE, PlcOptions(devices=DeviceGrouping.GROUPS))

    assert set(chosen.groups) == {"kitchen", "heating", "station"}
    assert chosen.group_of("Heating.pump") == chosen.groups["heating"]
    # A top-level variable sits on the source's own device.
    assert chosen.group_of("Outside") is None
    station = chosen.group_of("Station.level")
    assert station is not None
    assert (station.key, station.name, station.model) == ("station", "Garage", "S-2")


def test_everything_on_one_device() -> None:
    chosen = select(HOUSE, PlcOptions(devices=DeviceGrouping.SINGLE))

    assert chosen.groups == {}
    assert chosen.group_of("Station.level") is None


def test_a_group_named_a_room_suggests_its_area_only_with_areas() -> None:
    with_areas = select(HOUSE, PlcOptions(devices=DeviceGrouping.GROUPS_AND_AREAS))
    without = select(HOUSE, PlcOptions(devices=DeviceGrouping.GROUPS))

    # Only a room: where entity IDs start with the area, it would say it twice.
    expected = None if AREA_IN_ENTITY_ID else "Kitchen"
    assert with_areas.groups["kitchen"].area == expected
    assert without.groups["kitchen"].area is None


def test_a_composition_adds_a_typed_device_or_tells_what_breaks_it() -> None:
    fits = Composition(
        subentry_id="s1",
        kind=DeviceKind.SWITCH,
        name="Pump",
        roles={"onoff": "heating.pump"},
    )
    broken = Composition(
        subentry_id="s2",
        kind=DeviceKind.SWITCH,
        name="Gone",
        roles={"onoff": "heating.gone"},
    )

    chosen = select(HOUSE, PlcOptions(), [fits, broken])

    (device,) = chosen.devices.values()
    assert device.composed
    assert device.name == "Pump"
    assert "heating.pump" in chosen.watched
    assert set(chosen.broken) == {"s2"}
    # A composed device is a device of its own, named as the user named it.
    assert chosen.places[device.key].name == "Pump"


def test_compositions_are_read_from_the_entry_s_subentries() -> None:
    subentry = SimpleNamespace(
        title="Garden pump", data={"kind": "switch", "roles": {"onoff": "pump"}}
    )

    assert compositions_of({"s1": subentry}) == [
        Composition(
            subentry_id="s1",
            kind=DeviceKind.SWITCH,
            name="Garden pump",
            roles={"onoff": "pump"},
        )
    ]


@pytest.mark.parametrize(
    ("where", "what", "name"),
    [
        ("Dětský pokoj", "Thermostat", "Dětský pokoj thermostat"),
        ("Kuchyň", "LED pásek", "Kuchyň LED pásek"),
        ("Kuchyň", "CO2 sensor", "Kuchyň CO2 sensor"),
    ],
)
def test_a_name_says_where_then_what(where: str, what: str, name: str) -> None:
    assert joined(where, what) == name
