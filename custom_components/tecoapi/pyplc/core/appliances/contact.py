"""Contacts: a door, window or motion contact's ``state`` flag."""

from collections.abc import Mapping
from typing import Any

from ..devices import Role
from .base import Appliance


class Contact(Appliance):
    """A contact: on (open, motion) or off, from its ``state`` point.

    An inverted ``state`` reads as its opposite. It is only read: a contact
    has no commands.
    """

    __slots__ = ()

    def state(self, values: Mapping[str, Any]) -> bool | None:
        """Whether it is on (None: unknown)."""
        return self.flag(Role.STATE, values)
