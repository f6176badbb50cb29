"""Constants of the integration (domain ``tecoapi``, kept from its first release)."""

from datetime import timedelta
from enum import StrEnum
import logging
from typing import Final

DOMAIN: Final = "tecoapi"
LOGGER: Final = logging.getLogger(__package__)
# The version of what a config entry stores: 1.1 kept a push server's settings
# at the top level of the options, 1.2 as one mapping (``async_migrate_entry``).
ENTRY_VERSION: Final = 1
ENTRY_MINOR_VERSION: Final = 2

# Options (config entry options; the connection itself lives in entry.data).
CONF_ATTRIBUTE_INTERVAL: Final = "attribute_interval"
CONF_PLAIN_VARIABLES: Final = "plain_variables"
CONF_INCLUDE: Final = "include"
CONF_EXCLUDE: Final = "exclude"
CONF_DEVICES: Final = "devices"
# The settings of the push server a source's descriptor may declare beside it
# (its companion: ``host``, ``port``, ...), stored in the options as one mapping,
# as its form section shows them. Entries of version 1.1 kept them at the top
# level, under the companion's legacy keys, where the release before reads them:
# they are written there too, in step (see ``options.reconciled_options``).
CONF_PUSH: Final = "push"
# How an entry reaches its PLC (entry data; a missing value is TecoApi).
CONF_TRANSPORT: Final = "transport"

DEFAULT_SCAN_INTERVAL: Final = timedelta(seconds=5)
MIN_SCAN_INTERVAL: Final = timedelta(seconds=1)
MAX_SCAN_INTERVAL: Final = timedelta(seconds=300)
DEFAULT_ATTRIBUTE_INTERVAL: Final = timedelta(seconds=60)
MIN_ATTRIBUTE_INTERVAL: Final = timedelta(seconds=5)
MAX_ATTRIBUTE_INTERVAL: Final = timedelta(hours=1)

# Seconds one request to the PLC may take before it counts as unreachable.
REQUEST_TIMEOUT: Final = 10.0
# Seconds a streaming connection (a push server's) may stay silent -- an answer,
# or, while connected, a line of any kind -- before it counts as stalled.
STREAM_TIMEOUT: Final = 5.0

# Repair issue shown while the PLC's user program is not running (HALT or ERR).
ISSUE_PLC_NOT_RUNNING: Final = "plc_not_running"
# Repair issue of a composed device whose points the program no longer has.
ISSUE_COMPOSITION_BROKEN: Final = "composition_broken"
# Repair issue listing the points the device refuses with a code of its own.
ISSUE_POINTS_REFUSED: Final = "points_refused"
# Repair issue of a device that cannot serve the list of its public variables.
ISSUE_VARIABLE_LIST: Final = "variable_list"


class PlainVariables(StrEnum):
    """What becomes of variables a device tells without metadata (plain variables).

    Plain variables carry no title, unit or read-only flag, so they are only
    ever shown read-only, named by their path.
    """

    DISABLED = "disabled"
    """Created, but disabled in the entity registry until the user enables them."""

    ENABLED = "enabled"
    """Created and enabled."""

    IGNORED = "ignored"
    """Not created at all (and not polled)."""


DEFAULT_PLAIN_VARIABLES: Final = PlainVariables.DISABLED


class DeviceGrouping(StrEnum):
    """Which devices a PLC's entities sit on (see ``selection``)."""

    GROUPS_AND_AREAS = "groups_and_areas"
    """A device per top-level struct, program instance or array; rooms get areas."""

    GROUPS = "groups"
    """A device per top-level struct, program instance or array; no areas."""

    SINGLE = "single"
    """Every entity on the PLC's device."""


DEFAULT_DEVICE_GROUPING: Final = DeviceGrouping.GROUPS_AND_AREAS

# Keys of the PLC status entities. A dash cannot occur in an IEC 61131-3 name,
# so these never collide with a point key in a unique ID.
STATUS_MODE: Final = "plc-mode"
STATUS_RUNNING_PROBLEM: Final = "plc-running-problem"
STATUS_PROGRAM_NAME: Final = "plc-program-name"
STATUS_PROGRAM_COMPILED: Final = "plc-program-compiled"
STATUS_CLOCK_OFFSET: Final = "plc-clock-offset"
# The ticking "PLC clock" timestamp sensor of earlier versions ("plc-clock") is no
# status key any more: setup removes its registry entry like any stale one.
STATUS_KEYS: Final = frozenset(
    {
        STATUS_MODE,
        STATUS_RUNNING_PROBLEM,
        STATUS_PROGRAM_NAME,
        STATUS_PROGRAM_COMPILED,
        STATUS_CLOCK_OFFSET,
    }
)
