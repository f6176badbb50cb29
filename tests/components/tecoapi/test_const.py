"""The integration's constants that entries, registries and options store.

Unique IDs are forever and a previous release must read what this one stores:
the domain, the option keys and their choices' values, the status entities'
keys and the entry's version never change their spelling.
"""

from custom_components.tecoapi import const


def test_what_entries_store_keeps_its_spelling() -> None:
    assert const.DOMAIN == "tecoapi"
    assert (const.ENTRY_VERSION, const.ENTRY_MINOR_VERSION) == (1, 2)
    assert [
        const.CONF_ATTRIBUTE_INTERVAL,
        const.CONF_PLAIN_VARIABLES,
        const.CONF_INCLUDE,
        const.CONF_EXCLUDE,
        const.CONF_DEVICES,
        const.CONF_PUSH,
        const.CONF_TRANSPORT,
    ] == [
        "attribute_interval",
        "plain_variables",
        "include",
        "exclude",
        "devices",
        "push",
        "transport",
    ]
    assert [choice.value for choice in const.PlainVariables] == [
        "disabled",
        "enabled",
        "ignored",
    ]
    assert [choice.value for choice in const.DeviceGrouping] == [
        "groups_and_areas",
        "groups",
        "single",
    ]


def test_status_keys_never_collide_with_a_point_s() -> None:
    """A dash is in no IEC 61131-3 name: a status entity's unique ID is its own."""
    assert {
        "plc-mode",
        "plc-running-problem",
        "plc-program-name",
        "plc-program-compiled",
        "plc-clock-offset",
    } == const.STATUS_KEYS


def test_the_polling_bounds_hold_their_defaults() -> None:
    assert const.MIN_SCAN_INTERVAL <= const.DEFAULT_SCAN_INTERVAL
    assert const.DEFAULT_SCAN_INTERVAL <= const.MAX_SCAN_INTERVAL
    assert const.MIN_ATTRIBUTE_INTERVAL <= const.DEFAULT_ATTRIBUTE_INTERVAL
    assert const.DEFAULT_ATTRIBUTE_INTERVAL <= const.MAX_ATTRIBUTE_INTERVAL
