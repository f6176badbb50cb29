"""What the PLCComS-backed sources share: T_ApiObjects from LIST:, values, bursts."""

import asyncio
from datetime import UTC, date, datetime
from typing import Any

import pytest

from custom_components.tecoapi.pyplc import ValueKind
from custom_components.tecoapi.pyplc.tecomat.plccoms.catalogue import (
    build_catalogue,
    find_api_objects,
    meta_of,
)
from custom_components.tecoapi.pyplc.tecomat.plccoms.push import (
    PushBatch,
    json_shaped,
    point_value,
)
from custom_components.tecoapi.pyplc.tecomat.plccoms.variables import PlcComsVariable
from custom_components.tecoapi.pyplc.tecomat.points import (
    api_object_attributes,
    tecomat_point,
)

ATTRIBUTES = [
    ("enable", "BOOL"),
    ("visibility", "BOOL"),
    ("readOnly", "BOOL"),
    ("title", "STRING"),
    ("minValue", "REAL"),
    ("maxValue", "LREAL"),
    ("units", "STRING"),
]
META = api_object_attributes(
    title="t",
    units="u",
    read_only=False,
    min_value=0.0,
    max_value=1.0,
    enable=True,
    visibility=True,
)


def api_object(path: str, value_type: str = "REAL") -> list[PlcComsVariable]:
    return [
        PlcComsVariable(f"{path}.value", value_type),
        *(PlcComsVariable(f"{path}.attr.{name}", kind) for name, kind in ATTRIBUTES),
    ]


def test_t_api_objects_are_found_in_structs_and_arrays() -> None:
    variables = [
        PlcComsVariable("__PLC_RUN", "BOOL"),
        *api_object("Main.setpoint"),
        *api_object("lights[2]", "BOOL"),
        PlcComsVariable("plain", "INT"),
    ]

    objects = find_api_objects(variables)

    assert objects.keys() == {"main.setpoint", "lights[2]"}
    assert objects["main.setpoint"].path == "Main.setpoint"
    assert objects["lights[2]"].attributes["readonly"] == "lights[2].attr.readOnly"


@pytest.mark.parametrize(
    "variables",
    [
        # a struct with one more member is not a T_ApiObject
        [*api_object("box"), PlcComsVariable("box.extra", "INT")],
        # nor one whose attribute has another type
        [
            PlcComsVariable(v.name, "INT") if v.name.endswith("title") else v
            for v in api_object("box")
        ],
        # nor one missing an attribute
        api_object("box")[:-1],
        # nor a value of a type nobody knows
        api_object("box", "POINTER"),
    ],
)
def test_what_is_not_a_t_api_object(variables: list[PlcComsVariable]) -> None:
    assert find_api_objects(variables) == {}


def test_a_t_api_object_without_metadata_stays_plain_points() -> None:
    variables = [
        *api_object("a"),
        *api_object("b"),
        PlcComsVariable("odd", "POINTER"),
    ]
    objects = find_api_objects(variables)

    catalogue = build_catalogue(variables, objects, {"a": META})

    assert catalogue.points["a"] == tecomat_point("a", ValueKind.REAL, META)
    assert "a.value" not in catalogue.points
    assert catalogue.points["b.value"].attributes is None
    assert catalogue.points["b.attr.title"].kind is ValueKind.STRING
    assert catalogue.groups == ("a", "b")
    assert catalogue.skipped_groups == ("odd",)


def test_meta_of_attribute_values() -> None:
    values: dict[str, Any] = {
        "enable": True,
        "visibility": True,
        "readonly": False,
        "title": "t",
        "units": "u",
        "minvalue": 0,
        "maxvalue": 1.0,
    }

    assert meta_of(values) == META
    assert meta_of({**values, "enable": None}) is None
    assert meta_of({**values, "title": 5}) is None
    assert meta_of({**values, "maxvalue": float("inf")}) is None


@pytest.mark.parametrize(
    ("kind", "value", "shown"),
    [
        (ValueKind.REAL, 0.10000000149011612, 0.1),  # a float32 printed in full
        (ValueKind.REAL, 21.799999237060547, 21.799999),  # as TecoApi prints it
        (ValueKind.REAL, 3, 3.0),
        (ValueKind.REAL, True, None),
        (ValueKind.REAL, float("nan"), None),
        (ValueKind.INTEGER, 5.0, 5),
        (ValueKind.INTEGER, 5.5, None),
        (ValueKind.DATE, "2024-02-29", date(2024, 2, 29)),
        (
            ValueKind.DATETIME,
            "2024-02-29T10:00:00.000Z",
            datetime(2024, 2, 29, 10, tzinfo=UTC),
        ),
        (ValueKind.DATE, date(2024, 2, 29), date(2024, 2, 29)),
        (ValueKind.STRING, "x", "x"),
    ],
)
def test_point_value_reads_as_tecoapi(kind: ValueKind, value: Any, shown: Any) -> None:
    point = tecomat_point("p", kind)

    assert point_value(point, value) == shown


def test_json_shaped() -> None:
    assert json_shaped(date(2024, 2, 29)) == "2024-02-29"
    assert (
        json_shaped(datetime(2024, 2, 29, 10, tzinfo=UTC)) == "2024-02-29T10:00:00.000Z"
    )
    assert json_shaped(1.5) == 1.5


async def test_a_batch_hands_each_burst_on_once() -> None:
    delivered: list[dict[str, Any]] = []
    done = asyncio.Event()

    def deliver(values: dict[str, Any]) -> None:
        delivered.append(values)
        done.set()

    batch = PushBatch(deliver, window=0)
    batch.add("a", 1)
    batch.add("b", 2)
    batch.add("a", 3)
    await done.wait()

    assert delivered == [{"a": 3, "b": 2}]
    assert (batch.bursts, batch.values) == (1, 3)

    batch.add("c", 4)
    batch.cancel()
    batch.flush()
    assert delivered == [{"a": 3, "b": 2}]
    with pytest.raises(ValueError, match="negative"):
        PushBatch(deliver, window=-1)
