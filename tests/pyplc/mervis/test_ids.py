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
    "ident",
    [None, 17, "svc://OtherConnection/1[0,1]", "svc://DefaultConnection/x", ""],
)
def test_what_is_no_id_of_the_local_connection(ident: object) -> None:
    assert parse_id(ident) is None
