"""Appliances: typed devices that read their state and turn a command into one write batch.

A :class:`~..devices.TypedDevice` says which points play which role. An
appliance made of it and the catalogue's points holds a :class:`RoleValue`
per role -- the point's key and how its value is read and written (its
transcoder) -- and gives:

- typed **state** read from a values mapping (:class:`LightState`,
  :class:`CoverState`, :class:`ThermostatState`, a switch's or a contact's
  flag, a display's number with its unit and precision, a button's counters
  and the events between two readings of them);
- **commands** (switch a light on at a brightness and colour, move a cover,
  set a thermostat's mode, switch a switch) that each return ONE ordered
  write batch: point key to the value to write, in the point's kind, to be
  sent together;
- for a device the PLC moves to a target (a blind, a light dimming to a target
  level) the points to read while it moves and whether it ``arrived``.

Values are read and written with the device's :class:`~..devices.Readings`
(its recogniser's: they may read text), and an inverted flag is read and
written as its opposite. An appliance knows nothing of Home Assistant.

The base (transcoders, :class:`Appliance`) is ``base``'s; each kind of
appliance has a module of its own.
"""

from ..exceptions import MissingPointError
from .base import FULL, Appliance, Batch, RoleValue
from .button import COUNTER_EVENTS, Button, ButtonEvent
from .contact import Contact
from .cover import Cover, CoverState, percent
from .display import MAX_PRECISION, Display
from .light import (
    BRIGHTNESS_SCALE,
    Light,
    LightState,
    brightness_level,
    level_brightness,
    rgb_packed,
    rgb_split,
)
from .switch import Switch
from .thermostat import (
    DEFAULT_RANGE,
    FINE_STEP,
    MODE_FLAGS,
    ONE_MODE,
    STEP,
    Thermostat,
    ThermostatAction,
    ThermostatMode,
    ThermostatState,
    thermostat_modes,
)

__all__ = [
    "BRIGHTNESS_SCALE",
    "COUNTER_EVENTS",
    "DEFAULT_RANGE",
    "FINE_STEP",
    "FULL",
    "MAX_PRECISION",
    "MODE_FLAGS",
    "ONE_MODE",
    "STEP",
    "Appliance",
    "Batch",
    "Button",
    "ButtonEvent",
    "Contact",
    "Cover",
    "CoverState",
    "Display",
    "Light",
    "LightState",
    "MissingPointError",
    "RoleValue",
    "Switch",
    "Thermostat",
    "ThermostatAction",
    "ThermostatMode",
    "ThermostatState",
    "brightness_level",
    "level_brightness",
    "percent",
    "rgb_packed",
    "rgb_split",
    "thermostat_modes",
]
