"""Tekon's ASUD.SCADA: the opcconnector OPC-HTTP gateway in front of an OPC DA server.

``TekonSource`` (the session, the subscription, the address space and its hash)
over ``TekonClient`` (the gateway's HTTP API); ``catalogue`` makes the neutral
model of an address space: devices from dotted names, points from properties.
"""

from .catalogue import AddressSpace, build_address_space, parse_record
from .client import AddressItem, ItemUpdate, ServerInformation, TekonClient
from .source import TekonSource

__all__ = [
    "AddressItem",
    "AddressSpace",
    "ItemUpdate",
    "ServerInformation",
    "TekonClient",
    "TekonSource",
    "build_address_space",
    "parse_record",
]
