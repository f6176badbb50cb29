"""Mervis (Unipi) as a caller offers it: the web panel API and the project's ``.vlist``.

The controller's address (HTTP or HTTPS, any port), the web panel's user and
password (both optional: a project may have none) and the ``.vlist`` the
Mervis IDE exports, uploaded in the same form, with the installation's project
where the file's is not the right one (:func:`~.vlist.adopt_vlist`). The points are the file's
variables; a newer file, and points added, changed (marked writable) or
removed, come through the options. A new entry leaves out the thousands of
``hw.*`` variables a Unipi project exports but for its inputs' and outputs'
states (:data:`DEFAULT_EXCLUDE`).
"""

from collections.abc import Mapping
from typing import Any, Final

from ..core.descriptor import (
    CONF_HOST,
    CONF_PASSWORD,
    CONF_POINT_MAP,
    CONF_USERNAME,
    CONF_VERIFY_SSL,
    Capability,
    ErrorRule,
    Field,
    FieldKind,
    Form,
    SourceContext,
    SourceDescriptor,
    SourceOptions,
    Words,
)
from ..core.exceptions import (
    InvalidHostError,
    NoPublicVariablesError,
    NotAPlcError,
    PlcAuthenticationError,
    PlcConnectionError,
    PlcResponseError,
    PlcTlsError,
    VariableNotFoundError,
)
from ..core.host import normalize_host
from ..core.models import ValueKind
from ..core.pointmap import MapPoint, type_name
from ..core.structs import STRUCTS
from ..core.texts import Template, Text
from .client import MervisClient
from .ids import Address
from .source import MANUFACTURER, MervisSource
from .vlist import PROJECT, adopt_vlist, load_vlist, type_widths

NAME: Final = "mervis"

DEFAULT_EXCLUDE: Final = (
    "hw.*",
    "!hw.*_di_?.??",
    "!hw.*_do_?.??",
    "!hw.*_ro_?.??",
    "!hw.*_ai_?.??",
    "!hw.*_ao_?.??",
)
"""What a new entry leaves out: the ``hw`` namespace (a Unipi board's thousands of
settings, counters and registers) but the states of its digital inputs and
outputs, relays and analog inputs and outputs (``hw.neuron_s103_di_1.04``)."""

_HOST: Final = Field(key=CONF_HOST, kind=FieldKind.URL)
_USERNAME: Final = Field(key=CONF_USERNAME, kind=FieldKind.USERNAME, required=False)
_PASSWORD: Final = Field(key=CONF_PASSWORD, kind=FieldKind.PASSWORD, required=False)
_VERIFY_SSL: Final = Field(key=CONF_VERIFY_SSL, kind=FieldKind.BOOLEAN, default=True)
_VLIST: Final = Field(key=CONF_POINT_MAP, kind=FieldKind.POINT_MAP)
_PROJECT: Final = Field(key=PROJECT, kind=FieldKind.TEXT, required=False, of_map=True)
"""The installation's project, where the file's is not the right one (see
:func:`~.vlist.adopt_vlist`)."""


def _connection(form: Mapping[str, Any]) -> dict[str, Any]:
    """Return the submitted connection: a base URL, empty credentials left out.

    An invalid host stays as typed: making the source reports it on the field.
    """
    try:
        host = normalize_host(form[CONF_HOST])
    except InvalidHostError:
        host = form[CONF_HOST]
    connection = {**form, CONF_HOST: host}
    for key in (CONF_USERNAME, CONF_PASSWORD):
        if not connection.get(key):
            connection.pop(key, None)
    return connection


def _create(
    context: SourceContext, data: Mapping[str, Any], options: SourceOptions
) -> MervisSource:
    """Make a Mervis controller's source: its web panel, the map's points."""
    if options.point_map is None:
        raise NoPublicVariablesError("A Mervis controller needs its .vlist")
    verify_ssl: bool = data.get(CONF_VERIFY_SSL, True)
    client = MervisClient(
        context.http(verify_ssl),
        data[CONF_HOST],
        data.get(CONF_USERNAME, ""),
        data.get(CONF_PASSWORD, ""),
        verify_ssl=verify_ssl,
        timeout=context.timeout,
    )
    return MervisSource(
        client,
        options.point_map,
        identity=options.identity,
        cache=context.cache,
        metadata_interval=options.metadata_interval,
        clock=context.clock,
    )


NOT_AN_ADDRESS: Final = Template(
    "mervis_not_address", "not CommUid[offset,length] (7001[4,4])"
)
WIDTH: Final = Template("mervis_width", "a {type} takes {bytes} bytes, not {length}")
WIDTHS: Final = Template(
    "mervis_widths", "a {type} takes {low} or {high} bytes, not {length}"
)


def check_address(point: MapPoint) -> Text | None:
    """Check a point's address: ``CommUid[offset,length]``, as wide as its type."""
    try:
        address = Address.parse(point.address)
    except ValueError:
        return NOT_AN_ADDRESS()
    if point.type.kind is ValueKind.STRING:
        return None
    widths = sorted(type_widths(point.type))
    if address.length in widths:
        return None
    name = type_name(point.type).upper()
    if len(widths) == 1:
        return WIDTH(type=name, bytes=widths[0], length=address.length)
    return WIDTHS(type=name, low=widths[0], high=widths[-1], length=address.length)


MERVIS: Final = SourceDescriptor(
    name=NAME,
    title="Mervis (Unipi)",
    manufacturer=MANUFACTURER,
    noun="controller",
    connect=Form(
        step_id=NAME,
        fields=(_HOST, _USERNAME, _PASSWORD, _VERIFY_SSL, _VLIST, _PROJECT),
    ),
    reconfigure=Form(
        step_id=f"reconfigure_{NAME}",
        fields=(_HOST, _USERNAME, _PASSWORD, _VERIFY_SSL),
    ),
    credentials=(_USERNAME, _PASSWORD),
    prepare=_connection,
    create=_create,
    # The web panel tells no serial number: adding a unit of the same project
    # never moves an entry, and an address is one controller's.
    address=(),
    location=(CONF_HOST,),
    capabilities=frozenset({Capability.POINT_MAP, Capability.CREDENTIALS}),
    errors=(
        ErrorRule(error=InvalidHostError, key="invalid_host", field=CONF_HOST),
        ErrorRule(error=PlcTlsError, key="mervis_tls_not_trusted"),
        ErrorRule(error=PlcConnectionError, key="mervis_cannot_connect"),
        ErrorRule(error=PlcAuthenticationError, key="mervis_invalid_auth"),
        ErrorRule(error=NotAPlcError, key="not_mervis"),
        ErrorRule(error=VariableNotFoundError, key="vlist_unknown"),
        ErrorRule(error=PlcResponseError, key="unknown", logged=True),
    ),
    point_map_loaders={"vlist": load_vlist},
    adopt_map=adopt_vlist,
    check_address=check_address,
    default_exclude=DEFAULT_EXCLUDE,
    words=Words.of(NAME, settings=True, reauth=True, points=True),
    # Tecomat's conventions: a function block's members follow the struct one.
    recognisers=(STRUCTS,),
)

DESCRIPTORS: Final = (MERVIS,)
