"""Who hears of an update: the keys the entities listen with, and who is told.

Every entity of the integration listens with the keys of what it shows (its
listener's context: a point entity its point's key, a typed entity its points'),
and writes its state only when one of them changed, the poll's success flipped or
a new selection came (``entity.PlcEntity``). :class:`KeyedCoordinator` reads the
listeners by those keys, so that:

- the polled keys are worked out once while the listeners and the selection
  stay the same (an entity added or removed works them out again);
- an update that neither flips the success nor brings a new selection tells the
  entities whose keys changed, and every listener without keys (the platforms'
  followers); any other update tells every listener, as Home Assistant does. An
  entity left out would only have found that nothing of its own changed.

Nothing is kept per listener beyond what Home Assistant keeps (its listeners,
read here as the base class's): a thousand entities cost no memory more.
"""

from homeassistant.core import CALLBACK_TYPE, callback
from homeassistant.helpers.update_coordinator import DataUpdateCoordinator

from .data import PlcData


class KeyedCoordinator(DataUpdateCoordinator[PlcData]):
    """A data update coordinator whose listeners are told by their keys."""

    # The polled keys, with the selection and the listeners they were worked out
    # for (the latest listener's number and how many listen).
    _polled: tuple[object, tuple[int, int], frozenset[str]] | None = None
    # The success and the selection every listener was told of last.
    _told: tuple[bool, object] | None = None
    # The listeners without keys, with the listeners they were found among.
    _keyless: tuple[tuple[int, int], list[CALLBACK_TYPE]] | None = None

    def _listening(self) -> tuple[int, int]:
        """Return what changes whenever a listener comes or goes.

        The latest listener's number (Home Assistant counts them) and how many
        listen now.
        """
        return self._last_listener_id, len(self._listeners)

    @property
    def polled_keys(self) -> frozenset[str]:
        """Keys of the points with an entity listening.

        A point entity listens with its key, a typed entity with the keys of the
        points it is built from.
        """
        selection = self.data.selection
        listening = self._listening()
        polled = self._polled
        if polled is not None and polled[0] is selection and polled[1] == listening:
            return polled[2]
        keys: set[str] = set()
        for context in self.async_contexts():
            if isinstance(context, str):
                keys.add(context)
            else:
                keys.update(context)
        found = frozenset(keys & selection.watched)
        self._polled = (selection, listening, found)
        return found

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
        if not changed:
            # Nothing changed: no entity is told, only the listeners without keys.
            self._tell(self._keyless_listeners())
            return
        told_now: list[CALLBACK_TYPE] = []
        for update_callback, context in list(self._listeners.values()):
            # Left out: a listener with a key, or keys, none of them changed.
            if isinstance(context, str):
                if context not in changed:
                    continue
            elif isinstance(context, frozenset | set) and changed.isdisjoint(context):
                continue
            told_now.append(update_callback)
        self._tell(told_now)

    def _keyless_listeners(self) -> list[CALLBACK_TYPE]:
        """Return the listeners without keys (found again when listeners change)."""
        listening = self._listening()
        keyless = self._keyless
        if keyless is None or keyless[0] != listening:
            found = [
                update_callback
                for update_callback, context in self._listeners.values()
                if not isinstance(context, str | frozenset | set)
            ]
            keyless = self._keyless = (listening, found)
        return keyless[1]

    @callback
    def _tell(self, listeners: list[CALLBACK_TYPE]) -> None:
        """Call listeners in turn; one that fails is logged, the others still hear."""
        for update_callback in listeners:
            try:
                update_callback()
            except Exception:
                self.logger.exception(
                    "Unexpected error updating listener %s for %s",
                    id(update_callback),
                    self.name,
                )
