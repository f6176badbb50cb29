"""The Tekon gateway as a caller offers it: its URL, checked on the gateway.

The form asks for the gateway's URL (HTTP or HTTPS, any port) and whether its
certificate is checked; the check reads ``ServerInformation``, opens a session
and reads the address space. An entry is polled every second unless the user
says otherwise: each poll is one ``GetUpdatesText``. The actions read and write
any item by its name (``PATHS``), an entity's or not.
"""

from collections.abc import Mapping
from dataclasses import replace
from datetime import timedelta
from typing import Any, Final

from ..core.descriptor import (
    CONF_HOST,
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
    AccessDeniedError,
    InvalidHostError,
    NotAPlcError,
    PlcConnectionError,
    PlcResponseError,
    PlcTlsError,
    ServiceUnavailableError,
)
from ..core.host import normalize_host
from ..core.source import PlcSource
from ..core.structs import STRUCTS
from .client import TekonClient
from .source import MANUFACTURER, TekonSource

NAME: Final = "tekon"
SCAN_INTERVAL: Final = timedelta(seconds=1)

_URL: Final = Field(key=CONF_HOST, kind=FieldKind.URL)
_VERIFY_SSL: Final = Field(key=CONF_VERIFY_SSL, kind=FieldKind.BOOLEAN, default=True)


def _connection(form: Mapping[str, Any]) -> dict[str, Any]:
    """Return the submitted connection with the URL as a base URL."""
    return {**form, CONF_HOST: normalize_host(str(form[CONF_HOST]))}


def _create(
    context: SourceContext, data: Mapping[str, Any], options: SourceOptions
) -> PlcSource:
    verify_ssl: bool = data.get(CONF_VERIFY_SSL, True)
    return TekonSource(
        TekonClient(
            context.http(verify_ssl),
            data[CONF_HOST],
            verify_ssl=verify_ssl,
            timeout=context.timeout,
        ),
        cache=context.cache,
        metadata_interval=options.metadata_interval,
        clock=context.clock,
        overrides=options.overrides,
    )


TEKON: Final = SourceDescriptor(
    name=NAME,
    title="Tekon ASUD.SCADA (OPC-HTTP)",
    manufacturer=MANUFACTURER,
    noun="gateway",
    connect=Form(step_id=NAME, fields=(_URL, _VERIFY_SSL)),
    reconfigure=Form(step_id=f"reconfigure_{NAME}", fields=(_URL, _VERIFY_SSL)),
    prepare=_connection,
    create=_create,
    capabilities=frozenset({Capability.DISCOVERY, Capability.PATHS}),
    errors=(
        ErrorRule(error=InvalidHostError, key="invalid_host", field=CONF_HOST),
        ErrorRule(error=PlcTlsError, key="tekon_tls_not_trusted"),
        ErrorRule(error=AccessDeniedError, key="tekon_forbidden"),
        ErrorRule(error=ServiceUnavailableError, key="tekon_opc_unavailable"),
        ErrorRule(error=PlcConnectionError, key="tekon_cannot_connect"),
        ErrorRule(error=NotAPlcError, key="not_tekon"),
        ErrorRule(error=PlcResponseError, key="unknown", logged=True),
    ),
    scan_interval=SCAN_INTERVAL,
    # Its options are a menu (the points' changes beside the settings); the
    # settings keep the step they had.
    words=replace(
        Words.of(NAME), options_step_id=f"{NAME}_menu", settings_step_id=NAME
    ),
    # A gateway's names may follow Tecomat's conventions.
    recognisers=(STRUCTS,),
)

DESCRIPTORS: Final = (TEKON,)
