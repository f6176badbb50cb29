"""The PLC's JSON layout, checked against the manual's printed Content-Lengths."""

import pytest

from tests.simulator import errors
from tests.simulator.json_render import (
    render,
    render_error,
    render_name_list,
    scalar_text,
)


@pytest.mark.parametrize(
    ("value", "text"),
    [
        (True, "true"),
        (False, "false"),
        (-2222, "-2222"),
        (1000.0, "1000.000000"),
        (-0.5, "-0.500000"),
        (0.1, "0.100000"),
        ("°C", '"°C"'),
        ('"Blue"', '"\\"Blue\\""'),
        ("a\nb", '"a\\nb"'),
    ],
)
def test_scalars(value: object, text: str) -> None:
    assert scalar_text(value) == text


def test_only_plc_scalars() -> None:
    with pytest.raises(TypeError):
        scalar_text(None)


def test_empty_containers_stay_on_their_line() -> None:
    assert render({"a": {}, "b": [], "c": [[]]}) == (
        b'{\r\n  "a": {},\r\n  "b": [],\r\n  "c":\r\n  [\r\n    []\r\n  ]\r\n}\r\n'
    )


def test_non_ascii_is_utf8() -> None:
    assert render({"units": "°C"}) == '{\r\n  "units": "°C"\r\n}\r\n'.encode()


def test_manual_content_lengths() -> None:
    info = {
        "api": {"version": "TecoApi v1.0.0"},
        "plc": {
            "family": "Fx2",
            "type": "CP2080",
            "serialNumber": "PP 0004",
            "version": "Fx2 CP2080I v1.1",
            "mac": "F8-DC-7A-11-F4-DC",
            "mode": "RUN ",
            "userProg": {
                "name": "DOC_TECOAPI v1.0",
                "compiled": "2018-01-18T16:39:38.000Z",
                "stamp": "E28AE29B",
            },
            "time": "2018-01-31T16:50:39.949Z",
        },
    }
    names = ["plcName", "plcType", "plcDesc"]
    time = "2018-01-29T18:29:39.730Z"

    assert len(render(info)) == 428
    assert len(render_name_list(names, as_array=False)) == 59
    assert len(render_name_list(names, as_array=True)) == 71
    assert len(render_error(errors.authentication_requested(), time)) == 133
    assert len(render_error(errors.unimplemented("GET", "GetData"), time)) == 151


def test_empty_name_lists() -> None:
    assert render_name_list([], as_array=False) == b"{}\r\n"
    assert render_name_list([], as_array=True) == b"[]\r\n"
