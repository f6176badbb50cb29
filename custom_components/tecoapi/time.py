"""Times of day: writable TIME_OF_DAY points (``hh:mm:ss.zzz`` below 24 h)."""

from datetime import time, timedelta
from typing import override

from homeassistant.components.time import TimeEntity
from homeassistant.const import Platform

from .entity import PlcValueEntity
from .follower import entity_platform
from .pyplc.core.scalars import time_of_day

PARALLEL_UPDATES = 1


class PlcTime(PlcValueEntity[time], TimeEntity):
    """A writable time of day."""

    @property
    @override
    def native_value(self) -> time | None:
        """The point's time of day (None for a TIME past 24 h)."""
        value = self.point_value
        return time_of_day(value) if isinstance(value, timedelta) else None


async_setup_entry = entity_platform(Platform.TIME, points=PlcTime)
