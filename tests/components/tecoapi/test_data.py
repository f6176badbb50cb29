"""What the entities show, and which of it an update changed.

The first snapshot selects from its catalogue; later ones merge what they read
into what is shown and mark changed only the keys whose value, attributes,
quality or availability differ: an update costs what it read.
"""

from dataclasses import replace
from datetime import UTC, datetime, timedelta
from typing import Final

from custom_components.tecoapi.const import (
    STATUS_CLOCK_OFFSET,
    STATUS_MODE,
    STATUS_PROGRAM_NAME,
    STATUS_RUNNING_PROBLEM,
)
from custom_components.tecoapi.data import PlcData, shown_clock_offset, updated_data
from custom_components.tecoapi.options import PlcOptions
from custom_components.tecoapi.pyplc import PointQuality, Quality
from custom_components.tecoapi.pyplc.core.models import DeviceNode, PlcMode
from custom_components.tecoapi.selection import selector
from tests.components.tecoapi.catalogues import (
    BOOL,
    INFO,
    catalogue,
    point,
    snapshot,
)

SELECT: Final = selector(PlcOptions(), [], [])
HOUSE: Final = catalogue(
    point("Outside", title="Outside temperature", unit="°C"),
    point("Heating.setpoint", title="Setpoint", writable=True),
    point("Pump", kind=BOOL, title="Pump"),
    point("Station.level", title="Level", device="station"),
    values={"outside": 4.5, "heating.setpoint": 21.5, "pump": False},
    devices={"station": DeviceNode(key="station", name="Station")},
)
NOW: Final = datetime(2026, 3, 14, 10, tzinfo=UTC)


def _first() -> PlcData:
    return updated_data(None, snapshot(HOUSE), SELECT)


def test_the_first_snapshot_selects_and_changes_nothing() -> None:
    data = _first()

    assert set(data.points) == {"outside", "heating.setpoint", "pump", "station.level"}
    assert data.values["outside"] == 4.5
    assert data.attributes["outside"].unit == "°C"
    assert data.changed == frozenset()
    assert data.running


def test_a_poll_marks_changed_only_what_differs() -> None:
    before = _first()

    after = updated_data(
        before, snapshot(HOUSE, {"outside": 4.5, "heating.setpoint": 22.0}), SELECT
    )

    assert after.changed == {"heating.setpoint"}
    assert after.values["heating.setpoint"] == 22.0
    # What was not read is still shown; the selection is the same object.
    assert after.values["pump"] is False
    assert after.selection is before.selection


def test_a_value_of_another_type_is_a_change() -> None:
    """``0`` read as ``False`` (or ``1.0`` as ``1``) shows otherwise."""
    before = _first()

    after = updated_data(before, snapshot(HOUSE, {"pump": 0}), SELECT)

    assert after.changed == {"pump"}


def test_quality_and_the_device_s_mode_change_what_is_shown() -> None:
    before = _first()
    bad = {"outside": PointQuality(quality=Quality.BAD, reason="gone")}

    missing = updated_data(before, snapshot(HOUSE, {}, quality=bad), SELECT)
    stopped = updated_data(
        missing, snapshot(HOUSE, {}, info=replace(INFO, mode=PlcMode.STOPPED)), SELECT
    )

    assert missing.changed == {"outside"}
    assert missing.missing == {"outside"}
    assert not missing.point_available("outside")
    assert missing.point_available("pump")
    # Stopped: every point's availability and the mode's entities change.
    assert stopped.changed == {
        *stopped.selection.watched,
        STATUS_MODE,
        STATUS_RUNNING_PROBLEM,
    }
    assert not stopped.point_available("pump")


def test_a_device_offline_changes_its_points_only() -> None:
    before = _first()

    after = updated_data(
        before, snapshot(HOUSE, {}, offline={"station": "no data"}), SELECT
    )

    assert after.changed == {"station.level"}
    assert not after.device_available("station")
    assert after.device_available("")
    assert not after.point_available("station.level")


def test_a_new_program_is_selected_anew() -> None:
    before = _first()
    program = catalogue(point("Outside", title="Outside"), point("Garage", kind=BOOL))

    after = updated_data(
        before,
        snapshot(program, info=replace(INFO, program_name="HOUSE v2")),
        SELECT,
    )

    assert set(after.points) == {"outside", "garage"}
    assert after.selection is not before.selection
    assert STATUS_PROGRAM_NAME in after.changed


def test_attributes_come_from_the_latest_read_else_the_catalogue() -> None:
    data = _first()

    assert (
        data.point_attributes("heating.setpoint")
        == HOUSE.points["heating.setpoint"].attributes
    )
    assert data.point_attributes("nothing") is None


def test_the_clock_offset_moves_only_beyond_its_tolerance() -> None:
    info = replace(INFO, time=NOW + timedelta(seconds=30.4))

    assert shown_clock_offset(info, NOW, None) == 30
    assert shown_clock_offset(info, NOW, 31) == 31
    assert shown_clock_offset(info, NOW, 29) == 30
    assert shown_clock_offset(replace(INFO, time=None), NOW, 30) is None


def test_a_new_clock_offset_is_a_change() -> None:
    before = _first()
    read = replace(
        snapshot(HOUSE, {}, info=replace(INFO, time=NOW + timedelta(seconds=5))),
        info_read_at=NOW,
    )

    after = updated_data(before, read, SELECT)

    assert after.clock_offset == 5
    assert STATUS_CLOCK_OFFSET in after.changed
