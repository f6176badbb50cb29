"""An entry's options: read typed, the patterns they filter by, their form, as stored.

What the form holds follows the source's capabilities (a gateway has no
attribute cadence nor plain variables; a source with a push server beside it
has its section), and a push server's settings are stored where this release
and the one before read them, in step.
"""

from datetime import timedelta
from typing import Final

from homeassistant.const import CONF_HOST, CONF_PORT, CONF_SCAN_INTERVAL
import pytest

from custom_components.tecoapi.const import DeviceGrouping, PlainVariables
from custom_components.tecoapi.options import (
    PlcOptions,
    options_schema,
    options_used,
    reconciled_options,
    settings_schema,
    stored_options,
)
from custom_components.tecoapi.pyplc.core.registry import source

TECOAPI: Final = source("tecoapi")
TEKON: Final = source("tekon")
PUSH: Final = "push"
"""Where an entry stores a push server's settings (the stored key, as stored)."""
LEGACY: Final = {"plccoms_host": "", "plccoms_port": 5010}


def test_options_are_read_typed_with_defaults_for_the_rest() -> None:
    options = PlcOptions.from_form(
        {
            CONF_SCAN_INTERVAL: 2,
            "plain_variables": "ignored",
            "include": [" Rooms.* ", "", "HEATING.*"],
            "devices": "single",
        }
    )

    assert options.scan_interval == timedelta(seconds=2)
    assert options.attribute_interval == timedelta(seconds=60)
    assert options.plain_variables is PlainVariables.IGNORED
    assert options.include == ("rooms.*", "heating.*")
    assert options.devices is DeviceGrouping.SINGLE
    assert not options.shows_plain
    assert options.push == {}


def test_a_source_s_defaults_are_its_own() -> None:
    """A gateway polls at its own pace; a push server beside a PLC is off."""
    assert PlcOptions.defaults_of(TEKON).scan_interval == TEKON.scan_interval
    tecoapi = PlcOptions.defaults_of(TECOAPI)
    assert tecoapi.push == {CONF_HOST: "", CONF_PORT: 5010}
    assert tecoapi.push_server is None
    switched_on = PlcOptions.from_form(
        {PUSH: {CONF_HOST: " 10.0.0.5 "}}, tecoapi, TECOAPI.companion
    )
    assert switched_on.push_server == {CONF_HOST: "10.0.0.5", CONF_PORT: 5010}


@pytest.mark.parametrize(
    ("include", "exclude", "key", "matches"),
    [
        ((), (), "anything", True),
        (("rooms.*",), (), "rooms.kitchen", True),
        (("rooms.*",), (), "heating.pump", False),
        ((), ("*debug*",), "rooms.debugflag", False),
        ((), ("hw.*", "!hw.*_ro_*"), "hw.neuron_ro_1", True),
        ((), ("hw.*", "!hw.*_ro_*"), "hw.neuron_di_1", False),
    ],
)
def test_the_patterns_let_a_path_through(
    include: tuple[str, ...], exclude: tuple[str, ...], key: str, matches: bool
) -> None:
    assert PlcOptions(include=include, exclude=exclude).matches(key) is matches


def test_only_the_entities_chosen_tell_options_apart() -> None:
    options = PlcOptions()

    assert options.same_entities(PlcOptions(scan_interval=timedelta(seconds=9)))
    assert not options.same_entities(PlcOptions(include=("rooms.*",)))
    assert not options.same_entities(PlcOptions(devices=DeviceGrouping.SINGLE))


def test_stored_options_read_back_as_they_were() -> None:
    options = PlcOptions.from_form(
        {CONF_SCAN_INTERVAL: 3, "exclude": ["*x*"], PUSH: {CONF_HOST: "h"}},
        None,
        TECOAPI.companion,
    )

    assert PlcOptions.from_form(options.as_dict(), None, TECOAPI.companion) == options


def test_the_form_holds_what_the_source_can_use() -> None:
    gateway = {str(marker) for marker in options_schema(TEKON).schema}
    plc = {str(marker) for marker in settings_schema(TECOAPI, {}).schema}

    assert gateway == {CONF_SCAN_INTERVAL, "include", "exclude", "devices"}
    assert plc == gateway | {"attribute_interval", "plain_variables", PUSH}
    devices = options_schema(TEKON).schema
    (marker,) = (marker for marker in devices if str(marker) == "devices")
    assert devices[marker].config["translation_key"] == TEKON.words.devices


def test_the_push_section_is_folded_while_push_is_off() -> None:
    def folded(shown: dict[str, object]) -> bool:
        schema = settings_schema(TECOAPI, shown).schema
        (marker,) = (marker for marker in schema if str(marker) == PUSH)
        return bool(schema[marker].options["collapsed"])

    assert folded({})
    assert not folded({PUSH: {CONF_HOST: "10.0.0.5"}})


def test_an_entry_keeps_only_the_options_its_source_uses() -> None:
    used = options_used(TEKON, PlcOptions())

    assert set(used) == {CONF_SCAN_INTERVAL, "include", "exclude", "devices"}


def test_push_is_stored_where_the_release_before_reads_it_too() -> None:
    options = PlcOptions.from_form(
        {PUSH: {CONF_HOST: "10.0.0.5", CONF_PORT: 5011}}, None, TECOAPI.companion
    )

    stored = stored_options(TECOAPI, options)

    assert stored[PUSH] == {CONF_HOST: "10.0.0.5", CONF_PORT: 5011}
    assert (stored["plccoms_host"], stored["plccoms_port"]) == ("10.0.0.5", 5011)
    assert PUSH not in stored_options(TEKON, PlcOptions())


def test_what_the_release_before_changed_is_read_back() -> None:
    """Push switched off there (its legacy keys only) is off here too."""
    older = {PUSH: {CONF_HOST: "10.0.0.5", CONF_PORT: 5010}, **LEGACY}

    reconciled = reconciled_options(TECOAPI, older)

    assert reconciled[PUSH] == {CONF_HOST: "", CONF_PORT: 5010}
    assert reconciled_options(TECOAPI, {CONF_SCAN_INTERVAL: 5}) == {
        CONF_SCAN_INTERVAL: 5
    }
    assert reconciled_options(None, older) == older
