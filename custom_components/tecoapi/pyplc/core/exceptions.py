"""The library's exceptions: every failure a PLC source reports is one of these.

They are transport-neutral: each class says what happened (a variable was not
found, a value was refused, the credentials were rejected), never how a protocol
spells it. A source keeps its own detail in ``code`` and ``status`` for logs and
diagnostics; callers decide by class, never by code.

No message ever carries a password: messages name hosts, services, variable
paths, values written and the PLC's own error text, nothing else.

A message is English, for logs. What a user reads is :meth:`PlcError.text`
(:mod:`.texts`: a key a caller says in its user's language, with its
parameters): each class says what happened in a text of its own, a refused
write why; and :attr:`PlcError.said`, the device's own words (its code and
message) where it gave them, which no caller translates.
"""

from typing import Any, Final

from .texts import Template, Text

FAILED: Final = Template("error_failed", "the device failed")
NO_CONNECTION: Final = Template(
    "error_connection",
    "the connection was refused, timed out or dropped, or the device is unreachable",
)
NOT_TRUSTED: Final = Template(
    "error_tls", "the device's TLS certificate is not trusted"
)
ACCESS_DENIED: Final = Template(
    "error_access_denied", "the device refuses connections from this address"
)
UNAVAILABLE: Final = Template(
    "error_unavailable", "the device's service is unavailable for now"
)
UNREACHABLE: Final = Template(
    "error_unreachable", "the server in front of the PLC cannot reach the PLC"
)
CREDENTIALS: Final = Template("error_auth", "the device refused the credentials")
NOT_THE_DEVICE: Final = Template(
    "error_not_the_device", "it does not answer as the device it should be"
)
NOT_A_HOST: Final = Template("error_invalid_host", "not a host name or address")
ANSWERED_ERROR: Final = Template("error_response", "the device answered with an error")
MALFORMED: Final = Template("error_malformed", "the device's answer cannot be read")
TOO_LARGE: Final = Template(
    "error_too_large", "the device's answer is larger than {limit} bytes"
)
NOT_FOUND: Final = Template(
    "error_not_found", "the device does not know the variable {path}"
)
INVALID_PATH: Final = Template(
    "error_invalid_path", "the device refuses the variable's name"
)
NO_VARIABLES: Final = Template(
    "error_no_variables", "the program publishes no variables"
)
LIST_TOO_LARGE: Final = Template(
    "error_list_too_large", "the list of public variables is too big"
)
LIST_UNREADABLE: Final = Template(
    "error_list_unreadable", "the device cannot read its list of public variables"
)
TOO_MANY_ITEMS: Final = Template(
    "error_too_many_items", "the request asked for more items than one answer holds"
)
VALUE_REJECTED: Final = Template("error_value_rejected", "the device refused the value")
WRITES_DISABLED: Final = Template(
    "error_writes_disabled", "writing is switched off in the device's settings"
)
INVALID_WRITE: Final = Template(
    "error_invalid_write", "the value does not fit the point"
)
READ_ONLY: Final = Template("error_read_only", "the variable is read-only")
OUT_OF_RANGE: Final = Template(
    "error_out_of_range", "outside the allowed range {low}..{high}"
)
TOO_EARLY: Final = Template(
    "error_too_early", "earlier than {earliest}, the first the type holds"
)
DURATION: Final = Template(
    "error_duration",
    "outside the durations the type holds, 00:00:00.000 to {longest}",
)
NOT_ENCODABLE: Final = Template(
    "error_not_encodable", "the device takes {encoding} text only"
)
NOT_ASCII: Final = Template("error_not_ascii", "the PLC takes ASCII text only")


class PlcError(Exception):
    """Base of every error a PLC source raises.

    ``said`` is the device's own words (its code and message), "" where it
    gave none (the message is then the source's).
    """

    def __init__(self, *args: object, said: str = "", why: Text | None = None) -> None:
        """Keep the message, the device's own words and why, where the source tells."""
        super().__init__(*args)
        self.said = said
        self.why = why

    def text(self) -> Text:
        """Return what happened, in a user's words: why, where told, else its class's."""
        return self.why or self.what()

    def what(self) -> Text:
        """Return what happened, as the class says it (see the module)."""
        return FAILED()


class PlcConnectionError(PlcError):
    """The PLC could not be reached: refused, unreachable, timed out, dropped."""

    def what(self) -> Text:
        """Return what happened: no connection."""
        return NO_CONNECTION()


class PlcTlsError(PlcConnectionError):
    """The PLC's TLS certificate was not trusted (verification failed)."""

    def what(self) -> Text:
        """Return what happened: the certificate is not trusted."""
        return NOT_TRUSTED()


class AccessDeniedError(PlcConnectionError):
    """The device refuses this client by its address (an allow-list of clients).

    Not a matter of credentials: the device's own settings must let this
    client's address in.
    """

    def what(self) -> Text:
        """Return what happened: the device refuses this address."""
        return ACCESS_DENIED()


class ServiceUnavailableError(PlcConnectionError):
    """The device answers, but the service behind it is unavailable now.

    A gateway whose server is being restarted: it is worth trying again later.
    """

    def what(self) -> Text:
        """Return what happened: the service is unavailable."""
        return UNAVAILABLE()


class PlcUnreachableError(ServiceUnavailableError):
    """The server in front of the PLC answers, but cannot reach the PLC itself.

    A communication server (PLCComS) whose PLC is off, unplugged or at another
    address: the server is fine, and the PLC is worth trying again later.
    """

    def what(self) -> Text:
        """Return what happened: the PLC is out of the server's reach."""
        return UNREACHABLE()


class PlcAuthenticationError(PlcError):
    """The PLC rejected the credentials."""

    def what(self) -> Text:
        """Return what happened: the credentials were refused."""
        return CREDENTIALS()


class NotAPlcError(PlcError):
    """The host answers, but not as the kind of PLC server the source speaks to."""

    def what(self) -> Text:
        """Return what happened: another kind of server."""
        return NOT_THE_DEVICE()


class InvalidHostError(PlcError, ValueError):
    """The host given to a source is not a host (it has a path, query, ...)."""

    def what(self) -> Text:
        """Return what happened: not a host."""
        return NOT_A_HOST()


class PlcResponseError(PlcError):
    """The PLC answered with an error, or with an answer the source cannot read.

    ``code`` and ``status`` are the source's own spelling of the error (for
    TecoApi the ``XXX.YYY`` code and the HTTP status), kept for logs and
    diagnostics only. ``message`` is the PLC's own text where it gave one, else
    the source's; ``said`` the device's own words for a user (its code and
    message), "" where the message is the source's.
    """

    def __init__(
        self,
        message: str,
        *,
        code: str = "",
        status: int = 0,
        said: str = "",
        why: Text | None = None,
    ) -> None:
        """Keep the PLC's message and the source's code and status."""
        super().__init__(f"{code}: {message}" if code else message, said=said, why=why)
        self.code = code
        self.status = status
        self.message = message

    def what(self) -> Text:
        """Return what happened: the device answered with an error."""
        return ANSWERED_ERROR()


class MalformedResponseError(PlcResponseError):
    """The PLC's answer is not what the protocol promises (broken JSON, wrong shape)."""

    def what(self) -> Text:
        """Return what happened: the answer cannot be read."""
        return MALFORMED()


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

    def what(self) -> Text:
        """Return what happened: the answer is too large."""
        return TOO_LARGE(limit=self.limit)


class VariableNotFoundError(PlcResponseError):
    """A variable is not (or no longer) a public variable of the PLC's program.

    ``path`` is the variable the PLC named, or the one asked for ("" if unknown).
    """

    def __init__(
        self,
        message: str,
        *,
        path: str = "",
        code: str = "",
        status: int = 0,
        said: str = "",
    ) -> None:
        """Name the variable that was not found."""
        super().__init__(message, code=code, status=status, said=said)
        self.path = path

    def what(self) -> Text:
        """Return what happened: the variable is not known."""
        return NOT_FOUND(path=self.path)


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

    def what(self) -> Text:
        """Return what happened: the name is refused."""
        return INVALID_PATH()


class NoPublicVariablesError(PlcResponseError):
    """The PLC's program publishes no variable."""

    def what(self) -> Text:
        """Return what happened: no public variables."""
        return NO_VARIABLES()


class VariableListTooLargeError(PlcResponseError):
    """The device's list of its public variables is larger than it can serve.

    The program publishes too many: publishing fewer is the cure.
    """

    def what(self) -> Text:
        """Return what happened: the list is too big."""
        return LIST_TOO_LARGE()


class VariableListUnreadableError(PlcResponseError):
    """The device cannot read its own list of public variables.

    The program publishes some, but the list is damaged or cannot be read:
    downloading the program again is the cure.
    """

    def what(self) -> Text:
        """Return what happened: the list cannot be read."""
        return LIST_UNREADABLE()


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
        said: str = "",
    ) -> None:
        """Keep the limit the PLC stated."""
        super().__init__(message, code=code, status=status, said=said)
        self.allowed = allowed

    def what(self) -> Text:
        """Return what happened: too many items at once."""
        return TOO_MANY_ITEMS()


class ValueRejectedError(PlcResponseError):
    """The PLC refused a written value (outside the variable's type, unparsable).

    ``why`` is why in a user's words where the source can tell it (a STRING's
    length, from the PLC's answer); None: the device's own words say it.
    """

    def __init__(
        self,
        message: str,
        *,
        path: str,
        value: Any,
        code: str = "",
        status: int = 0,
        said: str = "",
        why: Text | None = None,
    ) -> None:
        """Name the variable and the value the PLC refused."""
        super().__init__(message, code=code, status=status, said=said, why=why)
        self.args = (f"The PLC refused value {value!r} for {path!r} ({message})",)
        self.path = path
        self.value = value

    def what(self) -> Text:
        """Return what happened: the value was refused."""
        return VALUE_REJECTED()


class WritesDisabledError(PlcResponseError):
    """The device takes no writes at all: writing is switched off in its settings."""

    def what(self) -> Text:
        """Return what happened: writing is off."""
        return WRITES_DISABLED()


class InvalidWriteError(PlcError, ValueError):
    """A write refused before anything was sent: the value does not fit the point.

    ``reason`` says why: a :class:`~.texts.Text` (what :meth:`text` returns),
    or English text of a source's own (then the text is only that the value
    does not fit).
    """

    def __init__(self, path: str, value: Any, reason: str | Text) -> None:
        """Name the variable, the value and why it was refused."""
        super().__init__(
            f"Cannot write {value!r} to {path!r}: {reason}",
            why=reason if isinstance(reason, Text) else None,
        )
        self.path = path
        self.value = value
        self.reason = str(reason)

    def what(self) -> Text:
        """Return what happened: the value does not fit."""
        return INVALID_WRITE()


class ReadOnlyError(InvalidWriteError):
    """The point is read-only."""

    def __init__(self, path: str, value: Any) -> None:
        """Name the read-only variable."""
        super().__init__(path, value, READ_ONLY())


class OutOfRangeError(InvalidWriteError):
    """The value lies outside the point's ``[min_value, max_value]``."""

    def __init__(
        self, path: str, value: Any, min_value: float, max_value: float
    ) -> None:
        """Name the variable, the value and the allowed range."""
        super().__init__(
            path, value, OUT_OF_RANGE(low=f"{min_value:g}", high=f"{max_value:g}")
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
        super().__init__(path, value, TOO_EARLY(earliest=earliest))
        self.earliest = earliest


class DurationOutOfRangeError(InvalidValueError):
    """A duration the point's type cannot hold: negative, or longer than its longest.

    ``longest`` is the longest, as the library writes a duration
    (``596:31:23.647``).
    """

    def __init__(self, path: str, value: Any, longest: str) -> None:
        """Name the variable, the value and the longest the type holds."""
        super().__init__(path, value, DURATION(longest=longest))
        self.longest = longest


class NotEncodableError(InvalidValueError):
    """Text the device cannot take: a character its text encoding does not have.

    ``encoding`` is the codec name of what the device takes.
    """

    def __init__(
        self, path: str, value: Any, encoding: str, reason: Text | None = None
    ) -> None:
        """Name the variable, the text and the encoding."""
        super().__init__(path, value, reason or NOT_ENCODABLE(encoding=encoding))
        self.encoding = encoding


class NotAsciiError(NotEncodableError):
    """Text the PLC cannot take: it accepts ASCII characters only."""

    def __init__(self, path: str, value: Any) -> None:
        """Name the variable and the text."""
        super().__init__(path, value, "ascii", NOT_ASCII())
