"""Dates: writable DATE points."""

from datetime import date

from homeassistant.components.date import DateEntity
from homeassistant.const import Platform

from .entity import PlcValueEntity
from .follower import entity_platform

PARALLEL_UPDATES = 1


class PlcDate(PlcValueEntity[date], DateEntity):
    """A writable DATE."""

    _value_type = date


async_setup_entry = entity_platform(Platform.DATE, points=PlcDate)
