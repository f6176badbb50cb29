"""Gateways of API 2.1 and 2.0: by ItemID where the name forms answer 404 (seed: history).

2.1 added subscribing and updates by name (``SubscriberText``, ``GetUpdatesText``),
2.2 the Text reads and writes; before 2.1 everything went by ``ItemID``, and
``ServerInformation`` (2.0's) tells the version, though a gateway may tell it
wrong or not at all.
"""

import pytest

from custom_components.tecoapi.pyplc import NotAPlcError, ValueRejectedError
from custom_components.tecoapi.pyplc.tekon import TekonSource
from tests.pyplc.tekon.conftest import discovered, key, subscribed
from tests.simulator.tekon import TekonGateway, channel
from tests.simulator.tekon.building import CONTROLLER, NUMBER, VT_R4

SETPOINT = f"{CONTROLLER}.Уставка"
DOOR = f"{CONTROLLER}.Дверь подъезда"
INTERCOM = f"{CONTROLLER}.Переговорное устройство"
POLLED = frozenset({key(SETPOINT), key(DOOR)})


async def test_a_2_1_gateway_reads_and_writes_by_item_id(
    gateway: TekonGateway, source: TekonSource
) -> None:
    gateway.api_version = "2.1"
    info = await source.identify()
    assert info.api_version == "2.1"
    snapshot = await discovered(source, POLLED)
    assert snapshot.values == {key(SETPOINT): 20.0, key(DOOR): False}
    assert "SubscriberText" in gateway.requests
    gateway.clear_requests()
    assert await source.read_variable(SETPOINT) == 20.0
    await source.write(key(SETPOINT), 22.5)
    await source.write(key(INTERCOM), True)
    # Its version says the Text reads and writes are not there: none is tried.
    assert gateway.requests == [
        "ReadItemValueSync",
        "WriteItemsValues",
        "WriteItemsValues",
    ]
    assert gateway.writes == [(SETPOINT, "22.5"), (INTERCOM, "1")]
    gateway.clear_requests()
    assert (await source.poll(POLLED)).values == {key(SETPOINT): 22.5}
    assert gateway.requests == ["GetUpdatesText"]


async def test_a_gateway_that_tells_a_newer_version_is_answered_after_a_404(
    gateway: TekonGateway, source: TekonSource
) -> None:
    gateway.api_version = "2.1"
    gateway.reported_version = "2.2"
    await discovered(source, POLLED)
    gateway.clear_requests()
    await source.write(key(SETPOINT), 23)
    await source.write(key(SETPOINT), 24)
    assert gateway.requests == [
        "WriteItemsValuesText",
        "WriteItemsValues",
        "WriteItemsValues",
    ]
    assert gateway.value(SETPOINT) == "24.0"
    assert source.diagnostics()["text_calls_without_text"] == ["WriteItemsValues"]


async def test_a_gateway_that_tells_an_older_version_is_answered_too(
    gateway: TekonGateway, source: TekonSource
) -> None:
    """A 2.2 gateway telling 2.0: the plain URLs, by name and ID, answer it right."""
    gateway.reported_version = "2.0"
    snapshot = await discovered(source, POLLED)
    assert snapshot.values == {key(SETPOINT): 20.0, key(DOOR): False}
    await source.write(key(SETPOINT), 21)
    assert await source.read_variable(SETPOINT) == 21.0
    assert not [call for call in gateway.requests if call.endswith("Text")]


@pytest.mark.parametrize("server_information", [True, False])
async def test_a_2_0_gateway_goes_by_item_id_throughout(
    gateway: TekonGateway, source: TekonSource, server_information: bool
) -> None:
    """No Text call at all; without ServerInformation each is found out once (404)."""
    gateway.api_version = "2.0"
    if not server_information:
        gateway.failing["ServerInformation"] = 404
    info = await source.identify()
    assert info.api_version == ("2.0" if server_information else None)
    snapshot = await discovered(source, POLLED)
    assert snapshot.values == {key(SETPOINT): 20.0, key(DOOR): False}
    assert {SETPOINT, DOOR} <= subscribed(gateway)
    gateway.set_value(DOOR, "1")
    sent = list(gateway.requests)
    gateway.clear_requests()
    assert (await source.poll(POLLED)).values == {key(DOOR): True}
    assert gateway.requests == ["GetUpdates"]
    await source.write(key(SETPOINT), 25)
    assert gateway.value(SETPOINT) == "25.0"
    assert await source.read_variable(SETPOINT) == 25.0
    probed = [call for call in [*sent, *gateway.requests] if call.endswith("Text")]
    if server_information:
        assert probed == []
    else:
        # Each Text call tried once, never again.
        assert sorted(probed) == [
            "GetUpdatesText",
            "ReadItemValueSyncText",
            "SubscriberText",
            "WriteItemsValuesText",
        ]


async def test_a_gateway_without_server_information_nor_sessions_is_none(
    gateway: TekonGateway, source: TekonSource
) -> None:
    gateway.failing["ServerInformation"] = 404
    gateway.failing["NewSession"] = 404
    with pytest.raises(NotAPlcError):
        await source.identify()


async def test_ids_that_moved_are_never_written(
    gateway: TekonGateway, source: TekonSource
) -> None:
    """A new address space while a 2.1 gateway's session was lost: no ID of the old one."""
    gateway.api_version = "2.1"
    await discovered(source, POLLED)
    await source.write(key(SETPOINT), 21)
    new = channel("Дом 1.Новый", NUMBER, "1", vartype=VT_R4, access=3)
    gateway.configuration_mode(add=[new], first=True)  # every ID moves
    gateway.clear_requests()
    with pytest.raises(ValueRejectedError):
        await source.write(key(SETPOINT), 26)
    assert gateway.requests == [
        "WriteItemsValues",
        "NewSession",
        "GetAddressSpaceHash",
        "WriteItemsValues",
    ]
    # Nothing was written: the old IDs were not sent.
    assert gateway.writes == [(SETPOINT, "21.0")]
    assert gateway.value("Дом 1.Новый") == "1"
    # The next poll follows the new address space; its IDs are written.
    changed = await source.poll(POLLED)
    assert changed.program_changed
    await source.write(key(SETPOINT), 26)
    assert gateway.writes[-1] == (SETPOINT, "26.0")
    assert gateway.value(SETPOINT) == "26.0"


async def test_a_2_1_gateway_s_lost_session_is_written_by_the_ids_it_still_has(
    gateway: TekonGateway, source: TekonSource
) -> None:
    gateway.api_version = "2.1"
    await discovered(source, POLLED)
    gateway.expire_sessions()
    gateway.clear_requests()
    await source.write(key(SETPOINT), 23)
    assert gateway.requests == [
        "WriteItemsValues",
        "NewSession",
        "GetAddressSpaceHash",
        "WriteItemsValues",
    ]
    assert gateway.value(SETPOINT) == "23.0"
