"""The one write path of every entity and action: send, name what was refused, show.

An entity's value, a typed device's command (one batch) and the actions' writes
and reads of any path go to the coordinator's source through :class:`PlcWriter`.
The source checks and sends them (a value it refuses sends nothing); an error
becomes Home Assistant's translated one in ``helpers.plc_action``, naming the
point refused. The source pushes what the device acknowledged (the entities
show it at once) and reads it back: a read-back that finds the same is no
second update, so a command is one update and each entity's state one write.
"""

from collections.abc import Awaitable, Callable, Mapping
from contextlib import AbstractContextManager
from typing import TYPE_CHECKING, Any

from .helpers import plc_action
from .pyplc import PlcError, Point
from .pyplc.core.appliances import Batch, MissingPointError
from .pyplc.core.source import PlcSource, Snapshot

if TYPE_CHECKING:
    from .coordinator import PlcCoordinator


class PlcWriter:
    """Writes a coordinator's points and variables through its source now.

    A source swapped in (push switched on or off) is written from then on.
    """

    def __init__(self, coordinator: "PlcCoordinator") -> None:
        """Write through ``coordinator``'s source; show through it."""
        self._coordinator = coordinator

    async def async_write(self, key: str, value: Any) -> None:
        """Write a value to a point: an entity's write.

        The source checks and sends it; the entity shows what was written and
        what the device holds then, in one update. Raises a translated error
        when the value is refused, the point is gone or the device could not
        be written; the entity then keeps showing the device's value.
        """
        await self._async_send({key: value}, lambda source: source.write(key, value))

    async def async_write_many(self, values: Mapping[str, Any]) -> None:
        """Write several points' values as one batch: one command of a device.

        The source checks every value before it sends any, so a refused one
        leaves the device and Home Assistant as they were; the translated
        error names the point refused.
        """
        if values:
            await self._async_send(values, lambda source: source.write_many(values))

    async def async_send(self, command: Callable[[], Batch]) -> Batch:
        """Send the batch a typed device's command makes; return it.

        A command that needs a point its device no longer has sends nothing:
        the translated error names the point.
        """
        with self._mapped("write", ""):
            batch = command()
        await self.async_write_many(batch)
        return batch

    async def async_write_variable(self, path: str, value: Any) -> None:
        """Write a JSON-shaped value to any variable path (the action)."""
        with self._mapped("write_variable", path, value):
            await self._async_show(self._coordinator.source.write_variable(path, value))

    async def async_read_variable(self, path: str) -> Any:
        """Read any variable path: its JSON-shaped value (the action)."""
        with self._mapped("read_variable", path):
            return await self._coordinator.source.read_variable(path)

    async def _async_send(
        self,
        values: Mapping[str, Any],
        send: Callable[[PlcSource], Awaitable[Snapshot | None]],
    ) -> None:
        """Send points' values; on failure raise the error naming the point refused.

        A key that is no point of the catalogue shown (the library refused it
        before sending, as a variable it does not know or a point it does not
        have) is told as a variable the device does not know.
        """
        coordinator = self._coordinator
        try:
            await self._async_show(send(coordinator.source))
        except (PlcError, MissingPointError) as err:
            points = coordinator.data.catalogue.points
            named = getattr(err, "path", None) or getattr(err, "key", None)
            key = refused_key(values, points, named)
            point = points.get(key)
            operation, path = (
                ("write", point.path) if point is not None else ("write_variable", key)
            )
            with self._mapped(operation, path, values[key]):
                raise

    def _mapped(
        self, operation: str, path: str, value: Any = None
    ) -> AbstractContextManager[None]:
        """Turn a library error raised inside into the entry's translated one."""
        coordinator = self._coordinator
        return plc_action(
            coordinator.hass,
            coordinator.config_entry,
            operation=operation,
            path=path,
            value=value,
        )

    async def _async_show(self, write: Awaitable[Snapshot | None]) -> None:
        """Await a write; show what it read back, unless its push showed it all.

        The source pushed what the device acknowledged (shown at once, between
        polls): a read-back that finds the same tells nobody again. One that
        finds more or otherwise is shown; one that read nothing back (or found
        a new program) is followed by a poll.
        """
        confirmed = await write
        coordinator = self._coordinator
        if confirmed is None or confirmed.catalogue is not coordinator.data.catalogue:
            await coordinator.async_request_refresh()
            return
        data = coordinator.updated(confirmed)
        if data.changed or not coordinator.last_update_success:
            coordinator.async_set_updated_data(data)
        else:
            coordinator.data = data


def refused_key(
    values: Mapping[str, Any], points: Mapping[str, Point], refused: str | None
) -> str:
    """Return the key of a batch's value an error names, else the batch's first.

    A source names a point by its key, its path or its address, or by a path
    within it (the member that holds its value), in any case; ``points`` are
    the catalogue's (a key not among them is named by itself only).
    """
    name = (refused or "").lower()
    within: list[tuple[int, str]] = []
    for key in values:
        point = points.get(key)
        if name and (
            name == key.lower()
            or (
                point is not None
                and name in {point.path.lower(), point.address.lower()}
            )
        ):
            return key
        if point is not None and name.startswith(f"{point.path.lower()}."):
            within.append((len(point.path), key))
    return max(within)[1] if within else next(iter(values))
