"""What the user changed of discovered points: which changes a point takes, applied.

A source that discovers its points (a PLC's program, a gateway's address space)
describes them as its device does; the user may see it otherwise: a variable
without metadata that should be written, a counter in kWh whose history is a
total, a contact that is true when its door is closed. A
:class:`~.models.PointOverride` per point key says so; a source is given them
(``overrides``, :class:`~.source.BaseSource`) and applies them to every
catalogue it discovers (:func:`apply_overrides`), so its writes are checked as
the point now is. A point that is gone keeps its override for when it comes
back (a new program); a change a point cannot take (an inverted number, a
writable point its device does not write) is left out of it.

Which changes a point takes (:func:`override_problems`):

- ``writable``: made writable where its device takes a write (a writable point,
  or a :attr:`~.models.Point.settable` one: a Tecomat variable without
  metadata), or read only;
- ``unit``, ``state_class``, ``minimum``, ``maximum``, ``step``: a number's
  (a range's lowest not above its highest, both ends known: one given where
  the device has the other; a step above 0);
- ``device_class``: a flag's or a number's;
- ``invert``: a flag's;
- ``platform``: any point's (the caller says what it may be shown as);
- nothing of a record (a lift's state) or of a point written only (a button).

Nothing here does I/O.
"""

from collections.abc import Mapping
from dataclasses import dataclass, fields, replace
import math
from typing import Any, Final

from .models import (
    NUMERIC_KINDS,
    Catalogue,
    Point,
    PointOverride,
    ValueKind,
)

FLAG_FIELDS: Final = frozenset({"writable", "device_class", "invert", "platform"})
"""What a flag's override may change."""
NUMBER_FIELDS: Final = frozenset(
    {
        "writable",
        "unit",
        "device_class",
        "state_class",
        "minimum",
        "maximum",
        "step",
        "platform",
    }
)
"""What a number's override may change."""
OTHER_FIELDS: Final = frozenset({"writable", "platform"})
"""What the override of a text, a date, a time or a duration may change."""
NOT_WRITABLE: Final = "not_writable"
"""A problem's reason: the device does not take a write of the point."""
NOT_TAKEN: Final = "not_taken"
"""A problem's reason: the point's kind has no such field (a text's unit)."""
RANGE: Final = "range"
"""A problem's reason: the lowest value is above the highest."""
HALF_RANGE: Final = "half_range"
"""A problem's reason: one end of a range, and the device has no other end."""
STEP: Final = "step"
"""A problem's reason: a step that is not above 0."""


@dataclass(frozen=True, slots=True)
class OverrideProblem:
    """Why a point does not take one of an override's changes.

    ``field`` is the override's field (``minimum``...), ``reason`` one of this
    module's reasons (:data:`NOT_WRITABLE`...).
    """

    field: str
    reason: str


class OverrideError(ValueError):
    """An override a point does not take: its first problem."""

    def __init__(self, problem: OverrideProblem) -> None:
        """Say which field, and why."""
        super().__init__(f"{problem.field}: {problem.reason}")
        self.field = problem.field
        self.reason = problem.reason


def fields_of(point: Point) -> frozenset[str]:
    """Return the fields an override of a point may change, by the value it shows.

    None of a point that cannot be read (written only: a button) or that is a
    record (read only, shown as its text).
    """
    attributes = point.attributes
    if point.kind is ValueKind.RECORD or (
        attributes is not None and not attributes.access.readable
    ):
        return frozenset()
    if point.kind is ValueKind.BOOL:
        return FLAG_FIELDS
    if point.kind in NUMERIC_KINDS:
        return NUMBER_FIELDS
    return OTHER_FIELDS


def write_allowed(point: Point) -> bool:
    """Whether the point's device takes a write of it (the user may make it writable)."""
    return point.settable or (
        point.attributes is not None and point.attributes.writable
    )


def override_problems(point: Point, override: PointOverride) -> list[OverrideProblem]:
    """Return what of an override the point does not take (none: it takes it all).

    ``point`` is as its source describes it (no override of its own applied).
    """
    taken = fields_of(point)
    problems = [
        OverrideProblem(item.name, NOT_TAKEN)
        for item in fields(override)
        if getattr(override, item.name) is not None and item.name not in taken
    ]
    if override.writable and "writable" in taken and not write_allowed(point):
        problems.append(OverrideProblem("writable", NOT_WRITABLE))
    if "minimum" in taken:
        low, high = replace(point, override=override).range_of()
        given = "minimum" if override.minimum is not None else "maximum"
        if (override.minimum, override.maximum) != (None, None) and (
            low is None or high is None
        ):
            problems.append(OverrideProblem(given, HALF_RANGE))
        elif low is not None and high is not None and low > high:
            problems.append(OverrideProblem(given, RANGE))
        step = override.step
        if step is not None and not (math.isfinite(step) and step > 0):
            problems.append(OverrideProblem("step", STEP))
    return problems


def check_override(point: Point, override: PointOverride) -> None:
    """Raise :class:`OverrideError` for the first change the point does not take."""
    if problems := override_problems(point, override):
        raise OverrideError(problems[0])


def fitting(point: Point, override: PointOverride) -> PointOverride:
    """Return the override without the changes the point does not take."""
    while problems := override_problems(point, override):
        override = replace(override, **{problem.field: None for problem in problems})
    return override


def apply_override(point: Point, override: PointOverride) -> Point:
    """Return the point as the user changed it (what it does not take left out)."""
    fit = fitting(point, override)
    if fit.empty:
        return point
    return replace(
        point,
        override=fit,
        platform=_or(fit.platform, point.platform),
        device_class=_or(fit.device_class, point.device_class),
        state_class=_or(fit.state_class, point.state_class),
        step=_or(fit.step, point.step),
        invert=_or(fit.invert, point.invert),
    )


def apply_overrides(
    catalogue: Catalogue, overrides: Mapping[str, PointOverride]
) -> Catalogue:
    """Return the catalogue with the overrides of its points applied (itself: none)."""
    changed = {
        key: applied
        for key, override in overrides.items()
        if (point := catalogue.points.get(key)) is not None
        and (applied := apply_override(point, override)) is not point
    }
    if not changed:
        return catalogue
    return replace(catalogue, points={**catalogue.points, **changed})


def _or[T](given: T | None, kept: T) -> T:
    return kept if given is None else given


def override_json(override: PointOverride) -> dict[str, Any]:
    """Return an override as JSON (what it changes only)."""
    return {
        item.name: value
        for item in fields(override)
        if (value := getattr(override, item.name)) is not None
    }


def override_from_json(data: Mapping[str, Any]) -> PointOverride:
    """Return an override stored by :func:`override_json` (unknown keys ignored)."""
    known = {item.name for item in fields(PointOverride)}
    return PointOverride(**{key: data[key] for key in known if key in data})


def overrides_json(overrides: Mapping[str, PointOverride]) -> dict[str, Any]:
    """Return overrides by point key as JSON, leaving out those that change nothing."""
    return {
        key: override_json(override)
        for key, override in overrides.items()
        if not override.empty
    }


def overrides_from_json(data: Mapping[str, Any]) -> dict[str, PointOverride]:
    """Return overrides by point key stored by :func:`overrides_json`."""
    return {key: override_from_json(item) for key, item in data.items()}
