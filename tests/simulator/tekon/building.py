"""A building's dispatch data as Tekon's OPC server holds it: items, properties, values.

An :class:`Item` is one channel (or one device's ``.Status``): its name, its
``ItemID`` (its position: IDs move when items come or go), its properties as
``GetAddressSpace`` lists them, and its value as the gateway sends it (text),
with an OPC DA quality and the local time of its last change.

:func:`small_building` is the demo's building: a controller at an entrance with
its door, fire alarm, lighting, intercom, temperature and heating setpoint, a
display; a lift with its state XML and its shaft door; two meters; the OPC
server's own monitoring items. :func:`large_building` makes ``items`` channels
of many controllers and devices (a district's dispatch centre).
"""

from collections.abc import Iterable
from dataclasses import dataclass, field
from datetime import datetime
import hashlib
import json
from typing import Any, Final

VT_UI2: Final = 18
VT_UI4: Final = 19
VT_I4: Final = 3
VT_R4: Final = 4
VT_R8: Final = 5
VT_BOOL: Final = 11
VT_BSTR: Final = 8

DISCRETE: Final = 3000
INTERCOM: Final = 3001
CONTROL: Final = 3002
STATUS: Final = 3005
NUMBER: Final = 3060
STRING: Final = 3061
LIFT_STATE: Final = 3070

READ: Final = 1
WRITE: Final = 2
READ_WRITE: Final = 3

GOOD: Final = 192

# Property ID: (its Datatype, its Desc), as GetAddressSpace lists it.
PROPERTIES: Final[dict[int, tuple[int, str]]] = {
    1: (VT_UI2, "Тип данных"),
    3: (VT_UI4, "Права доступа"),
    5: (VT_UI4, "Права доступа"),
    100: (VT_BSTR, "EU units"),
    102: (VT_R8, "High EU"),
    103: (VT_R8, "Low EU"),
    5001: (VT_UI4, "Тип данных канала"),
    5003: (VT_BSTR, "Комментарий"),
    6000: (VT_BSTR, "IP-адрес"),
    6001: (VT_BSTR, "Адрес установки"),
    6003: (VT_I4, "Минимальное значение статуса"),
    6004: (VT_I4, "Максимальное значение статуса"),
    7000: (VT_BSTR, "Категория неисправности"),
    7001: (VT_BSTR, "Описание неисправности"),
    9002: (VT_BSTR, "Регистрационный номер"),
}


@dataclass(slots=True)
class Item:
    """One item of the address space and its current value."""

    name: str
    properties: dict[int, str]
    value: str
    quality: int = GOOD
    time: datetime = field(default_factory=lambda: datetime(2025, 2, 7, 15, 27, 9))  # noqa: DTZ001 (the gateway's local time)
    item_id: int = 0

    @property
    def vartype(self) -> int:
        """The item's value type (property 1)."""
        return int(self.properties.get(1, VT_BSTR))

    @property
    def channel_type(self) -> int | None:
        """The item's channel data type (property 5001), if it has one."""
        text = self.properties.get(5001)
        return None if text is None else int(text)

    @property
    def writable(self) -> bool:
        """Whether the item's access rights (5, else 3) let it be written."""
        access = self.properties.get(5, self.properties.get(3, str(READ)))
        return int(access) & WRITE != 0

    def described(self) -> dict[str, Any]:
        """The item as ``GetAddressSpace`` lists it."""
        return {
            "ItemProps": [
                {
                    "Datatype": PROPERTIES.get(prop, (VT_BSTR, ""))[0],
                    "ID": prop,
                    "Value": value,
                    "Error": 0,
                    "Desc": PROPERTIES.get(prop, (VT_BSTR, ""))[1],
                }
                for prop, value in self.properties.items()
            ],
            "ItemID": self.item_id,
            "ItemName": self.name,
        }


def channel(
    name: str,
    kind: int | None,
    value: str,
    *,
    vartype: int = VT_UI4,
    access: int = READ,
    description: str = "",
    comment: str = "",
    unit: str = "",
    low: float | None = None,
    high: float | None = None,
    access_property: int = 5,
) -> Item:
    """A channel of a kind (5001, None: none) with its properties."""
    properties: dict[int, str] = {1: str(vartype), access_property: str(access)}
    if kind is not None:
        properties[5001] = str(kind)
    if comment:
        properties[5003] = comment
    if description:
        properties[7001] = description
    if unit:
        properties[100] = unit
    if low is not None and high is not None:
        properties[103] = f"{low:g}"
        properties[102] = f"{high:g}"
    return Item(name=name, properties=properties, value=value)


def status(
    device: str,
    value: int = 10,
    *,
    ip: str = "",
    address: str = "",
    registration: str = "",
    maximum: int = 10,
) -> Item:
    """A device's ``.Status`` channel, its identification in its properties."""
    properties = {1: str(VT_UI4), 5: str(READ), 5001: str(STATUS), 6004: str(maximum)}
    if ip:
        properties[6000] = ip
    if address:
        properties[6001] = address
    if registration:
        properties[9002] = registration
    properties[7000] = "Связь"
    return Item(name=f"{device}.Status", properties=properties, value=str(value))


class Building:
    """The items of an OPC server, by name, with their IDs in order."""

    def __init__(self, items: Iterable[Item]) -> None:
        """Hold the items; their IDs are their positions."""
        self.items: list[Item] = []
        self.by_name: dict[str, Item] = {}
        self._described: tuple[str, bytes] | None = None
        self.replace(items)

    def replace(self, items: Iterable[Item]) -> None:
        """A new address space: the items given, numbered from 0 in order."""
        self.items = list(items)
        for item_id, item in enumerate(self.items):
            item.item_id = item_id
        self.by_name = {item.name: item for item in self.items}
        self._described = None

    def add(self, items: Iterable[Item], *, first: bool = False) -> None:
        """Add items (``first``: before the others, moving every ID)."""
        added = list(items)
        self.replace([*added, *self.items] if first else [*self.items, *added])

    def remove(self, names: Iterable[str]) -> None:
        """Remove items by name (the IDs after them move)."""
        gone = set(names)
        self.replace(item for item in self.items if item.name not in gone)

    def address_space(self) -> bytes:
        """``GetAddressSpace``'s answer (made once per address space)."""
        return self._describe()[1]

    def hash(self) -> str:
        """``GetAddressSpaceHash``: MD5 of the address space, in capitals."""
        return self._describe()[0]

    def _describe(self) -> tuple[str, bytes]:
        if self._described is None:
            body = json.dumps(
                [item.described() for item in self.items], ensure_ascii=False
            ).encode()
            digest = hashlib.md5(body, usedforsecurity=False).hexdigest().upper()
            self._described = (digest, body)
        return self._described


CONTROLLER: Final = "Дом 1.КУН-IP8 - 1"
LIFT: Final = f"{CONTROLLER}.Лифт 1"
METERS: Final = "Дом 1.Счётчики"
LIFT_XML: Final = (
    "<Lift><State>{State}</State><Floor>{Floor}</Floor>"
    "<Direction>{Direction}</Direction><Door>{Door}</Door></Lift>"
)


def lift_state(
    state: str = "Норма", floor: int = 1, direction: str = "нет", door: str = "закрыта"
) -> str:
    """A lift's state as the OPC server's XML."""
    return LIFT_XML.format(**lift_parts(state, floor, direction, door))


def lift_parts(
    state: str = "Норма", floor: int = 1, direction: str = "нет", door: str = "закрыта"
) -> dict[str, str]:
    """The parts of a lift's state (:func:`lift_state`'s XML) by their tags."""
    return {"State": state, "Floor": str(floor), "Direction": direction, "Door": door}


def small_building() -> Building:
    """The demo's building (see the module's docstring)."""
    return Building(
        [
            channel(
                "DBMonitoring.ConnectFailDevices",
                None,
                "0",
                access=READ,
                comment="Устройств без связи",
            ),
            channel(
                "DBMonitoring.KIR_BatteryFail",
                None,
                "0",
                access=READ_WRITE,
                access_property=3,
            ),
            status(
                CONTROLLER,
                ip="192.168.10.21",
                address="ул. Лесная, 5, подъезд 1",
                registration="0451-КУН",
            ),
            channel(
                f"{CONTROLLER}.Дверь подъезда",
                DISCRETE,
                "0",
                description="Дверь подъезда открыта",
            ),
            channel(
                f"{CONTROLLER}.Пожарная сигнализация",
                DISCRETE,
                "0",
                description="Пожарная тревога",
            ),
            channel(
                f"{CONTROLLER}.Освещение",
                CONTROL,
                "1",
                access=READ_WRITE,
                description="Освещение подъезда",
            ),
            channel(
                f"{CONTROLLER}.Переговорное устройство",
                INTERCOM,
                "0",
                access=READ_WRITE,
                description="Вызов переговорного устройства",
            ),
            channel(
                f"{CONTROLLER}.Температура",
                NUMBER,
                "21.5",
                vartype=VT_R4,
                unit="°C",
                comment="Температура в подъезде",
            ),
            channel(
                f"{CONTROLLER}.Уставка",
                NUMBER,
                "20",
                vartype=VT_R4,
                access=READ_WRITE,
                unit="°C",
                low=15,
                high=28,
                comment="Уставка отопления",
            ),
            channel(
                f"{CONTROLLER}.Табло",
                STRING,
                "Добро пожаловать",
                vartype=VT_BSTR,
                access=READ_WRITE,
                comment="Сообщение на табло",
            ),
            status(LIFT, registration="Л-0017", address="Подъезд 1"),
            channel(
                f"{LIFT}.Состояние",
                LIFT_STATE,
                lift_state(),
                vartype=VT_BSTR,
                comment="Состояние лифта",
            ),
            channel(
                f"{LIFT}.Дверь шахты",
                DISCRETE,
                "0",
                description="Дверь шахты открыта",
            ),
            status(f"{METERS}.Электросчётчик", registration="ЭС-551"),
            channel(
                f"{METERS}.Электросчётчик.Энергия",
                NUMBER,
                "1520.5",
                vartype=VT_R8,
                unit="kWh",
                comment="Энергия",
            ),
            status(f"{METERS}.Водосчётчик", registration="ВС-102"),
            channel(
                f"{METERS}.Водосчётчик.Объём",
                NUMBER,
                "312.25",
                vartype=VT_R8,
                unit="m³",
                comment="Объём воды",
            ),
        ]
    )


def large_building(items: int, *, devices_per_controller: int = 9) -> Building:
    """A district's dispatch data: exactly ``items`` items, statuses included.

    Each device (a controller, then the devices below it) has a status and up
    to eighteen channels of every kind.
    """
    made: list[Item] = []
    controller = 0
    while len(made) < items:
        controller += 1
        top = f"Район.КУН-IP8 - {controller}"
        for device in range(devices_per_controller + 1):
            prefix = top if device == 0 else f"{top}.Устройство {device}"
            made.append(
                status(
                    prefix, ip=f"10.{controller // 250}.{controller % 250}.{device + 1}"
                )
            )
            made.extend(_channel_of(prefix, index) for index in range(18))
    return Building(made[:items])


def _channel_of(prefix: str, index: int) -> Item:
    """The ``index``-th channel of a device in a large building (every kind)."""
    name = f"{prefix}.Канал {index + 1}"
    match index % 6:
        case 0:
            return channel(name, DISCRETE, "0", description=f"Датчик {index + 1}")
        case 1:
            return channel(name, CONTROL, "0", access=READ_WRITE)
        case 2:
            return channel(name, NUMBER, "12.5", vartype=VT_R4, unit="°C")
        case 3:
            return channel(name, NUMBER, "7", vartype=VT_UI4, access=READ_WRITE)
        case 4:
            return channel(name, STRING, "текст", vartype=VT_BSTR)
        case _:
            return channel(name, INTERCOM, "0", access=READ_WRITE)
