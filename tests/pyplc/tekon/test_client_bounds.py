"""The Tekon client's parsing at its edges: what is an item, a value, a count, an error.

Each test pins an edge a flipped test or an off-by-one would move (scripts/mutate
found them unpinned): a property read with ``Error`` 0 or none is kept and any other
is left out, a blank name or a boolean ID is no item, a 409 is a lost session with
its status.
"""

from typing import Any

import aiohttp
from aiohttp import web
from hypothesis import given, strategies as st
import pytest

from custom_components.tecoapi.pyplc import MalformedResponseError
from custom_components.tecoapi.pyplc.tekon.client import (
    AddressItem,
    SessionLostError,
    TekonClient,
    address_item,
    item_updates,
    parse_time,
)
from tests.pyplc.tekon.test_client import serving
from tests.simulator.tekon import TekonGateway


def prop(prop_id: Any, value: Any = "1", **extra: Any) -> dict[str, Any]:
    """One entry of an item's ``ItemProps``."""
    return {"ID": prop_id, "Value": value, **extra}


def test_a_property_read_without_error_is_kept_and_one_with_an_error_is_not() -> None:
    """The seed's ``"Error":0`` is a property read; no ``Error`` or null too."""
    raw = {
        "ItemName": "A",
        "ItemID": 7,
        "ItemProps": [
            prop(1, "zero", Error=0),
            prop(2, "absent"),
            prop(3, "null", Error=None),
            prop(4, "one", Error=1),
            prop(5, "minus one", Error=-1),
            prop(6, None, Error=0),
            prop(True, "a boolean ID"),
            prop("8", "a text ID"),
            "not a property",
        ],
    }
    assert address_item(raw) == AddressItem(
        name="A",
        item_id=7,
        properties={1: "zero", 2: "absent", 3: "null", 6: ""},
    )


def test_only_the_properties_kept_are_kept() -> None:
    raw = {"ItemName": "A", "ItemID": 7, "ItemProps": [prop(1), prop(2), prop(3)]}
    item = address_item(raw, keep={2, 9})
    assert item is not None
    assert item.properties == {2: "1"}
    assert address_item(raw, keep=()) == AddressItem(name="A", item_id=7, properties={})


@pytest.mark.parametrize(
    "raw",
    [
        {"ItemName": "", "ItemID": 1},
        {"ItemName": "   ", "ItemID": 1},
        {"ItemName": 5, "ItemID": 1},
        {"ItemName": "A", "ItemID": True},
        {"ItemName": "A", "ItemID": "1"},
        {"ItemName": "A"},
        ["ItemName", "A"],
    ],
)
def test_what_is_no_item(raw: Any) -> None:
    assert address_item(raw) is None


def test_an_item_without_properties_is_an_item() -> None:
    """A name and an ID make an item; ``ItemProps`` that is no list gives no properties."""
    for props in ([], None, {"ID": 1}):
        assert address_item({"ItemName": "A", "ItemID": 0, "ItemProps": props}) == (
            AddressItem(name="A", item_id=0, properties={})
        )


@given(
    name=st.text(min_size=1).filter(str.strip),
    item_id=st.integers(),
    quality=st.integers(),
    value=st.one_of(st.none(), st.text(), st.integers()),
)
def test_an_update_keeps_its_name_id_quality_and_value(
    name: str, item_id: int, quality: int, value: Any
) -> None:
    raw = {"ItemName": name, "ItemID": item_id, "Qual": quality, "V": value}
    [update] = item_updates([raw])
    assert (update.name, update.item_id, update.quality) == (name, item_id, quality)
    assert update.value == ("" if value is None else str(value))


@pytest.mark.parametrize(
    "raw",
    [
        {"ItemName": "A", "Qual": True, "V": "1"},
        {"ItemName": "A", "Qual": "192", "V": "1"},
        {"ItemName": 5, "ItemID": "5", "Qual": 192, "V": "1"},
        {"ItemID": False, "Qual": 192, "V": "1"},
    ],
)
def test_an_update_without_a_quality_or_a_name_and_id_is_left_out(raw: Any) -> None:
    assert item_updates([raw]) == []


def test_an_update_with_a_name_or_an_id_alone_is_kept() -> None:
    updates = item_updates(
        [
            {"ItemName": "A", "ItemID": True, "Qual": 0, "V": 1},
            {"ItemName": 5, "ItemID": 9, "Qual": 0, "V": 2},
        ]
    )
    assert [(u.name, u.item_id, u.value) for u in updates] == [
        ("A", None, "1"),
        (None, 9, "2"),
    ]


def test_updates_that_are_no_list_are_malformed() -> None:
    for answer in ({"result": []}, None, "[]"):
        with pytest.raises(MalformedResponseError):
            item_updates(answer)


def test_a_gateway_time_is_read_and_anything_else_is_none() -> None:
    parsed = parse_time(" 2024-05-02 10:36:06 ")
    assert parsed is not None
    assert parsed.isoformat() == "2024-05-02T10:36:06"
    for text in (None, 20240502, "2024-05-02", "2024-05-02T10:36:06"):
        assert parse_time(text) is None


async def test_a_lost_session_says_409_and_a_count_must_be_a_number(
    socket_enabled: None,
) -> None:
    async with aiohttp.ClientSession() as http, TekonGateway() as gateway:
        client = TekonClient(http, gateway.url)
        with pytest.raises(SessionLostError) as never_opened:
            await client.subscribers_count()
        assert never_opened.value.status == 409
        await client.open_session()
        gateway.expire_sessions()
        with pytest.raises(SessionLostError) as expired:
            await client.subscribers_count()
        assert expired.value.status == 409
        assert client.session_id is None

    answers: list[Any] = [True, 2.5, None, [3], {"count": 3}]

    async def handler(request: web.Request) -> web.Response:
        if request.path == "/NewSession":
            return web.json_response({"sessionid": "S"})
        return web.json_response({"result": answers.pop(0)})

    async with aiohttp.ClientSession() as http, serving(handler) as url:
        client = TekonClient(http, url)
        await client.open_session()
        for _ in range(len(answers)):
            with pytest.raises(MalformedResponseError, match="no count"):
                await client.subscribers_count()
