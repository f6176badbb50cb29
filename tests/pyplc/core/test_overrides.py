"""What the user changes of a discovered point: which changes it takes, applied, kept.

The write checks of a changed point (``codec.check_write``) are tested here
too: a plain point made writable or read only, a range given in place of the
device's.
"""

from dataclasses import replace
from typing import Any

import pytest

from custom_components.tecoapi.pyplc import (
    Access,
    Catalogue,
    DataType,
    OutOfRangeError,
    Point,
    PointAttributes,
    ReadOnlyError,
    ValueKind,
)
from custom_components.tecoapi.pyplc.core.codec import check_write
from custom_components.tecoapi.pyplc.core.composition import is_writable
from custom_components.tecoapi.pyplc.core.models import NO_OVERRIDE, PointOverride
from custom_components.tecoapi.pyplc.core.overrides import (
    HALF_RANGE,
    NOT_TAKEN,
    NOT_WRITABLE,
    RANGE,
    STEP,
    OverrideError,
    OverrideProblem,
    apply_override,
    apply_overrides,
    check_override,
    fitting,
    override_from_json,
    override_json,
    override_problems,
    overrides_from_json,
    overrides_json,
)

INTEGER = DataType(kind=ValueKind.INTEGER, bits=16)


def plain(kind: ValueKind = ValueKind.INTEGER, *, settable: bool = True) -> Point:
    """A variable without metadata (a Tecomat plain variable: settable)."""
    data_type = INTEGER if kind is ValueKind.INTEGER else DataType(kind=kind)
    return Point(
        key="counter",
        path="Counter",
        address="Counter",
        type=data_type,
        settable=settable,
    )


def described(
    kind: ValueKind = ValueKind.INTEGER,
    access: Access = Access.READ,
    *,
    settable: bool = False,
    **attributes: Any,
) -> Point:
    """A point with attributes (a T_ApiObject, a gateway's item)."""
    data_type = INTEGER if kind is ValueKind.INTEGER else DataType(kind=kind)
    return Point(
        key="item",
        path="Item",
        address="Item",
        type=data_type,
        attributes=PointAttributes(name="Item", access=access, **attributes),
        settable=settable,
    )


# --- which changes a point takes ------------------------------------------------------


def test_a_plain_variable_the_device_writes_may_be_made_writable() -> None:
    point = plain()
    override = PointOverride(writable=True, unit="kWh", state_class="total_increasing")

    assert override_problems(point, override) == []
    changed = apply_override(point, override)
    assert changed.writable
    assert not point.writable
    assert changed.unit_of() == "kWh"
    assert changed.state_class == "total_increasing"
    # Still a plain variable: the source reads it as one.
    assert not changed.described


def test_a_point_whose_rights_are_read_only_cannot_be_made_writable() -> None:
    """A gateway's item whose access rights say read: the device takes no write."""
    point = described()

    with pytest.raises(OverrideError) as raised:
        check_override(point, PointOverride(writable=True))

    assert (raised.value.field, raised.value.reason) == ("writable", NOT_WRITABLE)
    assert not apply_override(point, PointOverride(writable=True)).writable


def test_a_point_shown_read_only_whose_rights_allow_a_write_may_be() -> None:
    """A discrete input whose rights say read and write."""
    point = described(ValueKind.BOOL, settable=True)

    check_override(point, PointOverride(writable=True))

    assert apply_override(point, PointOverride(writable=True)).writable


@pytest.mark.parametrize(
    ("kind", "override", "field"),
    [
        (ValueKind.INTEGER, PointOverride(invert=True), "invert"),
        (ValueKind.BOOL, PointOverride(unit="kWh"), "unit"),
        (ValueKind.BOOL, PointOverride(minimum=0.0), "minimum"),
        (ValueKind.STRING, PointOverride(state_class="total"), "state_class"),
        (ValueKind.STRING, PointOverride(device_class="door"), "device_class"),
        (ValueKind.RECORD, PointOverride(platform="sensor"), "platform"),
    ],
)
def test_a_change_the_kind_has_no_place_for_is_not_taken(
    kind: ValueKind, override: PointOverride, field: str
) -> None:
    assert override_problems(plain(kind), override) == [
        OverrideProblem(field, NOT_TAKEN)
    ]


def test_a_point_written_only_takes_no_change() -> None:
    """A button (an intercom's call): it is never read, nothing of it is shown."""
    point = described(ValueKind.BOOL, Access.WRITE)

    assert override_problems(point, PointOverride(writable=False)) == [
        OverrideProblem("writable", NOT_TAKEN)
    ]


def test_a_range_is_checked_with_the_device_s_bound_where_one_end_is_given() -> None:
    point = described(minimum=10.0, maximum=30.0)

    assert override_problems(point, PointOverride(maximum=5.0)) == [
        OverrideProblem("maximum", RANGE)
    ]
    assert override_problems(point, PointOverride(minimum=40.0)) == [
        OverrideProblem("minimum", RANGE)
    ]
    assert override_problems(point, PointOverride(minimum=40.0, maximum=50.0)) == []


def test_one_end_of_a_range_needs_the_device_s_other_end() -> None:
    """A range is checked with both ends: a half one would check nothing."""
    assert override_problems(plain(), PointOverride(maximum=5.0)) == [
        OverrideProblem("maximum", HALF_RANGE)
    ]
    assert (
        override_problems(
            described(minimum=0.0, maximum=10.0), PointOverride(maximum=5.0)
        )
        == []
    )
    assert apply_override(plain(), PointOverride(maximum=5.0)).range_of() == (
        None,
        None,
    )


@pytest.mark.parametrize("step", [0.0, -1.0, float("inf")])
def test_a_step_is_above_zero(step: float) -> None:
    assert override_problems(plain(), PointOverride(step=step)) == [
        OverrideProblem("step", STEP)
    ]


def test_what_a_point_does_not_take_is_left_out_until_it_fits() -> None:
    """After a new program a variable may be another kind, or another range."""
    point = described(minimum=10.0, maximum=30.0)
    override = PointOverride(minimum=50.0, maximum=5.0, unit="kWh", invert=True)

    assert fitting(point, override) == PointOverride(unit="kWh")
    changed = apply_override(point, override)
    assert changed.range_of() == (10.0, 30.0)
    assert not changed.invert


# --- applied ------------------------------------------------------------------------------


def test_how_a_point_is_shown_is_the_user_s() -> None:
    point = described(ValueKind.BOOL, Access.READ_WRITE)
    override = PointOverride(device_class="door", invert=True, platform="binary_sensor")

    changed = apply_override(point, override)

    assert (changed.device_class, changed.invert, changed.platform) == (
        "door",
        True,
        "binary_sensor",
    )
    assert changed.override == override
    # What it changes nothing of stays the device's.
    assert changed.attributes == point.attributes


def test_an_override_that_changes_nothing_leaves_the_point_as_it_is() -> None:
    point = described()

    assert apply_override(point, NO_OVERRIDE) is point
    assert apply_override(point, PointOverride(writable=True)) is point


def test_a_catalogue_gets_the_overrides_of_its_points_and_keeps_the_others() -> None:
    point, other = plain(), replace(plain(), key="other", path="Other")
    catalogue = Catalogue(
        points={point.key: point, other.key: other},
        values={},
        groups=(),
        skipped_groups=(),
    )
    overrides = {
        "counter": PointOverride(writable=True),
        "gone": PointOverride(writable=True),
    }

    changed = apply_overrides(catalogue, overrides)

    assert changed.points["counter"].writable
    assert changed.points["other"] is other
    assert "gone" not in changed.points
    assert apply_overrides(catalogue, {"gone": PointOverride(unit="kWh")}) is catalogue


# --- what a changed point takes in a write ------------------------------------------------


def test_a_plain_variable_made_read_only_refuses_a_write() -> None:
    """A plain variable's write is taken (an action's); made read only, not."""
    point = plain()
    check_write(point, 5)

    with pytest.raises(ReadOnlyError):
        check_write(apply_override(point, PointOverride(writable=False)), 5)
    assert not is_writable(apply_override(point, PointOverride(writable=False)))


def test_a_read_only_point_made_writable_takes_a_write_whatever_its_latest_attributes() -> (
    None
):
    """A T_ApiObject whose readOnly is true (the PLC takes a write anyway)."""
    point = described(settable=True)
    changed = apply_override(point, PointOverride(writable=True))

    assert check_write(changed, 7, point.attributes) == 7
    with pytest.raises(ReadOnlyError):
        check_write(point, 7)


def test_a_range_given_checks_a_write_in_place_of_the_device_s() -> None:
    point = described(access=Access.READ_WRITE, minimum=0.0, maximum=100.0)
    changed = apply_override(point, PointOverride(maximum=50.0))

    assert check_write(point, 80) == 80
    with pytest.raises(OutOfRangeError) as raised:
        check_write(changed, 80, point.attributes)
    assert (raised.value.min_value, raised.value.max_value) == (0.0, 50.0)


def test_a_plain_variable_s_range_is_the_user_s() -> None:
    changed = apply_override(
        plain(), PointOverride(writable=True, minimum=1.0, maximum=9.0)
    )

    assert check_write(changed, 9) == 9
    with pytest.raises(OutOfRangeError):
        check_write(changed, 10)


# --- kept as JSON -----------------------------------------------------------------------------


def test_an_override_is_kept_as_what_it_changes() -> None:
    override = PointOverride(writable=True, unit="kWh", minimum=0.0, invert=False)

    assert override_json(override) == {
        "writable": True,
        "unit": "kWh",
        "minimum": 0.0,
        "invert": False,
    }
    assert override_from_json(override_json(override)) == override


def test_overrides_that_change_nothing_are_not_kept_and_unknown_keys_are_ignored() -> (
    None
):
    overrides = {"a": PointOverride(unit="W"), "b": NO_OVERRIDE}

    assert overrides_json(overrides) == {"a": {"unit": "W"}}
    assert overrides_from_json({"a": {"unit": "W", "colour": "red"}}) == {
        "a": PointOverride(unit="W")
    }
