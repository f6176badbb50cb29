"""The tables that turn a point into an entity description."""

from homeassistant.components.binary_sensor import BinarySensorDeviceClass
from homeassistant.components.number import NumberDeviceClass, NumberMode
from homeassistant.components.sensor import SensorDeviceClass, SensorStateClass
from homeassistant.components.sensor.const import DEVICE_CLASS_UNITS
from homeassistant.const import Platform
import pytest

from custom_components.tecoapi.const import PlainVariables
from custom_components.tecoapi.mapping import (
    HUMIDITY,
    PLATFORM_BY_KIND,
    UNITS,
    UnitMapping,
    binary_class_of,
    describe,
    display_precision,
    entity_name,
    is_clock,
    number_device_class,
    number_mode,
    number_range,
    number_step,
    platform_for,
    readable_path,
    unit_mapping,
)
from custom_components.tecoapi.pyplc import (
    Access,
    DataType,
    Point,
    PointAttributes,
    ValueKind,
)
from custom_components.tecoapi.pyplc.core.pointmap import TYPE_NAMES
from custom_components.tecoapi.pyplc.tecomat.points import (
    api_object_attributes,
    tecomat_point,
)


def api_object(
    kind: ValueKind = ValueKind.REAL,
    *,
    title: str = "",
    units: str = "",
    read_only: bool = True,
    min_value: float = 0.0,
    max_value: float = 0.0,
    path: str = "Main.myObject1",
) -> Point:
    """A T_ApiObject point."""
    return tecomat_point(
        path,
        kind,
        api_object_attributes(
            title=title,
            units=units,
            read_only=read_only,
            min_value=min_value,
            max_value=max_value,
            enable=True,
            visibility=True,
        ),
    )


def plain(kind: ValueKind, path: str = "plcData.varInt") -> Point:
    """A plain variable point."""
    return tecomat_point(path, kind)


def gateway_point(kind: ValueKind, access: Access = Access.WRITE) -> Point:
    """A gateway's point (by default written and never read: an intercom's call)."""
    return Point(
        key="call",
        path="Call",
        address="Call",
        type=DataType(kind=kind),
        attributes=PointAttributes(access=access),
    )


@pytest.mark.parametrize(
    ("point", "platform"),
    [
        (api_object(ValueKind.BOOL), Platform.BINARY_SENSOR),
        (api_object(ValueKind.BOOL, read_only=False), Platform.SWITCH),
        (api_object(ValueKind.REAL), Platform.SENSOR),
        (api_object(ValueKind.INTEGER, read_only=False), Platform.NUMBER),
        (api_object(ValueKind.STRING), Platform.SENSOR),
        (api_object(ValueKind.STRING, read_only=False), Platform.TEXT),
        (api_object(ValueKind.DATETIME), Platform.SENSOR),
        (api_object(ValueKind.DATETIME, read_only=False), Platform.DATETIME),
        (api_object(ValueKind.DATE, read_only=False), Platform.DATE),
        (api_object(ValueKind.TIME), Platform.SENSOR),
        (api_object(ValueKind.TIME, read_only=False), Platform.TIME),
        (plain(ValueKind.BOOL), Platform.BINARY_SENSOR),
        (plain(ValueKind.REAL), Platform.SENSOR),
        (plain(ValueKind.STRING), Platform.SENSOR),
        (gateway_point(ValueKind.RECORD, Access.READ), Platform.SENSOR),
        (gateway_point(ValueKind.RECORD, Access.READ_WRITE), Platform.SENSOR),
        (gateway_point(ValueKind.BOOL), Platform.BUTTON),
        (gateway_point(ValueKind.INTEGER), Platform.BUTTON),
        (gateway_point(ValueKind.REAL), Platform.NUMBER),
    ],
)
def test_platform_for(point: Point, platform: Platform) -> None:
    """Kind and writability choose the platform; plain variables are read-only."""
    assert platform_for(point) is platform


def test_every_kind_has_a_platform() -> None:
    """No kind is left without an entity, writable or not."""
    assert set(PLATFORM_BY_KIND) == {
        (kind, writable) for kind in ValueKind for writable in (False, True)
    }


@pytest.mark.parametrize("units", list(UNITS))
def test_every_unit_is_valid_for_its_device_class(units: str) -> None:
    """Home Assistant accepts each mapped unit for its device and state class."""
    mapping = UNITS[units]
    if mapping.device_class is not None:
        assert mapping.unit in DEVICE_CLASS_UNITS[mapping.device_class]
        assert number_device_class(mapping) is NumberDeviceClass(
            mapping.device_class.value
        )


@pytest.mark.parametrize(
    ("title", "units", "expected"),
    [
        ("outside temperature", "°C", UNITS["°C"]),
        ("boiler", "degC", UnitMapping("°C", SensorDeviceClass.TEMPERATURE)),
        ("Living room humidity", "%", HUMIDITY),
        ("Relativní vlhkost", "%", HUMIDITY),
        ("Blind position", "%", UnitMapping("%")),
        ("meter", "kWh", UNITS["kWh"]),
        ("flow", " l/min ", UNITS["l/min"]),
        ("odd", "furlong", UnitMapping("furlong")),
    ],
)
def test_unit_mapping(title: str, units: str, expected: UnitMapping) -> None:
    """Unit spellings map to Home Assistant's; unknown units stay, as a measurement."""
    assert unit_mapping(api_object(title=title, units=units)) == expected


def test_energy_is_total_increasing() -> None:
    """Energy counters feed long-term statistics as increasing totals."""
    for units in ("Wh", "kWh", "MWh"):
        assert UNITS[units].state_class is SensorStateClass.TOTAL_INCREASING


def test_no_unit_mapping_without_a_number_and_a_unit() -> None:
    """Strings, plain variables and unit-less numbers get no unit mapping."""
    assert unit_mapping(api_object(ValueKind.STRING, units="°C")) is None
    assert unit_mapping(plain(ValueKind.REAL)) is None
    assert unit_mapping(api_object(units="  ")) is None


def test_number_device_class_only_where_number_has_it() -> None:
    """A sensor-only device class has no number counterpart."""
    assert number_device_class(None) is None
    assert number_device_class(UnitMapping("%")) is None
    assert number_device_class(UnitMapping("x", SensorDeviceClass.DATE)) is None


@pytest.mark.parametrize(
    ("point", "name"),
    [
        (api_object(title="  requested temperature "), "requested temperature"),
        (api_object(path="Main.heatingPump_1[2]"), "Main heating pump 1 2"),
        (plain(ValueKind.INTEGER, "plcData.varInt"), "plcData.varInt"),
    ],
)
def test_entity_name(point: Point, name: str) -> None:
    """Title first; an untitled object's path in words; a plain variable's path."""
    assert entity_name(point, point.attributes) == name


@pytest.mark.parametrize(
    ("point", "name"),
    [
        (plain(ValueKind.INTEGER, "plcData.varInt"), "varInt"),
        (plain(ValueKind.INTEGER, "Main.sub.count"), "sub.count"),
        (plain(ValueKind.INTEGER, "arr[2].x"), "arr[2].x"),
        (plain(ValueKind.INTEGER, "plcType"), "plcType"),
        (api_object(path="Main.heatingPump_1[2]"), "Heating pump 1 2"),
        (api_object(path="Main.pump", title="Pump"), "Pump"),
    ],
)
def test_entity_name_in_group(point: Point, name: str) -> None:
    """On its group's device an entity is named without the group's own name."""
    assert entity_name(point, point.attributes, in_group=True) == name


def test_an_untitled_object_does_not_say_its_device_again() -> None:
    """A path in words is trimmed as a title is: on *Heating*, not *Heating curve*."""
    point = api_object(path="Heating.heatingCurve")
    assert entity_name(point, point.attributes, in_group=True) == "Heating curve"
    assert (
        entity_name(point, point.attributes, in_group=True, said=("Heating",))
        == "Curve"
    )


def test_readable_path() -> None:
    """Paths read as words, first letter upper case."""
    assert readable_path("myObject.favorites.food") == "My object favorites food"
    assert readable_path("arr3[1][2][0]") == "Arr 3 1 2 0"


@pytest.mark.parametrize(
    ("point", "expected"),
    [
        (
            api_object(read_only=False, min_value=10.0, max_value=30.0),
            ((10.0, 30.0), 0.1, NumberMode.SLIDER),
        ),
        (
            api_object(read_only=False, min_value=0.0, max_value=1.0),
            ((0.0, 1.0), 0.01, NumberMode.SLIDER),
        ),
        (
            api_object(read_only=False, min_value=0.0, max_value=5000.0),
            ((0.0, 5000.0), 0.1, NumberMode.BOX),
        ),
        (
            api_object(read_only=False),
            ((-1e9, 1e9), 0.1, NumberMode.BOX),
        ),
        (
            api_object(ValueKind.INTEGER, read_only=False, max_value=3.0),
            ((0.0, 3.0), 1, NumberMode.SLIDER),
        ),
        (
            # TecoApi's JSON says no IEC type: any of DINT..UDINT may be written.
            api_object(ValueKind.INTEGER, read_only=False),
            ((-2147483648, 4294967295), 1, NumberMode.BOX),
        ),
    ],
)
def test_number_range_step_and_mode(
    point: Point, expected: tuple[tuple[float, float], float, NumberMode]
) -> None:
    """Range from attr (kind's range without one), step by kind, mode by steps."""
    minimum, maximum = number_range(point, point.attributes)
    step = number_step(point, minimum, maximum)
    assert ((minimum, maximum), step, number_mode(minimum, maximum, step)) == expected


def typed(
    type_name: str,
    *,
    scale: float = 1.0,
    minimum: float | None = None,
    maximum: float | None = None,
) -> Point:
    """A writable point of a map, of a type a map names."""
    return Point(
        key="p",
        path="p",
        address="DT1",
        type=TYPE_NAMES[type_name],
        attributes=PointAttributes(
            access=Access.READ_WRITE, minimum=minimum, maximum=maximum
        ),
        scale=scale,
    )


@pytest.mark.parametrize(
    ("point", "expected"),
    [
        (typed("int"), (-32768, 32767)),
        (typed("uint"), (0, 65535)),
        (typed("udint"), (0, 4294967295)),  # a Tekon VT_UI4 takes 3,000,000,000
        (typed("sint"), (-128, 127)),
        (typed("int", scale=0.1), (-3276.8, 3276.7)),
        (typed("int", scale=-0.5), (-16383.5, 16384.0)),
        (typed("int", scale=0.1, minimum=15, maximum=28), (15, 28)),
        # What the map says is cut to what the type holds; wholly outside: the type's.
        (typed("uint", minimum=-10, maximum=100_000), (0, 65535)),
        (typed("uint", minimum=70_000, maximum=80_000), (0, 65535)),
        (typed("real", minimum=-5, maximum=5), (-5, 5)),
        (typed("real"), (-1e9, 1e9)),
    ],
)
def test_a_number_s_range_is_its_type_s_within_its_map_s(
    point: Point, expected: tuple[float, float]
) -> None:
    """A type's width, signedness and scale bound a number, intersected with its map."""
    assert number_range(point, point.attributes) == expected
    if not point.attributes or not point.attributes.has_range:
        assert number_range(point, None) == expected


@pytest.mark.parametrize(
    ("title", "device_class"),
    [
        ("Ventilation filter clogged", BinarySensorDeviceClass.PROBLEM),
        ("Filtr rekuperace zanesený", BinarySensorDeviceClass.PROBLEM),
        ("Ucpaný filtr", BinarySensorDeviceClass.PROBLEM),
        ("Heat pump fault", BinarySensorDeviceClass.PROBLEM),
        ("Kouř v kuchyni", BinarySensorDeviceClass.SMOKE),
        ("Bedroom window open", BinarySensorDeviceClass.WINDOW),
        ("Kids room blind moving", None),
        ("Boiler", None),
        # A Tekon gateway's channels, in Russian.
        ("Дверь подъезда открыта", BinarySensorDeviceClass.DOOR),
        ("Пожарная тревога", BinarySensorDeviceClass.SMOKE),
        ("Протечка в подвале", BinarySensorDeviceClass.MOISTURE),
        ("Окно чердака", BinarySensorDeviceClass.WINDOW),
        ("Датчик движения", BinarySensorDeviceClass.MOTION),
        ("Неисправность насоса", BinarySensorDeviceClass.PROBLEM),
        ("Авария лифта", BinarySensorDeviceClass.PROBLEM),
        ("Освещение", None),
        ("Garage door", BinarySensorDeviceClass.DOOR),
        # A title that says which state is on never turns it into its opposite.
        ("Garage door closed", None),
        ("Front door locked", None),
        ("Window shut", None),
        ("Gate off", None),
        ("Alarm off", None),
        ("Vstupní dveře zavřeno", None),
        ("Dveře zamčeno", None),
        ("Okno zavřené", None),
        ("Дверь закрыта", None),
        ("Office door", BinarySensorDeviceClass.DOOR),
    ],
)
def test_binary_class_from_the_title(
    title: str, device_class: BinarySensorDeviceClass | None
) -> None:
    """A title that says what the flag watches gives its device class."""
    assert binary_class_of(title) == device_class


@pytest.mark.parametrize(
    ("point", "clock"),
    [
        (api_object(ValueKind.DATETIME, title="Controller clock"), True),
        (api_object(ValueKind.DATETIME, title="Systémový čas"), True),
        (api_object(ValueKind.DATETIME, path="plcClock"), True),
        (api_object(ValueKind.DATETIME, title="Last restart"), False),
        (api_object(ValueKind.STRING, title="Clock"), False),
    ],
)
def test_a_clock_is_a_diagnostic_disabled_until_wanted(
    point: Point, clock: bool
) -> None:
    """A clock changes every poll: not a state to record (a sensor only)."""
    assert is_clock(point) is clock
    description = describe(point, PlainVariables.ENABLED)
    assert (description.diagnostic, description.enabled_default) == (clock, not clock)


def scaled(type_name: str, scale: float = 1.0, offset: float = 0.0) -> Point:
    """A map's point of a type, scaled."""
    found = TYPE_NAMES[type_name]
    return Point(
        key="p",
        path="p",
        address="1[0,4]",
        type=found,
        attributes=PointAttributes(name="P"),
        scale=scale,
        offset=offset,
    )


@pytest.mark.parametrize(
    ("point", "precision"),
    [
        # A real: two decimals (an LREAL of hours a PLC computes: 3.69083333333333).
        (scaled("lreal"), 2),
        (scaled("real"), 2),
        (scaled("real", scale=0.001), 3),
        # A register in tenths, quarters; an offset's decimals count too.
        (scaled("int", scale=0.1), 1),
        (scaled("int", scale=0.25), 2),
        (scaled("uint", offset=-273.15), 2),
        (scaled("int", scale=1e-9), 6),
        # Whole numbers, however scaled; text, dates, flags, durations: none.
        (scaled("int"), None),
        (scaled("int", scale=10.0), None),
        (scaled("udint", scale=2.0, offset=-5.0), None),
        (scaled("dt"), None),
        (scaled("bool"), None),
        (scaled("time"), None),
    ],
)
def test_a_sensor_s_display_precision(point: Point, precision: int | None) -> None:
    assert display_precision(point) == precision
    assert describe(point, PlainVariables.ENABLED).precision == precision
