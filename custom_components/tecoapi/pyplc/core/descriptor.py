"""What a way into a device declares about itself, in one place.

A :class:`SourceDescriptor` is everything a caller needs to offer a source to a
user without knowing it: the forms that connect it (:class:`Form` of
:class:`Field`), reconfigure it and sign in again, what it is made from and
with (``create``), how the submitted form becomes its connection (``prepare``),
which failure shows which form error (``errors``), what it can do
(:class:`Capability`), which of its stored keys are secret, which point map
formats it takes, the server its options may name beside it (a
:class:`Companion`: a push server, with a form of its own) and which conventions
its typed devices follow (``recognisers``). Home Assistant's config flow, options, diagnostics and
repairs read descriptors; none of them names a source (compare Home
Assistant's ``zha``, whose radio types map to their libraries in one table, and
whose port form comes from the radio library's own schema).

A descriptor's ``name`` is stored with every entry made with it: it never
changes.
"""

from collections.abc import Awaitable, Callable, Mapping
from dataclasses import dataclass, field
from datetime import timedelta
from enum import StrEnum
from typing import TYPE_CHECKING, Any, Final, Protocol

from .devices import Recogniser
from .exceptions import PlcError
from .models import PointOverride
from .pointmap import TYPE_NAMES, AddressCheck, Loader, PointMap
from .source import DEFAULT_METADATA_INTERVAL, Clock, PlcSource, utcnow

if TYPE_CHECKING:
    import aiohttp

CONF_HOST: Final = "host"
CONF_PORT: Final = "port"
CONF_USERNAME: Final = "username"
CONF_PASSWORD: Final = "password"  # noqa: S105 (the key, not a password)
CONF_VERIFY_SSL: Final = "verify_ssl"
CONF_POINT_MAP: Final = "point_map"
"""The field of a form that uploads a point map (its value: the uploaded file)."""


class Capability(StrEnum):
    """What a source can do; options, actions, status entities and repairs follow.

    A push server its options may name beside it is no capability: that is its
    descriptor's ``companion`` (one fact, one place).
    """

    DISCOVERY = "discovery"
    """It lists its points itself (a program change is followed)."""
    POINT_MAP = "point_map"
    """Its points come from a map the user supplies (and edits)."""
    PUSH = "push"
    """It delivers changes between polls by itself."""
    MODE = "mode"
    """It tells a run mode (a :class:`~.models.PlcMode`): a repair issue while
    it does not run."""
    PROGRAM = "program"
    """It tells the program it runs: its name, when it was compiled."""
    CLOCK = "clock"
    """It tells its clock (an offset from Home Assistant's is shown)."""
    METADATA = "metadata"
    """It reads its points' attributes again on a cadence of their own."""
    PATHS = "paths"
    """It reads and writes any variable by its path (the actions)."""
    CREDENTIALS = "credentials"
    """It signs in (rejected credentials start reauthentication)."""
    PLAIN_VARIABLES = "plain_variables"
    """It has points it knows nothing of but the value (shown or not, by option)."""


class FieldKind(StrEnum):
    """What a form field takes."""

    URL = "url"
    """A host, or a base URL with its scheme and port."""
    HOST = "host"
    """A host name or an IP address, nothing around it."""
    PORT = "port"
    TEXT = "text"
    USERNAME = "username"
    PASSWORD = "password"  # noqa: S105 (a kind of field)
    BOOLEAN = "boolean"
    POINT_MAP = "point_map"
    """A point map file, uploaded."""


@dataclass(frozen=True, slots=True, kw_only=True)
class Field:
    """One field of a form.

    ``secret`` fields are never shown again, never logged and redacted in
    diagnostics; in a reconfigure form an empty one keeps the stored value.
    A field ``of_map`` says what the map uploaded with it is (a Mervis
    project's name), not where the device is: the descriptor's ``adopt_map``
    takes it with the map, and it is never stored with the connection.
    """

    key: str
    kind: FieldKind
    required: bool = True
    default: Any = None
    of_map: bool = False

    @property
    def secret(self) -> bool:
        """Whether the value is a secret (a password)."""
        return self.kind is FieldKind.PASSWORD


@dataclass(frozen=True, slots=True, kw_only=True)
class Form:
    """A form the user fills: its step's ID (its texts' key) and its fields."""

    step_id: str
    fields: tuple[Field, ...]
    placeholders: Mapping[str, str] = field(default_factory=dict)
    """Texts the form's description shows as they are (``{PUBLIC_API}``)."""


@dataclass(frozen=True, slots=True, kw_only=True)
class Words:
    """The keys of the texts that speak of one system in its own words.

    A caller's texts vary by key only (Home Assistant's translations: a step's
    texts by its step ID, an abort's by its reason, a choice's labels by its
    translation key): each system names here the keys of its own texts, so
    that none is told of another system's PLC, file or serial number. The
    defaults are no system's: Home Assistant's own keys (``init``,
    ``reauth_confirm``, ``already_configured`` ...) and plain ones, whose texts a
    source that names no words of its own must bring (:meth:`of` names each
    after its system, as every built-in source does). ``options_step_id`` is
    the options' first step (a menu: a map's editor, or the changes of the
    points a source discovers, beside the settings), ``settings_step_id`` the
    form of its settings, a step of its own behind the menu (a descriptor must
    give one; unless given, it is the first step itself), ``reauth_step_id``
    the sign-in form of a reauthentication, ``upload_step_id`` the form behind
    the menu that takes a newer map file (titled as its menu's choice: *Upload
    a newer .vlist*); ``devices`` the labels of the device grouping's
    choices; ``already_configured``, ``wrong_device`` and ``reconfigured``
    abort reasons: the device is configured already, the address reached is
    another device, a reconfiguration is stored. A source whose points the
    user supplies names the forms of one point: ``add_point_step_id`` adds
    one, ``point_step_id`` changes one (their help and examples speak of its
    addresses, its devices, its scale), and ``point_refused`` is the error of
    a point the device does not read; ``points_refused`` the repair issue of
    the points a running device refuses (its map's words: a controller's
    variables and its ``.vlist``, a gateway's registers and its map).
    """

    options_step_id: str = "init"
    settings_step_id: str = ""
    reauth_step_id: str = "reauth_confirm"
    upload_step_id: str = "upload"
    devices: str = "devices"
    already_configured: str = "already_configured"
    wrong_device: str = "wrong_device"
    reconfigured: str = "reconfigure_successful"
    add_point_step_id: str = "add_point"
    point_step_id: str = "point"
    point_refused: str = "point_refused"
    points_refused: str = "points_refused"

    def __post_init__(self) -> None:
        """Put the settings on the first step when they have no step of their own."""
        if not self.settings_step_id:
            object.__setattr__(self, "settings_step_id", self.options_step_id)

    @classmethod
    def of(
        cls,
        name: str,
        *,
        settings: bool = False,
        reauth: bool = False,
        points: bool = False,
    ) -> "Words":
        """Return the keys of a system's own texts, each named after the system.

        Its options step is ``name``, its device choices ``devices_<name>``, its
        aborts ``<name>_already_configured``, ``<name>_wrong_device`` and
        ``<name>_reconfigured``; ``settings``: its settings form is a step of
        its own behind the menu (``<name>_settings``), as its map's upload
        form is (``<name>_upload``); ``reauth``: it signs in again on
        ``reauth_<name>``; ``points``: its forms of one point are
        ``<name>_add_point`` and ``<name>_point``, a point its device does not
        read ``<name>_point_refused``, the points it refuses while it runs
        ``<name>_points_refused``.
        """
        own = {"reauth_step_id": f"reauth_{name}"} if reauth else {}
        if settings:
            own["upload_step_id"] = f"{name}_upload"
        if points:
            own |= {
                "add_point_step_id": f"{name}_add_point",
                "point_step_id": f"{name}_point",
                "point_refused": f"{name}_point_refused",
                "points_refused": f"{name}_points_refused",
            }
        return cls(
            options_step_id=name,
            settings_step_id=f"{name}_settings" if settings else "",
            devices=f"devices_{name}",
            already_configured=f"{name}_already_configured",
            wrong_device=f"{name}_wrong_device",
            reconfigured=f"{name}_reconfigured",
            **own,
        )


@dataclass(frozen=True, slots=True, kw_only=True)
class ErrorRule:
    """Which form error a failure shows: the first rule whose class matches wins.

    ``field`` is the form field it shows on ("base": the whole form); a rule
    ``logged`` is a failure worth a traceback in the log (unexpected).
    ``placeholders`` are attributes of the failure its message shows (the
    device's own code: ``{code}``), passed to the form as text.
    """

    error: type[PlcError]
    key: str
    field: str = "base"
    logged: bool = False
    placeholders: tuple[str, ...] = ()

    def shown(self, err: PlcError) -> dict[str, str]:
        """Return the placeholders of a failure's message."""
        return {name: str(getattr(err, name, "")) for name in self.placeholders}


class SourceCache(Protocol):
    """What a source keeps between runs, beside its entry (a device's address space).

    One JSON-shaped object per entry: what :meth:`save` stored last, until the
    entry goes. A source reads it instead of asking the device again for what
    has not changed.
    """

    async def load(self) -> Any:
        """Return what was saved last (None: nothing)."""

    async def save(self, data: Any) -> None:
        """Keep ``data`` (JSON-shaped) in place of what was saved before."""


@dataclass(frozen=True, slots=True, kw_only=True)
class SourceContext:
    """What a caller gives every source it makes.

    ``http`` returns a shared HTTP session (verifying TLS or not; a source
    never closes it); ``clock`` the current UTC time; ``run_blocking`` runs CPU
    work off the event loop; ``timeout`` is the seconds one request may take,
    ``stream_timeout`` those a streaming connection may stay silent. ``cache``
    is where the source of a stored entry keeps what it learned of the device
    between runs (None: nowhere, as while a form is checked).
    """

    http: Callable[[bool], "aiohttp.ClientSession"]
    clock: Clock = utcnow
    run_blocking: Callable[[Callable[[], Any]], Awaitable[Any]] | None = None
    timeout: float = 10.0
    stream_timeout: float = 5.0
    cache: SourceCache | None = None


@dataclass(frozen=True, slots=True, kw_only=True)
class SourceOptions:
    """What the user's options tell a source.

    ``metadata_interval`` is how often attributes are read again;
    ``companion`` the connection of the companion the user switched on beside
    it (its :class:`Companion`'s form, as stored: ``host``, ``port``, ...;
    None: none);
    ``point_map`` the user's points (sources that take one); ``identity`` the
    identity an entry knows its device by (None: a device being added). A
    source whose device tells no identity of its own (a gateway without a
    serial number) keeps the one it was added with, wherever it moves.
    ``overrides`` are what the user changed of the points it discovers, by key
    (a source that discovers: its :class:`~.source.SourceSettings`).
    """

    metadata_interval: timedelta = DEFAULT_METADATA_INTERVAL
    companion: Mapping[str, Any] | None = None
    point_map: PointMap | None = None
    identity: str | None = None
    overrides: Mapping[str, PointOverride] = field(default_factory=dict)


type AdoptMap = Callable[[PointMap, Mapping[str, Any], PointMap | None], PointMap]
"""An uploaded map as an entry takes it: the form's fields ``of_map`` applied,
and what the entry's stored map (None: a device being added) says that the
file does not. Raises :class:`~.pointmap.PointMapError` naming the field at
fault as its column."""
type SourceFactory = Callable[
    [SourceContext, Mapping[str, Any], SourceOptions], PlcSource
]
type Prepare = Callable[[Mapping[str, Any]], dict[str, Any]]
type CanonicalIdentity = Callable[[str], Awaitable[str]]
type Probe = Callable[["aiohttp.ClientSession", str], Awaitable[tuple[str | None, str]]]
"""Whether a device at an IP address is one: None and the host to store, or why not."""


def as_given(connection: Mapping[str, Any]) -> dict[str, Any]:
    """Return a submitted connection as it is (a ``prepare`` that changes nothing)."""
    return dict(connection)


@dataclass(frozen=True, slots=True, kw_only=True)
class Companion:
    """A server a source's options may name beside it: a push server.

    A source that polls may have a server beside it that pushes its device's
    changes (Tecomat TecoApi's PLCComS); its descriptor declares it, and a
    caller offers it as a part of the source's options, built from this: its
    ``title`` (log lines say it), the ``fields`` of its connection (a section
    of the options form), the failures of a check and their form errors
    (``errors``; ``other_device``: it answers, but lists none of the device's
    points), how a submitted section becomes its connection (``prepare``,
    raising :class:`~.exceptions.InvalidHostError` for a host that is none)
    and how a source of the companion alone is made (``create``), through
    which a caller checks it before it is stored: it answers, it lists points,
    and some of them are the device's. ``legacy_keys`` are the option keys
    its fields were stored under before entries kept a companion's settings
    apart (an old key, its field's key), where an older release still reads
    them: a caller keeps them in step with the settings.

    A companion is reached at a host: its ``host`` field. It is off while the
    host is empty, and nothing but the user fills it: the field is never
    required and has no default (checked here), so a new entry's companion is
    off (a push server without authentication is never switched on unasked).
    How long its stream may stay silent is the caller's, as for every stream
    (``SourceContext.stream_timeout``).
    """

    title: str
    fields: tuple[Field, ...]
    create: SourceFactory
    errors: tuple[ErrorRule, ...]
    other_device: str
    prepare: Prepare = as_given
    legacy_keys: Mapping[str, str] = field(default_factory=dict)

    def __post_init__(self) -> None:
        """Refuse a companion that is on before the user names its host."""
        host = next((item for item in self.fields if item.key == CONF_HOST), None)
        if host is None or host.required or host.default is not None:
            raise ValueError(
                f"{self.title}: a companion has a host field, optional and empty"
            )

    def settings(self, values: Mapping[str, Any]) -> dict[str, Any]:
        """Return its fields' values from stored or submitted ones, typed.

        Text is stripped (empty: none), a port is a whole number, a field
        not given has its default (a text field without one: empty).
        """
        settings: dict[str, Any] = {}
        for item in self.fields:
            value = values.get(item.key)
            if value is None or value == "":
                value = item.default
            if item.kind is FieldKind.PORT:
                settings[item.key] = None if value is None else int(value)
            elif item.kind is FieldKind.BOOLEAN:
                settings[item.key] = bool(value)
            else:
                settings[item.key] = str(value or "").strip()
        return settings

    def error_for(self, err: PlcError) -> ErrorRule | None:
        """Return the rule of a failure of its check (None: not one the form shows)."""
        return next((rule for rule in self.errors if isinstance(err, rule.error)), None)


def switched_on(settings: Mapping[str, Any]) -> bool:
    """Whether a companion's settings name its host (else it is off)."""
    return bool(settings.get(CONF_HOST))


@dataclass(frozen=True, slots=True, kw_only=True)
class SourceDescriptor:
    """One way into a device, as a caller offers it (see the module's docstring).

    ``connect`` is the form that adds it (its step ID is the descriptor's
    ``name``), ``reconfigure`` the form that changes where it is, ``credentials``
    the fields a reauthentication (or a discovered device's confirmation) asks.
    ``prepare`` turns a submitted form into the connection stored (it raises
    :class:`~.exceptions.InvalidHostError` for a host that is none) and
    ``create`` makes the source of a stored connection. ``address`` are the
    connection's keys a known device's entry takes over when it is added again
    at another address (none: an entry moves only when its user reconfigures
    it). ``location`` are the keys that tell where a device is, for a source
    whose device tells no identity of its own: two entries with the same never
    reach two devices, so a device there is not added again and no entry is
    moved to another's; a device added where an entry was added before (that
    entry moved since) is another: its identity is numbered when an entry
    holds it (``<identity> (2)``). ``manufacturer`` names the vendor a user searches for.
    ``point_map_loaders`` are the files a map is read from, by the file name's
    ending, each with its loader (the core's CSV, a system's own), ``check_address``
    checks a map point's address, ``point_types`` are the type names a map's
    point may take (a point's form offers them, an unknown type's error lists them); ``probe`` answers whether a host that joined
    the network is such a device (DHCP discovery), with one of
    ``probe_reasons`` when it is not; ``companion`` is the server its options
    may name beside it (a push server: :class:`Companion`). An entry stores the descriptor's name as
    its ``transport`` (``stores_name``), but TecoApi's: an entry without one is
    TecoApi's (entries made before there was a choice have none).
    """

    name: str
    title: str
    manufacturer: str
    connect: Form
    reconfigure: Form
    create: SourceFactory
    capabilities: frozenset[Capability]
    errors: tuple[ErrorRule, ...]
    credentials: tuple[Field, ...] = ()
    prepare: Prepare = as_given
    address: tuple[str, ...] = (CONF_HOST,)
    location: tuple[str, ...] = ()
    point_map_loaders: Mapping[str, Loader] = field(default_factory=dict)
    check_address: AddressCheck | None = None
    point_types: tuple[str, ...] = tuple(TYPE_NAMES)
    canonical_identity: CanonicalIdentity | None = None
    """The identity a known device's identity stands for now, for a device known
    by its address (a name resolved): the same device added again under another
    spelling is found (None: an identity is the device's own)."""
    probe: Probe | None = None
    probe_reasons: tuple[str, ...] = ()
    companion: Companion | None = None
    stores_name: bool = True
    status: frozenset[Capability] | None = None
    """The status entities shown (MODE, PROGRAM, CLOCK); None: by capabilities."""
    scan_interval: timedelta | None = None
    """How often its entries are polled unless the user says otherwise (None:
    the caller's default)."""
    noun: str = "device"
    """What the device reached is called in log lines and the diagnostics
    download: ``PLC``, ``gateway``, ``controller`` (a source of a gateway is
    never spoken of as a PLC)."""
    default_exclude: tuple[str, ...] = ()
    """Glob patterns of the point keys a new entry leaves out until the user says
    otherwise (its options start with them); a pattern starting with ``!`` takes
    back what the patterns before it leave out."""
    words: Words = Words()
    """The keys of the texts that speak of it in its own words (:class:`Words`)."""
    recognisers: tuple[Recogniser, ...] = ()
    """The conventions its typed devices are found by in its catalogue, run in
    order (:func:`~.devices.find_devices`); none: only the devices the user
    composes."""
    adopt_map: AdoptMap | None = None
    """How an uploaded map is taken (:data:`AdoptMap`; None: as the file is)."""

    @property
    def map_fields(self) -> tuple[Field, ...]:
        """The connection form's fields that say what its uploaded map is."""
        return tuple(item for item in self.connect.fields if item.of_map)

    def __post_init__(self) -> None:
        """Refuse a source whose settings share its options' first step.

        Every source's options open on a menu (a map's editor, or the changes
        of the points it discovers, beside the settings): its settings form
        needs a step of its own (:class:`Words`).
        """
        if self.words.settings_step_id == self.words.options_step_id:
            raise ValueError(
                f"{self.name}: its options' menu and settings need steps of their own"
            )

    @property
    def point_map_formats(self) -> tuple[str, ...]:
        """The file name endings a map is read from (none: the source takes no map)."""
        return tuple(self.point_map_loaders)

    @property
    def connection_keys(self) -> frozenset[str]:
        """The stored keys a source is built from: a change needs a new source.

        A point map is not one, nor what a field says of it: the entry keeps
        it (its store's ID) when it is reconfigured, and a new map applies in
        place, through the options.
        """
        return frozenset(
            {"transport"}
            | {
                item.key
                for item in (*self.connect.fields, *self.reconfigure.fields)
                if item.kind is not FieldKind.POINT_MAP and not item.of_map
            }
        )

    @property
    def secrets(self) -> frozenset[str]:
        """The stored keys that are secrets (never shown, logged or downloaded).

        Its companion's among them (its settings are stored in the options).
        """
        fields = (*self.connect.fields, *self.reconfigure.fields, *self.credentials)
        if self.companion is not None:
            fields += self.companion.fields
        return frozenset(item.key for item in fields if item.secret)

    @property
    def status_entities(self) -> frozenset[Capability]:
        """Which status entities an entry of this source shows."""
        if self.status is not None:
            return self.status
        return self.capabilities & {
            Capability.MODE,
            Capability.PROGRAM,
            Capability.CLOCK,
        }

    def error_for(self, err: PlcError) -> ErrorRule | None:
        """Return the rule of a failure (None: not one the forms show)."""
        return next((rule for rule in self.errors if isinstance(err, rule.error)), None)
