"""What of a PLC's catalogue becomes entities and devices in Home Assistant.

- **Points**: the variables the options select (include/exclude patterns, and
  whether plain variables are shown) each become an entity (``mapping``).
- **Typed devices**: GTSAP1 block families and structs in our convention, found
  among the points the include/exclude patterns select (GTSAP1 variables are
  plain variables: they count whatever the plain-variables option says), and
  the devices the user composed in the UI (config subentries). The points a
  typed device is built from stay reachable as plain entities, disabled by
  default (unless the options leave plain variables out altogether).
- **Groups** (rooms and subsystems): with the ``devices`` option on
  ``groups_and_areas`` (the default) or ``groups``, each top-level struct,
  program instance or array becomes a device of its own under the PLC, named
  from its variable name (``detskyPokoj`` → *Detsky pokoj*); the points and
  typed devices inside it sit on it. Top-level variables (and GTSAP1 families of
  top-level variables) stay on the PLC's device. With ``groups_and_areas`` a
  group whose name says it is a room
  (English or Czech, accents ignored: living, kitchen, bedroom, bathroom, ...,
  obývák, kuchyň, ložnice, koupelna, pokoj, ...) suggests an area of that name.
"""

from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
import re
from typing import Any, Final
import unicodedata

from .const import DeviceGrouping
from .mapping import PointDescription, describe, readable_path
from .options import TecoApiOptions
from .pyplc import Catalogue, Point
from .pyplc.core.devices import (
    CompositionError,
    DeviceKind,
    TypedDevice,
    compose,
    find_devices,
)

# Words that make a group's name a room (accents and case folded away).
ROOM_WORDS: Final = re.compile(
    r"\b(?:living|lounge|kitchen|dining|bed ?room|bath ?room|toilet|wc|hall|hallway"
    r"|corridor|garage|office|study|kids|children|nursery|guest|attic|basement"
    r"|cellar|laundry|room|obyvak\w*|kuchyn\w*|jidelna|loznice|koupeln\w*|zachod"
    r"|chodb\w*|predsin\w*|garaz\w*|pracovn\w*|detsk\w*|pokoj\w*|podkrovi|sklep"
    r"|pradeln\w*|spiz\w*)\b"
)


@dataclass(frozen=True, slots=True, kw_only=True)
class Composition:
    """A typed device the user composed: a config subentry's kind, name and roles."""

    subentry_id: str
    kind: DeviceKind
    name: str
    roles: Mapping[str, str]


@dataclass(frozen=True, slots=True, kw_only=True)
class Group:
    """A device under the PLC for one top-level struct, program instance or array."""

    key: str
    name: str
    area: str | None


@dataclass(frozen=True, slots=True, kw_only=True)
class Selection:
    """What one catalogue becomes; the same object until a new program is discovered.

    ``watched`` is every point an entity may show: the selected points and
    those typed devices are built from. ``broken`` holds the compositions that
    do not fit the program (a point vanished), by subentry ID.
    """

    points: Mapping[str, Point]
    descriptions: Mapping[str, PointDescription]
    devices: Mapping[str, TypedDevice]
    broken: Mapping[str, CompositionError]
    groups: Mapping[str, Group]
    watched: frozenset[str]

    def group_of(self, path: str) -> Group | None:
        """Return the group a path's entity sits in (None: the PLC's own device)."""
        return self.groups.get(_root(path))


def _root(path: str) -> str:
    """Return the lower-case top-level name of a path: ``Rooms.living[2]`` → ``rooms``."""
    return re.split(r"[.\[]", path, maxsplit=1)[0].lower()


def _folded(text: str) -> str:
    decomposed = unicodedata.normalize("NFKD", text)
    return "".join(c for c in decomposed if not unicodedata.combining(c)).casefold()


def _groups(
    paths: Iterable[str], spelled: Mapping[str, str], grouping: DeviceGrouping
) -> dict[str, Group]:
    """Return the groups of the paths under a top-level name (a member or an index)."""
    if grouping is DeviceGrouping.SINGLE:
        return {}
    groups: dict[str, Group] = {}
    for path in paths:
        root = _root(path)
        if root in groups or len(path) == len(root):
            continue
        name = readable_path(spelled.get(root, root))
        area = None
        if grouping is DeviceGrouping.GROUPS_AND_AREAS and ROOM_WORDS.search(
            _folded(name)
        ):
            area = name
        groups[root] = Group(key=root, name=name, area=area)
    return groups


def select(
    catalogue: Catalogue,
    options: TecoApiOptions,
    compositions: Iterable[Composition] = (),
) -> Selection:
    """Decide what a catalogue becomes (see the module's docstring)."""
    patterned = {
        key: point for key, point in catalogue.points.items() if options.matches(key)
    }
    found = find_devices(patterned, catalogue.values)
    devices = dict(found.devices)
    broken: dict[str, CompositionError] = {}
    for composition in compositions:
        try:
            device = compose(
                composition.kind,
                composition.roles,
                catalogue.points,
                ident=composition.subentry_id,
                name=composition.name,
            )
        except CompositionError as err:
            broken[composition.subentry_id] = err
        else:
            devices[device.key] = device
    consumed = found.consumed
    points = {
        key: point
        for key, point in patterned.items()
        if point.described or options.shows_plain
    }
    descriptions = {
        key: describe(point, options.plain_variables, consumed=key in consumed)
        for key, point in points.items()
    }
    spelled = {root.lower(): root for root in catalogue.roots}
    bases = [device.base for device in devices.values()]
    paths = [point.path for point in points.values()] + bases
    watched = frozenset(points).union(*(device.points for device in devices.values()))
    return Selection(
        points=points,
        descriptions=descriptions,
        devices=devices,
        broken=broken,
        groups=_groups(paths, spelled, options.devices),
        watched=watched,
    )


type Selector = Callable[[Catalogue], Selection]


def selector(options: TecoApiOptions, compositions: Iterable[Composition]) -> Selector:
    """Return the function that selects from each new catalogue."""
    kept = tuple(compositions)
    return lambda catalogue: select(catalogue, options, kept)


def compositions_of(subentries: Mapping[str, Any]) -> list[Composition]:
    """Return the compositions stored in a config entry's subentries."""
    return [
        Composition(
            subentry_id=subentry_id,
            kind=DeviceKind(subentry.data["kind"]),
            name=subentry.title,
            roles=dict(subentry.data["roles"]),
        )
        for subentry_id, subentry in subentries.items()
    ]
