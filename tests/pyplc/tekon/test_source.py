"""The Tekon source against the simulated gateway over HTTP: its schedule and its sessions."""

import contextlib
from datetime import UTC, datetime, timedelta
import json
from typing import Any

import aiohttp
import pytest

from custom_components.tecoapi.pyplc import (
    InvalidValueError,
    OutOfRangeError,
    PlcConnectionError,
    PlcResponseError,
    PointQuality,
    Quality,
    ReadOnlyError,
    Record,
    ServiceUnavailableError,
    Snapshot,
    VariableNotFoundError,
    WritesDisabledError,
)
from custom_components.tecoapi.pyplc.tekon import TekonClient, TekonSource
from custom_components.tecoapi.pyplc.tekon.client import (
    AddressItem,
    ItemUpdate,
    SessionLostError,
)
from custom_components.tecoapi.pyplc.tekon.source import identity_of, zone_offset
from tests.pyplc.conftest import Clock, Heard
from tests.pyplc.tekon.conftest import discovered, key, subscribed
from tests.simulator.tekon import TekonGateway, channel, lift_state
from tests.simulator.tekon.building import (
    CONTROLLER,
    LIFT,
    METERS,
    NUMBER,
    READ_WRITE,
    VT_R4,
    lift_parts,
)
from tests.simulator.tekon.server import LOST

SETPOINT = f"{CONTROLLER}.Уставка"
DOOR = f"{CONTROLLER}.Дверь подъезда"
LIGHT = f"{CONTROLLER}.Освещение"
INTERCOM = f"{CONTROLLER}.Переговорное устройство"
TEMPERATURE = f"{CONTROLLER}.Температура"
DISPLAY = f"{CONTROLLER}.Табло"
LIFT_STATE = f"{LIFT}.Состояние"
ENERGY = f"{METERS}.Электросчётчик.Энергия"
BESIDE = 2
"""Points read beside the items' own: the intercom's call state and its calls."""


class MemoryCache:
    """A source cache in memory (Home Assistant's is a Store)."""

    def __init__(self) -> None:
        self.data: Any = None
        self.saves = 0

    async def load(self) -> Any:
        return self.data

    async def save(self, data: Any) -> None:
        self.data = data
        self.saves += 1


async def test_identify_reads_the_gateway_and_its_address_space(
    gateway: TekonGateway, source: TekonSource
) -> None:
    info = await source.identify()
    assert info.identity.startswith("OPC-")
    assert (info.manufacturer, info.model, info.firmware, info.api_version) == (
        "Tekon",
        "ASUD.SCADA OPC-HTTP",
        "2.2.0.41",
        "2.2",
    )
    assert gateway.requests == [
        "ServerInformation",
        "NewSession",
        "GetAddressSpaceHash",
        "GetAddressSpace",
    ]
    snapshot = await source.poll(())
    # Discovery uses what identify read: no request but the updates.
    assert gateway.requests[4:] == ["GetUpdatesText"]
    catalogue = snapshot.catalogue
    assert len(catalogue.points) == len(gateway.building.items) + BESIDE
    assert catalogue.devices[key(LIFT)].parent == key(CONTROLLER)
    assert snapshot.values == {}
    assert source.statistics.discoveries == 1


async def test_a_quiet_poll_is_one_get_updates(
    gateway: TekonGateway, source: TekonSource
) -> None:
    polled = frozenset({key(SETPOINT), key(DOOR), key(LIFT_STATE)})
    snapshot = await discovered(source, polled)
    assert snapshot.values == {
        key(SETPOINT): 20.0,
        key(DOOR): False,
        key(LIFT_STATE): Record(
            text="Норма",
            parts=(
                ("State", "Норма"),
                ("Floor", "1"),
                ("Direction", "нет"),
                ("Door", "закрыта"),
            ),
        ),
    }
    gateway.clear_requests()
    quiet = await source.poll(polled)
    assert gateway.requests == ["GetUpdatesText"]
    assert quiet.values == {}
    assert source.statistics.last_poll_requests == 1
    gateway.set_value(SETPOINT, "21.5")
    changed = await source.poll(polled)
    assert changed.values == {key(SETPOINT): 21.5}


async def test_only_the_polled_points_and_their_devices_statuses_are_subscribed(
    gateway: TekonGateway, source: TekonSource
) -> None:
    await discovered(source, frozenset({key(LIFT_STATE), key(INTERCOM)}))
    # The lift's state, the lift's status and its controller's; an intercom is
    # written, never read.
    assert subscribed(gateway) == {LIFT_STATE, f"{LIFT}.Status", f"{CONTROLLER}.Status"}
    gateway.clear_requests()
    await source.poll(frozenset({key(ENERGY)}))
    assert gateway.requests == [
        "SubscriberText",
        "UnSubscriberText",
        "ReadAllItemsValues",
        "GetUpdatesText",
    ]
    assert subscribed(gateway) == {ENERGY, f"{METERS}.Электросчётчик.Status"}
    gateway.clear_requests()
    await source.poll(frozenset({key(ENERGY), "no.such.point"}))
    assert gateway.requests == ["GetUpdatesText"]


async def test_one_bad_value_costs_its_point_alone(
    gateway: TekonGateway, source: TekonSource
) -> None:
    polled = frozenset({key(SETPOINT), key(DOOR), key(TEMPERATURE), key(ENERGY)})
    await discovered(source, polled)
    gateway.set_value(SETPOINT, quality=0x18)
    gateway.set_value(DOOR, "1", quality=0x44)
    gateway.set_value(TEMPERATURE, "warm")
    gateway.set_value(ENERGY, "1521.5")
    snapshot = await source.poll(polled)
    assert snapshot.values == {
        key(SETPOINT): 20.0,
        key(DOOR): True,
        key(TEMPERATURE): None,
        key(ENERGY): 1521.5,
    }
    assert snapshot.quality == {
        key(SETPOINT): PointQuality(quality=Quality.BAD, reason="comm_failure"),
        key(DOOR): PointQuality(quality=Quality.UNCERTAIN, reason="last_usable"),
        key(TEMPERATURE): PointQuality(quality=Quality.BAD, reason="malformed_value"),
    }
    gateway.set_value(SETPOINT, "20")
    gateway.set_value(DOOR, "0")
    gateway.set_value(TEMPERATURE, "21,0")
    recovered = await source.poll(polled)
    assert recovered.quality == {}
    assert recovered.values[key(TEMPERATURE)] == 21.0


async def test_a_device_s_status_decides_its_health(
    gateway: TekonGateway, source: TekonSource
) -> None:
    polled = frozenset({key(LIFT_STATE)})
    snapshot = await discovered(source, polled)
    assert snapshot.offline == {}
    gateway.set_value(f"{LIFT}.Status", "0")
    assert (await source.poll(polled)).offline == {key(LIFT): "no_data_exchange"}
    gateway.set_value(f"{LIFT}.Status", "10")
    gateway.set_value(f"{CONTROLLER}.Status", "10", quality=0x18)
    assert (await source.poll(polled)).offline == {key(CONTROLLER): "comm_failure"}
    gateway.set_value(f"{CONTROLLER}.Status", "7")
    assert (await source.poll(polled)).offline == {}
    # A status below its minimum (6003) is no data exchange either.
    gateway.building.by_name[f"{LIFT}.Status"].properties[6003] = "2"
    gateway.configuration_mode()
    gateway.set_value(f"{LIFT}.Status", "2")
    changed = await source.poll(polled)
    assert changed.program_changed
    assert changed.offline == {key(LIFT): "no_data_exchange"}
    # Health is forgotten with the subscription of its status.
    assert (await source.poll(frozenset({key(ENERGY)}))).offline == {}


async def test_a_lost_session_is_opened_again_within_the_poll(
    gateway: TekonGateway, source: TekonSource
) -> None:
    polled = frozenset({key(SETPOINT), key(DOOR)})
    await discovered(source, polled)
    gateway.expire_sessions()
    gateway.set_value(SETPOINT, "23.5")  # changed while no session saw it
    gateway.clear_requests()
    snapshot = await source.poll(polled)
    assert gateway.requests == [
        "GetUpdatesText",  # 409
        "NewSession",
        "GetAddressSpaceHash",
        "SubscriberText",
        "ReadAllItemsValues",
        "GetUpdatesText",
    ]
    assert not snapshot.program_changed
    assert snapshot.values == {key(SETPOINT): 23.5, key(DOOR): False}
    assert source.sessions == 2
    assert source.statistics.failed_polls == 0


async def test_an_unavailable_opc_server_is_asked_again_later_and_later(
    gateway: TekonGateway, source: TekonSource, clock: Clock
) -> None:
    polled = frozenset({key(SETPOINT)})
    await discovered(source, polled)
    gateway.opc_available = False
    gateway.clear_requests()
    tried: list[int] = []
    for _ in range(8):
        before = len(gateway.requests)
        with pytest.raises(ServiceUnavailableError):
            await source.poll(polled)
        tried.append(len(gateway.requests) - before)
        clock.tick(1)
    # 503 at once; then after 1 s, 2 s and 4 s (the polls between send nothing).
    assert tried == [1, 1, 0, 1, 0, 0, 0, 1]
    assert gateway.requests == [
        "GetUpdatesText",
        "NewSession",
        "NewSession",
        "NewSession",
    ]
    gateway.opc_available = True
    while True:
        clock.tick(1)
        try:
            snapshot = await source.poll(polled)
        except ServiceUnavailableError:
            continue
        break
    assert snapshot.values == {key(SETPOINT): 20.0}
    assert source.diagnostics()["requests"]["backoff_seconds"] == 0.0


async def test_a_restart_through_configuration_mode_brings_the_new_address_space(
    gateway: TekonGateway, source: TekonSource, clock: Clock
) -> None:
    """Unavailable (503) while configured; then a new session finds a new hash."""
    polled = frozenset({key(SETPOINT)})
    await discovered(source, polled)
    gateway.opc_available = False
    with pytest.raises(ServiceUnavailableError):
        await source.poll(polled)
    gateway.configuration_mode(add=[channel("Дом 1.Новый", NUMBER, "1", vartype=VT_R4)])
    gateway.opc_available = True
    clock.tick(1)
    snapshot = await source.poll(polled)
    assert snapshot.program_changed
    assert "дом 1.новый" in snapshot.catalogue.points
    assert snapshot.values == {key(SETPOINT): 20.0}


async def test_an_update_of_an_item_the_catalogue_lacks_is_left_out(
    gateway: TekonGateway, source: TekonSource
) -> None:
    polled = frozenset({key(SETPOINT)})
    await discovered(source, polled)
    # An item added without configuration mode (its session kept), subscribed
    # by another hand.
    gateway.building.add([channel("Дом 1.Чужой", NUMBER, "1", vartype=VT_R4)])
    await source.client.subscribe(["Дом 1.Чужой"])
    gateway.set_value("Дом 1.Чужой", "2")
    gateway.set_value(SETPOINT, "21")
    assert (await source.poll(polled)).values == {key(SETPOINT): 21.0}


async def test_the_backoff_is_capped(
    gateway: TekonGateway, http: aiohttp.ClientSession, clock: Clock
) -> None:
    source = TekonSource(TekonClient(http, gateway.url), clock=clock, max_backoff=3)
    await discovered(source, frozenset())
    gateway.opc_available = False
    for _ in range(12):
        with contextlib.suppress(ServiceUnavailableError):
            await source.poll(frozenset())
        clock.tick(1)
    assert source.diagnostics()["requests"]["backoff_seconds"] == 3
    await source.close()


async def test_configuration_mode_with_a_new_address_space_is_a_program_change(
    gateway: TekonGateway, source: TekonSource
) -> None:
    polled = frozenset({key(SETPOINT), key(DOOR)})
    before = await discovered(source, polled)
    new = channel(
        f"{CONTROLLER}.Давление", NUMBER, "1.5", vartype=VT_R4, access=READ_WRITE
    )
    # The new item comes first: every ItemID moves.
    gateway.configuration_mode(add=[new], remove=[DOOR], first=True)
    gateway.clear_requests()
    snapshot = await source.poll(polled)
    assert snapshot.program_changed
    assert gateway.requests == [
        "GetUpdatesText",
        "NewSession",
        "GetAddressSpaceHash",
        "GetAddressSpace",
        "SubscriberText",
        "ReadAllItemsValues",
        "GetUpdatesText",
    ]
    points = snapshot.catalogue.points
    assert key(new.name) in points
    assert key(DOOR) not in points
    assert snapshot.catalogue is not before.catalogue
    # The points kept are read at once; the one gone is not asked for.
    assert snapshot.values == {key(SETPOINT): 20.0}
    assert subscribed(gateway) == {SETPOINT, f"{CONTROLLER}.Status"}
    assert source.statistics.program_changes == 1
    gateway.clear_requests()
    await source.poll(polled | {key(new.name)})
    assert gateway.requests == [
        "SubscriberText",
        "ReadAllItemsValues",
        "GetUpdatesText",
    ]


async def test_configuration_mode_with_the_same_address_space_changes_nothing(
    gateway: TekonGateway, source: TekonSource
) -> None:
    polled = frozenset({key(SETPOINT)})
    before = await discovered(source, polled)
    gateway.configuration_mode()
    snapshot = await source.poll(polled)
    assert not snapshot.program_changed
    assert snapshot.catalogue is before.catalogue
    assert "GetAddressSpace" not in gateway.requests[-5:]


async def test_the_address_space_is_read_only_when_its_hash_changed(
    gateway: TekonGateway, http: aiohttp.ClientSession
) -> None:
    cache = MemoryCache()
    first = TekonSource(TekonClient(http, gateway.url), cache=cache)
    identity = (await first.identify()).identity
    await first.close()
    assert cache.saves == 1
    assert cache.data["hash"] == gateway.building.hash()
    gateway.clear_requests()
    second = TekonSource(TekonClient(http, gateway.url), cache=cache)
    assert (await second.identify()).identity == identity
    snapshot = await second.poll(())
    assert "GetAddressSpace" not in gateway.requests
    assert len(snapshot.catalogue.points) == len(gateway.building.items) + BESIDE
    await second.close()
    # New top-level names would make another identity: the kept one stays.
    gateway.configuration_mode(add=[channel("Новый корень.Датчик", None, "1")])
    gateway.clear_requests()
    third = TekonSource(TekonClient(http, gateway.url), cache=cache)
    assert (await third.identify()).identity == identity
    assert gateway.calls["GetAddressSpace"] == 1
    assert cache.saves == 2
    await third.close()
    # What the cache holds that is not its own is read again from the gateway.
    cache.data = {"version": 0}
    fourth = TekonSource(TekonClient(http, gateway.url), cache=cache)
    assert (await fourth.identify()).identity != identity
    await fourth.close()


async def test_an_address_space_kept_as_stored_before_is_taken_from_the_store(
    gateway: TekonGateway, http: aiohttp.ClientSession
) -> None:
    """A store as the sources wrote it before the core kept it: nothing is read again.

    Version 1: the identity, the hash, and each item as ``[name, ItemID,
    {property: text}]``, through JSON as Home Assistant's store keeps it.
    """
    kept = [item for item in gateway.building.items if item.name.startswith(CONTROLLER)]
    cache = MemoryCache()
    cache.data = json.loads(
        json.dumps(
            {
                "version": 1,
                "identity": "OPC-0123456789AB",
                "hash": gateway.building.hash(),
                "items": [[item.name, item.item_id, item.properties] for item in kept],
            }
        )
    )
    source = TekonSource(TekonClient(http, gateway.url), cache=cache)
    assert (await source.identify()).identity == "OPC-0123456789AB"
    snapshot = await discovered(source, frozenset({key(SETPOINT)}))
    await source.close()
    assert "GetAddressSpace" not in gateway.requests
    assert cache.saves == 0
    assert {key(item.name) for item in kept} <= snapshot.catalogue.points.keys()
    assert key(ENERGY) not in snapshot.catalogue.points
    assert snapshot.values[key(SETPOINT)] == 20.0


async def test_a_gateway_answering_by_id_only(
    gateway: TekonGateway, source: TekonSource
) -> None:
    gateway.text_urls = "plain"
    polled = frozenset({key(SETPOINT), key(DOOR)})
    snapshot = await discovered(source, polled)
    assert snapshot.values == {key(SETPOINT): 20.0, key(DOOR): False}
    # IDs move with a new address space; names still find the points.
    gateway.configuration_mode(
        add=[channel("Дом 1.Новый", NUMBER, "1", vartype=VT_R4)], first=True
    )
    gateway.set_value(SETPOINT, "24")
    changed = await source.poll(polled)
    assert changed.program_changed
    assert changed.values == {key(SETPOINT): 24.0, key(DOOR): False}


async def test_writes_are_checked_spelled_and_pushed(
    gateway: TekonGateway, source: TekonSource
) -> None:
    polled = frozenset({key(SETPOINT), key(LIGHT), key(DISPLAY)})
    await discovered(source, polled)
    heard = Heard[Snapshot](source.subscribe)
    await source.write(key(LIGHT), False)
    await source.write(key(SETPOINT), 22.5)
    await source.write(key(DISPLAY), "Лифт не работает")
    await source.write(key(INTERCOM), True)
    assert gateway.writes == [
        (LIGHT, "0"),
        (SETPOINT, "22.5"),
        (DISPLAY, "Лифт не работает"),
        (INTERCOM, "1"),
    ]
    assert [item.values for item in heard.items] == [
        {key(LIGHT): False},
        {key(SETPOINT): 22.5},
        {key(DISPLAY): "Лифт не работает"},
        {key(INTERCOM): True},
    ]
    after = await source.poll(polled)
    assert after.values == {
        key(LIGHT): False,
        key(SETPOINT): 22.5,
        key(DISPLAY): "Лифт не работает",
    }
    gateway.clear_requests()
    with pytest.raises(ReadOnlyError):
        await source.write(key(DOOR), True)
    with pytest.raises(OutOfRangeError):
        await source.write(key(SETPOINT), 40)
    with pytest.raises(ReadOnlyError):
        await source.write(key(LIFT_STATE), "up")
    with pytest.raises(InvalidValueError):
        await source.write(key(SETPOINT), "warm")
    assert gateway.requests == []
    assert source.statistics.writes == 4


async def test_reals_are_written_with_the_gateway_s_decimal_comma(
    gateway: TekonGateway, source: TekonSource
) -> None:
    gateway.decimal_commas = True
    polled = frozenset({key(SETPOINT)})
    assert (await discovered(source, polled)).values == {key(SETPOINT): 20.0}
    gateway.set_value(SETPOINT, "20.5")  # sent as "20,5"
    await source.poll(polled)
    await source.write(key(SETPOINT), 21.5)
    assert gateway.writes == [(SETPOINT, "21,5")]
    assert gateway.value(SETPOINT) == "21.5"
    gateway.decimal_commas = False
    gateway.set_value(SETPOINT, "22.5")
    await source.poll(polled)
    await source.write(key(SETPOINT), 23.5)
    assert gateway.writes[-1] == (SETPOINT, "23.5")


async def test_writes_disabled_in_the_gateway_change_nothing(
    gateway: TekonGateway, source: TekonSource
) -> None:
    polled = frozenset({key(SETPOINT)})
    await discovered(source, polled)
    gateway.writes_enabled = False
    heard = Heard[Snapshot](source.subscribe)
    with pytest.raises(WritesDisabledError):
        await source.write(key(SETPOINT), 22.5)
    assert gateway.value(SETPOINT) == "20"
    assert heard.items == []
    assert source.statistics.failed_writes == 1


async def test_a_write_in_a_lost_session_is_sent_again_in_a_new_one(
    gateway: TekonGateway, source: TekonSource
) -> None:
    polled = frozenset({key(SETPOINT)})
    await discovered(source, polled)
    gateway.expire_sessions()
    gateway.clear_requests()
    await source.write(key(SETPOINT), 25)
    assert gateway.requests == [
        "WriteItemsValuesText",
        "NewSession",
        "WriteItemsValuesText",
    ]
    assert gateway.value(SETPOINT) == "25.0"
    gateway.clear_requests()
    snapshot = await source.poll(polled)
    # The next poll compares the hash and subscribes again.
    assert gateway.requests == [
        "GetAddressSpaceHash",
        "SubscriberText",
        "ReadAllItemsValues",
        "GetUpdatesText",
    ]
    assert snapshot.values == {key(SETPOINT): 25.0}


async def test_follow_subscribes_the_polled_points_and_pushes_their_values(
    gateway: TekonGateway, source: TekonSource
) -> None:
    await source.follow({key(SETPOINT)})  # before discovery: nothing to do
    assert gateway.requests == []
    await source.poll(())
    heard = Heard[Snapshot](source.subscribe)
    await source.follow({key(SETPOINT)})
    assert heard.items[0].values == {key(SETPOINT): 20.0}
    assert source.statistics.polls == 0
    gateway.opc_available = False
    await source.follow({key(DOOR)})  # a failure is left to the next poll
    assert len(heard.items) == 1


async def test_an_idle_session_is_kept_alive(
    gateway: TekonGateway, http: aiohttp.ClientSession
) -> None:
    """Far apart polls keep their session: a request before the gateway's timeout."""
    gateway.session_timeout = 0.2
    source = TekonSource(TekonClient(http, gateway.url), keepalive=0.02)
    polled = frozenset({key(SETPOINT)})
    await discovered(source, polled)
    gateway.clear_requests()
    # Ten keepalives: longer idle than the session's timeout.
    await gateway.wait_for_call("GetSubscribersCount", 10)
    await source.poll(polled)
    assert "NewSession" not in gateway.requests
    assert source.sessions == 1
    await source.close()
    assert "CloseSession" in gateway.requests
    assert gateway.sessions == {}


async def test_a_failed_keepalive_is_left_to_the_next_poll(
    gateway: TekonGateway, http: aiohttp.ClientSession
) -> None:
    source = TekonSource(TekonClient(http, gateway.url), keepalive=0.02)
    polled = frozenset({key(SETPOINT)})
    await discovered(source, polled)
    gateway.expire_sessions()
    await gateway.wait_for_call("GetSubscribersCount", 1)
    snapshot = await source.poll(polled)
    assert snapshot.values == {key(SETPOINT): 20.0}
    assert source.sessions == 2
    await source.close()


async def test_read_and_write_an_item_by_its_name(
    gateway: TekonGateway, source: TekonSource
) -> None:
    await discovered(source, frozenset())
    assert await source.read_variable(SETPOINT) == 20.0
    # An uncertain value is a value; a bad one, or one not of its type, is not.
    gateway.set_value(DOOR, "1", quality=0x44)
    assert await source.read_variable(DOOR) is True
    gateway.set_value(TEMPERATURE, "warm")
    with pytest.raises(PlcResponseError, match="malformed_value"):
        await source.read_variable(TEMPERATURE)
    gateway.set_value(TEMPERATURE, "21", quality=0x0C)
    with pytest.raises(PlcResponseError, match="device_failure"):
        await source.read_variable(TEMPERATURE)
    assert await source.read_variable(LIFT_STATE) == {
        "text": "Норма",
        "parts": lift_parts(),
    }
    assert await source.write_variable(SETPOINT, 21) is None
    assert gateway.value(SETPOINT) == "21.0"
    with pytest.raises(VariableNotFoundError):
        await source.read_variable("No.Such.Item")
    with pytest.raises(VariableNotFoundError):
        await source.write_variable("No.Such.Item", 1)
    gateway.building.remove([SETPOINT])
    with pytest.raises(VariableNotFoundError):
        await source.read_variable(SETPOINT)
    assert await source.read_points({key(DOOR)}) is None


async def test_diagnostics_and_the_gateway_s_local_time(
    gateway: TekonGateway, source: TekonSource, clock: Clock
) -> None:
    gateway.zone = timedelta(hours=5)
    clock.now = datetime.now(UTC)
    await discovered(source, frozenset({key(SETPOINT)}))
    diagnostics = source.diagnostics()
    subscription = diagnostics["subscription"]
    assert subscription["session_id"] == source.client.session_id
    assert diagnostics["gateway_zone_offset_minutes"] == 300
    assert diagnostics["points"] == len(gateway.building.items) + BESIDE
    assert diagnostics["roots"] == 2
    assert subscription["items"] == 2
    assert subscription["sessions"] == 1
    assert diagnostics["requests"]["by_call"]["GetUpdatesText"] == 2
    # The value's local time, as UTC.
    item_time = gateway.building.by_name[SETPOINT].time
    assert (
        subscription["last_update"]
        == (item_time - timedelta(hours=5)).replace(tzinfo=UTC).isoformat()
    )


async def test_the_device_page_is_the_gateway_s_server_information(
    gateway: TekonGateway, source: TekonSource, http: aiohttp.ClientSession
) -> None:
    """A link a browser opens without a session (issue 39): the gateway's versions."""
    assert source.configuration_url == f"{gateway.url}/ServerInformation"
    async with http.get(source.configuration_url) as response:
        assert response.status == 200
        answer = await response.json(content_type=None)
    assert answer["version"] == (await source.identify()).api_version


async def test_a_discovery_whose_session_was_lost_opens_another(
    gateway: TekonGateway, source: TekonSource
) -> None:
    """The address space identify read is kept, unless its hash changed."""
    await source.identify()
    gateway.expire_sessions()
    with pytest.raises(SessionLostError):
        await source.poll(())
    gateway.clear_requests()
    snapshot = await source.poll(())
    assert gateway.requests == ["NewSession", "GetAddressSpaceHash", "GetUpdatesText"]
    assert snapshot.catalogue.points
    assert source.statistics.discoveries == 1
    gateway.expire_sessions()
    await source.close()
    fresh = TekonSource(source.client)
    await fresh.identify()
    gateway.configuration_mode(remove=[DOOR])
    with pytest.raises(SessionLostError):
        await fresh.poll(())
    gateway.clear_requests()
    changed = await fresh.poll(())
    assert gateway.requests == [
        "NewSession",
        "GetAddressSpaceHash",
        "GetAddressSpace",
        "GetUpdatesText",
    ]
    assert key(DOOR) not in changed.catalogue.points
    await fresh.close()


def test_the_identity_is_the_address_space_s_top_level_names() -> None:
    def items(*names: str) -> list[AddressItem]:
        return [AddressItem(name=name, item_id=0, properties={}) for name in names]

    one = identity_of(items("A.x", "B.y", "A.z"))
    assert one == identity_of(items("B.q", "A.r"))
    assert one != identity_of(items("A.x", "C.y"))


def test_the_gateway_s_zone_is_a_whole_quarter_of_an_hour() -> None:
    now = datetime(2026, 3, 14, 10, 0, tzinfo=UTC)
    assert zone_offset(datetime(2026, 3, 14, 13, 2, 11), now) == timedelta(hours=3)  # noqa: DTZ001
    assert zone_offset(datetime(2026, 3, 14, 15, 29), now) == timedelta(  # noqa: DTZ001
        hours=5, minutes=30
    )
    assert zone_offset(None, now) == timedelta(0)


async def test_a_lift_state_follows_the_lift(
    gateway: TekonGateway, source: TekonSource
) -> None:
    polled = frozenset({key(LIFT_STATE)})
    await discovered(source, polled)
    gateway.set_value(LIFT_STATE, lift_state("Движение", 4, "вверх"))
    value = (await source.poll(polled)).values[key(LIFT_STATE)]
    assert value.text == "Движение"
    assert dict(value.parts)["Floor"] == "4"


@pytest.mark.parametrize("initial_data", [False, True], ids=["seed", "opc_da"])
async def test_the_current_values_are_asked_for_once_per_subscription(
    gateway: TekonGateway, source: TekonSource, initial_data: bool
) -> None:
    """The seed's gateway sends a value once it changed: asked for after subscribing.

    Nothing changes on the gateway here; a gateway that sends OPC DA's initial
    update (the switch) shows the same.
    """
    gateway.initial_data = initial_data
    polled = frozenset({key(SETPOINT), key(DOOR)})
    await source.poll(())
    # Nothing subscribed: nothing to ask for.
    assert gateway.calls["ReadAllItemsValues"] == 0
    snapshot = await source.poll(polled)
    assert snapshot.values == {key(SETPOINT): 20.0, key(DOOR): False}
    for _ in range(3):
        assert (await source.poll(polled)).values == {}
    assert gateway.calls["ReadAllItemsValues"] == 1
    # A point newly polled: subscribed, and the values asked for once more.
    more = polled | {key(ENERGY)}
    assert (await source.poll(more)).values == {
        key(SETPOINT): 20.0,
        key(DOOR): False,
        key(ENERGY): 1520.5,
    }
    await source.poll(more)
    assert gateway.calls["ReadAllItemsValues"] == 2
    # Only points taken back: nothing new to ask for.
    await source.poll(polled)
    assert gateway.calls["ReadAllItemsValues"] == 2


@pytest.mark.parametrize("failure", [500, LOST], ids=["error", "lost-answer"])
async def test_a_failed_read_of_the_current_values_is_asked_again_at_the_next_poll(
    gateway: TekonGateway, source: TekonSource, failure: int
) -> None:
    gateway.failing["ReadAllItemsValues"] = failure
    polled = frozenset({key(SETPOINT)})
    snapshot = await discovered(source, polled)
    # The poll is not lost for it.
    assert snapshot.values == {}
    assert source.statistics.failed_polls == 0
    gateway.failing.clear()
    gateway.clear_requests()
    assert (await source.poll(polled)).values == {key(SETPOINT): 20.0}
    assert gateway.requests == ["ReadAllItemsValues", "GetUpdatesText"]
    gateway.clear_requests()
    await source.poll(polled)
    assert gateway.requests == ["GetUpdatesText"]


async def test_a_gateway_without_read_all_items_values_is_not_asked_again(
    gateway: TekonGateway, source: TekonSource, caplog: pytest.LogCaptureFixture
) -> None:
    """404 (a gateway without the call): its values come as they change."""
    gateway.read_all = False
    polled = frozenset({key(SETPOINT)})
    assert (await discovered(source, polled)).values == {}
    gateway.set_value(SETPOINT, "21")
    assert (await source.poll(polled)).values == {key(SETPOINT): 21.0}
    # A new session subscribes again; the call is not tried again.
    gateway.expire_sessions()
    await source.poll(polled)
    await source.poll(polled | {key(DOOR)})
    assert gateway.calls["ReadAllItemsValues"] == 1
    assert source.statistics.failed_polls == 0
    assert source.diagnostics()["subscription"]["reads_all_values"] is False
    assert [
        record.levelname for record in caplog.records if "ReadAll" in record.message
    ] == ["INFO"]


async def lose_an_answer(gateway: TekonGateway, source: TekonSource) -> frozenset[str]:
    """A poll whose updates' answer is lost after the setpoint changed; then the door."""
    polled = frozenset({key(SETPOINT), key(DOOR)})
    await discovered(source, polled)
    gateway.set_value(SETPOINT, "22")
    # aiohttp sends a GET again by itself once when the connection drops.
    gateway.lost_answers = 2
    with pytest.raises(PlcConnectionError):
        await source.poll(polled)
    gateway.set_value(DOOR, "1")
    return polled


async def test_after_a_lost_answer_the_values_of_now_are_shown(
    gateway: TekonGateway, source: TekonSource
) -> None:
    """The lost answer's rid is answered again (the seed); the next rid at once.

    Without it the poll after a lost answer shows the values of the lost
    answer's time: a change made since would wait a poll more.
    """
    polled = await lose_an_answer(gateway, source)
    gateway.clear_requests()
    values = (await source.poll(polled)).values
    assert values[key(SETPOINT)] == 22.0
    assert values[key(DOOR)] is True
    assert gateway.requests == ["GetUpdatesText", "GetUpdatesText"]
    # Then one request a poll again.
    gateway.clear_requests()
    await source.poll(polled)
    assert gateway.requests == ["GetUpdatesText"]


async def test_a_second_lost_answer_keeps_the_first_answer_s_updates(
    gateway: TekonGateway, source: TekonSource, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The repeated answer's updates count even if the next rid's answer is lost."""
    polled = await lose_an_answer(gateway, source)
    updates = source.client.updates
    asked: list[int] = []

    async def second_lost(rid: int) -> list[ItemUpdate]:
        asked.append(rid)
        if len(asked) == 2:
            raise PlcConnectionError("lost")
        return await updates(rid)

    monkeypatch.setattr(source.client, "updates", second_lost)
    assert (await source.poll(polled)).values == {key(SETPOINT): 22.0}
    # The next poll asks the lost rid and the one after it.
    values = (await source.poll(polled)).values
    assert values[key(DOOR)] is True
    assert asked == [asked[0], asked[0] + 1, asked[0] + 1, asked[0] + 2]
