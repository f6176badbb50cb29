"""Typed devices the user composes in the UI from any points: the rules per kind.

:data:`COMPOSITIONS` says which roles each composable kind has, which are
required and which the device writes; :func:`fitting_points` lists the points
that may play a role; :func:`compose` checks a user's choice and makes the
device. :func:`build` makes a device of chosen roles as strictly for a
recogniser whose convention names the members of a device (a struct's).
This module knows nothing of Home Assistant, nor of any system.
"""

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from enum import StrEnum
import re
from types import MappingProxyType
from typing import Any, Final

from .devices import (
    COMPOSED,
    ROLE_KINDS,
    ClimateSupport,
    CoverClass,
    DeviceKind,
    LightMode,
    Role,
    TypedDevice,
    folded,
    identifier_words,
    is_gate_name,
    name_from_base,
)
from .models import Point, ValueKind


@dataclass(frozen=True, slots=True, kw_only=True)
class RoleSpec:
    """One role of a composable kind.

    ``written``: the device writes it, so a point said to be read-only cannot
    play it. ``defaults_to``: when not chosen, the point of that role plays it too
    (a blind without a separate target is moved by writing its position).
    ``needs``: the role only makes sense with that one (colour temperature
    needs a level).
    """

    role: Role
    kinds: frozenset[ValueKind]
    required: bool = False
    written: bool = False
    defaults_to: Role | None = None
    needs: Role | None = None

    def accepts(self, point: Point) -> bool:
        """Whether ``point`` may play this role (its kind; writable if written)."""
        return point.kind in self.kinds and (not self.written or is_writable(point))


@dataclass(frozen=True, slots=True, kw_only=True)
class KindSpec:
    """The roles of a composable kind; ``needs_any_of``: at least one of these."""

    kind: DeviceKind
    roles: tuple[RoleSpec, ...]
    needs_any_of: frozenset[Role] = frozenset()

    def role(self, role: Role) -> RoleSpec | None:
        """Return the spec of one role, or None if the kind has no such role."""
        return next((spec for spec in self.roles if spec.role is role), None)


def _role(role: Role, **options: Any) -> RoleSpec:
    return RoleSpec(role=role, kinds=ROLE_KINDS[role], **options)


COMPOSITIONS: Final[Mapping[DeviceKind, KindSpec]] = MappingProxyType(
    {
        DeviceKind.LIGHT: KindSpec(
            kind=DeviceKind.LIGHT,
            roles=(
                _role(Role.ONOFF, written=True),
                _role(Role.LEVEL, defaults_to=Role.TARGET_LEVEL),
                _role(Role.TARGET_LEVEL, written=True, defaults_to=Role.LEVEL),
                _role(Role.COLOR_TEMP, written=True, needs=Role.LEVEL),
            ),
            needs_any_of=frozenset({Role.ONOFF, Role.LEVEL}),
        ),
        DeviceKind.COVER: KindSpec(
            kind=DeviceKind.COVER,
            roles=(
                _role(Role.POSITION, required=True),
                _role(Role.TARGET, written=True, defaults_to=Role.POSITION),
                _role(Role.MOVING),
            ),
        ),
        DeviceKind.CLIMATE: KindSpec(
            kind=DeviceKind.CLIMATE,
            roles=(
                _role(Role.TEMPERATURE, required=True),
                _role(Role.SETPOINT, required=True, written=True),
                _role(Role.HEAT_MODE, written=True),
                _role(Role.COOL_MODE, written=True),
                _role(Role.HEATING),
                _role(Role.COOLING),
            ),
        ),
        DeviceKind.BUTTON: KindSpec(
            kind=DeviceKind.BUTTON,
            roles=(_role(Role.CLICK_COUNT), _role(Role.PRESS_COUNT)),
            needs_any_of=frozenset({Role.CLICK_COUNT, Role.PRESS_COUNT}),
        ),
        DeviceKind.SWITCH: KindSpec(
            kind=DeviceKind.SWITCH,
            roles=(_role(Role.ONOFF, required=True, written=True),),
        ),
    }
)
"""What the UI may compose (contacts and displays are raw entities already)."""


def is_writable(point: Point) -> bool:
    """Whether a device may write the point: all but those said to be read-only.

    A plain variable does not say whether it is writable (and a convention's
    plain variables are written), so only attributes that say so forbid a
    write, or the user who made the point read only.
    """
    return point.takes_writes()


def fitting_points(
    kind: DeviceKind, role: Role, points: Mapping[str, Point]
) -> list[Point]:
    """Return the points that may play ``role`` in a composed ``kind``, in order.

    Beyond the kind of value (and writability) a role needs, a point must not say
    it is something else: a temperature role takes numbers in °C or °F (or,
    without a unit, whose title or path says temperature), a position or a
    level takes shares in % that are no humidity (or numbers without a unit
    that say no temperature). A plain variable says nothing but its path.
    """
    spec = COMPOSITIONS[kind].role(role)
    if spec is None:
        raise ValueError(f"a {kind} has no role {role}")
    says = _ROLE_MEASURES.get(role)
    return [
        point
        for point in points.values()
        if spec.accepts(point) and (says is None or says(point))
    ]


_TEMPERATURE_UNITS: Final = frozenset({"°c", "degc", "°f", "degf"})
_TEMPERATURE_WORDS: Final = re.compile(r"temp|tepl|setpoint|zadan|pozadovan")
# A light's colour temperature (in kelvin) is no temperature of a room.
_COLOUR_WORDS: Final = re.compile(r"colou?r ?temp|temp k\b|barv")
_HUMIDITY_WORDS: Final = re.compile(r"humid|vlhk")


def _units_and_words(point: Point) -> tuple[str, str]:
    """Return a point's unit and its title and path in folded words."""
    unit = point.unit_of().strip().casefold()
    if point.attributes is None:
        return unit, folded(identifier_words(point.path))
    title = point.attributes.name
    return unit, folded(f"{title} {identifier_words(point.path)}")


def _says_temperature(point: Point) -> bool:
    """Whether a number may be a temperature (not a share, a power, a count ...)."""
    units, words = _units_and_words(point)
    if units:
        return units in _TEMPERATURE_UNITS
    return (
        _TEMPERATURE_WORDS.search(words) is not None
        and _COLOUR_WORDS.search(words) is None
    )


def _says_share(point: Point) -> bool:
    """Whether a number may be a position or a level in % (not a humidity)."""
    units, words = _units_and_words(point)
    if units:
        return units == "%" and _HUMIDITY_WORDS.search(words) is None
    return _TEMPERATURE_WORDS.search(words) is None


_ROLE_MEASURES: Final[Mapping[Role, Callable[[Point], bool]]] = MappingProxyType(
    {
        Role.TEMPERATURE: _says_temperature,
        Role.SETPOINT: _says_temperature,
        Role.MIN_TEMP: _says_temperature,
        Role.MAX_TEMP: _says_temperature,
        Role.POSITION: _says_share,
        Role.TARGET: _says_share,
        Role.LEVEL: _says_share,
        Role.TARGET_LEVEL: _says_share,
    }
)
"""What the points a role lists must not contradict (see :func:`fitting_points`)."""


class CompositionProblem(StrEnum):
    """Why a choice of points does not make a device (a translation key)."""

    NOT_COMPOSABLE = "not_composable"
    UNKNOWN_ROLE = "unknown_role"
    MISSING_ROLE = "missing_role"
    MISSING_POINT = "missing_point"
    WRONG_KIND = "wrong_kind"
    NOT_WRITABLE = "not_writable"


class CompositionError(ValueError):
    """A choice of points that does not make a device of the kind.

    ``problem`` says why, ``role`` which role (None for the kind itself),
    ``point`` the chosen point key when one is involved.
    """

    def __init__(
        self,
        problem: CompositionProblem,
        message: str,
        *,
        kind: str,
        role: str | None = None,
        point: str | None = None,
    ) -> None:
        """Keep the problem, the kind, the role and the point for the UI."""
        super().__init__(message)
        self.problem = problem
        self.kind = kind
        self.role = role
        self.point = point


def compose(
    kind: DeviceKind | str,
    roles: Mapping[str, str],
    points: Mapping[str, Point],
    *,
    ident: str,
    name: str = "",
) -> TypedDevice:
    """Validate a user's choice of points for a kind and make the device.

    ``roles`` maps role names to point keys (or paths, any case); ``ident`` is
    the caller's stable identifier (a config subentry ID) and makes the key
    ``composed:<ident>``. Raises :class:`CompositionError` naming the role and
    the problem: a kind that cannot be composed, an unknown role, a point not
    in ``points`` (it vanished with a program download), a point of the wrong
    value kind, a read-only point where the device writes, a required role
    left out. Call it again after each program download to revalidate.
    """
    try:
        device_kind = DeviceKind(kind)
    except ValueError:
        device_kind = None
    if device_kind is None or device_kind not in COMPOSITIONS:
        raise CompositionError(
            CompositionProblem.NOT_COMPOSABLE,
            f"a {kind} cannot be composed",
            kind=str(kind),
        )
    if not ident:
        raise ValueError("a composed device needs an ident")
    chosen: dict[Role, str] = {}
    for role_name, key in roles.items():
        try:
            chosen[Role(role_name)] = key
        except ValueError:
            raise CompositionError(
                CompositionProblem.UNKNOWN_ROLE,
                f"a {device_kind} has no role {role_name!r}",
                kind=device_kind,
                role=role_name,
            ) from None
    return build(
        device_kind,
        chosen,
        points,
        source=COMPOSED,
        key=f"{COMPOSED}:{ident}",
        name=" ".join(name.split()),
    )


def build(
    kind: DeviceKind,
    chosen: Mapping[Role, str],
    points: Mapping[str, Point],
    *,
    source: str,
    key: str,
    name: str = "",
    base: str = "",
) -> TypedDevice:
    """Make a device from roles chosen by a user or by member names, checked strictly.

    Raises :class:`CompositionError` as :func:`compose` does.
    """
    spec = COMPOSITIONS[kind]
    roles: dict[Role, str] = {}
    for role, point_key in chosen.items():
        role_spec = spec.role(role)
        if role_spec is None:
            raise CompositionError(
                CompositionProblem.UNKNOWN_ROLE,
                f"a {kind} has no role {role}",
                kind=kind,
                role=role,
            )
        point = points.get(point_key.lower())
        if point is None:
            raise CompositionError(
                CompositionProblem.MISSING_POINT,
                f"{role}: the variable {point_key!r} no longer exists",
                kind=kind,
                role=role,
                point=point_key,
            )
        if point.kind not in role_spec.kinds:
            raise CompositionError(
                CompositionProblem.WRONG_KIND,
                f"{role}: {point.path} holds a {point.kind} value, "
                f"expected {' or '.join(sorted(role_spec.kinds))}",
                kind=kind,
                role=role,
                point=point.key,
            )
        roles[role] = point.key
    for role_spec in spec.roles:
        default = role_spec.defaults_to
        if role_spec.role not in chosen and default is not None and default in chosen:
            roles[role_spec.role] = roles[default]
    for role_spec in spec.roles:
        if role_spec.required and role_spec.role not in roles:
            raise _missing(kind, role_spec.role, f"a {kind} needs {role_spec.role}")
        needs = role_spec.needs
        if role_spec.role in roles and needs is not None and needs not in roles:
            raise _missing(kind, needs, f"{role_spec.role} needs {needs}")
    if spec.needs_any_of and not spec.needs_any_of & roles.keys():
        first, *_ = sorted(spec.needs_any_of)
        wanted = " or ".join(sorted(spec.needs_any_of))
        raise _missing(kind, first, f"a {kind} needs {wanted}")
    for role_spec in spec.roles:
        role = role_spec.role
        if role_spec.written and role in roles and not is_writable(points[roles[role]]):
            # Name the role the user chose: a defaulted role is played by another.
            shown = role if role in chosen else role_spec.defaults_to or role
            raise CompositionError(
                CompositionProblem.NOT_WRITABLE,
                f"{shown}: {points[roles[role]].path} is read-only "
                f"and the {kind} writes its {role}",
                kind=kind,
                role=shown,
                point=roles[role],
            )
    primary = next(r.role for r in spec.roles if r.role in roles)
    base = base or points[roles[primary]].path
    name = name or name_from_base(base)
    features = _features(kind, base, name, roles, points)
    return TypedDevice(
        key=key, kind=kind, source=source, base=base, name=name, roles=roles, **features
    )


def _missing(kind: DeviceKind, role: Role, message: str) -> CompositionError:
    return CompositionError(
        CompositionProblem.MISSING_ROLE, message, kind=kind, role=role
    )


def _features(
    kind: DeviceKind,
    base: str,
    name: str,
    roles: Mapping[Role, str],
    points: Mapping[str, Point],
) -> dict[str, Any]:
    """Return the feature of a device :func:`build` makes, from the roles it has."""
    match kind:
        case DeviceKind.LIGHT:
            mode = LightMode.ONOFF
            if Role.COLOR_TEMP in roles:
                mode = LightMode.COLOR_TEMP
            elif Role.LEVEL in roles:
                mode = LightMode.BRIGHTNESS
            return {"light_mode": mode}
        case DeviceKind.COVER:
            position = points[roles[Role.POSITION]]
            title = position.attributes.name if position.attributes is not None else ""
            gate = is_gate_name(name, base, title)
            return {"cover_class": CoverClass.GATE if gate else CoverClass.SHUTTER}
        case DeviceKind.CLIMATE:
            return {"climate": climate_support(roles)}
        case _:
            return {}


def climate_support(roles: Mapping[Role, str]) -> ClimateSupport:
    """Heating, cooling or both, from the roles present (heating unless only cooling)."""
    heats = bool({Role.HEAT_MODE, Role.HEATING} & roles.keys())
    cools = bool({Role.COOL_MODE, Role.COOLING} & roles.keys())
    if heats and cools:
        return ClimateSupport.BOTH
    return ClimateSupport.COOLING if cools else ClimateSupport.HEATING
