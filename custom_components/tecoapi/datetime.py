"""Dates and times: writable DT points (UTC on the PLC)."""

from datetime import datetime

from homeassistant.components.datetime import DateTimeEntity
from homeassistant.const import Platform

from .entity import PlcValueEntity
from .follower import entity_platform

PARALLEL_UPDATES = 1


class PlcDateTime(PlcValueEntity[datetime], DateTimeEntity):
    """A writable date and time (written in UTC)."""

    _value_type = datetime


async_setup_entry = entity_platform(Platform.DATETIME, points=PlcDateTime)
