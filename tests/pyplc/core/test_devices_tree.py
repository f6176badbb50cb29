"""The device tree's health: which devices, and so which points, serve live values.

A gateway's controller with two stations, a device on the first; what is offline
takes the devices below it along, never those beside or above it.
"""

from collections.abc import Mapping
from typing import Final

import pytest

from custom_components.tecoapi.pyplc import (
    Catalogue,
    DataType,
    DeviceNode,
    Point,
    ValueKind,
)

TREE: Final = (
    DeviceNode(key="controller", name="Controller"),
    DeviceNode(key="station_1", name="Station 1", parent="controller"),
    DeviceNode(key="station_2", name="Station 2", parent="controller"),
    DeviceNode(key="meter", name="Meter", parent="station_1"),
)


def point(key: str, device: str, *, diagnostic: bool = False) -> Point:
    return Point(
        key=key,
        path=key,
        address=key,
        type=DataType(kind=ValueKind.INTEGER),
        device=device,
        diagnostic=diagnostic,
    )


POINTS: Final = (
    point("own", ""),
    point("energy", "meter"),
    point("level", "station_2"),
    point("station_1_status", "station_1", diagnostic=True),
    point("controller_status", "controller", diagnostic=True),
    point("stray", "unknown"),
    point("stray_status", "unknown", diagnostic=True),
)


def catalogue(*nodes: DeviceNode) -> Catalogue:
    return Catalogue(
        points={p.key: p for p in POINTS},
        values={},
        groups=(),
        skipped_groups=(),
        devices={node.key: node for node in nodes or TREE},
    )


def serving(offline: Mapping[str, str], *, running: bool = True) -> set[str]:
    """The devices of the tree (and the source's own, "") that serve."""
    tree = catalogue()
    return {
        device
        for device in ("", *tree.devices, "unknown")
        if tree.device_serves(device, running=running, offline=offline)
    }


def served_points(offline: Mapping[str, str], *, running: bool = True) -> set[str]:
    tree = catalogue()
    return {
        key
        for key in (*tree.points, "no such point")
        if tree.point_serves(key, running=running, offline=offline)
    }


EVERY_DEVICE: Final = {"", "controller", "station_1", "station_2", "meter", "unknown"}


def test_every_device_serves_while_the_source_runs_and_none_is_offline() -> None:
    assert serving({}) == EVERY_DEVICE


def test_no_device_serves_while_the_source_does_not_run() -> None:
    """A PLC in HALT serves nothing, its own device included."""
    assert serving({}, running=False) == set()
    assert served_points({}, running=False) == set()


def test_an_offline_device_takes_the_devices_below_it_along() -> None:
    assert serving({"station_1": "no data exchange"}) == EVERY_DEVICE - {
        "station_1",
        "meter",
    }
    assert serving({"controller": "comm_failure"}) == {"", "unknown"}


def test_a_device_the_tree_does_not_know_sits_under_the_source() -> None:
    """It serves unless it is offline itself; nothing else takes it along."""
    assert "unknown" in serving({"controller": "comm_failure"})
    assert "unknown" not in serving({"unknown": "gone"})


def test_a_loop_in_the_tree_ends_the_walk() -> None:
    """Devices naming each other as parents are walked once (nothing hangs)."""
    tree = catalogue(
        DeviceNode(key="a", name="A", parent="b"),
        DeviceNode(key="b", name="B", parent="a"),
    )
    assert tree.device_serves("a", running=True, offline={})
    assert not tree.device_serves("a", running=True, offline={"b": "offline"})


def test_a_point_serves_with_its_device() -> None:
    assert served_points({}) == {p.key for p in POINTS}
    assert served_points({"station_1": "no data exchange"}) == {
        "own",
        "level",
        "station_1_status",
        "controller_status",
        "stray",
        "stray_status",
    }


@pytest.mark.parametrize(
    ("offline", "served"),
    [
        # A station's status tells that the station is offline: it is shown.
        ({"station_1": "no data exchange"}, True),
        # Its controller offline, nothing of the station can be told.
        ({"controller": "comm_failure"}, False),
    ],
)
def test_a_diagnostic_point_is_served_by_the_device_above_its_own(
    offline: Mapping[str, str], served: bool
) -> None:
    tree = catalogue()
    assert (
        tree.point_serves("station_1_status", running=True, offline=offline) is served
    )
    # The controller's own status sits under the source's device.
    assert tree.point_serves("controller_status", running=True, offline=offline)


def test_a_diagnostic_point_of_an_unknown_device_follows_that_device() -> None:
    """With no node to go above, it is served as its device is."""
    tree = catalogue()
    offline = {"unknown": "gone"}
    assert not tree.point_serves("stray_status", running=True, offline=offline)
    assert not tree.point_serves("stray", running=True, offline=offline)


def test_no_such_point_is_not_served() -> None:
    assert not catalogue().point_serves("no such point", running=True, offline={})
