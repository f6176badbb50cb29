"""PLC types and their request limits (manual chapter 3.7)."""

import pytest

from tests.simulator.plc import limit_for_type


@pytest.mark.parametrize(
    ("plc_type", "limit"),
    [
        ("CP-1000", 128),
        ("CP1004", 128),
        ("cp-1970", 128),
        ("CP-2080", 256),
        ("CP2080", 256),
        (" CP-2000 ", 256),
        ("CP-7004", 128),
        ("CP-W32", 128),
        ("", 128),
    ],
)
def test_limit_for_type(plc_type: str, limit: int) -> None:
    assert limit_for_type(plc_type) == limit
