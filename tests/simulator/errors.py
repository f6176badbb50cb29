"""TecoApi errors as the manual's chapter 3.7 lists them (`XXX.YYY` codes and texts)."""

from typing import Final

# The manual prints long names as 'NNN...'; we keep this many characters of them.
NAME_SHOWN_IN_ERRORS: Final = 64


class TecoError(Exception):
    """An error answer of the TecoApi server: HTTP status, Teco code and message."""

    def __init__(self, status: int, teco_code: int, message: str) -> None:
        """Create the error answered with `status` and body code `status.teco_code`."""
        super().__init__(message)
        self.status = status
        self.teco_code = teco_code
        self.message = message

    @property
    def code(self) -> str:
        """The body's `code` field, e.g. `400.005`."""
        return f"{self.status}.{self.teco_code:03d}"


def _shown(name: str) -> str:
    """A long name cut the way the manual's 'NNN...' placeholders suggest."""
    if len(name) <= NAME_SHOWN_IN_ERRORS:
        return name
    return name[:NAME_SHOWN_IN_ERRORS] + "..."


def no_variable() -> TecoError:
    """400.001: the request names no variable."""
    return TecoError(400, 1, "Bad parameters (any PLC variable is not specified)")


def too_many_variables(requested: int, allowed: int) -> TecoError:
    """413.002: more names in one request than the PLC answers at once."""
    return TecoError(
        413,
        2,
        f"Too many variables in one request (requested: {requested}, allowed: {allowed})",
    )


def empty_name() -> TecoError:
    """400.003: one of the names in the request is empty."""
    return TecoError(400, 3, "Name of variable is empty")


def too_many_items(allowed: int) -> TecoError:
    """413.004: the response would hold more leaf items than allowed."""
    return TecoError(413, 4, f"Too many variables (maximum is {allowed})")


def not_found(name: str) -> TecoError:
    """400.005: no public variable of that name."""
    return TecoError(400, 5, f"Variable '{_shown(name)}' is not found")


def no_variable_found() -> TecoError:
    """400.006: the public file lists no variable (internal error of the PLC)."""
    return TecoError(400, 6, "No variable is found")


def name_too_long(name: str) -> TecoError:
    """400.007: a variable name (or the whole request target) is too long."""
    return TecoError(400, 7, f"Name of variable '{_shown(name)}' is too long")


def item_name_too_long(name: str) -> TecoError:
    """400.008: one item (path segment or JSON member name) is over 64 characters."""
    return TecoError(400, 8, f"Name of item '{_shown(name)}' is too long")


def json_syntax(description: str) -> TecoError:
    """400.009: the PutObject body is not JSON the PLC's parser accepts."""
    return TecoError(400, 9, f"JSON syntax error ({description})")


def public_file_missing(file_name: str) -> TecoError:
    """500.010: the program was compiled without any `{PUBLIC_API}` variable."""
    return TecoError(500, 10, f"Public file '{file_name}' is not found")


def public_file_too_big(file_name: str) -> TecoError:
    """500.011: the public file is over 128 KB."""
    return TecoError(500, 11, f"Public file '{file_name}' is too big")


def public_file_unreadable(file_name: str) -> TecoError:
    """500.012: the public file cannot be read."""
    return TecoError(500, 12, f"Reading of public file '{file_name}' failed")


def unimplemented(method: str, service: str) -> TecoError:
    """501.013: no such service for that HTTP method."""
    return TecoError(501, 13, f"Unimplemented service 'HTTP {method} | {service}'")


def service_not_specified() -> TecoError:
    """400.014: `/TecoApi/` without a service name."""
    return TecoError(400, 14, "Service is not specified")


def value_not_written(value: str, name: str, type_name: str) -> TecoError:
    """400.015: the value does not fit the variable's type (nothing was written)."""
    return TecoError(
        400,
        15,
        f"Value {value} was not written to variable '{_shown(name)}' "
        f"(type of variable is {type_name})",
    )


def unknown_parameter_value(parameter: str, value: str) -> TecoError:
    """400.016: a known parameter with a value the service does not know."""
    return TecoError(
        400, 16, f"Unknown value of parameter (param: '{parameter}', value: '{value}')"
    )


def empty_parameter_name() -> TecoError:
    """400.017: a query parameter without a name."""
    return TecoError(400, 17, "Name of parameter is empty")


def unknown_parameter(service: str, parameter: str) -> TecoError:
    """400.018: a parameter the service does not take."""
    return TecoError(
        400, 18, f"Unknown parameter (service: '{service}', param: '{parameter}')"
    )


def empty_parameter_value(service: str, parameter: str) -> TecoError:
    """400.019: a parameter given without a value."""
    return TecoError(
        400,
        19,
        f"Value of parameter is empty (service: '{service}', param: '{parameter}')",
    )


def stale_nonce() -> TecoError:
    """401.020: the Digest nonce expired; a fresh one comes with `stale=true`."""
    return TecoError(401, 20, "New balls")


def unknown_credentials() -> TecoError:
    """401.021: unknown user name or wrong password."""
    return TecoError(401, 21, "Unknown name or password")


def unsupported_authentication() -> TecoError:
    """403.022: an authentication scheme the server does not offer."""
    return TecoError(403, 22, "Unsupported authentication method")


def authentication_requested() -> TecoError:
    """401.023: no credentials sent (text as in the manual's transcript)."""
    return TecoError(401, 23, "Authentication Requested")
