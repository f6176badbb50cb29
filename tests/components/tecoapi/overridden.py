"""Changing a discovered point in the options, as a user does (flows/point_override.py)."""

from typing import Any

from homeassistant.config_entries import ConfigEntry
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType

from custom_components.tecoapi.flows.point_override import CONF_POINT


def suggested(result: Any) -> dict[str, Any]:
    """The values a form shows before the user types anything (its suggestions)."""
    shown: dict[str, Any] = {}
    for key in result["data_schema"].schema:
        value = (key.description or {}).get("suggested_value")
        if value is not None:
            shown[str(key)] = value
    return shown


def as_stored(entry: ConfigEntry) -> tuple[Any, ...]:
    """What an entry stores itself: its data, options and version."""
    return dict(entry.data), dict(entry.options), entry.version, entry.minor_version


async def open_step(hass: HomeAssistant, entry: ConfigEntry, step: str) -> Any:
    """Open an entry's options and choose a step of its menu."""
    manager = hass.config_entries.options
    result = await manager.async_init(entry.entry_id)
    assert result["type"] is FlowResultType.MENU, result
    return await manager.async_configure(result["flow_id"], {"next_step_id": step})


async def open_point(hass: HomeAssistant, entry: ConfigEntry, point: str) -> Any:
    """Open an entry's options, choose *Change a point*, then the point (any case)."""
    manager = hass.config_entries.options
    result = await open_step(hass, entry, "override_point")
    assert result["step_id"] == "override_point", result
    options = result["data_schema"].schema[CONF_POINT].config["options"]
    (key,) = (
        option["value"]
        for option in options
        if option["value"].lower() == point.lower()
    )
    result = await manager.async_configure(result["flow_id"], {CONF_POINT: [key]})
    assert result["step_id"] == "point_override", result
    return result


CLASSES = ("device_class", "state_class")
"""The fields of the step after a point's form (flows/point_class.py)."""


def offered(result: Any) -> dict[str, str | None]:
    """The classes a class step offers: a device class's platform, a state class.

    Home Assistant's device class selector names its platform (``domain``);
    on 2026.2, which has none, the list's classes say which platform's they
    are. The state classes are a list of their own (None).
    """
    shown: dict[str, str | None] = {}
    for key, selector in result["data_schema"].schema.items():
        config = selector.config
        if str(key) == "state_class":
            assert list(config["options"]) == [
                "measurement",
                "measurement_angle",
                "total",
                "total_increasing",
            ]
            shown[str(key)] = None
        elif "domain" in config:
            shown[str(key)] = str(config["domain"])
        else:  # Home Assistant 2026.2: the platform's classes, by its names
            values = {option["value"]: option["label"] for option in config["options"]}
            shown[str(key)] = (
                "binary_sensor" if values.get("door") == "Door" else "number"
            )
            if shown[str(key)] == "number":
                assert values["energy"] == "Energy"
                assert "timestamp" not in values
    return shown


async def submit(hass: HomeAssistant, result: Any, **changes: Any) -> Any:
    """Submit a form as shown, with ``changes`` (None: a field emptied)."""
    values = {**suggested(result), **changes}
    return await hass.config_entries.options.async_configure(
        result["flow_id"],
        {key: value for key, value in values.items() if value is not None},
    )


async def change_point(
    hass: HomeAssistant, entry: ConfigEntry, point: str, **changes: Any
) -> Any:
    """Change a point: its form as shown, with ``changes`` (None: a field emptied).

    Its classes among ``changes`` go to the step that asks them, where the
    point takes any (and its form passed).
    """
    result = await open_point(hass, entry, point)
    classes = {key: changes.pop(key) for key in CLASSES if key in changes}
    result = await submit(hass, result, **changes)
    if result.get("step_id") == "point_class":
        result = await submit(hass, result, **classes)
    await hass.async_block_till_done(wait_background_tasks=True)
    return result
