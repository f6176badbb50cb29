"""The integration's flows, on one shared base (``config_flow`` registers them).

- :mod:`.base`: what the config and options flows share (:class:`~.base.PlcFlow`:
  the steps whose IDs a source names, an uploaded map; a failure as a form error)
- :mod:`.device`: checking a device and storing its entry (the config flow's core)
- :mod:`.config`: the config flow's steps (a new device, DHCP, reauthentication,
  reconfiguration)
- :mod:`.options`: the options flow (polling cadence, which points become
  entities, push)
- :mod:`.point_map`: the options flow's editor of a map (a newer file, one point,
  and the form of a point)
- :mod:`.subentry`: the subentry flow (a typed device composed of points)
"""
