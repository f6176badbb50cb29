"""GetInfo's body as a :class:`SourceInfo`, and what a CPU type tells of its limits."""

import re
from typing import Any, Final

from ...core.exceptions import NotAPlcError
from ...core.models import PlcMode, SourceInfo
from ..points import MANUFACTURER
from .values import parse_timestamp

ITEM_LIMIT_CP1: Final = 128
ITEM_LIMIT_CP2: Final = 256
ITEM_LIMIT_UNKNOWN: Final = ITEM_LIMIT_CP1

_CPU_SERIES: Final = re.compile(r"CP-?(\d)", re.IGNORECASE)
_MAC: Final = re.compile(r"[0-9A-Fa-f]{2}([-:.]?)(?:[0-9A-Fa-f]{2}\1){4}[0-9A-Fa-f]{2}")


def _text(container: Any, key: str) -> str | None:
    """Return a string member of a JSON object, stripped; None when absent or empty."""
    if not isinstance(container, dict):
        return None
    value = container.get(key)
    if isinstance(value, str | int | float) and not isinstance(value, bool):
        return str(value).strip() or None
    return None


def parse_mode(raw: Any) -> PlcMode:
    """Normalise the PLC mode: ``"RUN "`` → RUN; anything not RUN or HALT is ERR."""
    text = raw.strip().upper() if isinstance(raw, str) else ""
    return (
        PlcMode(text) if text in {PlcMode.RUNNING, PlcMode.STOPPED} else PlcMode.FAULT
    )


def normalize_mac(raw: str | None) -> str | None:
    """``F8-DC-7A-11-F4-DC`` → ``f8:dc:7a:11:f4:dc``; other text is kept as given."""
    if raw is None or not _MAC.fullmatch(raw):
        return raw
    digits = re.sub(r"[^0-9A-Fa-f]", "", raw).lower()
    return ":".join(digits[index : index + 2] for index in range(0, 12, 2))


def item_limit_for_type(plc_type: str | None) -> int:
    """Return the per-response item limit of a CPU type: 128 CP-1xxx, 256 CP-2xxx.

    Types the manual does not cover (CP-7xxx, simulators, unknown) get the
    smaller 128, which every TecoApi CPU accepts.
    """
    if plc_type and (match := _CPU_SERIES.search(plc_type)):
        if match.group(1) == "2":
            return ITEM_LIMIT_CP2
        if match.group(1) == "1":
            return ITEM_LIMIT_CP1
    return ITEM_LIMIT_UNKNOWN


def device_name(model: str | None) -> str:
    """Return the PLC device's name before the user renames it: ``Tecomat CP-2080``."""
    return f"Tecomat {model}" if model else "Tecomat PLC"


def parse_plc_info(body: Any) -> SourceInfo:
    """Parse the PLC info of a GetInfo body; missing optional fields are None.

    A body without a ``plc`` object or without a serial number is not a TecoApi
    answer (the serial number is the PLC's identity).
    """
    plc = body.get("plc") if isinstance(body, dict) else None
    serial_number = _text(plc, "serialNumber")
    if not isinstance(plc, dict) or serial_number is None:
        raise NotAPlcError("GetInfo did not describe a TecoApi PLC")
    program = plc.get("userProg")
    api = body.get("api")
    model = _text(plc, "type")
    return SourceInfo(
        identity=serial_number,
        name=device_name(model),
        manufacturer=MANUFACTURER,
        family=_text(plc, "family"),
        model=model,
        serial_number=serial_number,
        firmware=_text(plc, "version"),
        mac=normalize_mac(_text(plc, "mac")),
        mode=parse_mode(plc.get("mode")),
        program_name=_text(program, "name"),
        program_compiled=parse_timestamp(_text(program, "compiled")),
        program_stamp=_text(program, "stamp"),
        time=parse_timestamp(_text(plc, "time")),
        api_version=_text(api, "version"),
    )
