"""Faults a test can switch on a running simulator: slowness, broken answers, PLC mode."""

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, Final, Literal

type TransportFault = Literal[
    "hang", "drop_connection", "http_500", "truncated_json", "malformed_json"
]

# When several transport faults are on, one request gets the first of these.
TRANSPORT_FAULTS: Final[tuple[TransportFault, ...]] = (
    "hang",
    "drop_connection",
    "http_500",
    "truncated_json",
    "malformed_json",
)
PLC_MODES: Final = ("RUN", "HALT", "ERR")


@dataclass(slots=True)
class Faults:
    """What is wrong with the simulated PLC right now; every field may change any time.

    The transport faults (`hang`, `drop_connection`, `http_500`, `truncated_json`,
    `malformed_json`) hit authenticated requests only; with `remaining` set they hit
    that many requests and then clear themselves (a request left hanging stays hung
    until `hang` is switched off by hand, `clear()` is called, or the simulator stops).
    """

    latency: float = 0.0
    latency_per_item: float = 0.0
    drop_connection: bool = False
    http_500: bool = False
    truncated_json: bool = False
    malformed_json: bool = False
    hang: bool = False
    mode: str = "RUN"
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
        object.__setattr__(self, name, value)
        if name != "_listeners":
            for listener in getattr(self, "_listeners", ()):
                listener(name)

    def clear(self) -> None:
        """Back to a healthy PLC in RUN mode."""
        healthy = Faults()
        for name in (
            "latency",
            "latency_per_item",
            *TRANSPORT_FAULTS,
            "mode",
            "remaining",
        ):
            setattr(self, name, getattr(healthy, name))
        self.hidden_from_list = set()
        self.rejected_by_object = set()

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
