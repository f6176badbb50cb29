"""Variable IDs: addresses, both spellings, matching answers to requests."""

import pytest

from custom_components.tecoapi.pyplc.mervis.ids import Address, IdStyle, parse_id


def test_an_address_reads_and_writes_itself() -> None:
    address = Address.parse("8776[0,2]")
    assert (address.commuid, address.offset, address.length, address.end) == (
        8776,
        0,
        2,
        2,
    )
    assert str(address) == "8776[0,2]"
    assert Address.parse(" 8776 [ 0 , 2 ] ") == address


@pytest.mark.parametrize(
    "text", ["8776", "8776[0]", "x[0,1]", "1[0,0]", "1[-1,2]", "1[0,2097152]"]
)
def test_what_is_no_address(text: str) -> None:
    with pytest.raises(ValueError, match=r"CommUid|reads"):
        Address.parse(text)


def test_both_spellings_name_the_same_bytes() -> None:
    address = Address(8776, 0, 2)
    released = address.variable_id(IdStyle.RELEASED)
    seed = address.variable_id(IdStyle.SEED)
    assert released == "svc://DefaultConnection/8776[0,2]"
    assert seed == "svc:defaultConnection/8776[0,2]"
    assert parse_id(released) == parse_id(seed) == address
    assert parse_id("SVC://defaultconnection/8776[0, 2]") == address


@pytest.mark.parametrize(
    "ident", [None, 17, "svc://DefaultConnection/x", "svc:/1[0,1]", "1[0,1]", ""]
)
def test_what_is_no_id(ident: object) -> None:
    assert parse_id(ident) is None


@pytest.mark.parametrize(
    "text",
    ["svc:otherConnection/8776[0,2]", "svc://otherConnection/8776[0,2]"],
)
def test_a_variable_of_another_connection(text: str) -> None:
    """The seed's data request names ``svc:otherConnection/…``: both spellings are read."""
    address = Address.parse(text)
    assert (address.connection, address.commuid, address.offset, address.length) == (
        "otherConnection",
        8776,
        0,
        2,
    )
    assert str(address) == "svc://otherConnection/8776[0,2]"
    assert Address.parse(str(address)) == address
    assert address.variable_id(IdStyle.RELEASED) == "svc://otherConnection/8776[0,2]"
    assert address.variable_id(IdStyle.SEED) == "svc:otherConnection/8776[0,2]"
    # An answer spells the connection as it likes: matched without case.
    assert parse_id("SVC:OTHERCONNECTION/8776[0,2]") == address.folded
    assert address.variable != Address(8776, 0, 2).variable


def test_the_default_connection_named_is_the_local_one() -> None:
    assert Address.parse("svc://DefaultConnection/8776[0,2]") == Address(8776, 0, 2)
    assert Address.parse("svc:defaultconnection/ 8776[0,2]") == Address(8776, 0, 2)
