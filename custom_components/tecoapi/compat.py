"""Names whose home moved between the Home Assistant releases this integration supports.

The floor is Home Assistant 2026.2, the primary target 2026.10. Type checking
runs against the primary target; at run time each name comes from where the
running release keeps it.
"""

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from homeassistant.components.binary_sensor.const import BinarySensorDeviceClass
    import probatio as vol
else:
    # 2026.10 validates with probatio and aliases it as `voluptuous`; 2026.2 has
    # voluptuous itself. Both accept the same schemas.
    # 2026.10 moved the enum to binary_sensor.const and still re-exports it here.
    from homeassistant.components.binary_sensor import BinarySensorDeviceClass
    import voluptuous as vol

__all__ = ["BinarySensorDeviceClass", "vol"]
