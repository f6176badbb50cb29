"""What of a PLC's catalogue becomes entities and devices in Home Assistant.

- **Points**: the variables the options select (include/exclude patterns, and
  whether plain variables are shown) each become an entity (``mapping``).
- **Typed devices**: those the source's recognisers find (Tecomat's: GTSAP1
  block families and structs in our convention) among the points the
  include/exclude patterns select (a family's variables are plain variables:
  they count whatever the plain-variables option says), and
  the devices the user composed in the UI (config subentries). The points a
  typed device is built from stay reachable as plain entities, disabled by
  default (unless the options leave plain variables out altogether).
- **Groups** (rooms and subsystems): with the ``devices`` option on
  ``groups_and_areas`` (the default) or ``groups``, each top-level struct,
  program instance or array becomes a device of its own under the PLC, named
  from its variable name with the accents the program's texts give its words
  (``detskyPokoj`` → *Dětský pokoj*, ``Stineni`` → *Stínění*); the points inside
  it sit on it. Top-level variables stay on the PLC's device.
- **A typed device is a device** of its own under the PLC (unless everything
  is on the PLC's device), its entity the device's main feature. With
  ``groups_and_areas`` a device whose name says a room (English or Czech,
  accents ignored: living room, kitchen, bedroom, ..., obývák, kuchyň,
  ložnice, dětský pokoj, ...), or that sits in a group whose name does,
  suggests that room's area (``names``); so does a group whose name says a
  room besides something else (*Kuchyň světla*).

A typed device's name says what it is, and where when that is what tells it
apart (``Place.distinct``): a *Ložnice* light is the *Ložnice light*, two
*Strop* lights say their rooms, two *Thermostat* in no room their groups. Home
Assistant 2026.6 and later put the area first in an entity's ID: there a device
in an area whose name alone tells it apart is named without its room (the
*Strop* in the *Obývák*), the others' entities get IDs that say the room once
(``device_info.typed_entity_id``), and a group that is only a room (*Dětský pokoj*)
keeps its name and suggests no area, so that no ID says a room twice. Before,
IDs are made of the device's and the entity's names only, and the names keep
their room.
"""

from collections import Counter
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field, replace
import re
from typing import Any, Final

from .compat import AREA_IN_ENTITY_ID
from .const import DeviceGrouping
from .mapping import PointDescription, describe, readable_path
from .names import Room, folded, room_of, spelled, vocabulary, without_leading
from .options import PlcOptions
from .pyplc import Catalogue, Point
from .pyplc.core.composition import CompositionError, compose
from .pyplc.core.devices import DeviceKind, Recogniser, TypedDevice, find_devices


@dataclass(frozen=True, slots=True, kw_only=True)
class Composition:
    """A typed device the user composed: a config subentry's kind, name and roles."""

    subentry_id: str
    kind: DeviceKind
    name: str
    roles: Mapping[str, str]


@dataclass(frozen=True, slots=True, kw_only=True)
class Group:
    """A device under the source's own, where the points of a group sit.

    A device the source declares (a station, a controller), or one top-level
    struct, program instance or array. ``name`` is the device's name, ``area`` the
    area it suggests (None: none);
    ``parent`` the group it sits under (None: the source's own device);
    ``manufacturer``, ``model`` and ``serial_number`` what the source tells of
    it (None: the source's manufacturer, the program's name, none).
    """

    key: str
    name: str
    area: str | None
    parent: str | None = None
    alias: str | None = None
    """The name the source gives it, where the device is named otherwise."""
    manufacturer: str | None = None
    model: str | None = None
    serial_number: str | None = None


@dataclass(frozen=True, slots=True, kw_only=True)
class Place:
    """The device of a typed device: its names and the area it suggests.

    ``name`` says its room (*Obývák strop*, the *Dětský pokoj thermostat*),
    ``rest`` does not (*Strop*, *Thermostat*): the name of a device in its
    area where entity IDs start with the area, when it is ``distinct``. An
    empty ``rest`` is a device named by its kind and its room: a light named
    *Ložnice* is the *Ložnice light*.

    ``distinct``: whether ``rest`` alone tells the device apart, so that a
    device in its area is named by it. Not when it is a word of its family
    (*Thermostat*, *Světlo*) or another typed device of the PLC is named the
    same: its name then says its room too (*Dětský pokoj thermostat*).
    """

    name: str
    rest: str
    area: str | None
    distinct: bool = True


@dataclass(frozen=True, slots=True, kw_only=True)
class Selection:
    """What one catalogue becomes; the same object until a new program is discovered.

    ``watched`` is every point an entity may show: the selected points and
    those typed devices are built from. ``broken`` holds the compositions that
    do not fit the program (a point vanished), by subentry ID. ``places`` holds
    the typed devices that are devices of their own, by key.
    """

    points: Mapping[str, Point]
    descriptions: Mapping[str, PointDescription]
    devices: Mapping[str, TypedDevice]
    broken: Mapping[str, CompositionError]
    groups: Mapping[str, Group]
    watched: frozenset[str]
    places: Mapping[str, Place] = field(default_factory=dict)
    declared: Mapping[str, str] = field(default_factory=dict)
    """The device the source puts a point's path on, by path."""

    def group_of(self, path: str) -> Group | None:
        """Return the group a path's entity sits in (None: the source's own device).

        A path the source puts on a device of its own sits there; any other in
        the group of its top-level name.
        """
        if (device := self.declared.get(path)) is not None:
            return self.groups.get(device)
        return self.groups.get(_root(path))


def _root(path: str) -> str:
    """Return the lower-case top-level name of a path: ``Rooms.living[2]`` → ``rooms``."""
    return re.split(r"[.\[]", path, maxsplit=1)[0].lower()


def _room(name: str, grouping: DeviceGrouping) -> Room | None:
    """Return the room a name says, where rooms give areas (None: none)."""
    return room_of(name) if grouping is DeviceGrouping.GROUPS_AND_AREAS else None


def _groups(
    paths: Iterable[str], names: Mapping[str, str], grouping: DeviceGrouping
) -> dict[str, Group]:
    """Return the groups of the paths under a top-level name (a member or an index).

    ``names`` are the catalogue's groups' readable names, by lower-case group.
    """
    if grouping is DeviceGrouping.SINGLE:
        return {}
    groups: dict[str, Group] = {}
    for path in paths:
        root = _root(path)
        if root in groups or len(path) == len(root):
            continue
        name = names.get(root, root)
        room = _room(name, grouping)
        if room is None or (AREA_IN_ENTITY_ID and not room.rest):
            # No room; or only a room: in its area, IDs would say it twice.
            groups[root] = Group(key=root, name=name, area=None)
        else:
            # Kuchyň světla: the Světla in the Kuchyň (before 2026.6 named whole).
            shown = room.rest if AREA_IN_ENTITY_ID else name
            groups[root] = Group(key=root, name=shown, area=room.area)
    return groups


def _places(
    devices: Iterable[TypedDevice],
    names: Mapping[str, str],
    words: Mapping[str, str],
    grouping: DeviceGrouping,
) -> dict[str, Place]:
    """Return the device of each typed device that is a device of its own.

    Its room is the one its name says, else its group's (``names``: the
    catalogue's groups' readable names). A composed device is named as the user named it and
    suggests no area; with everything on the PLC's device, it is the only kind
    that is a device of its own.
    """
    places: dict[str, Place] = {}
    found: dict[str, tuple[Place, TypedDevice]] = {}
    for device in devices:
        if device.composed:
            # Named as the user named it, in the area the user chooses.
            places[device.key] = Place(name=device.name, rest=device.name, area=None)
            continue
        if grouping is DeviceGrouping.SINGLE:
            continue
        name = spelled(device.name, words)
        if (room := _room(name, grouping)) is not None:
            place = Place(name=name, rest=room.rest, area=room.area)
        elif (room := _room(names.get(_root(device.base), ""), grouping)) is not None:
            # The Thermostat of the Dětský pokoj.
            place = Place(name=joined(room.area, name), rest=name, area=room.area)
        else:
            place = Place(name=name, rest=name, area=None)
        found[device.key] = (place, device)
    # A name several typed devices have does not tell them apart.
    shared = Counter(folded(place.rest) for place, _ in found.values() if place.rest)
    for key, (place, device) in found.items():
        places[key] = _told_apart(
            place, device, shared[folded(place.rest)] > 1, names, words
        )
    return places


FAMILY_WORDS: Final[Mapping[DeviceKind, frozenset[str]]] = {
    kind: frozenset(folded(word) for word in words)
    for kind, words in {
        DeviceKind.LIGHT: ("light", "lights", "světlo", "světla", "osvětlení"),
        DeviceKind.COVER: ("blind", "blinds", "cover", "žaluzie", "roleta"),
        DeviceKind.CLIMATE: ("thermostat", "termostat"),
        DeviceKind.BUTTON: ("button", "tlačítko"),
        DeviceKind.CONTACT: ("contact", "kontakt"),
        DeviceKind.SWITCH: ("switch", "spínač", "relay", "relé"),
        DeviceKind.DISPLAY: ("sensor", "čidlo", "display"),
    }.items()
}
"""The words that say only which family a typed device is of (in folded spelling)."""


def _told_apart(
    place: Place,
    device: TypedDevice,
    shared: bool,
    names: Mapping[str, str],
    words: Mapping[str, str],
) -> Place:
    """Return a typed device's place, its name saying where when what is not enough.

    A name that is only its family's word (*Thermostat*) or that another typed
    device has too says its room (the device's is not ``distinct``: in its area
    it is named with the room as well); one in no room says its group
    (*Ground floor thermostat*), or a block of no group its own identifier
    (``ZASUVKA_VYCHOD`` named *Zásuvka*: *Zásuvka vychod*).
    """
    if not place.rest:
        return replace(place, distinct=False)
    bare = folded(place.rest) in FAMILY_WORDS[device.kind]
    if not (bare or shared):
        return place
    if place.area is not None:
        return replace(place, distinct=False)
    where = names.get(_root(device.base)) or spelled(readable_path(device.base), words)
    name = joined(where, without_leading(place.name, where))
    return replace(place, name=name, rest=name)


def joined(where: str, what: str) -> str:
    """Return a name saying where, then what: ``Dětský pokoj`` + ``Thermostat``.

    A capitalised word of the second name is lowered (*Dětský pokoj
    thermostat*); one written otherwise (*CO2*, *LED pásek*) stays as written.
    """
    first, _, others = what.partition(" ")
    if first[1:].islower():
        first = first.lower()
    return " ".join(part for part in (where, first, others) if part)


def select(
    catalogue: Catalogue,
    options: PlcOptions,
    compositions: Iterable[Composition] = (),
    recognisers: Iterable[Recogniser] = (),
) -> Selection:
    """Decide what a catalogue becomes (see the module's docstring).

    ``recognisers`` find the typed devices (the source's descriptor's).
    """
    patterned = {
        key: point for key, point in catalogue.points.items() if options.matches(key)
    }
    found = find_devices(patterned, catalogue.values, recognisers)
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
    words = vocabulary(_texts(catalogue))
    names = {
        group.lower(): spelled(readable_path(group), words)
        for group in catalogue.groups
    }
    declared = {point.path: point.device for point in points.values() if point.device}
    paths = [point.path for point in points.values() if not point.device]
    watched = frozenset(points).union(*(device.points for device in devices.values()))
    return Selection(
        points=points,
        descriptions=descriptions,
        devices=devices,
        broken=broken,
        groups={
            **_groups(paths, names, options.devices),
            **_declared_groups(
                catalogue, set(declared.values()), options.devices, words
            ),
        },
        watched=watched,
        places=_places(devices.values(), names, words, options.devices),
        declared=declared if options.devices is not DeviceGrouping.SINGLE else {},
    )


def _declared_groups(
    catalogue: Catalogue,
    used: set[str],
    grouping: DeviceGrouping,
    words: Mapping[str, str],
) -> dict[str, Group]:
    """Return the groups of the devices a source declares that points sit on.

    The devices above them come too (a controller above its devices). Their
    names get their accents as groups' do (``Jidelna`` → *Jídelna*), and a
    device that is only a room suggests no area where entity IDs start with the
    area, as a group of the same name (its IDs would say the room twice).
    """
    if grouping is DeviceGrouping.SINGLE:
        return {}
    groups: dict[str, Group] = {}
    waiting = list(used)
    while waiting:
        key = waiting.pop()
        node = catalogue.devices.get(key)
        if key in groups or node is None:
            continue
        board = _board(catalogue, key, node.name)
        name = board or spelled(node.name, words)
        room = _room(name, grouping)
        if room is not None and AREA_IN_ENTITY_ID and not room.rest:
            room = None
        groups[key] = Group(
            key=key,
            name=name,
            area=None if room is None else room.area,
            parent=node.parent or None,
            alias=node.name if board else None,
            manufacturer=node.manufacturer,
            # A board is its own model (Neuron L203), not its program's.
            model=node.model or board,
            serial_number=node.serial_number,
        )
        if node.parent:
            waiting.append(node.parent)
    return groups


_MODEL: re.Pattern[str] = re.compile(r"[a-z]+\d+[a-z\d]*")
"""A board's model as its points' names say it (``l203``, ``s103``)."""


def _board(catalogue: Catalogue, key: str, name: str) -> str | None:
    """Return the board a device's points all name (None: not a board's).

    Unipi's ``hw`` namespace holds one board's inputs and outputs
    (``hw.neuron_l203_di_1.01``, titled *Hw neuron l203 di 1.01*): the device
    is the board, *Neuron L203*, not *Hw*. Every point's name, after the
    device's own, starts with the same words, the last a model (letters and
    digits), and says more besides.
    """
    titles = [
        folded(without_leading(point.attributes.name, name)).split()
        for point in catalogue.points.values()
        if point.device == key and point.attributes is not None
    ]
    shared: list[str] = []
    for said in zip(*titles, strict=False):
        if len(set(said)) != 1:
            break
        shared.append(said[0])
    while shared and not _MODEL.fullmatch(shared[-1]):
        shared.pop()
    if len(titles) < 2 or not shared or min(map(len, titles)) == len(shared):
        return None
    return " ".join(
        word.upper() if _MODEL.fullmatch(word) else word.capitalize() for word in shared
    )


def _texts(catalogue: Catalogue) -> list[str]:
    """Return what the installer typed: titles and text values (GTSAP1 names)."""
    titles = [
        point.attributes.name
        for point in catalogue.points.values()
        if point.attributes is not None
    ]
    values = [value for value in catalogue.values.values() if isinstance(value, str)]
    return titles + values


type Selector = Callable[[Catalogue], Selection]


def selector(
    options: PlcOptions,
    compositions: Iterable[Composition],
    recognisers: Iterable[Recogniser],
) -> Selector:
    """Return the function that selects from each new catalogue."""
    kept, conventions = tuple(compositions), tuple(recognisers)
    return lambda catalogue: select(catalogue, options, kept, conventions)


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
