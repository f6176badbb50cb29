"""Faults a test can switch on a running simulator: slowness, broken answers, PLC mode.

Also the ways real devices differ from the manual (how they print text and REALs,
how they read service names): not faults of a PLC, but switches all the same.
"""

from collections.abc import Callable
from dataclasses import dataclass, field, fields
from typing import Any, Final, Literal, get_args

from .json_render import Printing

type TransportFault = Literal[
    "hang",
    "drop_connection",
    "http_500",
    "huge_body",
    "endless_body",
    "truncated_json",
    "malformed_json",
]

# When several transport faults are on, one request gets the first of these (in
# the order `TransportFault` lists them).
TRANSPORT_FAULTS: Final[tuple[TransportFault, ...]] = get_args(TransportFault.__value__)
PLC_MODES: Final = ("RUN", "HALT", "ERR")
# How answers encode their text: the manual's UTF-8, or Windows-1250 (Czech and
# Slovak Mosaic programs; Teco's PLCComS server speaks it).
TEXT_ENCODINGS: Final = ("utf-8", "windows-1250")
HUGE_BODY_BYTES: Final = 64 * 1024 * 1024
"""The `huge_body` fault's answer: 64 MiB, its `Content-Length` declared."""


@dataclass(slots=True)
class Faults:
    """What is wrong with the simulated PLC right now; every field may change any time.

    The transport faults (`hang`, `drop_connection`, `http_500`, `huge_body`,
    `endless_body`, `truncated_json`, `malformed_json`) hit authenticated requests
    only; with `remaining` set they hit that many requests and then clear themselves
    (a request left hanging stays hung until `hang` is switched off by hand, `clear()`
    is called, or the simulator stops).

    What real devices do unlike the manual: `text_encoding` (`windows-1250` prints
    titles, units, strings and error texts as Windows-1250 bytes), `short_reals`
    (REALs as `29.0`, not `29.000000`), and `exact_service_names` (the manual's
    spelling only, `/TecoApi/GetList`; real devices also answer `/tecoapi/getlist`).
    """

    latency: float = 0.0
    latency_per_item: float = 0.0
    drop_connection: bool = False
    http_500: bool = False
    truncated_json: bool = False
    malformed_json: bool = False
    hang: bool = False
    huge_body: bool = False
    endless_body: bool = False
    mode: str = "RUN"
    text_encoding: str = "utf-8"
    short_reals: bool = False
    exact_service_names: bool = False
    hidden_from_list: set[str] = field(default_factory=set)
    rejected_by_object: set[str] = field(default_factory=set)
    remaining: int | None = None
    _listeners: list[Callable[[str], None]] = field(
        default_factory=list, init=False, repr=False, compare=False
    )

    def __setattr__(self, name: str, value: Any) -> None:
        """Set a field and tell the simulator (it releases hung requests)."""
        if name == "mode" and value not in PLC_MODES:
            raise ValueError(f"mode must be one of {', '.join(PLC_MODES)}")
        if name == "text_encoding" and value not in TEXT_ENCODINGS:
            raise ValueError(
                f"text_encoding must be one of {', '.join(TEXT_ENCODINGS)}"
            )
        object.__setattr__(self, name, value)
        if name != "_listeners":
            for listener in getattr(self, "_listeners", ()):
                listener(name)

    def clear(self) -> None:
        """Back to a healthy PLC in RUN mode that prints and reads as by default."""
        healthy = Faults()
        for name in (item.name for item in fields(self) if item.init):
            setattr(self, name, getattr(healthy, name))

    @property
    def printing(self) -> Printing:
        """How answers are printed: encoding and REAL format."""
        return Printing(self.text_encoding, self.short_reals)

    def hides(self, name: str) -> bool:
        """Whether GetList leaves this root out (names compare case-insensitively)."""
        return name.lower() in {hidden.lower() for hidden in self.hidden_from_list}

    def rejects(self, name: str) -> bool:
        """Whether GetObject and the writes answer 400.005 for this root."""
        return name.lower() in {
            rejected.lower() for rejected in self.rejected_by_object
        }

    def take_transport_fault(self) -> TransportFault | None:
        """The transport fault for the next authenticated request, counting it."""
        if self.remaining is not None and self.remaining <= 0:
            self._clear_transport_faults()
            return None
        fault = next((f for f in TRANSPORT_FAULTS if getattr(self, f)), None)
        if fault is not None and self.remaining is not None:
            object.__setattr__(self, "remaining", self.remaining - 1)
            if self.remaining <= 0:
                self._clear_transport_faults()
        return fault

    def add_listener(self, listener: Callable[[str], None]) -> None:
        """Call `listener(field_name)` after every change of a field."""
        self._listeners.append(listener)

    def remove_listener(self, listener: Callable[[str], None]) -> None:
        """Stop calling a listener added before."""
        if listener in self._listeners:
            self._listeners.remove(listener)

    def _clear_transport_faults(self) -> None:
        # Quietly: requests already hung by `hang` stay hung (see the class doc).
        for name in TRANSPORT_FAULTS:
            object.__setattr__(self, name, False)
        object.__setattr__(self, "remaining", None)
