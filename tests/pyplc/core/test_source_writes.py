"""The base's one write path: check every value, send, push, read back.

A source gives its encoding, its batch form (what goes on the wire together),
the sending and its read-back; the base checks that each point exists and its
value is taken before anything is sent, counts the values and the failures,
pushes what the device took and leaves a failed read-back to the next poll.
The memory source (``tests.fake_source``) is such a source: it gives the
sending and a read-back that costs no request, the rest is the base's.
"""

from collections.abc import Iterable, Mapping, Sequence
from typing import Any

import pytest

from custom_components.tecoapi.pyplc import (
    MissingPointError,
    OutOfRangeError,
    PlcConnectionError,
    PlcResponseError,
    Snapshot,
    VariableNotFoundError,
)
from custom_components.tecoapi.pyplc.core.source import Write
from tests.fake_source import MemoryDevice, MemorySource, house_device, house_map


async def _discovered(source: MemorySource) -> MemorySource:
    await source.poll(())
    return source


def _told(source: MemorySource) -> list[Snapshot]:
    """The snapshots a source pushes from now on."""
    pushed: list[Snapshot] = []
    source.subscribe(pushed.append)
    return pushed


@pytest.fixture
async def device() -> MemoryDevice:
    return house_device("MEM-WRITES")


@pytest.fixture
async def memory(device: MemoryDevice) -> MemorySource:
    return await _discovered(MemorySource(device, house_map()))


class OneAtATime(MemorySource):
    """A device that takes one value at a time: each write is a send of its own."""

    def _sends(self, batch: Sequence[Write[Any]]) -> Iterable[Sequence[Write[Any]]]:
        return ([write] for write in batch)


class Batches(MemorySource):
    """A memory source that notes each batch as it is cut into sends."""

    def __init__(self, device: MemoryDevice) -> None:
        super().__init__(device, house_map())
        self.batches: list[list[str]] = []

    def _sends(self, batch: Sequence[Write[Any]]) -> Iterable[Sequence[Write[Any]]]:
        self.batches.append([write.key for write in batch])
        return (batch,)


class ReadBackFails(MemorySource):
    """A memory source whose read-back after a write fails."""

    async def _read_back(
        self, batch: Sequence[Write[Any]], carried: Mapping[str, Any]
    ) -> Snapshot | None:
        raise PlcResponseError("the read-back broke")


async def test_a_source_gives_the_sending_and_the_base_does_the_rest(
    memory: MemorySource, device: MemoryDevice
) -> None:
    """Encoded by the core's codec (a setpoint in tenths), pushed once sent, read back."""
    pushed = _told(memory)
    requests = device.requests

    confirmed = await memory.write_many({"garden_pump": False, "boiler_setpoint": 50})

    assert device.writes == [("m2", False), ("m4", 500)]
    assert device.requests - requests == 2  # a request a value, the read-back free
    assert [snapshot.values for snapshot in pushed] == [
        {"garden_pump": False, "boiler_setpoint": 50}
    ]
    assert confirmed is not None
    assert confirmed.values == {"garden_pump": False, "boiler_setpoint": 50}
    assert memory.statistics.writes == 2
    assert memory.statistics.failed_writes == 0


async def test_write_is_a_batch_of_one(device: MemoryDevice) -> None:
    batches = await _discovered(Batches(device))

    confirmed = await batches.write("garden_pump", False)

    assert batches.batches == [["garden_pump"]]
    assert confirmed is not None
    assert confirmed.values == {"garden_pump": False}


async def test_a_point_not_in_the_catalogue_is_refused_before_anything_is_sent(
    memory: MemorySource, device: MemoryDevice
) -> None:
    """One check that the point exists: the core's error, naming the key."""
    requests = device.requests

    with pytest.raises(MissingPointError) as raised:
        await memory.write_many({"garden_pump": False, "no_such_point": 1})

    error = raised.value
    assert isinstance(error, VariableNotFoundError)
    assert (error.key, error.path) == ("no_such_point", "no_such_point")
    with pytest.raises(MissingPointError):
        memory.check_write("no_such_point", 1)
    with pytest.raises(MissingPointError):
        await memory.write("no_such_point", 1)
    assert device.requests == requests
    assert device.writes == []
    assert memory.statistics.writes == 0
    assert memory.recent_errors == ()


async def test_a_refused_value_sends_nothing_and_counts_nothing(
    memory: MemorySource, device: MemoryDevice
) -> None:
    with pytest.raises(OutOfRangeError):
        await memory.write_many({"garden_pump": False, "boiler_setpoint": 90})

    assert device.writes == []
    assert memory.statistics.writes == 0
    assert memory.statistics.failed_writes == 0


async def test_a_failed_send_is_counted_kept_and_pushes_nothing(
    memory: MemorySource, device: MemoryDevice
) -> None:
    pushed = _told(memory)
    device.fail = PlcConnectionError("nothing answers")

    with pytest.raises(PlcConnectionError):
        await memory.write_many({"garden_pump": False, "boiler_setpoint": 50})

    assert pushed == []
    assert memory.statistics.writes == 2  # the send's values, counted as it went
    assert memory.statistics.failed_writes == 1
    assert [error.operation for error in memory.recent_errors] == ["write"]


async def test_a_device_taking_one_value_at_a_time_pushes_each_once_taken(
    device: MemoryDevice,
) -> None:
    """The second send fails: the first value stays written and told."""
    source = await _discovered(OneAtATime(device, house_map()))
    pushed = _told(source)
    del device.values["m4"]  # the setpoint is gone from the device

    with pytest.raises(VariableNotFoundError):
        await source.write_many({"garden_pump": False, "boiler_setpoint": 50})

    assert device.writes == [("m2", False)]
    assert [snapshot.values for snapshot in pushed] == [{"garden_pump": False}]
    assert source.statistics.writes == 2
    assert source.statistics.failed_writes == 1


async def test_a_read_back_that_fails_leaves_it_to_the_next_poll(
    device: MemoryDevice,
) -> None:
    """The write went through: pushed, counted, no failure kept; None returned."""
    source = await _discovered(ReadBackFails(device, house_map()))
    pushed = _told(source)

    confirmed = await source.write("garden_pump", False)

    assert confirmed is None
    assert device.writes == [("m2", False)]
    assert [snapshot.values for snapshot in pushed] == [{"garden_pump": False}]
    assert source.statistics.writes == 1
    assert source.statistics.failed_writes == 0
    assert source.recent_errors == ()


async def test_an_empty_batch_sends_and_tells_nothing(
    memory: MemorySource, device: MemoryDevice
) -> None:
    pushed = _told(memory)
    requests = device.requests

    assert await memory.write_many({}) is None

    assert device.requests == requests
    assert pushed == []
    assert memory.statistics.writes == 0
