"""The client's exceptions: every failure it reports is one of these.

No message ever carries a password: messages name hosts, services, variable
paths, values written and the PLC's own error text, nothing else.
"""

from typing import Any


class TecoApiError(Exception):
    """Base of every error the TecoApi client raises."""


class TecoApiConnectionError(TecoApiError):
    """The PLC could not be reached: refused, unreachable, timed out, dropped."""


class TecoApiTlsError(TecoApiConnectionError):
    """The PLC's TLS certificate was not trusted (verification failed)."""


class TecoApiAuthenticationError(TecoApiError):
    """The PLC rejected the credentials (401.021, 403.022 or a repeated 401)."""


class TecoApiNotTecoApiError(TecoApiError):
    """The host answers HTTP but is not a TecoApi server."""


class TecoApiInvalidHostError(TecoApiError, ValueError):
    """The host given to the client is not a host (it has a path, query, ...)."""


class TecoApiResponseError(TecoApiError):
    """The PLC answered with an error, or with a body that is not valid TecoApi.

    ``code`` is the PLC's ``XXX.YYY`` code (``400.005``); when the body is not the
    documented error JSON it is ``f"{status}.000"``.
    """

    def __init__(self, code: str, status: int, message: str) -> None:
        """Keep the Teco code, the HTTP status and the PLC's message."""
        super().__init__(f"{code}: {message}")
        self.code = code
        self.status = status
        self.message = message


class TecoApiValueRejectedError(TecoApiResponseError):
    """The PLC refused a written value (400.015: outside the variable's type)."""

    def __init__(
        self, code: str, status: int, message: str, *, path: str, value: Any
    ) -> None:
        """Name the variable and the value the PLC refused."""
        super().__init__(code, status, message)
        self.args = (f"The PLC refused value {value!r} for {path!r} ({message})",)
        self.path = path
        self.value = value


class TecoApiWriteError(TecoApiError):
    """A write refused by validation before anything was sent."""

    def __init__(self, path: str, value: Any, reason: str) -> None:
        """Name the variable, the value and why it was refused."""
        super().__init__(f"Cannot write {value!r} to {path!r}: {reason}")
        self.path = path
        self.value = value


class TecoApiReadOnlyError(TecoApiWriteError):
    """The point is read-only (``attr.readOnly``)."""

    def __init__(self, path: str, value: Any) -> None:
        """Name the read-only variable."""
        super().__init__(path, value, "the variable is read-only")


class TecoApiOutOfRangeError(TecoApiWriteError):
    """The value lies outside the point's ``[minValue, maxValue]``."""

    def __init__(
        self, path: str, value: Any, min_value: float, max_value: float
    ) -> None:
        """Name the variable, the value and the allowed range."""
        super().__init__(
            path, value, f"outside the allowed range {min_value:g}..{max_value:g}"
        )
        self.min_value = min_value
        self.max_value = max_value


class TecoApiInvalidValueError(TecoApiWriteError):
    """The value does not fit the point's kind (type, integer range, string, date)."""
