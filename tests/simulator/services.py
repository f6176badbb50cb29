"""The five TecoApi services, answering from a simulated PLC (manual chapter 3).

Every function here takes the request as the PLC sees it (raw percent-encoded query,
raw request target, body) and returns the answer, or raises a `TecoError`. HTTP,
authentication and faults are the server's business, not this module's.
"""

from collections.abc import Mapping
from dataclasses import dataclass
import datetime as dt
from typing import Final
from urllib.parse import unquote

from . import errors
from .faults import Faults
from .json_parser import parse_put_body
from .json_render import render, render_name_list
from .memory import Location
from .plc import Plc

API_VERSION: Final = "TecoApi v1.0.0"
# Manual 3.4/3.5: "the whole query may be at most 256 characters", read here as the
# request target `/TecoApi/GetObject?...` as sent (still percent-encoded).
MAX_TARGET_LENGTH: Final = 256
PUBLIC_FILE_NAME: Final = "tecoapi.pub"
# Which HTTP method each service answers.
SERVICE_METHODS: Final[Mapping[str, str]] = {
    "GetInfo": "GET",
    "GetList": "GET",
    "GetObject": "GET",
    "SetObject": "GET",
    "PutObject": "PUT",
}
LIST_TYPES: Final = ("struct", "array")
_BY_FOLDED_NAME: Final = {name.lower(): name for name in SERVICE_METHODS}


def service_name(requested: str, *, exact: bool) -> str:
    """The service a path names, spelled as the manual does when it is one.

    Real devices read service names in any case (`getlist`, `GETOBJECT`); with
    `exact` only the manual's spelling is a service. Anything else is returned as
    requested, for the 501.013 answer to quote.
    """
    if exact:
        return requested
    return _BY_FOLDED_NAME.get(requested.lower(), requested)


@dataclass(frozen=True, slots=True)
class ServiceAnswer:
    """A successful answer: status, body (empty for writes), leaf items returned."""

    status: int
    body: bytes = b""
    items: int = 0


def plc_time(moment: dt.datetime) -> str:
    """A moment as the PLC prints times: `2018-01-31T16:50:39.949Z` (UTC)."""
    utc = moment.astimezone(dt.UTC)
    return utc.strftime("%Y-%m-%dT%H:%M:%S.") + f"{utc.microsecond // 1000:03d}Z"


def serve(
    plc: Plc,
    faults: Faults,
    *,
    method: str,
    service: str,
    raw_query: str,
    raw_target: str,
    body: bytes,
    now: dt.datetime,
) -> ServiceAnswer:
    """Answer one authenticated request for `/TecoApi/<service>`."""
    if not service:
        raise errors.service_not_specified()
    if SERVICE_METHODS.get(service) != method:
        raise errors.unimplemented(method, service)
    if service == "GetInfo":
        _parameters(service, raw_query, ())
        return ServiceAnswer(
            200, render(get_info(plc, faults.mode, now), faults.printing)
        )
    _check_public_file(plc)
    if service == "GetList":
        list_type = _parameters(service, raw_query, ("listType",)).get(
            "listType", "struct"
        )
        if list_type not in LIST_TYPES:
            raise errors.unknown_parameter_value("listType", list_type)
        names = [name for name in plc.memory.names if not faults.hides(name)]
        return ServiceAnswer(
            200, render_name_list(names, as_array=list_type == "array")
        )
    if service == "GetObject":
        return get_object(plc, faults, raw_query, raw_target)
    if service == "SetObject":
        set_object(plc, faults, raw_query, raw_target)
        return ServiceAnswer(200)
    put_object(plc, faults, body)
    return ServiceAnswer(204)


def get_info(plc: Plc, mode: str, now: dt.datetime) -> dict[str, object]:
    """GetInfo's body (chapter 3.2); the mode is padded to four characters."""
    identity = plc.identity
    return {
        "api": {"version": API_VERSION},
        "plc": {
            "family": identity.family,
            "type": identity.type,
            "serialNumber": identity.serial_number,
            "version": identity.version,
            "mac": identity.mac,
            "mode": f"{mode:<4}",
            "userProg": {
                "name": plc.program.name,
                "compiled": plc.program.compiled,
                "stamp": plc.program.stamp,
            },
            "time": plc_time(now),
        },
    }


def get_object(
    plc: Plc, faults: Faults, raw_query: str, raw_target: str
) -> ServiceAnswer:
    """GetObject?name1&name2...: the values, nested and merged by root."""
    pieces = _names_in_query(plc, raw_query, raw_target)
    locations = [_locate(plc, faults, piece) for piece in pieces]
    items = sum(location.items for location in locations)
    if items > plc.limit:
        raise errors.too_many_items(plc.limit)
    return ServiceAnswer(
        200, render(plc.memory.answer(locations), faults.printing), items
    )


def set_object(plc: Plc, faults: Faults, raw_query: str, raw_target: str) -> None:
    """SetObject?name1=value1&...: all values written, or none."""
    pieces = _names_in_query(plc, raw_query, raw_target)
    transaction = plc.memory.transaction()
    for piece in pieces:
        raw_name, separator, raw_value = piece.partition("=")
        if not separator and raw_name:
            raise errors.empty_parameter_value("SetObject", unquote(raw_name))
        location = _locate(plc, faults, raw_name)
        transaction.write_text(location, unquote(raw_value))
    transaction.commit()


def put_object(plc: Plc, faults: Faults, body: bytes) -> None:
    """PutObject with a JSON body `{"name": value, ...}`: all written, or none."""
    document = parse_put_body(body)
    if not document:
        raise errors.no_variable()
    if len(document) > plc.limit:
        raise errors.too_many_variables(len(document), plc.limit)
    transaction = plc.memory.transaction()
    for name, value in document.items():
        location = plc.memory.resolve(name)
        if faults.rejects(location.root):
            raise errors.not_found(name)
        transaction.write_json(location, value)
    transaction.commit()


def _names_in_query(plc: Plc, raw_query: str, raw_target: str) -> list[str]:
    """The `&`-separated pieces of a GetObject/SetObject query, checked for limits."""
    if not raw_query:
        raise errors.no_variable()
    pieces = raw_query.split("&")
    if len(pieces) > plc.limit:
        raise errors.too_many_variables(len(pieces), plc.limit)
    if len(raw_target) > MAX_TARGET_LENGTH:
        raise errors.name_too_long(unquote(raw_query))
    return pieces


def _locate(plc: Plc, faults: Faults, raw_name: str) -> Location:
    """The location a percent-encoded name in a query points to."""
    if not raw_name:
        raise errors.empty_name()
    name = unquote(raw_name)
    if len(name) > plc.limit:
        raise errors.name_too_long(name)
    location = plc.memory.resolve(name)
    if faults.rejects(location.root):
        raise errors.not_found(name)
    return location


def _parameters(service: str, raw_query: str, known: tuple[str, ...]) -> dict[str, str]:
    """A service's `name=value` parameters (names exact, as the manual spells them)."""
    parameters: dict[str, str] = {}
    if not raw_query:
        return parameters
    for piece in raw_query.split("&"):
        raw_name, _, raw_value = piece.partition("=")
        name, value = unquote(raw_name), unquote(raw_value)
        if not name:
            raise errors.empty_parameter_name()
        if name not in known:
            raise errors.unknown_parameter(service, name)
        if not value:
            raise errors.empty_parameter_value(service, name)
        parameters[name] = value
    return parameters


def _check_public_file(plc: Plc) -> None:
    """The 500.01x/400.006 answers of a PLC whose public file is missing or bad."""
    state = plc.program.public_file
    if state == "missing" or not plc.program.declarations:
        raise errors.public_file_missing(PUBLIC_FILE_NAME)
    if state == "too_big":
        raise errors.public_file_too_big(PUBLIC_FILE_NAME)
    if state == "unreadable":
        raise errors.public_file_unreadable(PUBLIC_FILE_NAME)
    if state == "empty":
        raise errors.no_variable_found()
