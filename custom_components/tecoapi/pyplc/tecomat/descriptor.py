"""The Tecomat sources as a caller offers them: TecoApi, and PLCComS alone.

TecoApi is the PLC's own web server: signed in with a TecoApi user, it lists the
program's public variables and their T_ApiObject attributes, reads and writes any
path, tells the PLC's mode, program and clock, and may have a PLCComS server
beside it that pushes the values (its companion, :data:`PUSH`: off until the
user names its host). PLCComS alone has no authentication and tells the mode
and the program (no clock).

An entry of TecoApi stores no ``transport`` (entries made before there was a
choice have none); PLCComS's stores ``plccoms``.
"""

from collections.abc import Mapping
from dataclasses import replace
from typing import Any, Final

import aiohttp

from ..core.descriptor import (
    CONF_HOST,
    CONF_PASSWORD,
    CONF_PORT,
    CONF_USERNAME,
    CONF_VERIFY_SSL,
    Capability,
    Companion,
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
    PlcUnreachableError,
    VariableListTooLargeError,
    VariableListUnreadableError,
)
from ..core.host import is_host_name, normalize_host
from ..core.source import PlcSource
from .conventions import RECOGNISERS
from .plccoms.client import PlcComsClient
from .plccoms.protocol import DEFAULT_PORT as PLCCOMS_PORT
from .plccoms.pushed_session import PushedTecoApiSession
from .plccoms.source import PlcComsSource
from .points import MANUFACTURER
from .tecoapi.auth import is_tecoapi_challenge
from .tecoapi.client import TecoApiClient
from .tecoapi.source import TecoApiSession

TECOAPI_NAME: Final = "tecoapi"
PLCCOMS_NAME: Final = "plccoms"

HTTP_PORT: Final = 80
PROBE_TIMEOUT: Final = aiohttp.ClientTimeout(total=10)

# Shown in forms as the directive to write in Mosaic; braces cannot appear in a
# translation string, where they mark placeholders.
PLACEHOLDERS: Final = {"public_api": "{PUBLIC_API}"}

_HOST: Final = Field(key=CONF_HOST, kind=FieldKind.URL)
_USERNAME: Final = Field(key=CONF_USERNAME, kind=FieldKind.USERNAME)
_PASSWORD: Final = Field(key=CONF_PASSWORD, kind=FieldKind.PASSWORD)
_VERIFY_SSL: Final = Field(key=CONF_VERIFY_SSL, kind=FieldKind.BOOLEAN, default=True)
_PLCCOMS_HOST: Final = Field(key=CONF_HOST, kind=FieldKind.HOST)
_PLCCOMS_PORT: Final = Field(key=CONF_PORT, kind=FieldKind.PORT, default=PLCCOMS_PORT)
# The push server beside TecoApi: no host, no push.
_PUSH_HOST: Final = Field(key=CONF_HOST, kind=FieldKind.HOST, required=False)


def _tecoapi_connection(form: Mapping[str, Any]) -> dict[str, Any]:
    """Return the submitted connection with the host as a base URL, if it is one.

    An invalid host stays as typed: making the source reports it on the field.
    """
    try:
        host = normalize_host(form[CONF_HOST])
    except InvalidHostError:
        host = form[CONF_HOST]
    return {**form, CONF_HOST: host}


def _plccoms_connection(form: Mapping[str, Any]) -> dict[str, Any]:
    """Return a PLCComS entry's connection: a bare host name and a port."""
    host = str(form[CONF_HOST]).strip()
    if not is_host_name(host):
        raise InvalidHostError(f"{host!r} is not a host name")
    return {CONF_HOST: host, CONF_PORT: int(form[CONF_PORT])}


def _tecoapi(
    context: SourceContext, data: Mapping[str, Any], options: SourceOptions
) -> PlcSource:
    """TecoApi alone, or with a PLCComS server pushing its values."""
    verify_ssl: bool = data[CONF_VERIFY_SSL]
    client = TecoApiClient(
        context.http(verify_ssl),
        data[CONF_HOST],
        data[CONF_USERNAME],
        data[CONF_PASSWORD],
        verify_ssl=verify_ssl,
        timeout=context.timeout,
    )
    blocking: dict[str, Any] = (
        {"run_blocking": context.run_blocking} if context.run_blocking else {}
    )
    if (push := options.companion) is not None:
        return PushedTecoApiSession(
            client,
            PlcComsClient(
                push[CONF_HOST], push[CONF_PORT], timeout=context.stream_timeout
            ),
            metadata_interval=options.metadata_interval,
            clock=context.clock,
            overrides=options.overrides,
            **blocking,
        )
    return TecoApiSession(
        client,
        metadata_interval=options.metadata_interval,
        clock=context.clock,
        overrides=options.overrides,
        **blocking,
    )


def _plccoms(
    context: SourceContext, data: Mapping[str, Any], options: SourceOptions
) -> PlcSource:
    """PLCComS alone."""
    return PlcComsSource(
        PlcComsClient(data[CONF_HOST], data[CONF_PORT], timeout=context.stream_timeout),
        metadata_interval=options.metadata_interval,
        clock=context.clock,
        overrides=options.overrides,
    )


async def _probe(session: aiohttp.ClientSession, ip: str) -> tuple[str | None, str]:
    """Ask, without credentials, whether a TecoApi server answers at a new address.

    Discovery looks at plain HTTP on port 80 (a PLC serving only HTTPS or on
    another port is added by hand): an unauthenticated ``GET /TecoApi/GetInfo``
    answered with a 401 challenge for the ``TecoApi`` realm is a TecoApi PLC.
    Returns None and its base URL, or why it is not one.
    """
    base_url = normalize_host(f"{ip}:{HTTP_PORT}")
    try:
        async with session.get(
            f"{base_url}/TecoApi/GetInfo", allow_redirects=False, timeout=PROBE_TIMEOUT
        ) as response:
            status = response.status
            challenges = response.headers.getall("WWW-Authenticate", [])
    except (aiohttp.ClientError, TimeoutError):
        return "cannot_connect", base_url
    if status == 401 and is_tecoapi_challenge(challenges):
        return None, base_url
    return "not_tecoapi", base_url


PLCCOMS_ERRORS: Final = (
    ErrorRule(error=InvalidHostError, key="invalid_plccoms_host", field=CONF_HOST),
    ErrorRule(error=PlcUnreachableError, key="plccoms_plc_unreachable"),
    ErrorRule(error=PlcConnectionError, key="plccoms_cannot_connect"),
    ErrorRule(error=NoPublicVariablesError, key="plccoms_no_variables"),
    ErrorRule(error=NotAPlcError, key="not_plccoms"),
    ErrorRule(error=PlcResponseError, key="unknown", logged=True),
)

PUSH: Final = Companion(
    title="PLCComS",
    fields=(_PUSH_HOST, _PLCCOMS_PORT),
    prepare=_plccoms_connection,
    create=_plccoms,
    errors=PLCCOMS_ERRORS,
    other_device="plccoms_other_plc",
    # Version 1.1 of an entry kept them among its options, by these names.
    legacy_keys={"plccoms_host": CONF_HOST, "plccoms_port": CONF_PORT},
)

TECOAPI: Final = SourceDescriptor(
    name=TECOAPI_NAME,
    title="Tecomat (TecoApi)",
    manufacturer=MANUFACTURER,
    noun="PLC",
    connect=Form(
        step_id=TECOAPI_NAME,
        fields=(_HOST, _USERNAME, _PASSWORD, _VERIFY_SSL),
        placeholders=PLACEHOLDERS,
    ),
    reconfigure=Form(
        step_id="reconfigure",
        fields=(_HOST, _USERNAME, _PASSWORD, _VERIFY_SSL),
        placeholders=PLACEHOLDERS,
    ),
    credentials=(_USERNAME, _PASSWORD),
    prepare=_tecoapi_connection,
    create=_tecoapi,
    capabilities=frozenset(
        {
            Capability.DISCOVERY,
            Capability.MODE,
            Capability.PROGRAM,
            Capability.CLOCK,
            Capability.METADATA,
            Capability.PATHS,
            Capability.CREDENTIALS,
            Capability.PLAIN_VARIABLES,
        }
    ),
    errors=(
        ErrorRule(error=InvalidHostError, key="invalid_host", field=CONF_HOST),
        ErrorRule(error=PlcTlsError, key="tls_not_trusted"),
        ErrorRule(error=PlcConnectionError, key="cannot_connect"),
        ErrorRule(error=NoPublicVariablesError, key="no_public_variables"),
        ErrorRule(error=VariableListTooLargeError, key="public_file_too_big"),
        ErrorRule(error=VariableListUnreadableError, key="public_file_unreadable"),
        ErrorRule(error=PlcAuthenticationError, key="invalid_auth"),
        ErrorRule(error=NotAPlcError, key="not_tecoapi"),
        ErrorRule(error=PlcResponseError, key="unknown", logged=True),
    ),
    probe=_probe,
    probe_reasons=("cannot_connect", "not_tecoapi"),
    companion=PUSH,
    stores_name=False,
    # Its options are a menu (the points' changes beside the settings), its
    # settings a step of its own behind it; it signs in again on its own step.
    words=replace(
        Words.of(TECOAPI_NAME, reauth=True),
        options_step_id=f"{TECOAPI_NAME}_menu",
        settings_step_id=TECOAPI_NAME,
    ),
    recognisers=RECOGNISERS,
)

PLCCOMS: Final = SourceDescriptor(
    name=PLCCOMS_NAME,
    title="Tecomat (PLCComS)",
    manufacturer=MANUFACTURER,
    noun="PLC",
    connect=Form(step_id=PLCCOMS_NAME, fields=(_PLCCOMS_HOST, _PLCCOMS_PORT)),
    reconfigure=Form(
        step_id="reconfigure_plccoms", fields=(_PLCCOMS_HOST, _PLCCOMS_PORT)
    ),
    prepare=_plccoms_connection,
    create=_plccoms,
    address=(CONF_HOST, CONF_PORT),
    capabilities=frozenset(
        {
            Capability.DISCOVERY,
            Capability.PUSH,
            Capability.MODE,
            Capability.PROGRAM,
            Capability.METADATA,
            Capability.PATHS,
            Capability.PLAIN_VARIABLES,
        }
    ),
    # PLCComS tells no clock: its clock offset stays unknown, as before there
    # were descriptors (an entry keeps every entity it had).
    status=frozenset({Capability.MODE, Capability.PROGRAM, Capability.CLOCK}),
    errors=PLCCOMS_ERRORS,
    # The PLC is known by its EPSNET address: it tells no serial number here
    # (its own wrong device). Its options are a menu (the points' changes
    # beside the settings); the settings keep the step they had.
    words=replace(
        Words.of(PLCCOMS_NAME),
        options_step_id=f"{PLCCOMS_NAME}_menu",
        settings_step_id=PLCCOMS_NAME,
    ),
    recognisers=RECOGNISERS,
)

DESCRIPTORS: Final = (TECOAPI, PLCCOMS)
