"""The options of a config entry: typed, their form, and the point filter."""

from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from datetime import timedelta
from fnmatch import fnmatchcase
from typing import Any, Final, Self

from homeassistant.config_entries import ConfigEntry
from homeassistant.const import CONF_SCAN_INTERVAL
from homeassistant.data_entry_flow import SectionConfig, section
from homeassistant.helpers.selector import (
    NumberSelector,
    NumberSelectorConfig,
    NumberSelectorMode,
    SelectSelector,
    SelectSelectorConfig,
    SelectSelectorMode,
    TextSelector,
    TextSelectorConfig,
)

from .compat import vol
from .connection import descriptor_of
from .const import (
    CONF_ATTRIBUTE_INTERVAL,
    CONF_DEVICES,
    CONF_EXCLUDE,
    CONF_INCLUDE,
    CONF_PLAIN_VARIABLES,
    CONF_PUSH,
    DEFAULT_ATTRIBUTE_INTERVAL,
    DEFAULT_DEVICE_GROUPING,
    DEFAULT_PLAIN_VARIABLES,
    DEFAULT_SCAN_INTERVAL,
    MAX_ATTRIBUTE_INTERVAL,
    MAX_SCAN_INTERVAL,
    MIN_ATTRIBUTE_INTERVAL,
    MIN_SCAN_INTERVAL,
    DeviceGrouping,
    PlainVariables,
)
from .forms import form_schema
from .pyplc.core.descriptor import (
    Capability,
    Companion,
    SourceDescriptor,
    switched_on,
)


@dataclass(frozen=True, slots=True, kw_only=True)
class PlcOptions:
    """How often to poll and which PLC variables become entities.

    ``include`` and ``exclude`` are glob patterns (``*``, ``?``, ``[...]``) matched
    case-insensitively against a variable's path, e.g. ``main.*`` or ``*.debug*``.
    An empty ``include`` means every variable; ``exclude`` wins over ``include``.
    An exclude pattern starting with ``!`` takes back what the patterns before it
    exclude (``hw.*`` then ``!hw.*_ro_*``: of ``hw`` only the relays); no
    variable path has a ``!``, so no pattern meant otherwise reads so.
    ``push`` are the settings of the server the source's descriptor may have
    beside it (its companion: a push server), stored as one mapping under
    ``push`` (empty: the source has none); with its host empty it is off, and
    the user switches it on, nothing else does.
    """

    scan_interval: timedelta = DEFAULT_SCAN_INTERVAL
    attribute_interval: timedelta = DEFAULT_ATTRIBUTE_INTERVAL
    plain_variables: PlainVariables = DEFAULT_PLAIN_VARIABLES
    include: tuple[str, ...] = field(default=())
    exclude: tuple[str, ...] = field(default=())
    devices: DeviceGrouping = DEFAULT_DEVICE_GROUPING
    push: Mapping[str, Any] = field(default_factory=dict, hash=False)

    @classmethod
    def from_entry(cls, entry: ConfigEntry) -> Self:
        """Read the options stored in a config entry (defaults for what is missing).

        The polling interval's default is the entry's source's, where it has one.
        """
        descriptor = descriptor_of(entry.data)
        return cls.from_form(
            entry.options, cls.defaults_of(descriptor), descriptor.companion
        )

    @classmethod
    def defaults_of(cls, descriptor: SourceDescriptor) -> Self:
        """Return the options of an entry of a source before the user changes any.

        Its companion, where it has one, is off (its host empty).
        """
        companion = descriptor.companion
        return cls(
            scan_interval=descriptor.scan_interval or DEFAULT_SCAN_INTERVAL,
            push={} if companion is None else companion.settings({}),
        )

    @classmethod
    def from_form(
        cls,
        values: Mapping[str, Any],
        defaults: Self | None = None,
        companion: Companion | None = None,
    ) -> Self:
        """Read options from stored or submitted form values (``defaults`` for the rest).

        The settings of a source's ``companion`` are read from their mapping
        (the form's section): a source without one has none.
        """
        defaults = cls() if defaults is None else defaults
        push = values.get(CONF_PUSH) or {}
        return cls(
            scan_interval=_seconds(values, CONF_SCAN_INTERVAL, defaults.scan_interval),
            attribute_interval=_seconds(
                values, CONF_ATTRIBUTE_INTERVAL, defaults.attribute_interval
            ),
            plain_variables=PlainVariables(
                values.get(CONF_PLAIN_VARIABLES, defaults.plain_variables)
            ),
            include=_patterns(values.get(CONF_INCLUDE, ())),
            exclude=_patterns(values.get(CONF_EXCLUDE, ())),
            devices=DeviceGrouping(values.get(CONF_DEVICES, defaults.devices)),
            push={} if companion is None else companion.settings(push),
        )

    def as_dict(self) -> dict[str, Any]:
        """Return the options as stored in the config entry (JSON-serialisable)."""
        return {
            CONF_SCAN_INTERVAL: int(self.scan_interval.total_seconds()),
            CONF_ATTRIBUTE_INTERVAL: int(self.attribute_interval.total_seconds()),
            CONF_PLAIN_VARIABLES: self.plain_variables.value,
            CONF_INCLUDE: list(self.include),
            CONF_EXCLUDE: list(self.exclude),
            CONF_DEVICES: self.devices.value,
        } | ({CONF_PUSH: dict(self.push)} if self.push else {})

    @property
    def push_server(self) -> Mapping[str, Any] | None:
        """The settings of the companion pushing values, or None: it is off (or none)."""
        return self.push if switched_on(self.push) else None

    @property
    def shows_plain(self) -> bool:
        """Whether plain variables (no metadata) become entities at all."""
        return self.plain_variables is not PlainVariables.IGNORED

    def matches(self, key: str) -> bool:
        """Whether the include and exclude patterns let a (lower-case) path through."""
        if self.include and not any(fnmatchcase(key, p) for p in self.include):
            return False
        excluded = False
        for pattern in self.exclude:
            if pattern.startswith("!"):
                excluded = excluded and not fnmatchcase(key, pattern[1:])
            elif not excluded:
                excluded = fnmatchcase(key, pattern)
        return not excluded

    def same_entities(self, other: Self) -> bool:
        """Whether both options create the same entities (only the cadence differs)."""
        return (self.plain_variables, self.include, self.exclude, self.devices) == (
            other.plain_variables,
            other.include,
            other.exclude,
            other.devices,
        )


def _seconds(values: Mapping[str, Any], key: str, default: timedelta) -> timedelta:
    """Return a whole number of seconds from a form value, or the default."""
    if (seconds := values.get(key)) is None:
        return default
    return timedelta(seconds=int(seconds))


def _patterns(patterns: Iterable[str]) -> tuple[str, ...]:
    """Return glob patterns lower-cased (paths match case-insensitively), no blanks."""
    return tuple(
        pattern.strip().lower() for pattern in patterns if pattern and pattern.strip()
    )


def _seconds_selector(minimum: float, maximum: float) -> NumberSelector:
    """Return a selector for a whole number of seconds, typed in a box."""
    return NumberSelector(
        NumberSelectorConfig(
            min=minimum,
            max=maximum,
            step=1,
            mode=NumberSelectorMode.BOX,
            unit_of_measurement="s",
        )
    )


def _devices_selector(translation_key: str) -> SelectSelector:
    """Return the device grouping's choices, labelled in a system's words.

    What a group is differs by system (a program's struct, a function block,
    an FP PLC's station, a building's controller): each names its labels'
    key (``SourceDescriptor.words.devices``).
    """
    return SelectSelector(
        SelectSelectorConfig(
            options=[choice.value for choice in DeviceGrouping],
            mode=SelectSelectorMode.LIST,
            translation_key=translation_key,
        )
    )


PATTERNS_SELECTOR: Final = TextSelector(TextSelectorConfig(multiple=True))
OPTIONS_SCHEMA: Final = vol.Schema(
    {
        vol.Required(CONF_SCAN_INTERVAL): _seconds_selector(
            MIN_SCAN_INTERVAL.total_seconds(), MAX_SCAN_INTERVAL.total_seconds()
        ),
        vol.Required(CONF_ATTRIBUTE_INTERVAL): _seconds_selector(
            MIN_ATTRIBUTE_INTERVAL.total_seconds(),
            MAX_ATTRIBUTE_INTERVAL.total_seconds(),
        ),
        vol.Required(CONF_PLAIN_VARIABLES): SelectSelector(
            SelectSelectorConfig(
                options=[choice.value for choice in PlainVariables],
                mode=SelectSelectorMode.LIST,
                translation_key=CONF_PLAIN_VARIABLES,
            )
        ),
        vol.Optional(CONF_INCLUDE): PATTERNS_SELECTOR,
        vol.Optional(CONF_EXCLUDE): PATTERNS_SELECTOR,
        vol.Required(CONF_DEVICES): _devices_selector(CONF_DEVICES),
    }
)


# The options a source without a capability has no use for.
NEEDS: Final[Mapping[str, Capability]] = {
    CONF_ATTRIBUTE_INTERVAL: Capability.METADATA,
    CONF_PLAIN_VARIABLES: Capability.PLAIN_VARIABLES,
}


def options_schema(descriptor: SourceDescriptor) -> vol.Schema:
    """Return the options form of a source: the fields its capabilities use.

    Its device grouping's choices are labelled in its own words.
    """
    return vol.Schema(
        {
            marker: _devices_selector(descriptor.words.devices)
            if str(marker) == CONF_DEVICES
            else selector
            for marker, selector in OPTIONS_SCHEMA.schema.items()
            if (needed := NEEDS.get(str(marker))) is None
            or needed in descriptor.capabilities
        }
    )


def settings_schema(
    descriptor: SourceDescriptor, shown: Mapping[str, Any]
) -> vol.Schema:
    """Return the settings form of a source: its options, and its companion's section.

    The section (``push``) holds the fields the companion declares; it is
    folded away while the companion is off in what is ``shown`` (stored or
    submitted options).
    """
    schema = options_schema(descriptor)
    if (companion := descriptor.companion) is None:
        return schema
    settings = companion.settings(shown.get(CONF_PUSH) or {})
    folded = SectionConfig(collapsed=not switched_on(settings))
    return schema.extend(
        {vol.Required(CONF_PUSH): section(form_schema(companion.fields), folded)}
    )


def options_used(descriptor: SourceDescriptor, options: PlcOptions) -> dict[str, Any]:
    """Return the options an entry of a source has a use for, as stored.

    Those of its options form, and its companion's where it has one (a
    gateway's entry has no plain variables, no push server).
    """
    used = {str(marker) for marker in settings_schema(descriptor, {}).schema}
    return {key: value for key, value in options.as_dict().items() if key in used}


def stored_options(descriptor: SourceDescriptor, options: PlcOptions) -> dict[str, Any]:
    """Return options as an entry stores them: readable by this release and older ones.

    A source's companion keeps its settings in one mapping (``push``); its
    ``legacy_keys`` are where an older release (0.3, entry version 1.1) reads
    them, at the top level of the options (``plccoms_host``, ``plccoms_port``),
    and they are written there too, in step. Going back to that release keeps
    push as it was; what that release changes there is read back on the next
    start of this one (:func:`reconciled_options`).
    """
    return reconciled_options(descriptor, options.as_dict())


def reconciled_options(
    descriptor: SourceDescriptor | None, options: Mapping[str, Any]
) -> dict[str, Any]:
    """Return stored options with a companion's settings in both places, in step.

    This release writes the companion's settings under ``push`` and under its
    ``legacy_keys`` alike; an older release reads and writes the legacy keys
    only (its options form drops ``push``). So where a legacy key is stored, it
    is what the user set last: an entry of version 1.1 (migrated to 1.2 so),
    or one that an older release's options changed after a downgrade (push
    switched on, off, or moved there). A legacy key not stored keeps the value
    ``push`` has. Every other option stays as it is; a source without a
    companion (or one this version does not have: ``descriptor`` None) keeps
    its options as they are.
    """
    reconciled = dict(options)
    companion = None if descriptor is None else descriptor.companion
    if companion is None:
        return reconciled
    older = {
        key: reconciled[legacy]
        for legacy, key in companion.legacy_keys.items()
        if legacy in reconciled
    }
    if not older and CONF_PUSH not in reconciled:
        return reconciled  # push never set: nothing to keep in step
    push = companion.settings({**(reconciled.get(CONF_PUSH) or {}), **older})
    reconciled[CONF_PUSH] = push
    for legacy, key in companion.legacy_keys.items():
        reconciled[legacy] = push[key]
    return reconciled
