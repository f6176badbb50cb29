"""The library's exceptions: every failure a PLC source reports is one of these.

They are transport-neutral: each class says what happened (a variable was not
found, a value was refused, the credentials were rejected), never how a protocol
spells it. A source keeps its own detail in ``code`` and ``status`` for logs and
diagnostics; callers decide by class, never by code.

No message ever carries a password: messages name hosts, services, variable
paths, values written and the PLC's own error text, nothing else.
"""

from typing import Any


class PlcError(Exception):
    """Base of every error a PLC source raises."""


class PlcConnectionError(PlcError):
    """The PLC could not be reached: refused, unreachable, timed out, dropped."""


class PlcTlsError(PlcConnectionError):
    """The PLC's TLS certificate was not trusted (verification failed)."""


class AccessDeniedError(PlcConnectionError):
    """The device refuses this client by its address (an allow-list of clients).

    Not a matter of credentials: the device's own settings must let this
    client's address in.
    """


class ServiceUnavailableError(PlcConnectionError):
    """The device answers, but the service behind it is unavailable now.

    A gateway whose server is being restarted: it is worth trying again later.
    """


class PlcUnreachableError(ServiceUnavailableError):
    """The server in front of the PLC answers, but cannot reach the PLC itself.

    A communication server (PLCComS) whose PLC is off, unplugged or at another
    address: the server is fine, and the PLC is worth trying again later.
    """


class PlcAuthenticationError(PlcError):
    """The PLC rejected the credentials."""


class NotAPlcError(PlcError):
    """The host answers, but not as the kind of PLC server the source speaks to."""


class InvalidHostError(PlcError, ValueError):
    """The host given to a source is not a host (it has a path, query, ...)."""


class PlcResponseError(PlcError):
    """The PLC answered with an error, or with an answer the source cannot read.

    ``code`` and ``status`` are the source's own spelling of the error (for
    TecoApi the ``XXX.YYY`` code and the HTTP status), kept for logs and
    diagnostics only. ``message`` is the PLC's own text.
    """

    def __init__(self, message: str, *, code: str = "", status: int = 0) -> None:
        """Keep the PLC's message and the source's code and status."""
        super().__init__(f"{code}: {message}" if code else message)
        self.code = code
        self.status = status
        self.message = message


class MalformedResponseError(PlcResponseError):
    """The PLC's answer is not what the protocol promises (broken JSON, wrong shape)."""


class ResponseTooLargeError(PlcResponseError):
    """The answer grew beyond anything the PLC may legitimately send.

    ``limit`` is the most bytes the source reads of one answer; ``received`` the
    bytes it had read when it stopped (none when the answer declared its size).
    """

    def __init__(
        self,
        message: str,
        *,
        limit: int,
        received: int = 0,
        code: str = "",
        status: int = 0,
    ) -> None:
        """Keep the cap and how much was read."""
        super().__init__(message, code=code, status=status)
        self.limit = limit
        self.received = received


class VariableNotFoundError(PlcResponseError):
    """A variable is not (or no longer) a public variable of the PLC's program.

    ``path`` is the variable the PLC named, or the one asked for ("" if unknown).
    """

    def __init__(
        self, message: str, *, path: str = "", code: str = "", status: int = 0
    ) -> None:
        """Name the variable that was not found."""
        super().__init__(message, code=code, status=status)
        self.path = path


class MissingPointError(VariableNotFoundError, LookupError):
    """A point is not in the catalogue: nothing was sent, nothing can be written to it.

    Raised before anything goes on the wire (a write's check, an appliance
    encoding a command): ``key`` (and ``path``) is the point's key.
    """

    def __init__(self, key: str, message: str | None = None) -> None:
        """Name the point (its key)."""
        super().__init__(message or f"No point {key!r} in the catalogue", path=key)
        self.key = key


class InvalidPathError(PlcResponseError):
    """The PLC refused a variable name itself: empty, too long, a member too long."""


class NoPublicVariablesError(PlcResponseError):
    """The PLC's program publishes no variable."""


class VariableListTooLargeError(PlcResponseError):
    """The device's list of its public variables is larger than it can serve.

    The program publishes too many: publishing fewer is the cure.
    """


class VariableListUnreadableError(PlcResponseError):
    """The device cannot read its own list of public variables.

    The program publishes some, but the list is damaged or cannot be read:
    downloading the program again is the cure.
    """


class TooManyItemsError(PlcResponseError):
    """A request asked for more items than one answer of the PLC may hold.

    ``allowed`` is the limit the PLC stated, if it stated one.
    """

    def __init__(
        self,
        message: str,
        *,
        allowed: int | None = None,
        code: str = "",
        status: int = 0,
    ) -> None:
        """Keep the limit the PLC stated."""
        super().__init__(message, code=code, status=status)
        self.allowed = allowed


class ValueRejectedError(PlcResponseError):
    """The PLC refused a written value (outside the variable's type, unparsable)."""

    def __init__(
        self,
        message: str,
        *,
        path: str,
        value: Any,
        code: str = "",
        status: int = 0,
    ) -> None:
        """Name the variable and the value the PLC refused."""
        super().__init__(message, code=code, status=status)
        self.args = (f"The PLC refused value {value!r} for {path!r} ({message})",)
        self.path = path
        self.value = value


class WritesDisabledError(PlcResponseError):
    """The device takes no writes at all: writing is switched off in its settings."""


class InvalidWriteError(PlcError, ValueError):
    """A write refused before anything was sent: the value does not fit the point."""

    def __init__(self, path: str, value: Any, reason: str) -> None:
        """Name the variable, the value and why it was refused."""
        super().__init__(f"Cannot write {value!r} to {path!r}: {reason}")
        self.path = path
        self.value = value
        self.reason = reason


class ReadOnlyError(InvalidWriteError):
    """The point is read-only."""

    def __init__(self, path: str, value: Any) -> None:
        """Name the read-only variable."""
        super().__init__(path, value, "the variable is read-only")


class OutOfRangeError(InvalidWriteError):
    """The value lies outside the point's ``[min_value, max_value]``."""

    def __init__(
        self, path: str, value: Any, min_value: float, max_value: float
    ) -> None:
        """Name the variable, the value and the allowed range."""
        super().__init__(
            path, value, f"outside the allowed range {min_value:g}..{max_value:g}"
        )
        self.min_value = min_value
        self.max_value = max_value


class InvalidValueError(InvalidWriteError):
    """The value does not fit the point's kind (type, integer range, string, date)."""


class DateTooEarlyError(InvalidValueError):
    """A date, or a date and time, before the first one the point's type holds.

    ``earliest`` is that first one, as the library writes it (``1970-01-01``,
    ``1970-01-01T00:00:00.000Z``).
    """

    def __init__(self, path: str, value: Any, earliest: str) -> None:
        """Name the variable, the value and the earliest the type holds."""
        super().__init__(
            path, value, f"earlier than {earliest}, the first the type holds"
        )
        self.earliest = earliest


class DurationOutOfRangeError(InvalidValueError):
    """A duration the point's type cannot hold: negative, or longer than its longest.

    ``longest`` is the longest, as the library writes a duration
    (``596:31:23.647``).
    """

    def __init__(self, path: str, value: Any, longest: str) -> None:
        """Name the variable, the value and the longest the type holds."""
        super().__init__(
            path,
            value,
            f"outside the durations the type holds, 00:00:00.000 to {longest}",
        )
        self.longest = longest


class NotEncodableError(InvalidValueError):
    """Text the device cannot take: a character its text encoding does not have.

    ``encoding`` is the codec name of what the device takes.
    """

    def __init__(
        self, path: str, value: Any, encoding: str, reason: str | None = None
    ) -> None:
        """Name the variable, the text and the encoding."""
        super().__init__(
            path, value, reason or f"the device takes {encoding} text only"
        )
        self.encoding = encoding


class NotAsciiError(NotEncodableError):
    """Text the PLC cannot take: it accepts ASCII characters only."""

    def __init__(self, path: str, value: Any) -> None:
        """Name the variable and the text."""
        super().__init__(path, value, "ascii", "the PLC takes ASCII text only")
