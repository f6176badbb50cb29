"""A descriptor's companion: off until the user names its host, its settings typed.

A push server beside a source (Tecomat's PLCComS beside TecoApi) has no
authentication: nothing but the user may switch it on, so the core refuses a
companion that a new entry would start with switched on.
"""

from dataclasses import replace
from typing import Any

import pytest

from custom_components.tecoapi.pyplc.core.descriptor import (
    CONF_HOST,
    CONF_PORT,
    Companion,
    ErrorRule,
    Field,
    FieldKind,
    SourceContext,
    SourceOptions,
    switched_on,
)
from custom_components.tecoapi.pyplc.core.exceptions import (
    InvalidHostError,
    PlcConnectionError,
    PlcError,
)
from custom_components.tecoapi.pyplc.core.source import PlcSource
from custom_components.tecoapi.pyplc.tecomat.descriptor import PUSH, TECOAPI

HOST = Field(key=CONF_HOST, kind=FieldKind.HOST, required=False)
PORT = Field(key=CONF_PORT, kind=FieldKind.PORT, default=5010)


def _nowhere(
    context: SourceContext, connection: Any, options: SourceOptions
) -> PlcSource:
    raise AssertionError("not made here")


def companion(*fields: Field) -> Companion:
    """A companion of these fields (its check is never made here)."""
    return Companion(
        title="Test push",
        fields=fields,
        create=_nowhere,
        errors=(ErrorRule(error=PlcConnectionError, key="push_cannot_connect"),),
        other_device="push_other_device",
    )


@pytest.mark.parametrize(
    "host",
    [
        Field(key=CONF_HOST, kind=FieldKind.HOST),  # required
        Field(key=CONF_HOST, kind=FieldKind.HOST, required=False, default="plc"),
        Field(key="server", kind=FieldKind.HOST, required=False),  # no host field
    ],
)
def test_a_companion_on_before_the_user_names_it_is_refused(host: Field) -> None:
    with pytest.raises(ValueError, match="Test push: a companion has a host field"):
        companion(host, PORT)


def test_its_settings_are_typed_and_default_to_off() -> None:
    flag = Field(key="tls", kind=FieldKind.BOOLEAN, default=False)
    bare_port = Field(key="spare", kind=FieldKind.PORT, required=False)
    server = companion(HOST, PORT, flag, bare_port)
    defaults = server.settings({})
    assert defaults == {CONF_HOST: "", CONF_PORT: 5010, "tls": False, "spare": None}
    assert not switched_on(defaults)
    # As a form submits them: a port typed as a number, text with spaces.
    given = {CONF_HOST: " plc.local ", CONF_PORT: 5011.0, "tls": 1, "spare": "6000"}
    settings = server.settings(given)
    assert settings == {
        CONF_HOST: "plc.local",
        CONF_PORT: 5011,
        "tls": True,
        "spare": 6000,
    }
    assert switched_on(settings)
    # An emptied port takes its default again; a blank host is off.
    assert server.settings({CONF_HOST: "  ", CONF_PORT: ""}) == defaults


def test_its_check_s_failures_map_to_its_own_errors() -> None:
    server = companion(HOST, PORT)
    rule = server.error_for(PlcConnectionError("refused"))
    assert rule is not None
    assert rule.key == "push_cannot_connect"
    assert server.error_for(PlcError("other")) is None


def test_tecoapi_s_companion_is_plccoms_off_by_default() -> None:
    """PLCComS beside TecoApi: port 5010, its form's errors, its old option keys."""
    assert TECOAPI.companion is PUSH
    assert PUSH.settings({}) == {CONF_HOST: "", CONF_PORT: 5010}
    assert PUSH.prepare({CONF_HOST: "coms.local", CONF_PORT: 5011}) == {
        CONF_HOST: "coms.local",
        CONF_PORT: 5011,
    }
    with pytest.raises(InvalidHostError):
        PUSH.prepare({CONF_HOST: "http://coms.local", CONF_PORT: 5010})
    rule = PUSH.error_for(InvalidHostError("x"))
    assert rule is not None
    assert (rule.key, PUSH.other_device) == (
        "invalid_plccoms_host",
        "plccoms_other_plc",
    )
    assert dict(PUSH.legacy_keys) == {
        "plccoms_host": CONF_HOST,
        "plccoms_port": CONF_PORT,
    }


def test_a_companion_s_secret_is_its_descriptor_s() -> None:
    """Stored among the options, it is never shown, logged or downloaded either."""
    token = Field(key="token", kind=FieldKind.PASSWORD, required=False)
    with_token = replace(TECOAPI, companion=companion(HOST, PORT, token))
    assert TECOAPI.secrets == {"password"}
    assert with_token.secrets == {"password", "token"}
