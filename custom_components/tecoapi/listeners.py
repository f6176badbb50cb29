"""Who hears of an update: the keys the entities listen with, and who is told.

Every entity of the integration listens with the keys of what it shows (a point
entity its point's key, a typed entity its points'), and writes its state only
when one of them changed, the poll's success flipped or a new selection came
(``entity.PlcEntity``). :class:`KeyedCoordinator` keeps the listeners by those
keys, so that:

- the polled keys are worked out once while the listeners and the selection
  stay the same (an entity added or removed works them out again);
- an update that neither flips the success nor brings a new selection tells the
  entities whose keys changed, and every listener without keys (the platforms'
  followers); any other update tells every listener, as Home Assistant does. An
  entity left out would only have found that nothing of its own changed.
"""

from collections.abc import Callable
from typing import Any

from homeassistant.core import CALLBACK_TYPE, callback
from homeassistant.helpers.update_coordinator import DataUpdateCoordinator

from .data import PlcData


class KeyedCoordinator(DataUpdateCoordinator[PlcData]):
    """A data update coordinator whose listeners are known by their keys."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        """Start with no listener (the arguments are the base class's)."""
        # By listener, in the order they came: its callback and its keys (None:
        # told of every update).
        self._keyed: dict[object, tuple[CALLBACK_TYPE, frozenset[str] | None]] = {}
        # The polled keys, with the selection they were worked out for.
        self._polled: tuple[object, frozenset[str]] | None = None
        # The success and the selection every listener was told of last.
        self._told: tuple[bool, object] | None = None
        super().__init__(*args, **kwargs)

    @property
    def polled_keys(self) -> frozenset[str]:
        """Keys of the points with an entity listening.

        A point entity listens with its key, a typed entity with the keys of the
        points it is built from.
        """
        selection = self.data.selection
        if self._polled is not None and self._polled[0] is selection:
            return self._polled[1]
        keys: set[str] = set()
        for _, listened in self._keyed.values():
            if listened is not None:
                keys.update(listened)
        polled = frozenset(keys & selection.watched)
        self._polled = (selection, polled)
        return polled

    @callback
    def async_add_listener(
        self, update_callback: CALLBACK_TYPE, context: Any = None
    ) -> Callable[[], None]:
        """Listen for data updates; ``context`` is a key or the keys listened to."""
        remove = super().async_add_listener(update_callback, context)
        token = object()
        self._keyed[token] = (update_callback, _keys(context))
        self._polled = None

        @callback
        def remove_listener() -> None:
            del self._keyed[token]
            self._polled = None
            remove()

        return remove_listener

    @callback
    def async_update_listeners(self) -> None:
        """Tell the listeners of an update: an entity only when it may show more.

        While the success and the selection stay what every listener was told
        last, an entity none of whose keys changed is not told.
        """
        data: PlcData | None = self.data
        success = self.last_update_success
        told = self._told
        if (
            data is None
            or told is None
            or told[0] is not success
            or told[1] is not data.selection
        ):
            self._told = None if data is None else (success, data.selection)
            super().async_update_listeners()
            return
        changed = data.changed
        for update_callback, keys in list(self._keyed.values()):
            if keys is not None and keys.isdisjoint(changed):
                continue
            try:
                update_callback()
            except Exception:
                self.logger.exception(
                    "Unexpected error updating listener %s for %s",
                    id(update_callback),
                    self.name,
                )


def _keys(context: Any) -> frozenset[str] | None:
    """Return the keys a listener's context names (None: it listens to everything)."""
    if context is None:
        return None
    if isinstance(context, str):
        return frozenset((context,))
    return frozenset(context)
